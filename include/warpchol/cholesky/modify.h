#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <memory>
#include <vector>

/**
 * @file
 * Multiple-rank update and downdate of the supernodal factor in place (CHOLMOD's Modify
 * concern, cholmod_updown): L L^T + C S C^T, with C sparse (n x k, rows in the permuted
 * numbering) and S = diag(signs), +1 for an update, -1 for a downdate, both in one pass.
 *
 * Each column j of L is brought up to date with one J-orthogonal reflector that mixes it
 * with the columns of C still carrying the change (J = diag(1, S)): a Householder
 * reflector where every sign is +1, a hyperbolic one otherwise. On the row j it maps
 * (L_jj, w_j) to (r, 0), r^2 = L_jj^2 + sum_t s_t w_jt^2, and every row i below it
 * (l, w) to
 *   l' = tau (l + w . S v) - l,   w' = w - (l + l') v,   tau = 1 + L_jj / r,  v = w_j / (L_jj + r),
 * which keeps [L W] J [L W]^T, hence L L^T + W S W^T, and leaves L lower triangular.
 * (w' uses the new l', the "mixed" form, which keeps a hyperbolic downdate stable.)
 *
 * A column of C whose rows lie on one path of the elimination tree (its lowest row's
 * column of L holds all the others) keeps its entries on that path while the reflectors
 * move it up: the work is confined to the supernodes on the union of the columns' paths,
 * and two columns on different paths never meet until their paths join. Inside a
 * supernode, its reflectors are applied to a few vectors of rows at a time with the rank's
 * columns of those rows in registers, sized per SIMD target (simd::Family::update): every
 * entry of L on the paths is read and written once for up to 12 (16 registers) or 16 (32
 * registers) columns of C, 4 flops per entry and column.
 */
namespace warpchol::cholesky
{
  /** Where and at what cost a modification by a given C works. */
  struct ModificationPlan
  {
    /** The supernodes on the union of C's column paths, increasing (children first). */
    std::vector<Index>  supernodes;
    /** Per listed supernode: its first local column that changes (those before keep their values). */
    std::vector<Index>  start_columns;
    /** Per listed supernode: how many columns of C pass through it. */
    std::vector<Index>  ranks;
    /** Per listed supernode: the flops of modifying it. */
    std::vector<double> supernode_flops;
    /** Columns of L that change, and the entries of L in them. */
    Index               n_columns = 0;
    Index               n_entries = 0;
    /** Sum of supernode_flops. */
    double              flops = 0;
    /** Rank of the modification (columns of C). */
    Index               rank = 0;
  };

  /**
   * The plan of modifying the factor of @p symbolic by @p c (n x k, rows in the permuted
   * numbering, sorted within each column), C's columns taken in groups of at most
   * @p group_columns at a time as modify_supernodal() takes them.
   */
  ModificationPlan plan_modification(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c);

  /**
   * The plan of a modification whose k-th column starts at row @p first_rows[k] (permuted)
   * and runs up its path, without forming C: what a C factored from a change of A on those
   * rows (one column per row, LDL^T in elimination order) costs.
   */
  ModificationPlan plan_modification(const SupernodalSymbolic &symbolic, const std::vector<Index> &first_rows);

  /**
   * Throw InputError unless every column of @p c fits the factor's structure: its rows lie
   * in the structure of the column of L of its lowest row (then C C^T adds no entry outside
   * L's pattern). @p row_names maps a permuted row to the number the message shows (the
   * user's column); empty: the permuted one.
   */
  void check_modification_pattern(const SupernodalSymbolic &symbolic, const sparse::CSCMatrix &c,
                                  const std::vector<Index> &row_names = {});

  /** How a modification runs. */
  struct ModificationSettings
  {
    /**
     * A new pivot r^2 at or below this fraction of what the column held before
     * (L_jj^2 + the update's part) stops a downdate: the matrix is then not positive
     * definite, or so close to it that the result would keep fewer than four digits.
     */
    double       pivot_tolerance = 1e-12;
    /** Threads: independent paths side by side, and the rows of large supernodes split. */
    unsigned int n_threads = 1;
    /**
     * Whether a downdate that fails puts back the values it changed. It keeps a copy of
     * them as it goes; where the paths' columns outgrow the caches, the copy's memory
     * traffic makes a downdate of low rank two to three times as slow as an update. A
     * caller that can recompute the columns on the paths when it fails
     * (SparseCholesky::refactorize(), SparseCholesky::downdate() while its copy of A holds
     * the factored matrix) does without: the factor is then invalid until it does.
     */
    bool         restore_on_failure = true;
  };

  /** What a modification did. */
  struct ModificationResult
  {
    double flops = 0;
    Index  supernodes = 0;
    Index  columns    = 0;
  };

  /**
   * What modify_supernodal() keeps from one call to the next, so that repeated updates of
   * one factor allocate nothing and touch no fresh page (buffers of C's columns on the
   * paths, of each thread, and of a downdate's copy of what it changes).
   */
  class ModificationWorkspace
  {
  public:
    ModificationWorkspace();
    ~ModificationWorkspace();
    ModificationWorkspace(ModificationWorkspace &&) noexcept;
    ModificationWorkspace &operator=(ModificationWorkspace &&) noexcept;

    struct Buffers;
    Buffers &buffers();

  private:
    std::unique_ptr<Buffers> data;
  };

  /**
   * L L^T + C diag(@p signs) C^T in place on the supernodal factor values @p values of
   * @p symbolic: @p c as in plan_modification() and fitting the structure
   * (check_modification_pattern()), @p plan its plan_modification(), which the caller
   * computes once and reads too (the columns that change), one sign (+1 or -1) per column
   * of C. The columns are taken in groups of up to 64, each group one pass over its paths.
   * Bits do not depend on the number of threads.
   *
   * Throws NotPositiveDefinite with the permuted column and the would-be pivot r^2 if a
   * downdate loses positive definiteness (ModificationSettings::pivot_tolerance); the
   * values are then restored to what they were, bit for bit (unless
   * ModificationSettings::restore_on_failure is false: then the columns modify_supernodal()
   * would have changed, those of plan_modification(), hold no factor).
   */
  ModificationResult modify_supernodal(const SupernodalSymbolic &symbolic, double *values, const sparse::CSCMatrix &c,
                                       const ModificationPlan &plan, const std::vector<double> &signs,
                                       const ModificationSettings &settings, ModificationWorkspace &workspace);
} // namespace warpchol::cholesky
