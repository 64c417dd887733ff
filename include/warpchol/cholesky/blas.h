#pragma once

#include <string>

/**
 * @file
 * The few BLAS/LAPACK routines of the supernodal code, declared through their Fortran
 * symbols (OpenBLAS, 32-bit integers) and wrapped with C++ signatures. Matrices are
 * column-major; lower triangles.
 */
namespace warpchol::cholesky::blas
{
  /**
   * Pin OpenBLAS to one thread per call (idempotent, cheap). warpchol runs its own threads
   * above BLAS (subtrees, row blocks); OpenBLAS threads under them would oversubscribe the
   * cores. CHOLMOD, in the same process, then gets the same single-threaded kernels.
   */
  void use_single_threaded_blas();

  /**
   * For programs that time the solver: make the threads of the libraries below us what
   * the measurement needs, which only the environment at start-up can do.
   * - OPENBLAS_NUM_THREADS=1: OpenBLAS's pthread build otherwise starts worker threads at
   *   load time that spin (sched_yield) for a while, taking a core from us.
   * - OMP_THREAD_LIMIT=1: Debian's CHOLMOD opens OpenMP regions of a fixed 4 threads around
   *   cheap loops, which on a 2-core machine costs it up to 4x in thread wake-ups.
   * If either is unset, set both and restart the program in place (execv of
   * /proc/self/exe with @p argv); returns only when nothing needs doing or exec fails.
   * Call it first thing in main().
   */
  void restart_with_single_threaded_libraries(char **argv);

  /**
   * The name of the kernels OpenBLAS runs ("Haswell", "SkylakeX", ...): it picks them
   * from the CPU at load time, or from OPENBLAS_CORETYPE.
   */
  std::string kernel_name();

  /**
   * The OPENBLAS_CORETYPE this CPU should run where OpenBLAS fell back to kernels without
   * AVX2 on a CPU that has it (an OpenBLAS older than the CPU: Debian 12's 0.3.21 takes an
   * Intel Xeon of model 207 for a Prescott and runs dgemm at a fifth of its speed):
   * "SkylakeX" where the CPU has AVX-512 (F, CD, BW, DQ, VL), else "Haswell". nullptr where
   * OpenBLAS did not fall back, or OPENBLAS_CORETYPE is set (its kernels are then chosen).
   */
  const char *kernels_for_this_cpu();

  /**
   * For every program: where kernels_for_this_cpu() names kernels, set OPENBLAS_CORETYPE
   * to them and restart the program in place (execv of /proc/self/exe with @p argv), the
   * only way to choose OpenBLAS's kernels; returns only when nothing needs doing or exec
   * fails. Call it first thing in main().
   */
  void restart_with_blas_kernels_for_this_cpu(char **argv);

  /** C = alpha op(A) op(B) + beta C, op(A) m x k, op(B) k x n, op = transpose or not. */
  void gemm(bool transpose_a, bool transpose_b, int m, int n, int k, double alpha, const double *a,
            int lda, const double *b, int ldb, double beta, double *c, int ldc);

  /**
   * The machine's dgemm rate in GFLOP/s on this thread: the best of a few products of
   * 1000x1000 matrices (2 n^3 flops each), the ceiling of every supernodal factorization.
   */
  double measure_dgemm_gflops();

  /** C = alpha A B^T + beta C, A m x k, B n x k ("N","T"). */
  void gemm_nt(int m, int n, int k, double alpha, const double *a, int lda, const double *b,
               int ldb, double beta, double *c, int ldc);

  /** C = alpha A A^T + beta C on the lower triangle of the n x n C, A n x k. */
  void syrk_lower(int n, int k, double alpha, const double *a, int lda, double beta, double *c,
                  int ldc);

  /** B = B L^{-T} for the m x n B and the lower triangular n x n L ("R","L","T","N"). */
  void trsm_right_lower_transpose(int m, int n, const double *l, int ldl, double *b, int ldb);

  /** B = L^{-1} B (transpose = false) or L^{-T} B (transpose = true), L lower n x n, B n x nrhs. */
  void trsm_left_lower(bool transpose, int n, int nrhs, const double *l, int ldl, double *b, int ldb);

  /**
   * Cholesky factorization of the lower triangle of the n x n A in place. Returns 0, or
   * the 1-based column whose pivot is not positive; LAPACK leaves that pivot's value on
   * the diagonal.
   */
  int potrf_lower(int n, double *a, int lda);

  /** The same in single precision (sgemm, strsm): the triangular solves of a single-precision factor. */
  void gemm(bool transpose_a, bool transpose_b, int m, int n, int k, float alpha, const float *a,
            int lda, const float *b, int ldb, float beta, float *c, int ldc);
  void trsm_left_lower(bool transpose, int n, int nrhs, const float *l, int ldl, float *b, int ldb);
  /** The same in single precision (sgemm, ssyrk, strsm): a compliance renewed in single precision. */
  void gemm_nt(int m, int n, int k, float alpha, const float *a, int lda, const float *b, int ldb,
               float beta, float *c, int ldc);
  void syrk_lower(int n, int k, float alpha, const float *a, int lda, float beta, float *c, int ldc);
  void trsm_right_lower_transpose(int m, int n, const float *l, int ldl, float *b, int ldb);
} // namespace warpchol::cholesky::blas
