#include <warpchol/cholesky/blas.h>
#include <warpchol/base/stopwatch.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <limits>
#include <vector>
#include <unistd.h>

extern "C"
{
  void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k,
              const double *alpha, const double *a, const int *lda, const double *b, const int *ldb,
              const double *beta, double *c, const int *ldc);
  void dsyrk_(const char *uplo, const char *trans, const int *n, const int *k, const double *alpha,
              const double *a, const int *lda, const double *beta, double *c, const int *ldc);
  void dtrsm_(const char *side, const char *uplo, const char *transa, const char *diag, const int *m,
              const int *n, const double *alpha, const double *a, const int *lda, double *b,
              const int *ldb);
  void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info);
  void sgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k,
              const float *alpha, const float *a, const int *lda, const float *b, const int *ldb,
              const float *beta, float *c, const int *ldc);
  void strsm_(const char *side, const char *uplo, const char *transa, const char *diag, const int *m,
              const int *n, const float *alpha, const float *a, const int *lda, float *b,
              const int *ldb);
  void ssyrk_(const char *uplo, const char *trans, const int *n, const int *k, const float *alpha,
              const float *a, const int *lda, const float *beta, float *c, const int *ldc);
  void  openblas_set_num_threads(int n_threads);
  char *openblas_get_corename(void);
}

namespace warpchol::cholesky::blas
{
  void use_single_threaded_blas()
  {
    static const bool pinned = [] {
      openblas_set_num_threads(1);
      return true;
    }();
    (void)pinned;
  }

  void restart_with_single_threaded_libraries(char **argv)
  {
    const char *const kernels = kernels_for_this_cpu();
    if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr && std::getenv("OMP_THREAD_LIMIT") != nullptr &&
        kernels == nullptr)
      return;
    ::setenv("OPENBLAS_NUM_THREADS", "1", 0);
    ::setenv("OMP_THREAD_LIMIT", "1", 0);
    if (kernels != nullptr)
      ::setenv("OPENBLAS_CORETYPE", kernels, 0);
    ::execv("/proc/self/exe", argv); // returns only on failure: then run as we are
  }

  std::string kernel_name()
  {
    const char *const name = openblas_get_corename();
    return name != nullptr ? name : "unknown";
  }

  const char *kernels_for_this_cpu()
  {
#if defined(__x86_64__)
    // Kernels chosen by OPENBLAS_CORETYPE are the user's choice, whichever they are.
    if (std::getenv("OPENBLAS_CORETYPE") != nullptr)
      return nullptr;
    // The kernels OpenBLAS falls back to, none with AVX2: Prescott for an Intel CPU it does
    // not know, Barcelona for an AMD one; the others are CPUs without AVX2.
    std::string name = kernel_name();
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    for (const char *fallback : {"prescott", "core2", "penryn", "dunnington", "nehalem", "sandybridge", "barcelona"})
      if (name == fallback)
        {
          __builtin_cpu_init();
          if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
              __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
              __builtin_cpu_supports("avx512vl"))
            return "SkylakeX";
          if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
            return "Haswell";
          return nullptr;
        }
#endif
    return nullptr;
  }

  void restart_with_blas_kernels_for_this_cpu(char **argv)
  {
    const char *const kernels = kernels_for_this_cpu();
    if (kernels == nullptr)
      return;
    ::setenv("OPENBLAS_CORETYPE", kernels, 0);
    ::execv("/proc/self/exe", argv); // returns only on failure: then run as we are
  }

  void gemm(const bool transpose_a, const bool transpose_b, const int m, const int n, const int k,
            const double alpha, const double *a, const int lda, const double *b, const int ldb,
            const double beta, double *c, const int ldc)
  {
    if (m > 0 && n > 0)
      dgemm_(transpose_a ? "T" : "N", transpose_b ? "T" : "N", &m, &n, &k, &alpha, a, &lda, b, &ldb,
             &beta, c, &ldc);
  }

  void gemm_nt(const int m, const int n, const int k, const double alpha, const double *a,
               const int lda, const double *b, const int ldb, const double beta, double *c,
               const int ldc)
  {
    gemm(false, true, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
  }

  void syrk_lower(const int n, const int k, const double alpha, const double *a, const int lda,
                  const double beta, double *c, const int ldc)
  {
    if (n > 0)
      dsyrk_("L", "N", &n, &k, &alpha, a, &lda, &beta, c, &ldc);
  }

  void trsm_right_lower_transpose(const int m, const int n, const double *l, const int ldl,
                                  double *b, const int ldb)
  {
    const double one = 1.;
    if (m > 0 && n > 0)
      dtrsm_("R", "L", "T", "N", &m, &n, &one, l, &ldl, b, &ldb);
  }

  void trsm_left_lower(const bool transpose, const int n, const int nrhs, const double *l,
                       const int ldl, double *b, const int ldb)
  {
    const double one = 1.;
    if (n > 0 && nrhs > 0)
      dtrsm_("L", "L", transpose ? "T" : "N", "N", &n, &nrhs, &one, l, &ldl, b, &ldb);
  }

  void gemm(const bool transpose_a, const bool transpose_b, const int m, const int n, const int k,
            const float alpha, const float *a, const int lda, const float *b, const int ldb,
            const float beta, float *c, const int ldc)
  {
    if (m > 0 && n > 0)
      sgemm_(transpose_a ? "T" : "N", transpose_b ? "T" : "N", &m, &n, &k, &alpha, a, &lda, b, &ldb,
             &beta, c, &ldc);
  }

  void trsm_left_lower(const bool transpose, const int n, const int nrhs, const float *l,
                       const int ldl, float *b, const int ldb)
  {
    const float one = 1.f;
    if (n > 0 && nrhs > 0)
      strsm_("L", "L", transpose ? "T" : "N", "N", &n, &nrhs, &one, l, &ldl, b, &ldb);
  }

  void gemm_nt(const int m, const int n, const int k, const float alpha, const float *a, const int lda,
               const float *b, const int ldb, const float beta, float *c, const int ldc)
  {
    gemm(false, true, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
  }

  void syrk_lower(const int n, const int k, const float alpha, const float *a, const int lda, const float beta,
                  float *c, const int ldc)
  {
    if (n > 0)
      ssyrk_("L", "N", &n, &k, &alpha, a, &lda, &beta, c, &ldc);
  }

  void trsm_right_lower_transpose(const int m, const int n, const float *l, const int ldl, float *b, const int ldb)
  {
    const float one = 1.f;
    if (m > 0 && n > 0)
      strsm_("R", "L", "T", "N", &m, &n, &one, l, &ldl, b, &ldb);
  }

  int potrf_lower(const int n, double *a, const int lda)
  {
    int info = 0;
    if (n > 0)
      dpotrf_("L", &n, a, &lda, &info);
    return info;
  }
  double measure_dgemm_gflops()
  {
    const int           n = 1000;
    std::vector<double> a(n * n, 0.5), b(n * n, 0.25), c(n * n, 0.);
    double              best = std::numeric_limits<double>::infinity();
    for (int repetition = 0; repetition < 3; ++repetition)
      {
        const Stopwatch stopwatch;
        gemm(false, false, n, n, n, 1.0, a.data(), n, b.data(), n, 0.0, c.data(), n);
        best = std::min(best, stopwatch.seconds());
      }
    return 2.0 * n * n * n / best / 1e9;
  }
} // namespace warpchol::cholesky::blas
