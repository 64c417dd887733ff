#include <warpchol/backends/cholmod_reference.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>

#include <cholmod.h>

namespace warpchol::cholesky
{
  struct CholmodReference::Implementation
  {
    cholmod_common  common;
    cholmod_factor *factor = nullptr;
    Index           n      = 0;

    /**
     * A CHOLMOD view of our matrix (no copy): by default symmetric, the lower triangle
     * used (stype -1); stype 0 for a general one (the columns of an update).
     */
    static cholmod_sparse view(const sparse::CSCMatrix &matrix, const int stype = -1)
    {
      cholmod_sparse a{};
      a.nrow   = matrix.n_rows;
      a.ncol   = matrix.n_cols;
      a.nzmax  = matrix.n_nonzeros();
      a.p      = const_cast<Index *>(matrix.column_start.data());
      a.i      = const_cast<Index *>(matrix.row_index.data());
      a.x      = const_cast<double *>(matrix.values.data());
      a.stype  = stype;
      a.itype  = CHOLMOD_LONG;
      a.xtype  = CHOLMOD_REAL;
      a.dtype  = CHOLMOD_DOUBLE;
      a.sorted = 1;
      a.packed = 1;
      return a;
    }
  };

  CholmodReference::CholmodReference(const bool supernodal)
    : implementation(std::make_unique<Implementation>())
  {
    blas::use_single_threaded_blas();
    cholmod_common &common = implementation->common;
    cholmod_l_start(&common);
    common.supernodal         = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    common.final_ll           = 1;
    common.print              = 0;
    common.error_handler      = nullptr;
  }

  CholmodReference::~CholmodReference()
  {
    cholmod_l_free_factor(&implementation->factor, &implementation->common);
    cholmod_l_finish(&implementation->common);
  }

  void CholmodReference::analyze(const sparse::CSCMatrix &matrix, const std::vector<Index> &permutation)
  {
    // Exactly P^T A P: the given permutation, no postorder.
    cholmod_common &common    = implementation->common;
    common.nmethods           = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
    common.postorder          = 0;
    analyze_with(matrix, permutation.data());
  }

  void CholmodReference::analyze(const sparse::CSCMatrix &matrix)
  {
    // CHOLMOD's defaults (analyze() with a permutation replaces them).
    implementation->common.nmethods  = 0;
    implementation->common.postorder = 1;
    analyze_with(matrix, nullptr);
  }

  void CholmodReference::analyze_with(const sparse::CSCMatrix &matrix, const Index *permutation)
  {
    const Stopwatch stopwatch;
    cholmod_common &common = implementation->common;
    cholmod_l_free_factor(&implementation->factor, &common);
    cholmod_sparse a = Implementation::view(matrix);
    // No permutation: CHOLMOD orders as its settings say.
    implementation->factor = cholmod_l_analyze_p(&a, const_cast<Index *>(permutation), nullptr, 0, &common);
    if (implementation->factor == nullptr)
      throw Error("CHOLMOD analysis failed with status " + std::to_string(common.status));
    implementation->n = matrix.n_cols;
    analyze_seconds   = stopwatch.seconds();
  }

  void CholmodReference::factorize(const sparse::CSCMatrix &matrix)
  {
    const Stopwatch stopwatch;
    cholmod_sparse  a = Implementation::view(matrix);
    cholmod_l_factorize(&a, implementation->factor, &implementation->common);
    factorize_seconds = stopwatch.seconds();
    if (implementation->common.status == CHOLMOD_NOT_POSDEF)
      {
        const auto *perm = static_cast<const Index *>(implementation->factor->Perm);
        throw NotPositiveDefinite(perm[implementation->factor->minor], 0.);
      }
    if (implementation->common.status < CHOLMOD_OK)
      throw Error("CHOLMOD factorization failed with status " +
                  std::to_string(implementation->common.status));
  }

  std::vector<double> CholmodReference::solve(const std::vector<double> &b) const
  {
    cholmod_common &common = implementation->common;
    cholmod_dense   rhs{};
    rhs.nrow  = b.size();
    rhs.ncol  = 1;
    rhs.nzmax = b.size();
    rhs.d     = b.size();
    rhs.x     = const_cast<double *>(b.data());
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *x = cholmod_l_solve(CHOLMOD_A, implementation->factor, &rhs, &common);
    if (x == nullptr)
      throw Error("CHOLMOD solve failed");
    const auto         *values = static_cast<const double *>(x->x);
    std::vector<double> solution(values, values + b.size());
    cholmod_l_free_dense(&x, &common);
    return solution;
  }

  sparse::CSCMatrix CholmodReference::factor() const
  {
    cholmod_common &common = implementation->common;
    cholmod_factor *copy   = cholmod_l_copy_factor(implementation->factor, &common);
    cholmod_l_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, copy, &common);
    cholmod_sparse *l = cholmod_l_factor_to_sparse(copy, &common);
    cholmod_l_free_factor(&copy, &common);
    if (l == nullptr)
      throw Error("CHOLMOD factor conversion failed");
    sparse::CSCMatrix result = sparse::CSCMatrix::zero(l->nrow, l->ncol);
    const auto       *p      = static_cast<const Index *>(l->p);
    const auto       *i      = static_cast<const Index *>(l->i);
    const auto       *x      = static_cast<const double *>(l->x);
    result.column_start.assign(p, p + l->ncol + 1);
    result.row_index.assign(i, i + p[l->ncol]);
    result.values.assign(x, x + p[l->ncol]);
    cholmod_l_free_sparse(&l, &common);
    return result;
  }

  void CholmodReference::convert_for_updates()
  {
    // Real, LDL^T (not LL^T), simplicial, packed, monotonic.
    if (!cholmod_l_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, implementation->factor, &implementation->common))
      throw Error("CHOLMOD could not convert its factor to a simplicial LDL^T");
  }

  void CholmodReference::updown(const bool update, const sparse::CSCMatrix &c)
  {
    cholmod_sparse  view = Implementation::view(c, 0);
    const Stopwatch stopwatch;
    const int       ok = cholmod_l_updown(update ? 1 : 0, &view, implementation->factor, &implementation->common);
    updown_seconds     = stopwatch.seconds();
    if (implementation->common.status == CHOLMOD_NOT_POSDEF)
      throw NotPositiveDefinite(-1, 0.);
    if (!ok || implementation->common.status < CHOLMOD_OK)
      throw Error("CHOLMOD update/downdate failed with status " + std::to_string(implementation->common.status));
  }

  std::size_t CholmodReference::factor_bytes() const
  {
    const cholmod_factor *l = implementation->factor;
    if (l->is_super)
      return l->xsize * sizeof(double) + l->ssize * sizeof(Index) +
             3 * (l->nsuper + 1) * sizeof(Index);
    return l->nzmax * (sizeof(double) + sizeof(Index)) + (2 * l->n + 1) * sizeof(Index);
  }
} // namespace warpchol::cholesky
