#include <warpchol/base/exceptions.h>
#include <warpchol/fem/system_matrix.h>

#include <deal.II/base/multithread_info.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>

#include <warpchol/base/simd.h>

// What every target shares, compiled once (this file is included again per SIMD target).
#ifndef warpchol_fem_system_matrix_shared
#define warpchol_fem_system_matrix_shared
namespace warpchol::fem
{
  SystemCoefficients SystemCoefficients::implicit_euler(const double time_step,
                                                        const double rayleigh_mass,
                                                        const double rayleigh_stiffness)
  {
    SystemCoefficients coefficients;
    coefficients.mass      = 1 + time_step * rayleigh_mass;
    coefficients.stiffness = time_step * time_step + time_step * rayleigh_stiffness;
    coefficients.time_step = time_step;
    return coefficients;
  }

  ElementMatrix rest_element_matrix(const ElasticBody &body, const unsigned int e,
                                    const SystemCoefficients &coefficients)
  {
    ElementMatrix result = (coefficients.stiffness * body.element_stiffness_scale(e)) * body.rest_stiffness(e);
    const auto   &mass   = body.element_mass(e);
    for (unsigned int a = 0; a < 4; ++a)
      for (unsigned int b = 0; b < 4; ++b)
        if (mass(a, b) != 0)
          result.block<3, 3>(3 * a, 3 * b).diagonal().array() += coefficients.mass * mass(a, b);
    return result;
  }

  ElementMatrix warped_element_matrix(const ElasticBody &body, const unsigned int e,
                                      const SystemCoefficients     &coefficients,
                                      const std::array<Matrix3, 4> &nodal_rotations,
                                      const Matrix3                &element_rotation)
  {
    // T_a = S_a^T Q takes the element's rest frame to vertex a's frame.
    std::array<Matrix3, 4> to_vertex_frame;
    for (unsigned int a = 0; a < 4; ++a)
      to_vertex_frame[a] = nodal_rotations[a].transpose() * element_rotation;

    // K T^T column block by column block, then T (K T^T) row block by row block.
    const ElementMatrix &stiffness = body.rest_stiffness(e);
    ElementMatrix        right;
    for (unsigned int b = 0; b < 4; ++b)
      right.middleCols<3>(3 * b).noalias() =
        stiffness.middleCols<3>(3 * b) * to_vertex_frame[b].transpose();
    ElementMatrix result;
    const double stiffness_factor = coefficients.stiffness * body.element_stiffness_scale(e);
    for (unsigned int a = 0; a < 4; ++a)
      result.middleRows<3>(3 * a).noalias() = stiffness_factor * (to_vertex_frame[a] * right.middleRows<3>(3 * a));

    const auto &mass = body.element_mass(e);
    for (unsigned int a = 0; a < 4; ++a)
      for (unsigned int b = 0; b < 4; ++b)
        if (mass(a, b) != 0)
          {
            if (a == b)
              result.block<3, 3>(3 * a, 3 * a).diagonal().array() += coefficients.mass * mass(a, a);
            else
              result.block<3, 3>(3 * a, 3 * b) += (coefficients.mass * mass(a, b)) *
                                                  (nodal_rotations[a].transpose() *
                                                   nodal_rotations[b]);
          }
    return result;
  }

  ElementFrames ElementFrames::rest()
  {
    return {};
  }

  ElementFrames ElementFrames::rotated(const std::vector<Matrix3> &rotations)
  {
    ElementFrames frames;
    frames.kind              = Kind::rotated;
    frames.element_rotations = &rotations;
    return frames;
  }

  ElementFrames ElementFrames::warped(const std::vector<std::array<Matrix3, 4>> &frames)
  {
    ElementFrames result;
    result.kind          = Kind::warped;
    result.vertex_frames = &frames;
    return result;
  }

  ElementFrames ElementFrames::rerotated(const std::vector<std::array<Matrix3, 4>> &frames,
                                         const std::vector<char> &stored, const std::vector<Matrix3> &rotations)
  {
    ElementFrames result     = warped(frames);
    result.frames_stored     = &stored;
    result.element_rotations = &rotations;
    return result;
  }

  namespace
  {
    /** Elements whose blocks are formed as a group (one AVX-512 register of doubles). */
    constexpr unsigned int lanes = 8;
    /**
     * One value of 8 elements: a vector of the compiler (GCC's and clang's vector
     * extension), so that every element goes through the very same instructions, whatever
     * its lane; each target forms it in parts of its own register width (form_part()).
     */
    using Lane = double __attribute__((vector_size(8 * lanes)));
    /** The blocks (a, b), a >= b, numbered k = a (a + 1) / 2 + b. */
    constexpr unsigned int n_blocks = 10;
    constexpr unsigned int block_row[n_blocks]    = {0, 1, 1, 2, 2, 2, 3, 3, 3, 3};
    constexpr unsigned int block_column[n_blocks] = {0, 0, 1, 0, 1, 2, 0, 1, 2, 3};

