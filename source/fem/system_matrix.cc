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
  }

  template <typename Keep>
  void SystemMatrix::add_element(const unsigned int element, const ElementMatrix &contribution,
                                 const Keep &keep)
  {
    const auto &vertices = body.element_vertices(element);
    for (unsigned int a = 0; a < 4; ++a)
      {
        const Index row = body.first_unknown(vertices[a]);
        if (row < 0)
          continue;
        for (unsigned int i = 0; i < 3; ++i)
          {
            std::array<dealii::types::global_dof_index, 12> columns;
            std::array<double, 12>                          values;
            unsigned int                                    n_columns = 0;
            for (unsigned int b = 0; b < 4; ++b)
              {
                const Index col = body.first_unknown(vertices[b]);
                if (col < 0 || !keep(vertices[a], vertices[b]))
                  continue;
                for (unsigned int j = 0; j < 3; ++j)
                  {
                    columns[n_columns] = col + j;
                    values[n_columns]  = contribution(3 * a + i, 3 * b + j);
                    ++n_columns;
                  }
              }
            if (n_columns > 0)
              system_matrix.add(row + i, n_columns, columns.data(), values.data(), false, false);
          }
      }
  }

  void SystemMatrix::add_vertex_diagonal(const unsigned int v)
  {
    const Index first = body.first_unknown(v);
    if (coefficients.vertex_diagonal.empty() || first < 0 || coefficients.vertex_diagonal[v] == 0)
      return;
    for (unsigned int i = 0; i < 3; ++i)
      system_matrix.add(first + i, first + i, coefficients.vertex_diagonal[v]);
  }

  void SystemMatrix::assemble(const ElementMatrixFunction &element_matrix)
  {
    system_matrix = 0;
    ElementMatrix contribution;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        element_matrix(e, contribution);
        add_element(e, contribution, [](unsigned int, unsigned int) { return true; });
      }
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      add_vertex_diagonal(v);
    sparse::copy_values(system_matrix, system_csc);
  }

  std::vector<Index> SystemMatrix::reassemble(const std::vector<unsigned int> &changed_elements,
                                              const ElementMatrixFunction     &element_matrix)
  {
    if (changed_elements.empty())
      return {};
    std::vector<bool>         touched(body.n_vertices(), false);
    std::vector<unsigned int> touched_vertices;
    for (const unsigned int e : changed_elements)
      for (const unsigned int v : body.element_vertices(e))
        if (!touched[v])
          {
            touched[v] = true;
            touched_vertices.push_back(v);
          }
    std::sort(touched_vertices.begin(), touched_vertices.end());

    // Zero every entry in a row or a column of a touched vertex (the pattern is symmetric).
    std::vector<Index> changed_columns;
    for (const unsigned int v : touched_vertices)
      {
        const Index first = body.first_unknown(v);
        if (first < 0)
          continue;
        for (unsigned int i = 0; i < 3; ++i)
          {
            changed_columns.push_back(first + i);
            for (auto entry = system_matrix.begin(first + i); entry != system_matrix.end(first + i);
                 ++entry)
              {
                entry->value() = 0;
                system_matrix.set(entry->column(), first + i, 0.0);
              }
          }
      }

    // Add back, in element order, what every element around them gives to those entries.
    std::vector<unsigned int> around;
    for (const unsigned int v : touched_vertices)
      around.insert(around.end(), body.elements_of_vertex(v).begin(),
                    body.elements_of_vertex(v).end());
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    ElementMatrix contribution;
    for (const unsigned int e : around)
      {
        element_matrix(e, contribution);
        add_element(e, contribution,
                    [&](unsigned int row_vertex, unsigned int column_vertex) {
                      return touched[row_vertex] || touched[column_vertex];
                    });
      }
    for (const unsigned int v : touched_vertices)
      add_vertex_diagonal(v);
    sparse::copy_values(system_matrix, system_csc);
    return changed_columns;
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
