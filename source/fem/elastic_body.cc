#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/rotations.h>

#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace warpchol::fem
{
  double Material::lame_lambda() const
  {
    return youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  }

  double Material::lame_mu() const
  {
    return youngs_modulus / (2 * (1 + poisson_ratio));
  }

  namespace
  {
    Vector3 to_vector(const dealii::Point<3> &point)
    {
      return {point[0], point[1], point[2]};
    }
  } // namespace

  ElasticBody::ElasticBody(const dealii::Triangulation<3> &triangulation,
                           const Material &material, const MassMatrix mass_matrix,
                           const std::vector<bool> &fixed_vertex)
    : tria(triangulation)
    , body_material(material)
    , mass_type(mass_matrix)
    , fe(dealii::FE_SimplexP<3>(1), 3)
    , fe_mapping(dealii::FE_SimplexP<3>(1))
    , dofs(triangulation)
  {
    if (!(material.youngs_modulus > 0) || !(material.density > 0) ||
        !(material.poisson_ratio > -1 && material.poisson_ratio < 0.5))
      throw InputError("material: need E > 0, density > 0 and -1 < nu < 0.5, got E = " +
                       format_number(material.youngs_modulus) + ", nu = " +
                       format_number(material.poisson_ratio) + ", density = " +
                       format_number(material.density));
    if (triangulation.n_active_cells() == 0)
      throw InputError("the mesh has no cell");
    if (triangulation.n_used_vertices() != triangulation.n_vertices())
      throw InputError("the mesh has " +
                       std::to_string(triangulation.n_vertices() - triangulation.n_used_vertices()) +
                       " unused vertices");
    if (fixed_vertex.size() != triangulation.n_vertices())
      throw InputError("fixed vertex flags: " + std::to_string(fixed_vertex.size()) +
                       " given for " + std::to_string(triangulation.n_vertices()) + " vertices");
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->reference_cell().is_simplex())
        throw InputError("cell " + std::to_string(cell->active_cell_index()) +
                         " is not a tetrahedron");

    rest.resize(triangulation.n_vertices());
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      rest[v] = to_vector(triangulation.get_vertices()[v]);

    // Free vertices get consecutive unknowns in vertex order.
    first_unknown_of_vertex.assign(triangulation.n_vertices(), -1);
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      if (!fixed_vertex[v])
        {
          free_vertices.push_back(v);
          first_unknown_of_vertex[v] = unknown_count;
          unknown_count += 3;
        }

    // Renumber the dofs so that component c of vertex v is dof 3 v + c.
    dofs.distribute_dofs(fe);
    std::vector<dealii::types::global_dof_index> new_numbers(dofs.n_dofs());
    for (const auto &cell : dofs.active_cell_iterators())
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int c = 0; c < 3; ++c)
          new_numbers[cell->vertex_dof_index(a, c)] = 3 * cell->vertex_index(a) + c;
    dofs.renumber_dofs(new_numbers);

    vertices_of_element.resize(triangulation.n_active_cells());
    elements_around_vertex.resize(triangulation.n_vertices());
    for (const auto &cell : triangulation.active_cell_iterators())
      {
        const unsigned int e = cell->active_cell_index();
        for (unsigned int a = 0; a < 4; ++a)
          vertices_of_element[e][a] = cell->vertex_index(a);
      }
    for (unsigned int e = 0; e < vertices_of_element.size(); ++e)
      for (const unsigned int v : vertices_of_element[e])
        elements_around_vertex[v].push_back(e);

    compute_element_matrices();
  }

  void ElasticBody::compute_element_matrices()
  {
    const unsigned int n_cells = tria.n_active_cells();
    volumes.resize(n_cells);
    inverse_rest_edges.resize(n_cells);
    stiffness.resize(n_cells);
    mass.resize(n_cells);
    lumped_mass.assign(tria.n_vertices(), 0.0);

    // Rest edge matrices Dm = [X1 - X0, X2 - X0, X3 - X0]; a (nearly) singular one is a
    // flat element that has no stiffness to speak of: refuse it, naming the cell.
    for (unsigned int e = 0; e < n_cells; ++e)
      {
        const auto &v = vertices_of_element[e];
        Matrix3     edges;
        double      longest_edge = 0;
        for (unsigned int a = 1; a < 4; ++a)
          edges.col(a - 1) = rest[v[a]] - rest[v[0]];
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = a + 1; b < 4; ++b)
            longest_edge = std::max(longest_edge, (rest[v[a]] - rest[v[b]]).norm());
        const double signed_volume = edges.determinant() / 6;
        const double volume        = std::abs(signed_volume);
        volumes[e]                 = volume;
        const auto vertex_list     = std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                                 std::to_string(v[2]) + " " + std::to_string(v[3]);
        // A negatively oriented cell is folded over its neighbours (the readers orient
        // every cell of a valid mesh positively); its Jacobian determinant would also turn
        // its stiffness negative.
        if (signed_volume < 0)
          throw InputError("cell " + std::to_string(e) + " (vertices " + vertex_list +
                           ") is inverted: signed volume " + format_number(signed_volume));
        if (!(volume > 1e-10 * longest_edge * longest_edge * longest_edge))
          throw InputError("cell " + std::to_string(e) + " (vertices " + vertex_list +
                           ") is degenerate: volume " +
                           format_number(volume) + " for edges up to " +
                           format_number(longest_edge));
        inverse_rest_edges[e] = edges.inverse();
      }

    // K_e and M_e with the finite element machinery. The gradients of linear shape
    // functions are constant, the mass integrand quadratic: a degree-2 Gauss rule is exact.
    const double                lambda = body_material.lame_lambda();
    const double                mu     = body_material.lame_mu();
    const dealii::QGaussSimplex<3> quadrature(2);
    dealii::FEValues<3>         fe_values(fe_mapping, fe, quadrature,
                                  dealii::update_values | dealii::update_gradients |
                                    dealii::update_JxW_values);
    // Local dof i of the FESystem is component c of the cell's vertex a: row 3 a + c.
    std::array<unsigned int, 12> row_of_dof;
    std::array<unsigned int, 12> component_of_dof;
    for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
      {
        const auto [component, vertex] = fe.system_to_component_index(i);
        row_of_dof[i]                  = 3 * vertex + component;
        component_of_dof[i]            = component;
      }

    for (const auto &cell : dofs.active_cell_iterators())
      {
        const unsigned int e = cell->active_cell_index();
        fe_values.reinit(cell);
        ElementMatrix   &k = stiffness[e];
        Eigen::Matrix4d &m = mass[e];
        k.setZero();
        m.setZero();
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          for (unsigned int i = 0; i < 12; ++i)
            {
              const unsigned int ci     = component_of_dof[i];
              const auto        &grad_i = fe_values.shape_grad(i, q);
              for (unsigned int j = 0; j < 12; ++j)
                {
                  const unsigned int cj     = component_of_dof[j];
                  const auto        &grad_j = fe_values.shape_grad(j, q);
                  // sigma(u) : eps(v) with sigma = lambda tr(eps) I + 2 mu eps (step-8).
                  double value = lambda * grad_i[ci] * grad_j[cj] + mu * grad_i[cj] * grad_j[ci];
                  if (ci == cj)
                    value += mu * (grad_i * grad_j);
                  k(row_of_dof[i], row_of_dof[j]) += value * fe_values.JxW(q);
                  if (ci == 0 && cj == 0)
                    m(row_of_dof[i] / 3, row_of_dof[j] / 3) += body_material.density *
                                                               fe_values.shape_value(i, q) *
                                                               fe_values.shape_value(j, q) *
                                                               fe_values.JxW(q);
                }
            }
        // Symmetrize what rounding made unsymmetric: the solver checks symmetry.
        k = (0.5 * (k + k.transpose())).eval();
        const Eigen::Vector4d row_sums = m.rowwise().sum();
        for (unsigned int a = 0; a < 4; ++a)
          lumped_mass[vertices_of_element[e][a]] += row_sums[a];
        if (mass_type == MassMatrix::lumped)
          m = row_sums.asDiagonal();
      }
  }

  unsigned int ElasticBody::n_vertices() const
  {
    return rest.size();
  }

  unsigned int ElasticBody::n_elements() const
  {
    return vertices_of_element.size();
  }

  Index ElasticBody::n_unknowns() const
  {
    return unknown_count;
  }

  const std::array<unsigned int, 4> &ElasticBody::element_vertices(const unsigned int e) const
  {
    return vertices_of_element[e];
  }

  const std::vector<unsigned int> &ElasticBody::elements_of_vertex(const unsigned int v) const
  {
    return elements_around_vertex[v];
  }

  Index ElasticBody::first_unknown(const unsigned int v) const
  {
    return first_unknown_of_vertex[v];
  }

  unsigned int ElasticBody::vertex_of_unknown(const Index unknown) const
  {
    return free_vertices.at(unknown / 3);
  }

  bool ElasticBody::is_fixed(const unsigned int v) const
  {
    return first_unknown_of_vertex[v] < 0;
  }

  const std::vector<Vector3> &ElasticBody::rest_positions() const
  {
    return rest;
  }

  double ElasticBody::element_volume(const unsigned int e) const
  {
    return volumes[e];
  }

  double ElasticBody::total_volume() const
  {
    double sum = 0;
    for (const double volume : volumes)
      sum += volume;
    return sum;
  }

  double ElasticBody::total_mass() const
  {
    double sum = 0;
    for (const double m : lumped_mass)
      sum += m;
    return sum;
  }

  const Material &ElasticBody::material() const
  {
    return body_material;
  }

  MassMatrix ElasticBody::mass_matrix_type() const
  {
    return mass_type;
  }

  const ElementMatrix &ElasticBody::rest_stiffness(const unsigned int e) const
  {
    return stiffness[e];
  }

  const Eigen::Matrix4d &ElasticBody::element_mass(const unsigned int e) const
  {
    return mass[e];
  }

  double ElasticBody::vertex_mass(const unsigned int v) const
  {
    return lumped_mass[v];
  }

  Matrix3 ElasticBody::deformation_gradient(const unsigned int          e,
                                            const std::vector<Vector3> &positions) const
  {
    const auto &v = vertices_of_element[e];
    Matrix3     deformed_edges;
    for (unsigned int a = 1; a < 4; ++a)
      deformed_edges.col(a - 1) = positions[v[a]] - positions[v[0]];
    return deformed_edges * inverse_rest_edges[e];
  }

  void ElasticBody::compute_element_rotations(const std::vector<Vector3> &positions,
                                              std::vector<Matrix3> &element_rotations) const
  {
    element_rotations.resize(n_elements());
    // Independent per element: on the threads deal.II's MultithreadInfo allows.
    dealii::parallel::apply_to_subranges(
      0u, n_elements(),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int e = begin; e < end; ++e)
          element_rotations[e] = rotation_of(deformation_gradient(e, positions));
      },
      512);
  }

  void ElasticBody::compute_nodal_rotations(const std::vector<Matrix3> &element_rotations,
                                            std::vector<Matrix3>       &nodal_rotations) const
  {
    nodal_rotations.resize(n_vertices());
    dealii::parallel::apply_to_subranges(
      0u, n_vertices(),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int v = begin; v < end; ++v)
          {
            Matrix3 weighted_sum = Matrix3::Zero();
            for (const unsigned int e : elements_around_vertex[v])
              weighted_sum += volumes[e] * element_rotations[e];
            nodal_rotations[v] = rotation_of(weighted_sum);
          }
      },
      256);
  }

  ElementVector ElasticBody::gather(const unsigned int e, const std::vector<Vector3> &field) const
  {
    ElementVector result;
    for (unsigned int a = 0; a < 4; ++a)
      result.segment<3>(3 * a) = field[vertices_of_element[e][a]];
    return result;
  }

  void ElasticBody::add_elastic_forces(const std::vector<Vector3> &positions,
                                       const std::vector<Matrix3> *element_rotations,
                                       std::vector<Vector3>       &forces) const
  {
    for (unsigned int e = 0; e < n_elements(); ++e)
      {
        const auto   &v = vertices_of_element[e];
        ElementVector displacement;
        for (unsigned int a = 0; a < 4; ++a)
          displacement.segment<3>(3 * a) =
            (element_rotations ? Vector3((*element_rotations)[e].transpose() * positions[v[a]]) :
                                 positions[v[a]]) -
            rest[v[a]];
        const ElementVector local_force = stiffness[e] * displacement;
        for (unsigned int a = 0; a < 4; ++a)
          forces[v[a]] -= element_rotations ?
                            Vector3((*element_rotations)[e] * local_force.segment<3>(3 * a)) :
                            Vector3(local_force.segment<3>(3 * a));
      }
  }

  double ElasticBody::elastic_energy(const std::vector<Vector3> &positions,
                                     const std::vector<Matrix3> *element_rotations) const
  {
    double energy = 0;
    for (unsigned int e = 0; e < n_elements(); ++e)
      {
        const auto   &v = vertices_of_element[e];
        ElementVector displacement;
        for (unsigned int a = 0; a < 4; ++a)
          displacement.segment<3>(3 * a) =
            (element_rotations ? Vector3((*element_rotations)[e].transpose() * positions[v[a]]) :
                                 positions[v[a]]) -
            rest[v[a]];
        energy += 0.5 * displacement.dot(stiffness[e] * displacement);
      }
    return energy;
  }

  void ElasticBody::add_mass_times(const std::vector<Vector3> &velocities,
                                   std::vector<Vector3>       &out) const
  {
    if (mass_type == MassMatrix::lumped)
      {
        for (unsigned int v = 0; v < n_vertices(); ++v)
          out[v] += lumped_mass[v] * velocities[v];
        return;
      }
    for (unsigned int e = 0; e < n_elements(); ++e)
      {
        const auto &v = vertices_of_element[e];
        for (unsigned int a = 0; a < 4; ++a)
          for (unsigned int b = 0; b < 4; ++b)
            out[v[a]] += mass[e](a, b) * velocities[v[b]];
      }
  }

  double ElasticBody::kinetic_energy(const std::vector<Vector3> &velocities) const
  {
    std::vector<Vector3> momentum(n_vertices(), Vector3::Zero());
    add_mass_times(velocities, momentum);
    double energy = 0;
    for (unsigned int v = 0; v < n_vertices(); ++v)
      energy += 0.5 * velocities[v].dot(momentum[v]);
    return energy;
  }

  const dealii::Triangulation<3> &ElasticBody::triangulation() const
  {
    return tria;
  }

  const dealii::DoFHandler<3> &ElasticBody::dof_handler() const
  {
    return dofs;
  }

  const dealii::Mapping<3> &ElasticBody::mapping() const
  {
    return fe_mapping;
  }
} // namespace warpchol::fem