    /** The 10 blocks of up to 8 elements: entry (i, j) of block k of lane l at value[k][i + 3 j][l]. */
    struct LaneBlocks
    {
      Lane value[n_blocks][9];
    };

    /**
     * The blocks of the contributions of @p elements[0 .. count) in @p frames, lane by lane
     * (lanes past count repeat the last element), on the SIMD target chosen at run time;
     * block k of element e transposed where bit k of @p transposed[e] is set.
     */
    void form_blocks(const ElasticBody &body, const SystemCoefficients &coefficients, const ElementFrames &frames,
                     const std::uint16_t *transposed, const unsigned int *elements, const unsigned int count,
                     LaneBlocks &out);

    /** The blocks of the elements' dense matrices from @p element_matrix, lane by lane, alike. */
    auto function_blocks(const SystemMatrix::ElementMatrixFunction &element_matrix, const std::uint16_t *transposed)
    {
      return [&element_matrix, transposed](const unsigned int *elements, const unsigned int count, LaneBlocks &out) {
        ElementMatrix matrix;
        for (unsigned int l = 0; l < count; ++l)
          {
            element_matrix(elements[l], matrix);
            for (unsigned int k = 0; k < n_blocks; ++k)
              {
                // Block (b, a) = block (a, b)^T: A is symmetric.
                const bool         swap = (transposed[elements[l]] >> k) & 1u;
                const unsigned int row = swap ? block_column[k] : block_row[k];
                const unsigned int column = swap ? block_row[k] : block_column[k];
                for (unsigned int j = 0; j < 3; ++j)
                  for (unsigned int i = 0; i < 3; ++i)
                    out.value[k][i + 3 * j][l] = matrix(3 * row + i, 3 * column + j);
              }
          }
      };
    }

    /**
     * Add the blocks of lane @p l of @p blocks (formed as they land: transposed where bit k
     * of @p transposed is set) to @p values where @p where puts them (an ElementScatter),
     * those of a column @p selected rejects left out unless @p every_column. The blocks are
     * unrolled, so that whether a block is diagonal and whether a column is to be tested
     * are known at compile time, not tested per block.
     */
    template <bool every_column, typename Scatter, typename Selected>
    inline void add_blocks_of_lane(double *values, const Scatter &where, const std::uint16_t transposed,
                                   const LaneBlocks &blocks, const unsigned int l, const Selected &selected)
    {
#pragma GCC unroll 10
      for (unsigned int k = 0; k < n_blocks; ++k)
        {
          const std::int64_t p0 = where.position[k];
          if (p0 < 0 ||
              (!every_column && !selected(std::min(where.free_vertex[block_row[k]], where.free_vertex[block_column[k]]))))
            continue;
          // The block lands in the columns of its row vertex when transposed, else of its
          // column vertex (the diagonal blocks: either).
          const std::int64_t stride    = where.stride[(transposed >> k) & 1u ? block_row[k] : block_column[k]];
          const std::int64_t offset[3] = {0, stride, 2 * stride - 1};
          const auto        &block     = blocks.value[k];
          for (unsigned int c = 0; c < 3; ++c)
            for (unsigned int r = block_row[k] == block_column[k] ? c : 0; r < 3; ++r)
              values[p0 + offset[c] + r] += block[r + 3 * c][l];
        }
    }

    /** Above this share of the free vertices touched, re-assembly assembles all of A. */
    constexpr double reassembly_limit = 0.25;
  } // namespace

