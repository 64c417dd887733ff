#pragma once

#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <cstddef>
#include <memory>
#include <vector>

/**
 * @file
 * CHOLMOD (SuiteSparse) as the reference the tests and benchmarks compare against: the
 * same permutation, the same BLAS, in the same process.
 */
namespace warpchol::cholesky
{
  /**
   * A thin wrapper of cholmod_l_analyze_p / cholmod_l_factorize / cholmod_l_solve with a
   * permutation given by the caller (CHOLMOD_GIVEN, no postorder: CHOLMOD factors exactly
   * P^T A P), simplicial LL^T or supernodal.
   */
  class CholmodReference
  {
  public:
    explicit CholmodReference(bool supernodal);
    ~CholmodReference();
    CholmodReference(const CholmodReference &) = delete;
    CholmodReference &operator=(const CholmodReference &) = delete;

    /** Symbolic analysis of @p matrix (lower triangle used) with perm[k] = column of A. */
    void analyze(const sparse::CSCMatrix &matrix, const std::vector<Index> &permutation);

    /**
     * Symbolic analysis of @p matrix with CHOLMOD's own choice of ordering (its defaults:
     * AMD, and METIS too when AMD fills much; the elimination tree postordered), as a user
     * who calls cholmod_l_analyze gets it.
     */
    void analyze(const sparse::CSCMatrix &matrix);

    /** Numeric factorization; throws NotPositiveDefinite if CHOLMOD reports one. */
    void factorize(const sparse::CSCMatrix &matrix);

    /** Solve A x = b. */
    std::vector<double> solve(const std::vector<double> &b) const;

    /** L of P^T A P as a CSC matrix (supernodal factors converted to simplicial LL^T). */
    sparse::CSCMatrix factor() const;

    /**
     * Convert the factor to the simplicial LDL^T that cholmod_updown modifies (CHOLMOD
     * updates no other kind), as a user of CHOLMOD's Modify module must before updating.
     */
    void convert_for_updates();

    /**
     * L D L^T +/- C C^T by cholmod_l_updown (update if @p update, else downdate): @p c
     * n x k, its rows already permuted as the factor's (P^T C), sorted. Times it in
     * updown_seconds. Throws NotPositiveDefinite if CHOLMOD reports the downdate failed.
     * Needs convert_for_updates() first.
     */
    void updown(bool update, const sparse::CSCMatrix &c);

    /** Bytes CHOLMOD holds for the numeric factor (values, row indices, pointers). */
    std::size_t factor_bytes() const;

    double analyze_seconds   = 0;
    double factorize_seconds = 0;
    double updown_seconds    = 0;

  private:
    /** cholmod_l_analyze_p with @p permutation (null: CHOLMOD's own choice). */
    void analyze_with(const sparse::CSCMatrix &matrix, const Index *permutation);

    struct Implementation;
    std::unique_ptr<Implementation> implementation;
  };
} // namespace warpchol::cholesky
