#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <string>
#include <vector>

/**
 * @file
 * Fill-reducing orderings (CHOLMOD's "ordering" concern): natural, approximate minimum
 * degree (SuiteSparse AMD) and nested dissection (METIS_NodeND).
 *
 * A permutation is stored as CHOLMOD stores it: perm[k] is the column of A that becomes
 * column k of P^T A P.
 */
namespace warpchol::cholesky
{
  /** The fill-reducing ordering to apply before the symbolic analysis. */
  enum class OrderingMethod
  {
    natural,
    amd,
    metis
  };

  /** The names of the orderings (base/named_values.h): "natural", "amd", "metis". */
  inline constexpr NameTable<OrderingMethod, 3> ordering_names{
    {{OrderingMethod::natural, "natural"}, {OrderingMethod::amd, "amd"}, {OrderingMethod::metis, "metis"}}};

  /** "natural", "amd" or "metis". */
  std::string to_string(OrderingMethod method);

  /** Parse "natural", "amd" or "metis"; throws InputError on anything else. */
  OrderingMethod parse_ordering_method(const std::string &name);

  /** What to order and how. */
  struct OrderingSettings
  {
    OrderingMethod method = OrderingMethod::metis;
    /**
     * Number of consecutive dofs that share a mesh vertex: 1 orders the matrix graph,
     * 3 orders the vertex graph (n/3 nodes) and expands every vertex to its 3 dofs, which
     * is 3x cheaper and keeps the dofs of a vertex together. 0 detects it: 3 when n is a
     * multiple of 3 and the dofs 3v, 3v+1, 3v+2 of every vertex v touch the same vertices.
     */
    int vertex_block_size = 0;
  };

  /** A computed ordering. */
  struct Ordering
  {
    /** perm[k] = column of A that becomes column k of P^T A P. */
    std::vector<Index> permutation;
    /** The vertex block size that was used (1 or 3). */
    int vertex_block_size = 1;
  };

  /**
   * The fill-reducing ordering of the square matrix @p matrix (full or lower storage, only
   * its pattern is used, made symmetric).
   */
  Ordering compute_ordering(const sparse::CSCMatrix &matrix, const OrderingSettings &settings);

  /** 3 if the pattern of @p matrix groups into vertices of 3 dofs (see OrderingSettings), else 1. */
  int detect_vertex_block_size(const sparse::CSCMatrix &matrix);

  /** The inverse permutation: inverse[perm[k]] = k. */
  std::vector<Index> invert_permutation(const std::vector<Index> &permutation);

  /** The composition: result[k] = first[second[k]] (apply @p first, then @p second). */
  std::vector<Index> compose_permutations(const std::vector<Index> &first,
                                          const std::vector<Index> &second);
} // namespace warpchol::cholesky