  SystemMatrix::SystemMatrix(const ElasticBody &body, const SystemCoefficients &coefficients)
    : body(body)
    , coefficients(coefficients)
  {
    if (!coefficients.vertex_diagonal.empty() &&
        coefficients.vertex_diagonal.size() != body.n_vertices())
      throw InputError("system matrix: " + std::to_string(coefficients.vertex_diagonal.size()) +
                       " vertex diagonal values for " + std::to_string(body.n_vertices()) +
                       " vertices");
    const Index n_free = body.n_unknowns() / 3;

    // The free vertices of larger unknown that share an element with each free vertex.
    std::vector<std::vector<Index>> neighbours(n_free);
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      for (const unsigned int v : body.element_vertices(e))
        for (const unsigned int w : body.element_vertices(e))
          if (free_index(v) >= 0 && free_index(w) > free_index(v))
            neighbours[free_index(v)].push_back(free_index(w));
    for (auto &list : neighbours)
      {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
      }

    // Column 3 j + c holds the rows 3 j + c .. 3 j + 2 of the diagonal block, then the 3
    // rows of each neighbour in increasing order. Entry (r, c) of the block of neighbour q
    // then sits at p0 + offset(c) + r with p0 = start(3 j) + 3 + 3 q and offset(c) =
    // 0, s, 2 s - 1 for s = 3 n + 2 (the columns shrink by one diagonal entry each);
    // the diagonal block's (r >= c) alike with p0 = start(3 j).
    lower_matrix = sparse::CSCMatrix::zero(3 * n_free, 3 * n_free, sparse::Storage::lower);
    std::vector<std::int32_t> column_stride(n_free);
    for (Index j = 0; j < n_free; ++j)
      {
        column_stride[j] = 3 * static_cast<std::int32_t>(neighbours[j].size()) + 2;
        for (Index c = 0; c < 3; ++c)
          {
            for (Index r = c; r < 3; ++r)
              lower_matrix.row_index.push_back(3 * j + r);
            for (const Index i : neighbours[j])
              for (Index r = 0; r < 3; ++r)
                lower_matrix.row_index.push_back(3 * i + r);
            lower_matrix.column_start[3 * j + c + 1] = static_cast<Index>(lower_matrix.row_index.size());
          }
      }
    lower_matrix.values.assign(lower_matrix.row_index.size(), 0.);

    // 32-bit positions: a smaller scatter to read per element (A would hold 16 GiB first).
    if (lower_matrix.values.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
      throw MatrixError("system matrix: " + std::to_string(lower_matrix.values.size()) +
                        " entries in its lower triangle, more than the assembly's 32-bit positions reach");
    scatter.resize(body.n_elements());
    transposed_blocks.assign(body.n_elements(), 0);
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        const auto &vertices = body.element_vertices(e);
        for (unsigned int a = 0; a < 4; ++a)
          {
            const Index free           = free_index(vertices[a]);
            scatter[e].free_vertex[a] = static_cast<std::int32_t>(free);
            scatter[e].stride[a]      = free < 0 ? 0 : column_stride[free];
          }
        for (unsigned int k = 0; k < n_blocks; ++k)
          {
            const Index row = free_index(vertices[block_row[k]]), column = free_index(vertices[block_column[k]]);
            auto       &position = scatter[e].position[k];
            // The block lands in the column of the vertex of smaller unknown.
            if (row < 0 || column < 0)
              position = -1;
            else if (row == column)
              position = static_cast<std::int32_t>(lower_matrix.column_start[3 * column]);
            else
              {
                const Index low = std::min(row, column), high = std::max(row, column);
                const auto &list = neighbours[low];
                const Index rank = std::lower_bound(list.begin(), list.end(), high) - list.begin();
                position         = static_cast<std::int32_t>(lower_matrix.column_start[3 * low] + 3 + 3 * rank);
                if (row < column)
                  transposed_blocks[e] |= static_cast<std::uint16_t>(1u << k);
              }
          }
      }
    whole.first_vertex = 0;
    whole.end_vertex   = n_free;
    whole.elements.resize(body.n_elements());
    std::iota(whole.elements.begin(), whole.elements.end(), 0u);
  }

  Index SystemMatrix::free_index(const unsigned int vertex) const
  {
    const Index first = body.first_unknown(vertex);
    return first < 0 ? -1 : first / 3;
  }

  template <typename BlockSource>
  void SystemMatrix::assemble_range(const ColumnRange &range, const std::vector<unsigned int> &elements,
                                    const std::vector<char> *column_selected, const BlockSource &blocks)
  {
    const auto selected = [&](const Index column) {
      return column >= range.first_vertex && column < range.end_vertex &&
             (column_selected == nullptr || (*column_selected)[column]);
    };
    // The whole matrix from every element: no column to skip.
    const bool all_selected = column_selected == nullptr && range.first_vertex == 0 &&
                              range.end_vertex == body.n_unknowns() / 3;
    double    *values       = lower_matrix.values.data();
    // The range's columns are contiguous: zeroed at once unless some are left alone.
    if (column_selected == nullptr)
      std::fill(values + lower_matrix.column_start[3 * range.first_vertex],
                values + lower_matrix.column_start[3 * range.end_vertex], 0.);
    else
      for (Index j = range.first_vertex; j < range.end_vertex; ++j)
        if (selected(j))
          std::fill(values + lower_matrix.column_start[3 * j], values + lower_matrix.column_start[3 * j + 3], 0.);

    LaneBlocks lane_blocks;
    for (std::size_t first = 0; first < elements.size(); first += lanes)
      {
        const unsigned int count = static_cast<unsigned int>(std::min<std::size_t>(lanes, elements.size() - first));
        blocks(elements.data() + first, count, lane_blocks);
        for (unsigned int l = 0; l < count; ++l)
          {
            const unsigned int e = elements[first + l];
            if (all_selected)
              add_blocks_of_lane<true>(values, scatter[e], transposed_blocks[e], lane_blocks, l, selected);
            else
              add_blocks_of_lane<false>(values, scatter[e], transposed_blocks[e], lane_blocks, l, selected);
          }
      }

    // The tools' springs and the free particles' masses, after the elements: a column's
    // value is the same sum whoever assembles it. The first entry of each column is its
    // diagonal.
    for (Index j = range.first_vertex; j < range.end_vertex; ++j)
      if (selected(j))
        {
          const unsigned int vertex = body.vertex_of_unknown(3 * j);
          const double       extra  = (coefficients.vertex_diagonal.empty() ? 0. : coefficients.vertex_diagonal[vertex]) +
                                 coefficients.mass * body.free_particle_mass(vertex);
          if (extra != 0)
            for (Index c = 0; c < 3; ++c)
              values[lower_matrix.column_start[3 * j + c]] += extra;
        }
    full_current   = false;
    dealii_current = false;
  }

