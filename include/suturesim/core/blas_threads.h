#pragma once
/**
 * @file
 * One BLAS thread per process. Debian's BLAS here is OpenBLAS (pthreads), which starts
 * one thread per core; MUMPS's dense kernels then use both cores of this machine from one
 * accurate run, where its idle threads spin in sched_yield (39 % of all samples of the
 * accurate stitch, for a wall time only 7 % lower: issue 25), a parallel study's second
 * case loses its core, and an MPI rank's threads compete with the other ranks. The
 * result also depends on the thread count at round-off (the accurate stitch took 397
 * steps with two threads, 399 with one). The program's parallelism is its MPI ranks
 * and a study's cases, so each process uses one BLAS thread unless the user asks for
 * more with OPENBLAS_NUM_THREADS.
 */

namespace suturesim
{
  /// Sets OpenBLAS to one thread unless OPENBLAS_NUM_THREADS is set; returns the count it
  /// set (1), or 0 when it left the BLAS alone (the variable set, or a BLAS without
  /// openblas_set_num_threads, found at run time so that any libblas.so.3 links).
  int
  limit_blas_threads();
} // namespace suturesim
