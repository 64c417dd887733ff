#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/numeric_supernodal.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/permuted_matrix.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/cholesky/symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <string>
#include <vector>

/**
 * @file
 * The solver facade, in the spirit of Eigen's SimplicialLLT and CHOLMOD:
 * analyze (pattern) / factorize (values) / refactorize (values, changed columns) / solve.
 */
namespace warpchol::cholesky
{
  /** How the numeric factor is computed. */
  enum class FactorizationMethod
  {
    /** Column by column, left-looking: the one that refactorizes partially. */
    left_looking,
    /** Row by row (CSparse's cs_chol), the report's baseline: refactorization is full. */
    up_looking,
    /** Left-looking by supernodes with BLAS-3 kernels: the fast one, also refactorizes partially. */
    supernodal
  };

  /** "left", "up" or "supernodal". */
  std::string to_string(FactorizationMethod method);

  /** Parse "left" / "left_looking", "up" / "up_looking" or "supernodal"; throws InputError otherwise. */
  FactorizationMethod parse_factorization_method(const std::string &name);

  /**
   * A sparse Cholesky solver for symmetric positive definite matrices, A = P L L^T P^T,
   * whose factor can be *updated* when some columns of A change: refactorize() recomputes
   * the changed columns of C = P^T A P and their elimination-tree ancestors, and reuses
   * every other column of L as it is.
   *
   * @code
   *   SparseCholesky solver;          // METIS ordering, left-looking
   *   solver.analyze(A);              // ordering + symbolic analysis (pattern only)
   *   solver.factorize(A);            // numeric factorization
   *   solver.solve(b, x);
   *   ... change the entries of some columns of A (same pattern) ...
   *   solver.refactorize(A, changed_columns);
   *   solver.solve(b, x);
   * @endcode
   *
   * The matrix is given in CSC form, either with both triangles stored (then its pattern
   * and values must be symmetric) or with the lower triangle only.
   */
  class SparseCholesky
  {
  public:
    /** Choices made before analyze(). */
    struct Settings
    {
      OrderingSettings    ordering;
      FactorizationMethod method = FactorizationMethod::left_looking;
      /** Supernode amalgamation (supernodal method). */
      SupernodeRelaxation relaxation;
      /** Threads of the supernodal factorization (1: serial, no TBB). */
      unsigned int        n_threads = 1;
    };

    /** What the last calls did and cost. Times are wall-clock seconds. */
    struct Statistics
    {
      Index  n                 = 0;
      /** Stored entries of the lower triangle of A. */
      Index  nnz_a             = 0;
      /** Entries of L, diagonal included. */
      Index  nnz_l             = 0;
      /** Flops of a factorization without padding (sum of squared column counts, CHOLMOD's fl). */
      double flops             = 0;
      /** Flops a full factorization by the chosen method spends (supernodes: padding included). */
      double method_flops      = 0;
      /** Supernodes (supernodal method; 0 otherwise). */
      Index  n_supernodes      = 0;
      int    vertex_block_size = 1;
      double analyze_seconds   = 0;
      /** The last factorize(), or a refactorize() that had to factor everything. */
      double factorize_seconds = 0;
      /** The last refactorize(). */
      double refactorize_seconds = 0;
      /** The last solve(). */
      double solve_seconds       = 0;
      /** Columns of L the last refactorize() recomputed. */
      Index  columns_recomputed  = 0;
      /** Supernodes the last refactorize() recomputed (wholly or from a column on). */
      Index  supernodes_recomputed = 0;
      /** Flops the last refactorize() spent. */
      double flops_recomputed    = 0;
      Index  n_factorizations    = 0;
      Index  n_refactorizations  = 0;
      /** Bytes held by the numeric factor (values and the structure that indexes them). */
      std::size_t factor_bytes   = 0;

      /** nnz(L) / nnz(tril(A)). */
      double fill() const;
    };

    SparseCholesky();
    explicit SparseCholesky(const Settings &settings);

    /**
     * Fill-reducing ordering (postordered) and symbolic analysis of the pattern of the
     * square matrix @p matrix. Throws MatrixError on a non-square or (full storage)
     * non-symmetric pattern.
     */
    void analyze(const sparse::CSCMatrix &matrix);

    /**
     * Numeric factorization of @p matrix, which has the analyzed pattern. Throws
     * NotPositiveDefinite naming the column (user numbering) and value of the failed
     * pivot, MatrixError on another pattern, NaN/Inf or asymmetric values.
     */
    void factorize(const sparse::CSCMatrix &matrix);

    /**
     * Partial refactorization after the entries of @p changed_columns (user numbering) of
     * @p matrix changed: recompute exactly the columns of L on the elimination-tree paths
     * from those columns (permuted) to the root, reuse the others. A column of C whose
     * values changed without being listed is found while loading the values and recomputed
     * as well, so the factor always matches @p matrix. Throws InputError for a column out of
     * range, and what factorize() throws. If no valid factor exists yet, factors fully.
     */
    void refactorize(const sparse::CSCMatrix &matrix, const std::vector<Index> &changed_columns);

    /** Solve A x = b for one right-hand side. */
    void solve(const std::vector<double> &b, std::vector<double> &x) const;

    /**
     * Solve A X = B for @p n_rhs right-hand sides stored column by column (leading
     * dimension n) in @p b; the solutions go to @p x (which may alias @p b).
     */
    void solve(const double *b, double *x, Index n_rhs) const;

    /** L, the factor of P^T A P (permuted numbering; a triangular matrix, full storage). */
    sparse::CSCMatrix factor() const;

    /** perm[k] = column of A that is column k of P^T A P. */
    const std::vector<Index> &permutation() const;

    /** The column-by-column structure (left- and up-looking methods; empty for supernodal). */
    const SymbolicFactorization &symbolic() const;

    /** The supernodal structure (supernodal method; empty otherwise). */
    const SupernodalSymbolic &supernodal_symbolic() const;

    /** Parent of each column of P^T A P in the elimination tree. */
    const std::vector<Index> &elimination_tree() const;

    /** The columns of L (permuted numbering, sorted) that the last refactorize() recomputed. */
    const std::vector<Index> &recomputed_columns() const;

    const Statistics &statistics() const;

    const Settings &settings() const;

  private:
    /** Factor the given columns (all if empty); maps a failed pivot to the user's column. */
    double run_numeric(const std::vector<Index> &columns);

    Settings              solver_settings;
    std::vector<Index>    fill_reducing_permutation;
    std::vector<Index>    inverse_permutation;
    SymbolicFactorization symbolic_factorization;
    SupernodalSymbolic    supernodal_structure;
    PermutedMatrix        permuted_matrix;
    std::vector<double>   l_values;
    SupernodalFactor      supernodal_factor;
    std::vector<Index>    last_recomputed_columns;
    bool                  analyzed     = false;
    bool                  factor_valid = false;
    mutable Statistics    stats;
  };
} // namespace warpchol::cholesky
