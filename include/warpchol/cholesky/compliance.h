#pragma once

#include <warpchol/base/types.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <cstdint>
#include <vector>

/**
 * @file
 * The compliance W = H A^-1 H^T of a few constraint rows h_i from a supernodal factor
 * A = P L L^T P^T: what a constraint solver (contact, SOFA's GenericConstraintSolver)
 * needs of the linear solver. With Y = L^-1 P^T H^T, W = Y^T Y.
 *
 * Column i of Y is nonzero only on the rows the elimination tree reaches from the nonzeros
 * of h_i: the union of their paths to the root (Gilbert and Peierls' reach). The forward
 * solve is therefore restricted to the supernodes on those paths, and done for all the
 * columns whose paths cross a supernode at once, with dense BLAS-3 on its panel (dtrsm,
 * dgemm); near the top, where every path meets, that is every column. W is then summed
 * supernode by supernode (dsyrk of each panel) over those rows only.
 *
 * SOFA's SparseLDLSolver (addJMInvJt) builds the same W by one full-length forward solve
 * per row of H into a dense m x n array, then the dense product over all n rows:
 * compliance_by_full_solves() does that, the peer of the benchmarks and the reference of
 * the tests.
 */
namespace warpchol::cholesky
{
  /** How SparseCholesky::compliance() builds W. */
  enum class ComplianceMethod
  {
    /** Forward solves restricted to the elimination-tree paths, BLAS-3 per supernode. */
    paths,
    /** SOFA's way: a full-length forward solve per row, then the dense product. */
    full_solves
  };

  /** What building W cost. */
  struct ComplianceStatistics
  {
    /** Supernodes the forward solves visited (all of them for the full solves). */
    Index  supernodes_visited = 0;
    /** Flops of the forward solves and of the product. */
    double flops = 0;
  };

  /**
   * Y = L^-1 P^T H^T on the elimination-tree paths of H's columns, kept by supernode: what
   * W is made of, and what a caller may keep while the factor and the constraints do not
   * change (a contact that persists keeps its column).
   */
  struct PathForwardSolve
  {
    /** Columns of H^T (constraints). */
    Index m = 0;
    /** The supernodes on the union of the paths, increasing (children before parents). */
    std::vector<Index> supernodes;
    /**
     * For supernodes[k]: the constraints whose path crosses it, sorted, are
     * constraints[constraint_start[k] .. constraint_start[k+1]).
     */
    std::vector<Index> constraint_start;
    std::vector<Index> constraints;
    /**
     * The panel of supernodes[k]: Y restricted to its columns and its constraints,
     * transposed (one row per constraint, leading dimension the number of constraints),
     * from panels[panel_start[k]]: its constraints' values of one column of L are
     * contiguous, which the scatter into the ancestors reads.
     */
    std::vector<std::size_t> panel_start;
    std::vector<double>      panels;
    /**
     * The panels in single precision instead, laid out the same
     * (compliance_on_paths_in_single_precision()): one of the two is empty. Half the bytes
     * for the products that read them again (KeptInverseColumns).
     */
    std::vector<float> single_panels;
    /** Flops of the forward solve and of the product (dtrsm, dgemm, dsyrk as counted by their sizes). */
    double solve_flops   = 0;
    double product_flops = 0;
  };

  /**
   * The forward solve of the columns of @p ht (n x m, in the permuted numbering of the
   * factor: row k is column k of C = P^T A P) with the supernodal factor @p values of
   * @p symbolic, restricted to their paths.
   */
  PathForwardSolve forward_solve_on_paths(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                                          const sparse::CSCMatrix &ht);

  /** W = Y^T Y (m x m, column-major, both triangles) from the panels of @p solve. */
  std::vector<double> compliance_from_paths(const SupernodalSymbolic &symbolic, PathForwardSolve &solve);

  /**
   * forward_solve_on_paths() into @p solve and compliance_from_paths() in single
   * precision: the path supernodes' values rounded to float, then strsm, sgemm and ssyrk
   * at about twice the double kernels' rate. W (returned in double) and Y (kept in
   * single precision, PathForwardSolve::single_panels) are then those of the factor to
   * about 1e-6 relative: for a W that is checked against the direct solve anyway (a lagged
   * one, KeptInverseColumns::outlive_factor_changes).
   */
  std::vector<double> compliance_on_paths_in_single_precision(const SupernodalSymbolic &symbolic,
                                                              const std::vector<double> &values,
                                                              const sparse::CSCMatrix &ht, PathForwardSolve &solve);

