#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/named_values.h>
#include <warpchol/base/types.h>
#include <warpchol/cholesky/modify.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <memory>
#include <vector>

/**
 * @file
 * Supernodal left-looking numeric factorization (CHOLMOD's cholmod_super_numeric concern)
 * and its partial variant, with the supernodal triangular solves.
 */
namespace warpchol::cholesky
{
  /**
   * The precision of the copy of the factor that a preconditioner's solve reads
   * (SupernodalFactor::solve_preconditioner()): CG reads it twice per iteration, the
   * largest part of what an iteration moves.
   */
  enum class PreconditionerPrecision
  {
    /** No copy: the double factor itself (solve()). */
    full,
    /** 32 bits per entry: half the bytes of the double factor, about 1e-7 relative. */
    single,
    /**
     * 16 bits per entry (IEEE half, each column scaled by a power of two into its range),
     * single-precision arithmetic: a quarter of the bytes, about 5e-4 relative.
     */
    half
  };

  /** The names of the precisions (base/named_values.h): "double", "single", "half". */
  inline constexpr NameTable<PreconditionerPrecision, 3> preconditioner_precision_names{
    {{PreconditionerPrecision::full, "double"},
     {PreconditionerPrecision::single, "single"},
     {PreconditionerPrecision::half, "half"}}};

  /**
   * The numeric supernodal factor and the workspaces that compute it.
   *
   * For each supernode s, in elimination-tree order: gather the columns of C into the
   * dense block of s; subtract the update L_d(rows, :) L_d(cols, :)^T of every descendant d
   * whose rows meet the columns of s (dsyrk + dgemm into a workspace, then a scatter through
   * a map from rows to local positions; straight into the block when d's rows are
   * contiguous in s); then dpotrf on the diagonal block and dtrsm below it.
   *
   * Independent subtrees run in parallel (TBB), and the supernodes at the top of the tree,
   * where the subtrees have joined, split their dense work into row blocks. Every entry is
   * summed in the same order whatever the thread count.
   */
  class SupernodalFactor
  {
  public:
    SupernodalFactor();
    ~SupernodalFactor();
    SupernodalFactor(const SupernodalFactor &other);
    SupernodalFactor &operator=(const SupernodalFactor &other);
    /** Moves hand the values over without copying them (a swap of factors is cheap). */
    SupernodalFactor(SupernodalFactor &&other) noexcept;
    SupernodalFactor &operator=(SupernodalFactor &&other) noexcept;

    /**
     * Allocate the values for the structure @p symbolic (which every later call is given
     * too); with @p copy other than full, also a copy of the factor in that precision that
     * follows factorize() and modify() (for solve_preconditioner(), which rounds what they
     * changed into it when it first reads it).
     */
    void initialize(const SupernodalSymbolic &symbolic,
                    PreconditionerPrecision   copy = PreconditionerPrecision::full);

    /**
     * Free the values (a new analysis, or none needed): factorize() allocates them for its
     * structure, with the preconditioner's copy in the precision @p copy.
     */
    void clear(PreconditionerPrecision copy = PreconditionerPrecision::full);

    /**
     * Allocate the values for @p symbolic unless they are: what factorize() does first. A
     * caller that times factorize() calls it before, so that the time is the arithmetic's,
     * not the first touch of the factor's memory (which a virtual machine's page faults can
     * make several times the arithmetic).
     */
    void allocate(const SupernodalSymbolic &symbolic);

    /** Bytes of the values held now (and of the preconditioner's copy). */
    std::size_t memory_bytes() const;

    /**
     * Compute the listed @p supernodes (sorted; all of them if empty) from the lower-stored
     * permuted matrix @p lower. Supernode supernodes[k] is recomputed from its column
     * first_column + start_offsets[k] on (all of it if @p start_offsets is empty): the
     * columns before it must be valid already, as must every descendant that is not listed.
     * The list must be closed under supernodal-tree ancestry. Returns the flops spent.
     * Throws NotPositiveDefinite with the permuted column of a failed pivot.
     */
    double factorize(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &lower,
                     const std::vector<Index> &supernodes,
                     const std::vector<Index> &start_offsets, unsigned int n_threads);

    /**
     * What factorize() of @p supernodes from @p start_offsets would take, from the seconds
     * per flop each supernode took when computed (factorize() times each, a moving average
     * over its computations), on this machine and in its place in the tree: a supernode of
     * the top, large and dense, runs at a higher rate than the many small ones below, which
     * a factorization's average rate mixes. Negative if one of them was never timed (no
     * factorization yet).
     */
    double timed_seconds(const SupernodalSymbolic &symbolic, const std::vector<Index> &supernodes,
                         const std::vector<Index> &start_offsets) const;

    /**
     * L L^T + C diag(@p signs) C^T in place (modify_supernodal(), which says what @p c and
     * its @p plan must be), the preconditioner's copy following. Throws
     * NotPositiveDefinite, the values left as they were, if a downdate loses positive
     * definiteness.
     */
    ModificationResult modify(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c,
                              const ModificationPlan &plan, const std::vector<double> &signs,
                              const ModificationSettings &settings);

    /**
     * Round what factorize() and modify() changed into the preconditioner's copy now
     * (solve_preconditioner() does it on first use): where a thread of its own made the
     * factor, the rounding stays there.
     */
    void round_copy(const SupernodalSymbolic &symbolic);

    /**
     * Overwrite @p x (n x n_rhs, column-major) with the solution of L L^T z = x.
     * Independent subtrees of the tree are solved side by side on @p n_threads threads,
     * each summing what it subtracts from the top's rows in its own buffer, added in
     * subtree order; the split does not depend on the number of threads, so neither do
     * the bits of the result.
     */
    void solve(const SupernodalSymbolic &symbolic, double *x, Index n_rhs, unsigned int n_threads = 1) const;

    /**
     * The same for one right-hand side with the preconditioner's copy of L (initialize()),
     * in single-precision arithmetic: a half or a quarter of the memory traffic of the
     * double solve, which is memory-bound. Each column of the copy is scaled by a power of
     * two (its largest entry at most 1), the triangular solves are this project's own
     * kernels (scaled_solve.h), threaded as solve() is. The copy's columns that changed
     * since it was last read are rounded first, under a lock (round_copy()).
     */
    void solve_preconditioner(const SupernodalSymbolic &symbolic, double *x, unsigned int n_threads = 1) const;

    /** L as a CSC matrix (entries of every dense block on and below the diagonal). */
    sparse::CSCMatrix to_csc(const SupernodalSymbolic &symbolic) const;

    const std::vector<double> &values() const;

    /** Write the values (and the preconditioner's copy) to a checkpoint. */
    void save(BinaryWriter &writer) const;
    /**
     * Read what save() wrote, for the structure @p symbolic; throws InputError if the
     * sizes do not match it.
     */
    void load(BinaryReader &reader, const SupernodalSymbolic &symbolic);

  private:
    struct Implementation;
    std::unique_ptr<Implementation> implementation;
  };
} // namespace warpchol::cholesky