  void SystemMatrix::for_each_range(const std::function<void(const ColumnRange &)> &assemble)
  {
    const unsigned int n_threads = thread_count > 0 ? thread_count : dealii::MultithreadInfo::n_threads();
    const Index        n_free    = body.n_unknowns() / 3;
    if (n_threads <= 1 || n_free < 64)
      {
        assemble(whole);
        return;
      }
    if (ranges_threads != n_threads)
      {
        // Ranges of about equal numbers of entries, four per thread for the balance; each
        // lists the elements with a free vertex in it, in increasing order.
        const Index n_ranges = std::min<Index>(4 * n_threads, n_free);
        ranges.assign(n_ranges, ColumnRange());
        const double entries_per_range = static_cast<double>(lower_matrix.n_nonzeros()) / n_ranges;
        std::vector<Index> range_of(n_free);
        Index              current = 0;
        for (Index j = 0; j < n_free; ++j)
          {
            while (current + 1 < n_ranges &&
                   lower_matrix.column_start[3 * j] >= entries_per_range * static_cast<double>(current + 1))
              {
                ranges[current].end_vertex       = j;
                ranges[current + 1].first_vertex = j;
                ++current;
              }
            range_of[j] = current;
          }
        ranges[current].end_vertex = n_free;
        for (Index r = current + 1; r < n_ranges; ++r)
          ranges[r].first_vertex = ranges[r].end_vertex = n_free;
        for (unsigned int e = 0; e < body.n_elements(); ++e)
          for (const unsigned int v : body.element_vertices(e))
            if (free_index(v) >= 0)
              {
                auto &elements = ranges[range_of[free_index(v)]].elements;
                if (elements.empty() || elements.back() != e)
                  elements.push_back(e);
              }
        ranges_threads = n_threads;
      }
    tbb::parallel_for(std::size_t(0), ranges.size(), [&](const std::size_t r) { assemble(ranges[r]); });
  }

  void SystemMatrix::assemble(const ElementFrames &frames)
  {
    const auto blocks = [&](const unsigned int *elements, const unsigned int count, LaneBlocks &out) {
      form_blocks(body, coefficients, frames, transposed_blocks.data(), elements, count, out);
    };
    for_each_range([&](const ColumnRange &range) { assemble_range(range, range.elements, nullptr, blocks); });
    ++whole_changes;
  }

  std::vector<Index> SystemMatrix::touched_free_vertices(const std::vector<unsigned int> &changed_elements) const
  {
    std::vector<Index> touched;
    for (const unsigned int e : changed_elements)
      for (const unsigned int v : body.element_vertices(e))
        if (free_index(v) >= 0)
          touched.push_back(free_index(v));
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return touched;
  }

  std::vector<Index> SystemMatrix::columns_of(const std::vector<Index> &free_vertices)
  {
    std::vector<Index> columns;
    columns.reserve(3 * free_vertices.size());
    for (const Index j : free_vertices)
      for (Index c = 0; c < 3; ++c)
        columns.push_back(3 * j + c);
    return columns;
  }

  std::vector<Index> SystemMatrix::reassemble(const std::vector<unsigned int> &changed_elements,
                                              const ElementFrames             &frames)
  {
    return reassemble_free_vertices(touched_free_vertices(changed_elements), frames);
  }

  std::vector<Index> SystemMatrix::reassemble_vertices(const std::vector<unsigned int> &vertices,
                                                       const ElementFrames             &frames)
  {
    std::vector<Index> touched;
    for (const unsigned int v : vertices)
      if (free_index(v) >= 0)
        touched.push_back(free_index(v));
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return reassemble_free_vertices(touched, frames);
  }

  void SystemMatrix::set_vertex_diagonal(const unsigned int vertex, const double value)
  {
    if (coefficients.vertex_diagonal.empty())
      coefficients.vertex_diagonal.assign(body.n_vertices(), 0.);
    coefficients.vertex_diagonal.at(vertex) = value;
  }

  std::vector<Index> SystemMatrix::reassemble_free_vertices(const std::vector<Index> &touched,
                                                            const ElementFrames      &frames)
  {
    if (touched.empty())
      return {};
    if (static_cast<double>(touched.size()) > reassembly_limit * static_cast<double>(body.n_unknowns() / 3))
      {
        // Every other column gets the bits it has already.
        assemble(frames);
        return columns_of(touched);
      }
    std::vector<char> selected(body.n_unknowns() / 3, 0);
    for (const Index j : touched)
      selected[j] = 1;
    const auto blocks = [&](const unsigned int *elements, const unsigned int count, LaneBlocks &out) {
      form_blocks(body, coefficients, frames, transposed_blocks.data(), elements, count, out);
    };
    for_each_range([&](const ColumnRange &range) {
      // The elements around the touched vertices of this range, in increasing order.
      std::vector<unsigned int> elements;
      for (auto j = std::lower_bound(touched.begin(), touched.end(), range.first_vertex);
           j != touched.end() && *j < range.end_vertex; ++j)
        {
          const auto &around = body.elements_of_vertex(body.vertex_of_unknown(3 * *j));
          elements.insert(elements.end(), around.begin(), around.end());
        }
      if (elements.empty())
        return;
      std::sort(elements.begin(), elements.end());
      elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
      assemble_range(range, elements, &selected, blocks);
    });
    return columns_of(touched);
  }

