#pragma once
/**
 * @file
 * The BLAS's threads and kernels, set once per process.
 *
 * One BLAS thread per process. Debian's BLAS here is OpenBLAS (pthreads), which starts
 * one thread per core; MUMPS's dense kernels then use both cores of this machine from one
 * accurate run, where its idle threads spin in sched_yield (39 % of all samples of the
 * accurate stitch, for a wall time only 7 % lower: issue 25), a parallel study's second
 * case loses its core, and an MPI rank's threads compete with the other ranks. The
 * result also depends on the thread count at round-off (the accurate stitch took 397
 * steps with two threads, 399 with one). The program's parallelism is its MPI ranks
 * and a study's cases, so each process uses one BLAS thread unless the user asks for
 * more with OPENBLAS_NUM_THREADS.
 *
 * Kernels fit for the CPU. OpenBLAS picks its kernels from the CPU's model number as it
 * loads, and a model it does not know gets its generic Prescott (SSE3) kernels. Debian
 * 12's OpenBLAS 0.3.21 does not know Intel's Xeons of model 0xCF (Emerald Rapids, this
 * machine) and falls back: one thread's 1500 × 1500 dgemm took 0.476 s with them and
 * 0.096 s with the SkylakeX (AVX-512) kernels (docs/accurate_tissue.md, "BLAS kernels"),
 * and MUMPS's factorisation is mostly dgemm on its fronts. OpenBLAS reads
 * OPENBLAS_CORETYPE only while it loads, so select_blas_kernels() sets it and runs the
 * program again. To keep any kernels (Prescott's among them), set OPENBLAS_CORETYPE.
 */

#include <string>

namespace suturesim
{
  /// Sets OpenBLAS to one thread unless OPENBLAS_NUM_THREADS is set; returns the count it
  /// set (1), or 0 when it left the BLAS alone (the variable set, or a BLAS without
  /// openblas_set_num_threads, found at run time so that any libblas.so.3 links).
  int
  limit_blas_threads();

  /// The kernels OpenBLAS uses in this process (openblas_get_corename()), or "" for
  /// another BLAS.
  std::string
  blas_kernels();

  /// The OpenBLAS kernels this CPU should have instead of the ones loaded: "SkylakeX"
  /// (AVX-512 F, CD, DQ, BW and VL, as OpenBLAS's SkylakeX kernels need) or "Haswell"
  /// (AVX2 and FMA) when OpenBLAS fell back to its generic Prescott kernels; "" when
  /// OPENBLAS_CORETYPE is set (the user's choice, or this program's once it ran again),
  /// the BLAS is not OpenBLAS, OpenBLAS chose other kernels, or the CPU has neither.
  std::string
  better_blas_kernels();

  /// Before anything else in main(), before MPI starts: when better_blas_kernels() names
  /// kernels, sets OPENBLAS_CORETYPE to them and executes this program again with the
  /// same @p argv (its process, MPI rank and environment unchanged otherwise); returns
  /// only when there is nothing to do or the execution failed (the run then goes on
  /// with the kernels it has, as when the program was started through the dynamic loader,
  /// which /proc/self/exe then names). Processes this one starts inherit the choice.
  void
  select_blas_kernels(char **argv);
} // namespace suturesim
