#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/rotations.h>

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parallel.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/parallel_for.h>

#include <warpchol/base/simd.h>

// What every target shares, compiled once (this file is included again per SIMD target).
#ifndef warpchol_fem_elastic_body_shared
#define warpchol_fem_elastic_body_shared
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
    /** Elements (or vertices) whose rotations are computed together by rotations_of(). */
    constexpr unsigned int rotation_block = 64;
    /** Elements whose forces CorotatedForces() computes side by side. */
    constexpr unsigned int force_lanes = 8;

    Vector3 to_vector(const dealii::Point<3> &point)
    {
      return {point[0], point[1], point[2]};
    }

    /** What the fused element pass reads (per element arrays from element 0). */
    struct FusedPassInput
    {
      /** The positions (or, for a product, the field the stiffness multiplies). */
      const Vector3                     *positions;
      const std::array<unsigned int, 4> *vertices;
      const Matrix3                     *inverse_rest_edges;
      const double                      *volumes;
      /** nullptr where no change left a plastic strain (and for a product). */
      const Matrix3 *plastic_strains;
      double         mu, lambda;
      /** The rotations to use where the pass does not compute them (nullptr: R = I). */
      const Matrix3 *given_rotations;
      /** The corotated stiffness times the field (CorotatedForces()) instead of the forces. */
      bool product;
      /** Per vertex, the first and last element around it. */
      const std::array<unsigned int, 2> *element_span;
    };

    /** What it writes (per element, from element 0; energies and norms may be nullptr). */
    struct FusedPassOutput
    {
      /** The rotations computed here (rotations_of()); nullptr: the given ones. */
      Matrix3 *rotations;
      /** Per vertex: the forces of its elements added where the range holds them all. */
      Vector3 *vertex_forces;
      /** Per element: its forces, where a vertex of it has elements outside the range. */
      Matrix3 *shared_forces;
      double  *energies, *force_norms;
    };

    /** The forces of element forces @p forces (on vertices 1..3 as columns) on its vertex @p local. */
    inline void add_force_on_vertex(const Matrix3 &forces, const unsigned int local, Vector3 &sum)
    {
      // Vertex 0's is minus the sum of the others'.
      if (local == 0)
        sum -= forces.rowwise().sum();
      else
        sum += forces.col(local - 1);
    }

    /**
     * The fused element pass over the elements [begin, end) on the SIMD target chosen at run
     * time: F, R_e (computed or given), G = R_e^T F - I, the world forces and the energy; or
     * the corotated stiffness times a field.
     */
    void fused_pass_range(const FusedPassInput &in, const FusedPassOutput &out, unsigned int begin, unsigned int end,
                          RotationPaths &paths);
  } // namespace

  namespace
  {
    /** Throw InputError unless @p material is admissible and @p triangulation a mesh of tetrahedra. */
    void check_body(const dealii::Triangulation<3> &triangulation, const Material &material,
                    const std::vector<bool> &fixed_vertex)
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
    }
  } // namespace

  ElasticBody::ElasticBody(const dealii::Triangulation<3> &triangulation,
                           const Material &material, const MassMatrix mass_matrix,
                           const std::vector<bool>         &fixed_vertex,
                           const std::vector<unsigned int> &unknown_order)
    : tria(triangulation)
    , body_material(material)
    , mass_type(mass_matrix)
    , fe(dealii::FE_SimplexP<3>(1), 3)
    , fe_mapping(dealii::FE_SimplexP<3>(1))
    , dofs(triangulation)
  {
    check_body(triangulation, material, fixed_vertex);
    lambda = material.lame_lambda();
    mu     = material.lame_mu();
    rest.resize(triangulation.n_vertices());
    for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
      rest[v] = to_vector(triangulation.get_vertices()[v]);

    number_free_vertices(fixed_vertex, unknown_order);

    // Renumber the dofs so that component c of vertex v is dof 3 v + c.
    dofs.distribute_dofs(fe);
    std::vector<dealii::types::global_dof_index> new_numbers(dofs.n_dofs());
    for (const auto &cell : dofs.active_cell_iterators())
      for (unsigned int a = 0; a < 4; ++a)
        for (unsigned int c = 0; c < 3; ++c)
          new_numbers[cell->vertex_dof_index(a, c)] = 3 * cell->vertex_index(a) + c;
    dofs.renumber_dofs(new_numbers);

    list_elements_around_vertices();
    compute_element_matrices();
    rest_volumes = volumes;
    stiffness_scale.assign(n_elements(), 1.0);
    cut.assign(n_elements(), false);
    particle_mass.assign(n_vertices(), 0.0);
    live_elements.resize(n_vertices());
    for (unsigned int v = 0; v < n_vertices(); ++v)
      live_elements[v] = around_start[v + 1] - around_start[v];
  }

  void ElasticBody::number_free_vertices(const std::vector<bool>         &fixed_vertex,
                                         const std::vector<unsigned int> &unknown_order)
  {
    std::vector<unsigned int> order(unknown_order);
    if (order.empty())
      {
        order.resize(tria.n_vertices());
        std::iota(order.begin(), order.end(), 0u);
      }
    std::vector<bool> listed(tria.n_vertices(), false);
    for (const unsigned int v : order)
      {
        if (v >= listed.size() || listed[v])
          throw InputError("unknown order: vertex " + std::to_string(v) +
                           (v >= listed.size() ? " does not exist" : " is listed twice"));
        listed[v] = true;
      }
    if (order.size() != listed.size())
      throw InputError("unknown order: " + std::to_string(order.size()) + " vertices listed for " +
                       std::to_string(listed.size()));
    first_unknown_of_vertex.assign(tria.n_vertices(), -1);
    for (const unsigned int v : order)
      if (!fixed_vertex[v])
        {
          free_vertices.push_back(v);
          first_unknown_of_vertex[v] = unknown_count;
          unknown_count += 3;
        }
  }

  void ElasticBody::list_elements_around_vertices()
  {
    vertices_of_element.resize(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      {
        const unsigned int e = cell->active_cell_index();
        for (unsigned int a = 0; a < 4; ++a)
          vertices_of_element[e][a] = cell->vertex_index(a);
      }
    if (4 * vertices_of_element.size() > std::numeric_limits<unsigned int>::max())
      throw InputError("the mesh has " + std::to_string(vertices_of_element.size()) +
                       " cells, more than 2^30 (4 per cell around the vertices)");
    around_start.assign(tria.n_vertices() + 1, 0);
    for (const auto &vertices : vertices_of_element)
      for (const unsigned int v : vertices)
        ++around_start[v + 1];
    std::partial_sum(around_start.begin(), around_start.end(), around_start.begin());
    around_element.resize(around_start.back());
    around_local.resize(around_start.back());
    std::vector<unsigned int> filled(around_start.begin(), around_start.end() - 1);
    for (unsigned int e = 0; e < vertices_of_element.size(); ++e)
      for (unsigned int a = 0; a < 4; ++a)
        {
          const unsigned int k = filled[vertices_of_element[e][a]]++;
          around_element[k]    = e;
          around_local[k]      = static_cast<unsigned char>(a);
        }
    element_span.assign(tria.n_vertices(), {{0, 0}});
    for (unsigned int v = 0; v < tria.n_vertices(); ++v)
      if (around_start[v + 1] > around_start[v])
        element_span[v] = {{around_element[around_start[v]], around_element[around_start[v + 1] - 1]}};
  }

  std::vector<unsigned int> ElasticBody::cut_element(const unsigned int e)
  {
    std::vector<unsigned int> orphans;
    if (cut.at(e))
      return orphans;
    cut[e]             = true;
    stiffness_scale[e] = 0;
    volumes[e]         = 0;
    const Eigen::Vector4d row_sums = mass[e].rowwise().sum();
    mass[e].setZero();
    mass_diagonal[e].fill(0);
    for (unsigned int a = 0; a < 4; ++a)
      {
        const unsigned int v = vertices_of_element[e][a];
        if (--live_elements[v] == 0)
          {
            // Its last element: the vertex keeps the mass it has, as a free particle.
            particle_mass[v] = lumped_mass[v];
            orphans.push_back(v);
          }
        else
          lumped_mass[v] -= row_sums[a];
      }
    return orphans;
  }

  void ElasticBody::scale_element_stiffness(const unsigned int e, const double factor)
  {
    if (!(factor > 0) || !std::isfinite(factor))
      throw InputError("cell " + std::to_string(e) + ": a stiffness factor must be > 0, got " + format_number(factor));
    if (cut.at(e))
      return;
    stiffness_scale[e] *= factor;
    volumes[e] = rest_volumes[e] * stiffness_scale[e];
  }

  void ElasticBody::scale_element_stiffness_keeping_stress(const unsigned int e, const double factor,
                                                           const Matrix3 &displacement_gradient)
  {
    if (cut.at(e))
      return;
    scale_element_stiffness(e, factor);
    if (plastic_strains.empty())
      plastic_strains.assign(n_elements(), Matrix3::Zero());
    // s' C (eps - eps_p') = s C (eps - eps_p) with s' = factor s: the elastic strain shrinks
    // by the factor, the rest of the strain becomes plastic.
    const Matrix3 strain = 0.5 * (displacement_gradient + displacement_gradient.transpose());
    plastic_strains[e]   = strain - (strain - plastic_strains[e]) / factor;
  }

  Matrix3 ElasticBody::plastic_strain(const unsigned int e) const
  {
    return plastic_strains.empty() ? Matrix3::Zero() : plastic_strains[e];
  }

  void ElasticBody::save_changes(BinaryWriter &writer) const
  {
    writer.section("body changes");
    writer.write(cut);
    writer.write(stiffness_scale);
    writer.write(plastic_strains);
    writer.write(lumped_mass);
    writer.write(particle_mass);
    writer.write(live_elements);
  }

  void ElasticBody::load_changes(BinaryReader &reader)
  {
    reader.expect_section("body changes");
    reader.read(cut);
    reader.read(stiffness_scale);
    reader.read(plastic_strains);
    reader.read(lumped_mass);
    reader.read(particle_mass);
    reader.read(live_elements);
    if (cut.size() != n_elements() || stiffness_scale.size() != n_elements() || lumped_mass.size() != n_vertices() ||
        particle_mass.size() != n_vertices() || live_elements.size() != n_vertices() ||
        (!plastic_strains.empty() && plastic_strains.size() != n_elements()))
      reader.fail("the body's changes were written for another mesh");
    for (unsigned int e = 0; e < n_elements(); ++e)
      {
        volumes[e] = rest_volumes[e] * stiffness_scale[e];
        if (cut[e])
          {
            mass[e].setZero();
            mass_diagonal[e].fill(0);
          }
      }
  }

  bool ElasticBody::element_is_cut(const unsigned int e) const
  {
    return cut[e];
  }

  void ElasticBody::compute_element_matrices()
  {
    const unsigned int n_cells = tria.n_active_cells();
    volumes.resize(n_cells);
    inverse_rest_edges.resize(n_cells);
    stiffness.resize(n_cells);
    mass.resize(n_cells);
    mass_diagonal.resize(n_cells);
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
        for (unsigned int a = 0; a < 4; ++a)
          mass_diagonal[e][a] = m(a, a);
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

  dealii::ArrayView<const unsigned int> ElasticBody::elements_of_vertex(const unsigned int v) const
  {
    return {around_element.data() + around_start[v], around_start[v + 1] - around_start[v]};
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

  double ElasticBody::total_volume() const
  {
    double sum = 0;
    for (const double volume : rest_volumes)
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

  double ElasticBody::lame_lambda() const
  {
    return lambda;
  }

  double ElasticBody::lame_mu() const
  {
    return mu;
  }

  const ElementMatrix &ElasticBody::rest_stiffness(const unsigned int e) const
  {
    return stiffness[e];
  }

  double ElasticBody::vertex_mass(const unsigned int v) const
  {
    return lumped_mass[v];
  }

  Matrix3 ElasticBody::field_gradient(const unsigned int e, const std::vector<Vector3> &field) const
  {
    const auto &v = vertices_of_element[e];
    return field_gradient(e, std::array<Vector3, 4>{{field[v[0]], field[v[1]], field[v[2]], field[v[3]]}});
  }

  Matrix3 ElasticBody::field_gradient(const unsigned int e, const std::array<Vector3, 4> &vertex_values) const
  {
    Matrix3 edges;
    for (unsigned int a = 1; a < 4; ++a)
      edges.col(a - 1) = vertex_values[a] - vertex_values[0];
    return edges * inverse_rest_edges[e];
  }

  Matrix3 ElasticBody::deformation_gradient(const unsigned int          e,
                                            const std::vector<Vector3> &positions) const
  {
    return field_gradient(e, positions);
  }

  Matrix3 ElasticBody::displacement_gradient(const unsigned int e, const std::vector<Vector3> &positions,
                                             const bool rotated) const
  {
    const Matrix3 gradient = deformation_gradient(e, positions);
    Matrix3       rotation = Matrix3::Identity();
    if (rotated)
      rotations_of(&gradient, &rotation, 1);
    return rotation.transpose() * gradient - Matrix3::Identity();
  }

  double ElasticBody::element_energy(const unsigned int e, const Matrix3 &displacement_gradient) const
  {
    const Matrix3 strain = 0.5 * (displacement_gradient + displacement_gradient.transpose()) - plastic_strain(e);
    return 0.5 * volumes[e] * stress(strain).cwiseProduct(strain).sum();
  }

  Matrix3 ElasticBody::stress(const Matrix3 &displacement_gradient) const
  {
    const Matrix3 strain = 0.5 * (displacement_gradient + displacement_gradient.transpose());
    Matrix3       result = (2 * mu) * strain;
    result.diagonal().array() += lambda * strain.trace();
    return result;
  }

  Matrix3 ElasticBody::stiffness_forces(const unsigned int e, const Matrix3 &displacement_gradient) const
  {
    // The rows of Dm^-1 are the gradients of the shape functions of vertices 1..3: the
    // force on vertex a is V sigma grad N_a, i.e. the columns of V sigma Dm^-T.
    return volumes[e] * (stress(displacement_gradient) * inverse_rest_edges[e].transpose());
  }

  void ElasticBody::evaluate(const std::vector<Vector3> &positions, const Rotations rotations,
                             State &state) const
  {
    const unsigned int n_cells = n_elements();
    const bool         rotate  = rotations != Rotations::none;
    state.element_rotations.resize(rotate ? n_cells : 0);
    state.element_force_norms.resize(n_cells);
    std::vector<double> energies(n_cells);
    state.rotation_paths = RotationPaths();
    // The fused element pass: F, R_e, G = R_e^T F - I, the local forces K_e u_e and the
    // world forces -R_e K_e u_e, the energy.
    state.forces.assign(n_vertices(), Vector3::Zero());
    fused_pass(positions, nullptr, false, rotate ? state.element_rotations.data() : nullptr, state.forces,
               energies.data(), state.element_force_norms.data(), &state.rotation_paths, state.force_work);
    state.elastic_energy = 0;
    for (const double energy : energies)
      state.elastic_energy += energy;
    if (rotations == Rotations::elements_and_vertices)
      compute_nodal_rotations(state.element_rotations, state.nodal_rotations);
    else
      state.nodal_rotations.clear();
  }

  void ElasticBody::compute_element_rotations(const std::vector<Vector3> &positions,
                                              std::vector<Matrix3> &element_rotations) const
  {
    element_rotations.resize(n_elements());
    // Independent per element: on the threads deal.II's MultithreadInfo allows.
    dealii::parallel::apply_to_subranges(
      0u, n_elements(),
      [&](const unsigned int begin, const unsigned int end) {
        std::array<Matrix3, rotation_block> gradients;
        for (unsigned int first = begin; first < end; first += rotation_block)
          {
            const unsigned int count = std::min(rotation_block, end - first);
            for (unsigned int k = 0; k < count; ++k)
              gradients[k] = deformation_gradient(first + k, positions);
            rotations_of(gradients.data(), element_rotations.data() + first, count);
          }
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
        std::array<Matrix3, rotation_block> weighted_sums;
        for (unsigned int first = begin; first < end; first += rotation_block)
          {
            const unsigned int count = std::min(rotation_block, end - first);
            for (unsigned int k = 0; k < count; ++k)
              {
                weighted_sums[k].setZero();
                for (const unsigned int e : elements_of_vertex(first + k))
                  weighted_sums[k] += volumes[e] * element_rotations[e];
              }
            rotations_of(weighted_sums.data(), nodal_rotations.data() + first, count);
          }
      },
      256);
  }

  void ElasticBody::forces_at_given_rotations(const std::vector<Vector3> &positions,
                                              const std::vector<Matrix3> *element_rotations,
                                              std::vector<Vector3> &vertex_forces, std::vector<double> &energies) const
  {
    vertex_forces.assign(n_vertices(), Vector3::Zero());
    energies.resize(n_elements());
    std::vector<double> force_norms(n_elements());
    ForceWork           work;
    fused_pass(positions, element_rotations, false, nullptr, vertex_forces, energies.data(), force_norms.data(),
               nullptr, work);
  }

  void ElasticBody::add_elastic_forces(const std::vector<Vector3> &positions,
                                       const std::vector<Matrix3> *element_rotations,
                                       std::vector<Vector3>       &forces) const
  {
    // Summed apart, then added: each vertex gets the same sum whatever it held.
    std::vector<Vector3> sums;
    std::vector<double>  energies;
    forces_at_given_rotations(positions, element_rotations, sums, energies);
    for (unsigned int v = 0; v < n_vertices(); ++v)
      forces[v] += sums[v];
  }

  double ElasticBody::elastic_energy(const std::vector<Vector3> &positions,
                                     const std::vector<Matrix3> *element_rotations) const
  {
    double sum = 0;
    for (const double energy : element_energies(positions, element_rotations))
      sum += energy;
    return sum;
  }

  std::vector<double> ElasticBody::element_energies(const std::vector<Vector3> &positions,
                                                    const std::vector<Matrix3> *element_rotations) const
  {
    std::vector<Vector3> forces;
    std::vector<double>  energies;
    forces_at_given_rotations(positions, element_rotations, forces, energies);
    return energies;
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
    // Free particles (their elements all cut) keep their mass.
    for (unsigned int v = 0; v < n_vertices(); ++v)
      if (particle_mass[v] > 0)
        out[v] += particle_mass[v] * velocities[v];
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
#endif

// The corotated forces of a group of elements, once per SIMD target (Highway).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fem/elastic_body.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::fem::HWY_NAMESPACE
{
  /** Matrices of a group of elements side by side: entry i (column-major) of lane l at [i][l]. */
  using LaneMatrices = double[9][force_lanes];

  /**
   * The world forces -R K_e (R^T x_e - X_e) on vertices 1..3 (as columns; vertex 0's is
   * minus their sum), the energy 1/2 u^T K_e u = V/2 sigma : eps and the norm of the 12
   * nodal forces of the @p count (<= 8) elements whose deformation gradients and rotations
   * are the lanes of @p f and @p r and whose inverse rest edges and volumes start at
   * @p inverse_rest_edges and @p volumes, side by side in SIMD lanes: the hot loop of the
   * fused pass. With @p product, the corotated stiffness times the field whose gradients
   * are @p f: G = R^T F and the forces +R (V sigma Dm^-T); else G = R^T F - I and
   * -R (V sigma Dm^-T).
   */
  void CorotatedForces(const unsigned int count, const LaneMatrices &f, const LaneMatrices &r,
                       const Matrix3 *inverse_rest_edges, const double *volumes, const Matrix3 *plastic_strains,
                       const double mu, const double lambda, const bool product, Matrix3 *forces, double *energies,
                       double *force_norms)
  {
    // Lanes past count repeat the last element and are not stored.
    constexpr unsigned int lanes = force_lanes;
    const double identity = product ? 0. : 1.;
    const double sign     = product ? 1. : -1.;
    alignas(64) double d[9][lanes], volume[lanes];
    for (unsigned int l = 0; l < lanes; ++l)
      {
        const unsigned int k = std::min(l, count - 1);
        for (unsigned int i = 0; i < 9; ++i)
          d[i][l] = inverse_rest_edges[k].data()[i];
        volume[l] = volumes[k];
      }
    alignas(64) double g[9][lanes], stress_volume[9][lanes], local[9][lanes], world[9][lanes];
    alignas(64) double energy[lanes], norm[lanes];
    // G = R^T F - I (R^T F for a product).
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int l = 0; l < lanes; ++l)
          g[i + 3 * j][l] = r[3 * i][l] * f[3 * j][l] + r[1 + 3 * i][l] * f[1 + 3 * j][l] +
                            r[2 + 3 * i][l] * f[2 + 3 * j][l] - (i == j ? identity : 0.);
    // A change that kept the stress left a plastic strain: the elastic part is G - eps_p.
    if (plastic_strains != nullptr)
      for (unsigned int l = 0; l < lanes; ++l)
        {
          const Matrix3 &plastic = plastic_strains[std::min(l, count - 1)];
          for (unsigned int i = 0; i < 9; ++i)
            g[i][l] -= plastic.data()[i];
        }
    // V sigma with sigma = lambda tr(eps) I + 2 mu eps, eps = sym(G); the energy V/2 sigma : G.
    for (unsigned int l = 0; l < lanes; ++l)
      {
        const double trace = g[0][l] + g[4][l] + g[8][l];
        energy[l]          = 0;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            {
              const double sigma = mu * (g[i + 3 * j][l] + g[j + 3 * i][l]) + (i == j ? lambda * trace : 0.);
              stress_volume[i + 3 * j][l] = volume[l] * sigma;
              energy[l] += 0.5 * stress_volume[i + 3 * j][l] * g[i + 3 * j][l];
            }
      }
    // Local forces V sigma Dm^-T, world forces -R (V sigma Dm^-T).
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int l = 0; l < lanes; ++l)
          local[i + 3 * j][l] = stress_volume[i][l] * d[j][l] + stress_volume[i + 3][l] * d[j + 3][l] +
                                stress_volume[i + 6][l] * d[j + 6][l];
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int l = 0; l < lanes; ++l)
          world[i + 3 * j][l] = sign * (r[i][l] * local[3 * j][l] + r[i + 3][l] * local[1 + 3 * j][l] +
                                        r[i + 6][l] * local[2 + 3 * j][l]);
    // The norm of the 12 nodal forces (rotations keep norms): vertex 0's is minus the sum.
    // Not for a product (CG's hot loop), which asks for none.
    if (force_norms != nullptr)
      for (unsigned int l = 0; l < lanes; ++l)
        {
          double sum = 0;
          for (unsigned int i = 0; i < 3; ++i)
            {
              const double row = world[i][l] + world[i + 3][l] + world[i + 6][l];
              sum += row * row + world[i][l] * world[i][l] + world[i + 3][l] * world[i + 3][l] +
                     world[i + 6][l] * world[i + 6][l];
            }
          norm[l] = std::sqrt(sum);
        }
    for (unsigned int l = 0; l < count; ++l)
      {
        for (unsigned int i = 0; i < 9; ++i)
          forces[l].data()[i] = world[i][l];
        if (energies != nullptr)
          energies[l] = energy[l];
        if (force_norms != nullptr)
          force_norms[l] = norm[l];
      }
  }

  /** The rotations of a group of gradients, lane by lane, on this target (fem/rotations.cc). */
  void RotationLanes(const LaneMatrices &gradients, std::size_t used, LaneMatrices &rotations, RotationPaths &taken);

  /**
   * fused_pass_range() on this target: the gradients, rotations and forces of a range, eight
   * elements at a time, all in its code and in the lanes' layout (the group's matrices are
   * laid out once, not once per kernel).
   */
  void FusedPassRange(const FusedPassInput &in, const FusedPassOutput &out, const unsigned int begin,
                      const unsigned int end, RotationPaths &paths)
  {
    for (unsigned int first = begin; first < end; first += force_lanes)
      {
        const unsigned int count = std::min(force_lanes, end - first);
        // F = [x1 - x0, x2 - x0, x3 - x0] Dm^-1; lanes past count repeat the last element.
        alignas(64) LaneMatrices f, r;
        for (unsigned int l = 0; l < force_lanes; ++l)
          {
            const unsigned int e = first + std::min(l, count - 1);
            const auto        &v = in.vertices[e];
            Matrix3            edges;
            for (unsigned int a = 1; a < 4; ++a)
              edges.col(a - 1) = in.positions[v[a]] - in.positions[v[0]];
            const Matrix3 gradient = edges * in.inverse_rest_edges[e];
            for (unsigned int i = 0; i < 9; ++i)
              f[i][l] = gradient.data()[i];
          }
        if (out.rotations != nullptr)
          {
            RotationLanes(f, count, r, paths);
            for (unsigned int l = 0; l < count; ++l)
              for (unsigned int i = 0; i < 9; ++i)
                out.rotations[first + l].data()[i] = r[i][l];
            // The padding lanes as the forces expect them: the last element again.
            for (unsigned int l = count; l < force_lanes; ++l)
              for (unsigned int i = 0; i < 9; ++i)
                r[i][l] = r[i][count - 1];
          }
        else
          for (unsigned int l = 0; l < force_lanes; ++l)
            {
              const unsigned int k = std::min(l, count - 1);
              for (unsigned int i = 0; i < 9; ++i)
                r[i][l] = in.given_rotations != nullptr ? in.given_rotations[first + k].data()[i] : i % 4 == 0 ? 1. : 0.;
            }
        Matrix3 forces[force_lanes];
        CorotatedForces(count, f, r, in.inverse_rest_edges + first, in.volumes + first,
                        in.plastic_strains != nullptr ? in.plastic_strains + first : nullptr, in.mu, in.lambda,
                        in.product, forces, out.energies ? out.energies + first : nullptr,
                        out.force_norms ? out.force_norms + first : nullptr);
        // On the vertices whose elements this range holds all, in element order; kept for
        // the others.
        for (unsigned int l = 0; l < count; ++l)
          {
            const auto &v      = in.vertices[first + l];
            bool        shared = false;
            for (unsigned int a = 0; a < 4; ++a)
              {
                const auto &span = in.element_span[v[a]];
                if (span[0] < begin || span[1] >= end)
                  shared = true;
                else
                  add_force_on_vertex(forces[l], a, out.vertex_forces[v[a]]);
              }
            if (shared)
              out.shared_forces[first + l] = forces[l];
          }
      }
  }
} // namespace warpchol::fem::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::fem
{
  HWY_EXPORT(FusedPassRange);

  namespace
  {
    void fused_pass_range(const FusedPassInput &in, const FusedPassOutput &out, const unsigned int begin,
                          const unsigned int end, RotationPaths &paths)
    {
      simd::use_target_from_environment();
      HWY_DYNAMIC_DISPATCH(FusedPassRange)(in, out, begin, end, paths);
    }
  } // namespace

  void ElasticBody::fused_pass(const std::vector<Vector3> &field, const std::vector<Matrix3> *given_rotations,
                               const bool product, Matrix3 *computed_rotations, std::vector<Vector3> &vertex_forces,
                               double *energies, double *force_norms, RotationPaths *paths,
                               ForceWork &work) const
  {
    // A plastic strain shifts the forces, not the stiffness a product multiplies by.
    const FusedPassInput input{field.data(),
                               vertices_of_element.data(),
                               inverse_rest_edges.data(),
                               volumes.data(),
                               plastic_strains.empty() || product ? nullptr : plastic_strains.data(),
                               mu,
                               lambda,
                               given_rotations ? given_rotations->data() : nullptr,
                               product,
                               element_span.data()};
    // One range of consecutive elements per thread, of 512 elements at least: the fewer the
    // borders, the fewer the vertices two ranges share, and the fewer the sums that the
    // ranges' own arrays must add up afterwards.
    const unsigned int n_threads = dealii::MultithreadInfo::n_threads();
    const unsigned int n_ranges  = std::max(1u, std::min(n_threads, n_elements() / 512));
    std::vector<unsigned int> range_start(n_ranges + 1);
    for (unsigned int r = 0; r <= n_ranges; ++r)
      range_start[r] = static_cast<unsigned int>(static_cast<std::uint64_t>(n_elements()) * r / n_ranges);
    // On threads, each range sums into an array of its own: vertices of two ranges side by
    // side in memory would have their cache lines written by both threads.
    if (n_ranges > 1)
      {
        work.shared_forces.resize(n_elements());
        work.range_sums.resize(n_ranges);
      }
    std::vector<RotationPaths> range_paths(n_ranges);
    const auto                 pass_over_range = [&](const std::size_t r) {
      Vector3 *sums = vertex_forces.data();
      if (n_ranges > 1)
        {
          work.range_sums[r].assign(n_vertices(), Vector3::Zero());
          sums = work.range_sums[r].data();
        }
      const FusedPassOutput output{computed_rotations, sums, work.shared_forces.data(), energies, force_norms};
      fused_pass_range(input, output, range_start[r], range_start[r + 1], range_paths[r]);
    };
    if (n_ranges == 1)
      pass_over_range(0);
    else
      tbb::parallel_for(std::size_t(0), std::size_t(n_ranges), pass_over_range);
    if (paths != nullptr)
      for (const auto &taken : range_paths)
        *paths += taken;
    if (n_ranges == 1)
      return;
    // Each vertex's sum from the range that holds its elements, or, where two ranges share
    // them, from the kept forces, in element order.
    const auto range_of = [&](const unsigned int e) {
      return std::upper_bound(range_start.begin(), range_start.end(), e) - range_start.begin() - 1;
    };
    dealii::parallel::apply_to_subranges(
      0u, n_vertices(),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int v = begin; v < end; ++v)
          {
            if (around_start[v + 1] == around_start[v])
              continue;
            const auto range = range_of(element_span[v][0]);
            if (range == range_of(element_span[v][1]))
              {
                vertex_forces[v] += work.range_sums[range][v];
                continue;
              }
            Vector3 sum = Vector3::Zero();
            for (unsigned int k = around_start[v]; k < around_start[v + 1]; ++k)
              add_force_on_vertex(work.shared_forces[around_element[k]], around_local[k], sum);
            vertex_forces[v] += sum;
          }
      },
      256);
  }

  void ElasticBody::corotated_stiffness_times(const std::vector<Matrix3> *element_rotations,
                                              const std::vector<Vector3> &v, std::vector<Vector3> &out,
                                              ForceWork &work) const
  {
    // R_e K_e R_e^T v_e: the gradient of v in the element's frame is R_e^T grad v; a
    // plastic strain shifts the forces, not the matrix.
    out.assign(n_vertices(), Vector3::Zero());
    fused_pass(v, element_rotations, true, nullptr, out, nullptr, nullptr, nullptr, work);
  }

} // namespace warpchol::fem
#endif