  void SystemMatrix::assemble(const ElementMatrixFunction &element_matrix)
  {
    // The function need not be thread-safe: one range, one element after the other.
    assemble_range(whole, whole.elements, nullptr, function_blocks(element_matrix, transposed_blocks.data()));
    ++whole_changes;
  }

  std::vector<Index> SystemMatrix::reassemble(const std::vector<unsigned int> &changed_elements,
                                              const ElementMatrixFunction     &element_matrix)
  {
    const std::vector<Index> touched = touched_free_vertices(changed_elements);
    std::vector<char>        selected(body.n_unknowns() / 3, 0);
    std::vector<unsigned int> elements;
    for (const Index j : touched)
      {
        selected[j]        = 1;
        const auto &around = body.elements_of_vertex(body.vertex_of_unknown(3 * j));
        elements.insert(elements.end(), around.begin(), around.end());
      }
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    assemble_range(whole, elements, &selected, function_blocks(element_matrix, transposed_blocks.data()));
    return columns_of(touched);
  }

  const sparse::CSCMatrix &SystemMatrix::lower() const
  {
    return lower_matrix;
  }

  const sparse::CSCMatrix &SystemMatrix::csc() const
  {
    const Index n = lower_matrix.n_cols;
    if (full_source.empty() && n > 0)
      {
        // Column j: first the rows above the diagonal (the entries (j, r), r < j, of the
        // lower triangle, met in increasing r when the columns are scanned in order), then
        // column j of the lower triangle.
        std::vector<Index> above(n, 0);
        for (Index r = 0; r < n; ++r)
          for (Index k = lower_matrix.column_start[r]; k < lower_matrix.column_start[r + 1]; ++k)
            if (lower_matrix.row_index[k] != r)
              ++above[lower_matrix.row_index[k]];
        full_matrix = sparse::CSCMatrix::zero(n, n, sparse::Storage::full);
        for (Index j = 0; j < n; ++j)
          full_matrix.column_start[j + 1] = full_matrix.column_start[j] + above[j] +
                                            lower_matrix.column_start[j + 1] - lower_matrix.column_start[j];
        const Index nnz = full_matrix.column_start[n];
        full_matrix.row_index.resize(nnz);
        full_matrix.values.resize(nnz);
        full_source.resize(nnz);
        std::vector<Index> next(full_matrix.column_start.begin(), full_matrix.column_start.end() - 1);
        for (Index r = 0; r < n; ++r)
          for (Index k = lower_matrix.column_start[r]; k < lower_matrix.column_start[r + 1]; ++k)
            if (lower_matrix.row_index[k] != r)
              {
                const Index position          = next[lower_matrix.row_index[k]]++;
                full_matrix.row_index[position] = r;
                full_source[position]           = k;
              }
        for (Index j = 0; j < n; ++j)
          for (Index k = lower_matrix.column_start[j]; k < lower_matrix.column_start[j + 1]; ++k)
            {
              const Index position          = next[j]++;
              full_matrix.row_index[position] = lower_matrix.row_index[k];
              full_source[position]           = k;
            }
        full_current = false;
      }
    if (!full_current)
      {
        for (std::size_t k = 0; k < full_source.size(); ++k)
          full_matrix.values[k] = lower_matrix.values[full_source[k]];
        full_current = true;
      }
    return full_matrix;
  }

  const dealii::SparseMatrix<double> &SystemMatrix::matrix() const
  {
    const Index n = lower_matrix.n_cols;
    if (dealii_source.empty() && n > 0)
      {
        const sparse::CSCMatrix &full = csc();
        // Symmetric: row i of A has the rows of column i.
        dealii::DynamicSparsityPattern dynamic_pattern(n, n);
        for (Index i = 0; i < n; ++i)
          for (Index k = full.column_start[i]; k < full.column_start[i + 1]; ++k)
            dynamic_pattern.add(i, full.row_index[k]);
        pattern.copy_from(dynamic_pattern);
        dealii_matrix.reinit(pattern);
        // Where each entry, in the storage order the iterators visit, is in lower().
        dealii_source.reserve(pattern.n_nonzero_elements());
        for (Index i = 0; i < n; ++i)
          for (auto entry = pattern.begin(i); entry != pattern.end(i); ++entry)
            {
              const Index j = entry->column(), low = std::min<Index>(i, j), high = std::max<Index>(i, j);
              const auto  first = lower_matrix.row_index.begin() + lower_matrix.column_start[low];
              const auto  last  = lower_matrix.row_index.begin() + lower_matrix.column_start[low + 1];
              dealii_source.push_back(std::lower_bound(first, last, high) - lower_matrix.row_index.begin());
            }
        dealii_current = false;
      }
    if (!dealii_current)
      {
        std::size_t k = 0;
        for (auto &entry : dealii_matrix)
          entry.value() = lower_matrix.values[dealii_source[k++]];
        dealii_current = true;
      }
    return dealii_matrix;
  }

