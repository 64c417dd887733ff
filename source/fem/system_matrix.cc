#include <warpchol/base/exceptions.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/sparse/dealii_conversion.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>

#include <algorithm>

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
    ElementMatrix result = coefficients.stiffness * body.rest_stiffness(e);
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
    for (unsigned int a = 0; a < 4; ++a)
      result.middleRows<3>(3 * a).noalias() =
        coefficients.stiffness * (to_vertex_frame[a] * right.middleRows<3>(3 * a));

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

  SystemMatrix::SystemMatrix(const ElasticBody &body, const SystemCoefficients &coefficients)
    : body(body)
    , coefficients(coefficients)
  {
    if (!coefficients.vertex_diagonal.empty() &&
        coefficients.vertex_diagonal.size() != body.n_vertices())
      throw InputError("system matrix: " + std::to_string(coefficients.vertex_diagonal.size()) +
                       " vertex diagonal values for " + std::to_string(body.n_vertices()) +
                       " vertices");
    const Index                    n = body.n_unknowns();
    dealii::DynamicSparsityPattern dynamic_pattern(n, n);
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      for (const unsigned int row_vertex : body.element_vertices(e))
        for (const unsigned int column_vertex : body.element_vertices(e))
          {
            const Index row = body.first_unknown(row_vertex);
            const Index col = body.first_unknown(column_vertex);
            if (row < 0 || col < 0)
              continue;
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int j = 0; j < 3; ++j)
                dynamic_pattern.add(row + i, col + j);
          }
    // Free vertices in no element with another free vertex still own their diagonal.
    for (Index i = 0; i < n; ++i)
      dynamic_pattern.add(i, i);
    pattern.copy_from(dynamic_pattern);
    system_matrix.reinit(pattern);
    system_csc = sparse::to_csc(system_matrix);

    // Where every element entry lands: found once, so that assembly is a scatter.
    element_entries.resize(body.n_elements());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        const auto &vertices = body.element_vertices(e);
        for (unsigned int c = 0; c < 12; ++c)
          for (unsigned int r = 0; r < 12; ++r)
            {
              const Index row = body.first_unknown(vertices[r / 3]);
              const Index col = body.first_unknown(vertices[c / 3]);
              element_entries[e][12 * c + r] =
                row < 0 || col < 0 ? -1 : static_cast<std::int64_t>(pattern(row + r % 3, col + c % 3));
            }
      }
    diagonal_entries.resize(body.n_vertices());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      for (unsigned int i = 0; i < 3; ++i)
        {
          const Index first      = body.first_unknown(v);
          diagonal_entries[v][i] = first < 0 ? -1 : static_cast<std::int64_t>(pattern(first + i, first + i));
        }
    csc_position.resize(pattern.n_nonzero_elements());
    for (Index i = 0; i < n; ++i)
      for (auto entry = pattern.begin(i); entry != pattern.end(i); ++entry)
        {
          const Index column = entry->column();
          const auto  begin  = system_csc.row_index.begin() + system_csc.column_start[column];
          const auto  end    = system_csc.row_index.begin() + system_csc.column_start[column + 1];
          csc_position[entry->global_index()] = std::lower_bound(begin, end, i) - system_csc.row_index.begin();
        }
  }

  void SystemMatrix::add_to_entry(const std::int64_t k, const double value)
  {
    // Entry k of the SparsityPattern is value k of the SparseMatrix.
    dealii::SparseMatrix<double>::iterator(&system_matrix, k)->value() += value;
  }

  void SystemMatrix::set_entry(const std::int64_t k, const double value)
  {
    dealii::SparseMatrix<double>::iterator(&system_matrix, k)->value() = value;
  }

  void SystemMatrix::copy_to_csc(const std::int64_t k)
  {
    system_csc.values[csc_position[k]] =
      dealii::SparseMatrix<double>::const_iterator(&system_matrix, k)->value();
  }

  void SystemMatrix::save(BinaryWriter &writer) const
  {
    std::vector<double> values;
    values.reserve(system_matrix.n_nonzero_elements());
    for (const auto &entry : system_matrix)
      values.push_back(entry.value());
    writer.write(values);
    writer.write(contributions);
  }

  void SystemMatrix::load(BinaryReader &reader)
  {
    std::vector<double> values;
    reader.read(values);
    if (values.size() != system_matrix.n_nonzero_elements())
      reader.fail("the system matrix holds " + std::to_string(values.size()) + " entries, this body's " +
                  std::to_string(system_matrix.n_nonzero_elements()));
    reader.read(contributions);
    if (contributions.size() != body.n_elements())
      reader.fail("holds the contributions of " + std::to_string(contributions.size()) +
                  " elements, the body has " + std::to_string(body.n_elements()));
    // The iterators visit the entries in their storage order, that of save().
    std::size_t k = 0;
    for (auto &entry : system_matrix)
      entry.value() = values[k++];
    sparse::copy_values(system_matrix, system_csc);
  }

  void SystemMatrix::assemble(const ElementMatrixFunction &element_matrix)
  {
    system_matrix = 0;
    contributions.resize(body.n_elements());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        element_matrix(e, contributions[e]);
        const auto &entries = element_entries[e];
        for (unsigned int k = 0; k < 144; ++k)
          if (entries[k] >= 0)
            add_to_entry(entries[k], contributions[e].data()[k]);
      }
    if (!coefficients.vertex_diagonal.empty())
      for (unsigned int v = 0; v < body.n_vertices(); ++v)
        for (const auto k : diagonal_entries[v])
          if (k >= 0)
            add_to_entry(k, coefficients.vertex_diagonal[v]);
    sparse::copy_values(system_matrix, system_csc);
  }

  std::vector<Index> SystemMatrix::reassemble(const std::vector<unsigned int> &changed_elements,
                                              const ElementMatrixFunction     &element_matrix)
  {
    if (contributions.empty())
      throw MatrixError("system matrix: reassemble() before assemble()");
    std::vector<unsigned int> touched_vertices;
    ElementMatrix             updated;
    for (const unsigned int e : changed_elements)
      {
        element_matrix(e, updated);
        const ElementMatrix difference = updated - contributions[e];
        contributions[e]               = updated;
        const auto &entries            = element_entries[e];
        for (unsigned int k = 0; k < 144; ++k)
          if (entries[k] >= 0)
            {
              add_to_entry(entries[k], difference.data()[k]);
              copy_to_csc(entries[k]);
            }
        for (const unsigned int v : body.element_vertices(e))
          touched_vertices.push_back(v);
      }
    std::sort(touched_vertices.begin(), touched_vertices.end());
    touched_vertices.erase(std::unique(touched_vertices.begin(), touched_vertices.end()),
                           touched_vertices.end());

    std::vector<Index> changed_columns;
    for (const unsigned int v : touched_vertices)
      if (body.first_unknown(v) >= 0)
        for (unsigned int i = 0; i < 3; ++i)
          changed_columns.push_back(body.first_unknown(v) + i);
    return changed_columns;
  }

  const ElementMatrix &SystemMatrix::contribution(const unsigned int e) const
  {
    return contributions.at(e);
  }

  const dealii::SparseMatrix<double> &SystemMatrix::matrix() const
  {
    return system_matrix;
  }

  const sparse::CSCMatrix &SystemMatrix::csc() const
  {
    return system_csc;
  }

  Index SystemMatrix::size() const
  {
    return body.n_unknowns();
  }
} // namespace warpchol::fem
