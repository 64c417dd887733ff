#include <warpchol/base/format.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/sparse/conversions.h>

#include <algorithm>
#include <amd.h>
#include <metis.h>
#include <numeric>

namespace warpchol::cholesky
{
  std::string to_string(const OrderingMethod method)
  {
    return name_of(ordering_names, method);
  }

  OrderingMethod parse_ordering_method(const std::string &name)
  {
    return parse_name(ordering_names, name, "ordering");
  }

  namespace
  {
    /**
     * The graph of a symmetric pattern with every group of @p block_size consecutive
     * dofs merged into one node: adjacency lists in compressed form, sorted, without
     * self-loops.
     */
    struct Graph
    {
      Index              n_nodes = 0;
      std::vector<Index> start;
      std::vector<Index> neighbors;
    };

    Graph quotient_graph(const sparse::CSCMatrix &matrix, const int block_size)
    {
      Graph graph;
      graph.n_nodes = matrix.n_cols / block_size;
      // Every stored off-diagonal entry is recorded in both directions; duplicates
      // (from full storage and from merging dofs) are removed per node afterwards.
      std::vector<Index> count(graph.n_nodes + 1, 0);
      for (Index j = 0; j < matrix.n_cols; ++j)
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          {
            const Index I = matrix.row_index[k] / block_size, J = j / block_size;
            if (I != J)
              {
                ++count[I + 1];
                ++count[J + 1];
              }
          }
      std::partial_sum(count.begin(), count.end(), count.begin());
      std::vector<Index> raw(count.back());
      std::vector<Index> next(count.begin(), count.end() - 1);
      for (Index j = 0; j < matrix.n_cols; ++j)
        for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
          {
            const Index I = matrix.row_index[k] / block_size, J = j / block_size;
            if (I != J)
              {
                raw[next[I]++] = J;
                raw[next[J]++] = I;
              }
          }
      graph.start.assign(graph.n_nodes + 1, 0);
      graph.neighbors.reserve(raw.size() / 2);
      for (Index I = 0; I < graph.n_nodes; ++I)
        {
          const auto first = raw.begin() + count[I], last = raw.begin() + count[I + 1];
          std::sort(first, last);
          const auto unique_end = std::unique(first, last);
          graph.neighbors.insert(graph.neighbors.end(), first, unique_end);
          graph.start[I + 1] = static_cast<Index>(graph.neighbors.size());
        }
      return graph;
    }

    std::vector<Index> amd_ordering(const Graph &graph)
    {
      std::vector<Index> permutation(graph.n_nodes);
      if (graph.n_nodes == 0)
        return permutation;
      double control[AMD_CONTROL], info[AMD_INFO];
      amd_l_defaults(control);
      const auto status = amd_l_order(graph.n_nodes, graph.start.data(), graph.neighbors.data(),
                                      permutation.data(), control, info);
      if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED)
        throw Error("AMD ordering failed with status " + std::to_string(status));
      return permutation;
    }

    std::vector<Index> metis_ordering(const Graph &graph)
    {
      std::vector<Index> permutation(graph.n_nodes);
      if (graph.n_nodes == 0)
        return permutation;
      if (graph.neighbors.empty()) // METIS rejects a graph without edges
        {
          std::iota(permutation.begin(), permutation.end(), Index(0));
          return permutation;
        }
      idx_t              n_nodes = static_cast<idx_t>(graph.n_nodes);
      std::vector<idx_t> start(graph.start.begin(), graph.start.end());
      std::vector<idx_t> neighbors(graph.neighbors.begin(), graph.neighbors.end());
      std::vector<idx_t> metis_perm(graph.n_nodes), metis_iperm(graph.n_nodes);
      idx_t              options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      options[METIS_OPTION_NUMBERING] = 0;
      const int status = METIS_NodeND(&n_nodes, start.data(), neighbors.data(), nullptr,
                                      options, metis_perm.data(), metis_iperm.data());
      if (status != METIS_OK)
        throw Error("METIS_NodeND failed with status " + std::to_string(status));
      // METIS's perm[k] is the node placed at position k (checked on bcsstk16: taking
      // iperm instead doubles nnz(L)).
      for (Index k = 0; k < graph.n_nodes; ++k)
        permutation[k] = metis_perm[k];
      return permutation;
    }
  } // namespace

  int detect_vertex_block_size(const sparse::CSCMatrix &matrix)
  {
    if (matrix.n_cols == 0 || matrix.n_cols % 3 != 0 || matrix.n_rows != matrix.n_cols)
      return 1;
    const sparse::CSCMatrix full = sparse::to_full_storage(matrix);
    // The dofs 3v, 3v+1, 3v+2 must touch the same set of vertices.
    auto vertices_of_column = [&](const Index j) {
      std::vector<Index> vertices;
      for (Index k = full.column_start[j]; k < full.column_start[j + 1]; ++k)
        if (vertices.empty() || vertices.back() != full.row_index[k] / 3)
          vertices.push_back(full.row_index[k] / 3);
      return vertices;
    };
    for (Index v = 0; v < full.n_cols / 3; ++v)
      {
        const std::vector<Index> first = vertices_of_column(3 * v);
        if (vertices_of_column(3 * v + 1) != first || vertices_of_column(3 * v + 2) != first)
          return 1;
      }
    return 3;
  }

  Ordering compute_ordering(const sparse::CSCMatrix &matrix, const OrderingSettings &settings)
  {
    if (matrix.n_rows != matrix.n_cols)
      throw MatrixError("cannot order a non-square " + std::to_string(matrix.n_rows) + "x" +
                        std::to_string(matrix.n_cols) + " matrix");
    if (settings.vertex_block_size != 0 && settings.vertex_block_size != 1 &&
        settings.vertex_block_size != 3)
      throw InputError("vertex block size must be 0 (detect), 1 or 3, got " +
                       std::to_string(settings.vertex_block_size));
    Ordering ordering;
    ordering.vertex_block_size = settings.vertex_block_size == 0 ?
                                   detect_vertex_block_size(matrix) :
                                   settings.vertex_block_size;
    const int block = ordering.vertex_block_size;
    if (matrix.n_cols % block != 0)
      throw InputError("matrix size " + std::to_string(matrix.n_cols) +
                       " is not a multiple of the vertex block size " + std::to_string(block));

    std::vector<Index> vertex_permutation(matrix.n_cols / block);
    switch (settings.method)
      {
        case OrderingMethod::natural:
          std::iota(vertex_permutation.begin(), vertex_permutation.end(), Index(0));
          break;
        case OrderingMethod::amd:
          vertex_permutation = amd_ordering(quotient_graph(matrix, block));
          break;
        case OrderingMethod::metis:
          vertex_permutation = metis_ordering(quotient_graph(matrix, block));
          break;
      }
    ordering.permutation.resize(matrix.n_cols);
    for (Index k = 0; k < static_cast<Index>(vertex_permutation.size()); ++k)
      for (int c = 0; c < block; ++c)
        ordering.permutation[block * k + c] = block * vertex_permutation[k] + c;
    return ordering;
  }

  std::vector<Index> invert_permutation(const std::vector<Index> &permutation)
  {
    std::vector<Index> inverse(permutation.size());
    for (std::size_t k = 0; k < permutation.size(); ++k)
      inverse[permutation[k]] = static_cast<Index>(k);
    return inverse;
  }

  std::vector<Index> compose_permutations(const std::vector<Index> &first,
                                          const std::vector<Index> &second)
  {
    std::vector<Index> result(second.size());
    for (std::size_t k = 0; k < second.size(); ++k)
      result[k] = first[second[k]];
    return result;
  }
} // namespace warpchol::cholesky