  void SystemMatrix::set_thread_count(const unsigned int n_threads)
  {
    thread_count = n_threads;
  }

  void SystemMatrix::swap_values(SystemMatrix &other)
  {
    if (other.lower_matrix.values.size() != lower_matrix.values.size() || &other.body != &body)
      throw MatrixError("system matrix: swap_values() with the matrix of another body");
    lower_matrix.values.swap(other.lower_matrix.values);
    full_current = dealii_current = false;
    other.full_current = other.dealii_current = false;
    ++whole_changes;
    ++other.whole_changes;
  }

  std::uint64_t SystemMatrix::n_whole_changes() const
  {
    return whole_changes;
  }

  Index SystemMatrix::size() const
  {
    return body.n_unknowns();
  }

  void SystemMatrix::save(BinaryWriter &writer) const
  {
    writer.write(lower_matrix.values);
  }

  void SystemMatrix::load(BinaryReader &reader)
  {
    std::vector<double> values;
    reader.read(values);
    if (values.size() != lower_matrix.values.size())
      reader.fail("the system matrix holds " + std::to_string(values.size()) + " entries, this body's " +
                  std::to_string(lower_matrix.values.size()));
    lower_matrix.values = std::move(values);
    full_current        = false;
    dealii_current      = false;
    ++whole_changes;
  }
} // namespace warpchol::fem
#endif

// The blocks of a group of elements, once per SIMD target (Highway).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fem/system_matrix.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
// Products and sums contracted to FMAs where the target has them (the ISO mode's default
// is not to): a third fewer operations in the blocks.
#pragma GCC push_options
#pragma GCC optimize("fp-contract=fast")
namespace warpchol::fem::HWY_NAMESPACE
{
  namespace
  {
    /**
     * Elements a pass forms side by side on this target: one register of doubles (two on
     * SSE4 and the baseline), so that the 48 products of frames and gradients of a warped
     * element spill no more on AVX2's 16 registers than on AVX-512's 32. LaneBlocks holds
     * eight elements: a group of eight is formed in 8 / width passes.
     */
    constexpr unsigned int width = HWY_LANES(double) >= 8 ? 8 : HWY_LANES(double) >= 4 ? 4 : 2;
    using Part                   = double __attribute__((vector_size(8 * width)));

    /** What the blocks of the lanes [first, first + width) of a group are made of, lane by lane. */
    struct PartInputs
    {
      /** g[a][i]: component i of the gradient of vertex a's shape function (g_0 = -g_1 - g_2 - g_3). */
      Part g[4][3];
      /** c_K lambda V and c_K mu V. */
      Part lambda_volume, mu_volume;
      /** c_K mu V (g_a . g_b) + c_M m_ab: what block k adds to its diagonal (times T_a T_b^T). */
      Part diagonal[n_blocks];
    };

    PartInputs gather_inputs(const ElasticBody &body, const SystemCoefficients &coefficients,
                             const unsigned int *elements, const unsigned int count, const unsigned int first)
    {
      PartInputs   in;
      const double lambda = coefficients.stiffness * body.lame_lambda();
      const double mu     = coefficients.stiffness * body.lame_mu();
      const bool   lumped = body.mass_matrix_type() == MassMatrix::lumped;
      Part         mass[n_blocks];
      for (unsigned int l = 0; l < width; ++l)
        {
          const unsigned int e         = elements[std::min(first + l, count - 1)];
          const Matrix3     &gradients = body.rest_shape_gradients(e);
          for (unsigned int a = 1; a < 4; ++a)
            for (unsigned int i = 0; i < 3; ++i)
              in.g[a][i][l] = gradients(a - 1, i);
          // A cut element has no stiffness (and no mass: body.element_mass() is zero).
          const double volume  = body.element_stiffness_weight(e);
          in.lambda_volume[l] = lambda * volume;
          in.mu_volume[l]     = mu * volume;
          if (lumped)
            {
              // The diagonal alone: a quarter of the bytes of the whole 4x4 mass.
              const auto &m = body.element_mass_diagonal(e);
              for (unsigned int k = 0; k < n_blocks; ++k)
                mass[k][l] = block_row[k] != block_column[k] ? 0. : coefficients.mass * m[block_row[k]];
            }
          else
            {
              const auto &m = body.element_mass(e);
              for (unsigned int k = 0; k < n_blocks; ++k)
                mass[k][l] = coefficients.mass * m(block_row[k], block_column[k]);
            }
        }
      for (unsigned int i = 0; i < 3; ++i)
        in.g[0][i] = -(in.g[1][i] + in.g[2][i] + in.g[3][i]);
      for (unsigned int k = 0; k < n_blocks; ++k)
        {
          const unsigned int a = block_row[k], b = block_column[k];
          in.diagonal[k] =
            in.mu_volume * (in.g[a][0] * in.g[b][0] + in.g[a][1] * in.g[b][1] + in.g[a][2] * in.g[b][2]) + mass[k];
        }
      return in;
    }

