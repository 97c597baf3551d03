#pragma once
/**
 * @file
 * SUTURESIM_HOT_KERNEL marks the few loops that bound the haptic step (XPBD sweeps,
 * spring forces). GCC compiles each three times, for x86-64-v4 (AVX-512), x86-64-v3
 * (AVX2, FMA) and the baseline, and picks one when the library loads (function
 * multi-versioning through an ifunc): the build stays portable while a recent processor
 * runs the fused multiply-adds (measured in tests/benchmarks/realtime_benchmark.cc) and
 * AVX-512's wider registers and masked operations (on the seed-004-scale benchmark's
 * AMD EPYC the recording phase, mostly the boundary's reaction, took 17 µs against 25
 * with the v3 clone, four back-to-back pairs of development builds; docs/realtime.md).
 * Elsewhere it is empty, and under ThreadSanitizer, whose run time is not yet set up
 * when the loader calls the ifunc resolvers (the program crashes before main).
 */

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
  __GNUC__ >= 11 && !defined(__SANITIZE_THREAD__)
#  define SUTURESIM_HOT_KERNEL __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#  define SUTURESIM_HOT_KERNEL
#endif
