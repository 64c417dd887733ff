#pragma once

#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <cstdint>
#include <vector>

/**
 * @file
 * Changing the values of chosen columns of an SPD matrix while keeping it SPD, as a mesh
 * update would: the tool and the tests of partial refactorization use it.
 */
namespace warpchol::sparse
{
  /**
   * Add to @p matrix a random symmetric, diagonally dominant (hence positive
   * semidefinite) matrix E supported on the stored entries (i,j) with i and j both in
   * @p columns: E(i,j) = eps r_ij sqrt(|A(i,i) A(j,j)|) with r_ij uniform in [-1,1], and
   * E(j,j) = sum_i |E(i,j)| + eps |A(j,j)|. The pattern is unchanged, A + E stays SPD, and
   * only the listed columns (and rows) change. Deterministic for a given @p seed.
   */
  void perturb_columns_spd(CSCMatrix &matrix, const std::vector<Index> &columns,
                           std::uint64_t seed, double eps = 0.05);

  /**
   * @p count distinct columns of [0, n) drawn uniformly (sorted), deterministic for a
   * given @p seed.
   */
  std::vector<Index> random_columns(Index n, Index count, std::uint64_t seed);

  /**
   * The columns of @p n_vertices mesh vertices around a random one, as a local mesh update
   * touches them: vertices are groups of @p block_size consecutive columns, grown breadth
   * first through the graph of @p matrix from a vertex drawn with @p seed (sorted;
   * deterministic for a given seed).
   */
  std::vector<Index> local_vertex_columns(const CSCMatrix &matrix, int block_size, Index n_vertices,
                                          std::uint64_t seed);

  /**
   * A grasp's springs in low-rank form: C (n x |columns|) with the column sqrt(@p factor
   * A(j,j)) e_j for each of @p columns, so that A + C C^T adds factor A(j,j) to those
   * diagonal entries (rank |columns|).
   */
  CSCMatrix penalty_columns(const CSCMatrix &matrix, const std::vector<Index> &columns, double factor);

  /**
   * matrix += @p sign C C^T on the stored entries of @p matrix (either storage); throws
   * InputError if a product falls on an entry it does not store.
   */
  void add_outer_products(CSCMatrix &matrix, const CSCMatrix &c, double sign);
} // namespace warpchol::sparse