    /**
     * The blocks of the contributions of @p elements[0 .. count) in @p frames, lane by lane
     * (lanes past count repeat the last element): with g_a the shape function gradients,
     * V the volume, lambda and mu the material's,
     *   B_ab = c_K V (lambda u_aa u_bb^T + mu u_ab u_ba^T + mu (g_a.g_b) T_a T_b^T) + c_M m_ab T_a T_b^T
     * with u_ab = T_a g_b. Where every T_a is the same rotation R, T_a T_b^T = I and
     * u_ab = R g_b: the rotated and rest cases skip the products of frames. A diagonal
     * block is (lambda + mu) V u_aa u_aa^T plus its diagonal, formed in its lower triangle
     * (what is scattered); an off-diagonal block as it lands, transposed in the lanes whose
     * bit k of @p transposed is set. The three kinds of frames stay in one function: they
     * share the inputs gathered once per group and the lane stores.
     */
    void form_part(const ElasticBody &body, const SystemCoefficients &coefficients, const ElementFrames &frames,
                   const std::uint16_t *transposed, const unsigned int *elements, const unsigned int count,
                   const unsigned int first, LaneBlocks &out)
    {
      const PartInputs in = gather_inputs(body, coefficients, elements, count, first);
      using Bits = std::int64_t __attribute__((vector_size(8 * width)));
      // Entry (k, i) of lanes [first, first + width) of the group, but in the lanes where
      // `kept` is set (all ones), formed by the other pass.
      Bits       kept{};
      bool       keeps_some = false;
      const auto store      = [&](const unsigned int k, const unsigned int i, const Part &value) {
        double *const lanes_of_entry = reinterpret_cast<double *>(&out.value[k][i]) + first;
        Part          result         = value;
        if (keeps_some)
          {
            Part current;
            std::memcpy(&current, lanes_of_entry, sizeof current);
            result = kept ? current : value;
          }
        std::memcpy(lanes_of_entry, &result, sizeof result);
      };
      // Off-diagonal block k from its entries v(i, j) = value[i + 3 j]: a blend per lane,
      // not a branch per element in the scatter.
      Bits bits;
      for (unsigned int l = 0; l < width; ++l)
        bits[l] = transposed[elements[std::min(first + l, count - 1)]];
      // All ones in the lanes where block k lands transposed.
      const auto transposed_lanes = [&](const unsigned int k) -> Bits { return ((bits >> k) & 1) != 0; };
      const auto store_off_diagonal = [&](const unsigned int k, const Part (&value)[9]) {
        const Bits swap = transposed_lanes(k);
        for (unsigned int j = 0; j < 3; ++j)
          for (unsigned int i = 0; i < 3; ++i)
            store(k, i + 3 * j, i == j ? value[i + 3 * j] : swap ? value[j + 3 * i] : value[i + 3 * j]);
      };
      const auto store_diagonal = [&](const unsigned int k, const Part (&lambda_mu_u)[3], const Part (&u)[3]) {
        for (unsigned int j = 0; j < 3; ++j)
          for (unsigned int i = j; i < 3; ++i)
            store(k, i + 3 * j, i == j ? lambda_mu_u[i] * u[i] + in.diagonal[k] : lambda_mu_u[i] * u[j]);
      };
      const Part lambda_mu_volume = in.lambda_volume + in.mu_volume;
      // Per lane, whether its element is formed in frames of its own (warped) or by its
      // rotation (rotated, at rest, or warped without frames stored). An element formed by its
      // rotation gets the very bits of the rotated form whatever the other lanes of its
      // group: a column re-assembled later changes only where its elements' contributions
      // did (a change's update has no rounding-level entries to take in).
      const auto has_frames = [&](const unsigned int l) {
        return frames.kind == ElementFrames::Kind::warped &&
               (frames.frames_stored == nullptr || (*frames.frames_stored)[elements[std::min(first + l, count - 1)]]);
      };
      Bits own_frames;
      bool any_own = false, any_rotated = false;
      for (unsigned int l = 0; l < width; ++l)
        {
          const bool own = has_frames(l);
          own_frames[l]  = own ? -1 : 0;
          any_own        = any_own || own;
          any_rotated    = any_rotated || !own;
        }
      const auto form_rotated = [&]() {
        // h_a = R g_a (R = I at rest), and (lambda + mu) V h_a.
        Part h[4][3], lambda_mu_h[4][3];
        if (frames.kind == ElementFrames::Kind::rest)
          std::copy(&in.g[0][0], &in.g[0][0] + 12, &h[0][0]);
        else
          {
            Part r[9];
            for (unsigned int l = 0; l < width; ++l)
              {
                const Matrix3 &rotation = (*frames.element_rotations)[elements[std::min(first + l, count - 1)]];
                for (unsigned int i = 0; i < 9; ++i)
                  r[i][l] = rotation.data()[i];
              }
            for (unsigned int a = 0; a < 4; ++a)
              for (unsigned int i = 0; i < 3; ++i)
                h[a][i] = r[i] * in.g[a][0] + r[i + 3] * in.g[a][1] + r[i + 6] * in.g[a][2];
          }
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int i = 0; i < 3; ++i)
            lambda_mu_h[a][i] = lambda_mu_volume * h[a][i];
        for (unsigned int k = 0; k < n_blocks; ++k)
          {
            const unsigned int a = block_row[k], b = block_column[k];
            if (a == b)
              {
                store_diagonal(k, lambda_mu_h[a], h[a]);
                continue;
              }
            // B_ba = B_ab^T is the same formula with a and b exchanged: exchanged in the
            // lanes where the block lands transposed.
            const Bits swap = transposed_lanes(k);
            Part       h_a[3], h_b[3], lambda_h_a[3], mu_h_b[3];
            for (unsigned int i = 0; i < 3; ++i)
              {
                h_a[i]        = swap ? h[b][i] : h[a][i];
                h_b[i]        = swap ? h[a][i] : h[b][i];
                lambda_h_a[i] = in.lambda_volume * h_a[i];
                mu_h_b[i]     = in.mu_volume * h_b[i];
              }
            for (unsigned int j = 0; j < 3; ++j)
              for (unsigned int i = 0; i < 3; ++i)
                {
                  Part value = lambda_h_a[i] * h_b[j] + mu_h_b[i] * h_a[j];
                  if (i == j)
                    value += in.diagonal[k];
                  store(k, i + 3 * j, value);
                }
          }
      };
      const auto form_warped = [&]() {
        Part t[4][9];
        for (unsigned int l = 0; l < width; ++l)
          {
            const unsigned int e = elements[std::min(first + l, count - 1)];
            for (unsigned int a = 0; a < 4; ++a)
              {
                const Matrix3 &frame = own_frames[l] ? (*frames.vertex_frames)[e][a] : (*frames.element_rotations)[e];
                for (unsigned int i = 0; i < 9; ++i)
                  t[a][i][l] = frame.data()[i];
              }
          }
        // u[a][b] = T_a g_b.
        Part u[4][4][3];
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = 0; b < 4; ++b)
            for (unsigned int i = 0; i < 3; ++i)
              u[a][b][i] = t[a][i] * in.g[b][0] + t[a][i + 3] * in.g[b][1] + t[a][i + 6] * in.g[b][2];
        for (unsigned int k = 0; k < n_blocks; ++k)
          {
            const unsigned int a = block_row[k], b = block_column[k];
            if (a == b)
              {
                // T_a T_a^T = I.
                Part lambda_mu_u[3];
                for (unsigned int i = 0; i < 3; ++i)
                  lambda_mu_u[i] = lambda_mu_volume * u[a][a][i];
                store_diagonal(k, lambda_mu_u, u[a][a]);
                continue;
              }
            Part value[9];
            for (unsigned int j = 0; j < 3; ++j)
              for (unsigned int i = 0; i < 3; ++i)
                // The diagonal's coefficient times (T_a T_b^T)(i, j).
                value[i + 3 * j] =
                  in.lambda_volume * u[a][a][i] * u[b][b][j] + in.mu_volume * u[a][b][i] * u[b][a][j] +
                  in.diagonal[k] * (t[a][i] * t[b][j] + t[a][i + 3] * t[b][j + 3] + t[a][i + 6] * t[b][j + 6]);
            store_off_diagonal(k, value);
          }
      };
      if (any_own)
        form_warped();
      if (any_rotated)
        {
          kept       = own_frames;
          keeps_some = any_own;
          form_rotated();
        }
    }
  } // namespace

  /** form_blocks() on this target: the group of eight in parts of this target's width. */
  void FormBlocks(const ElasticBody &body, const SystemCoefficients &coefficients, const ElementFrames &frames,
                  const std::uint16_t *transposed, const unsigned int *elements, const unsigned int count,
                  LaneBlocks &out)
  {
    for (unsigned int first = 0; first < lanes; first += width)
      form_part(body, coefficients, frames, transposed, elements, count, first, out);
  }
} // namespace warpchol::fem::HWY_NAMESPACE
#pragma GCC pop_options
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::fem
{
  HWY_EXPORT(FormBlocks);

  namespace
  {
    void form_blocks(const ElasticBody &body, const SystemCoefficients &coefficients, const ElementFrames &frames,
                     const std::uint16_t *transposed, const unsigned int *elements, const unsigned int count,
                     LaneBlocks &out)
    {
      (*HWY_DISPATCH_TABLE(FormBlocks)[simd::dispatch_index(simd::Family::assembly)])(
        body, coefficients, frames, transposed, elements, count, out);
    }
  } // namespace
} // namespace warpchol::fem
#endif