  /**
   * The block of A^-1 among a set S of A's unknowns, kept from one call to the next as a
   * contact step keeps it: Y = L^-1 P^T E_S (E_S the unit columns of S) on the
   * elimination-tree paths, and G = Y^T Y, which is A^-1 on S x S when the factor is exact
   * (the preconditioner's inverse otherwise, as SparseCholesky::compliance() takes it).
   *
   * While the factor does not change (SparseCholesky::factor_revision()), an unknown that
   * stays in S keeps its column of Y and its place in G with its entries there: only the
   * new unknowns' columns are solved, their rows of G multiplied and written into places
   * that dropped unknowns left, so that nothing of G is copied. Unit columns rather than a
   * contact's rows: the rows h = w R^T n (a contact's normal or tangent, its weight, the
   * nodal rotation of a model that solves in a rotated frame) change from step to step
   * while the vertex does not, and W = H A^-1 H^T is then read from G through them
   * (fem::ContactCompliance: W = D^T G D, never formed).
   */
  struct KeptInverseColumns
  {
    /** The factor Y was last brought to (SparseCholesky::factor_revision(); 0: none). */
    std::uint64_t factor_revision = 0;
    /**
     * Whether the kept columns outlive a change of the factor: a lagged compliance, the
     * block of A^-1 as an earlier factor had it (Courtecuisse et al. 2014 take W from a
     * factor refreshed asynchronously). A new unknown's column is solved with the factor
     * as it is. False: every change of the factor drops what was kept.
     */
    bool outlive_factor_changes = false;
    /**
     * Whether the kept columns were renewed in single precision
     * (compliance_on_paths_in_single_precision(), as every renewal of columns that outlive
     * the factor's changes is): G is then A^-1 on S to about 1e-6 relative, and a caller
     * checks the W it makes as it checks a lagged one. Y is then kept in single precision,
     * new columns too (solved in double, then rounded), and their rows of G multiplied so.
     */
    bool single_precision = false;
    /** The changes of the factor since the oldest kept column was solved (0: all are the factor's as it is). */
    unsigned int factor_changes_behind = 0;
    /**
     * The unknowns come in groups of this many, each group's consecutive in the call and
     * given consecutive places of G starting at a multiple of it (a vertex's 3 unknowns,
     * which fem::ContactCompliance reads as one slot). The number of unknowns asked for
     * must be a multiple of it.
     */
    Index group = 1;
    /** The unknown (the factor's numbering, a row of P^T A P) at each place of G; -1: a free place. */
    std::vector<Index> rows;
    /** Of the last call: the place in G of each unknown asked for, in the order asked. */
    std::vector<Index> places;
    /**
     * Y, a unit column per unknown, in layers: those solved by one call each. A column
     * stays where it was solved while its unknown stays in S, so that a call whose S
     * changes by a few unknowns solves and multiplies those few; the layers are merged
     * into one once they hold more dropped columns than kept ones.
     */
    std::vector<PathForwardSolve> layers;
    /** For each layer, each column's place in G (-1: dropped). */
    std::vector<std::vector<Index>> layer_positions;
    /**
     * G = Y^T Y on the places (rows.size() x rows.size(), column-major, both triangles);
     * the entries of free places are stale. A set that outgrows the places, or leaves a
     * quarter of them free, is laid out anew.
     */
    std::vector<double> gram;
    /** Of the last call: the unknowns whose column was kept, and those solved. */
    Index kept = 0, solved = 0;

    /** G among the unknowns of the last call, in their order (|S| x |S|, a copy: tests). */
    std::vector<double> block() const;
  };

  /**
   * Bring @p columns to the unknowns @p rows (the factor's numbering, distinct) with the
   * factor @p values of @p symbolic, whose revision is @p factor_revision: all of it
   * anew if the revision differs from the kept one (unless the columns outlive factor
   * changes), else only the unknowns not kept.
   */
  void update_inverse_columns(const SupernodalSymbolic &symbolic, const std::vector<double> &values,
                              std::uint64_t factor_revision, const std::vector<Index> &rows,
                              KeptInverseColumns &columns);

  /**
   * SOFA's way, the peer: for each column of @p ht (permuted numbering) a full-length
   * forward solve L y_i = h_i (every supernode, one right-hand side at a time, as
   * SparseLDLSolver does) into a dense m x n array Y^T, then W = Y^T Y over all n rows
   * (dsyrk). m x m, column-major, both triangles.
   */
  std::vector<double> compliance_by_full_solves(const SupernodalSymbolic &symbolic,
                                                const std::vector<double> &values, const sparse::CSCMatrix &ht);
} // namespace warpchol::cholesky
