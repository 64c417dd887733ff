#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/fem/warp_canceling_model.h>

#include <deal.II/base/parallel.h>

#include <cmath>

namespace warpchol::fem
{
  WarpCancelingModel::WarpCancelingModel(const ElasticBody &body,
                                         const SystemCoefficients &coefficients,
                                         const cholesky::SparseCholesky::Settings &solver_settings,
                                         const double update_threshold)
    : ElasticityModel(body, coefficients, solver_settings)
    , threshold(update_threshold)
  {
    if (!(update_threshold >= 0))
      throw InputError("the WCC update threshold must be >= 0 (or inf), got " +
                       format_number(update_threshold));
    // At rest every rotation is the identity: A is the rest matrix.
    set_up_rest_system();
    solve_frame = &nodal_rotations;
    // Estimates exist only between the two limits (0: all updated, inf: none); at rest
    // they are 0.
    if (update_threshold > 0 && !std::isinf(update_threshold))
      record.error_estimate.assign(body.n_elements(), 0.0);
  }

  std::string WarpCancelingModel::name() const
  {
    return "warp_canceling";
  }

  double WarpCancelingModel::update_threshold() const
  {
    return threshold;
  }

  std::vector<unsigned int>
  WarpCancelingModel::elements_to_update(const std::vector<Vector3> &positions,
                                         const std::vector<Vector3> &velocities)
  {
    const unsigned int  n_elements = body.n_elements();
    std::vector<double> error(n_elements);
    std::vector<double> impulse(n_elements);
    // Independent per element (threads as deal.II's MultithreadInfo allows); the sum of
    // the impulses follows, in element order, so the result does not depend on threads.
    dealii::parallel::apply_to_subranges(
      0u, n_elements,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int e = begin; e < end; ++e)
          {
            const auto    &vertices         = body.element_vertices(e);
            const Matrix3 &element_rotation = element_rotations[e];
            // z = R^T v_e in the nodal frames; exact product A_e[R, R_e] z computed without
            // forming the matrix: the stiffness part is S_a^T R_e K_e R_e^T v (since
            // S_b S_b^T = I), the mass part m_ab S_a^T v_b.
            ElementVector z;
            ElementVector unrotated_velocity;
            ElementVector unrotated_displacement;
            for (unsigned int a = 0; a < 4; ++a)
              {
                const unsigned int v = vertices[a];
                z.segment<3>(3 * a)  = nodal_rotations[v].transpose() * velocities[v];
                unrotated_velocity.segment<3>(3 * a) = element_rotation.transpose() * velocities[v];
                unrotated_displacement.segment<3>(3 * a) =
                  element_rotation.transpose() * positions[v] - body.rest_positions()[v];
              }
            const ElementVector local_force = body.rest_stiffness(e) * unrotated_velocity;
            const auto         &mass        = body.element_mass(e);
            ElementVector       exact;
            for (unsigned int a = 0; a < 4; ++a)
              {
                Vector3 world =
                  coefficients.stiffness * (element_rotation * local_force.segment<3>(3 * a));
                for (unsigned int b = 0; b < 4; ++b)
                  if (mass(a, b) != 0)
                    world += (coefficients.mass * mass(a, b)) * velocities[vertices[b]];
                exact.segment<3>(3 * a) = nodal_rotations[vertices[a]].transpose() * world;
              }
            error[e]   = (exact - system.contribution(e) * z).norm();
            impulse[e] = exact.norm() + coefficients.time_step *
                                          (body.rest_stiffness(e) * unrotated_displacement).norm();
          }
      },
      512);
    double impulse_sum = 0;
    for (const double value : impulse)
      impulse_sum += value;

    const double scale = impulse_sum / n_elements;
    std::vector<unsigned int> update;
    for (unsigned int e = 0; e < n_elements; ++e)
      {
        // A body at rest has scale 0 and errors 0: no update (strict inequality).
        const double relative_error = scale > 0 ? error[e] / scale : 0.0;
        record.error_estimate[e]    = relative_error;
        if (error[e] > threshold * scale || !std::isfinite(error[e]))
          update.push_back(e);
      }
    return update;
  }

  ElementMatrix WarpCancelingModel::current_contribution(const unsigned int e) const
  {
    const auto            &vertices = body.element_vertices(e);
    std::array<Matrix3, 4> vertex_rotations;
    for (unsigned int a = 0; a < 4; ++a)
      vertex_rotations[a] = nodal_rotations[vertices[a]];
    return warped_element_matrix(body, e, coefficients, vertex_rotations, element_rotations[e]);
  }

  void WarpCancelingModel::prepare_step(const std::vector<Vector3> &positions,
                                        const std::vector<Vector3> &velocities,
                                        StepStatistics             &statistics)
  {
    Stopwatch stopwatch;
    body.compute_element_rotations(positions, element_rotations);
    body.compute_nodal_rotations(element_rotations, nodal_rotations);
    statistics.t_rotations += stopwatch.seconds();
    record_no_refactorization(statistics);

    // Updating an element stores its contribution with the current rotations: the system
    // matrix keeps it, the S_a and Q_e it was made with, until the next update.
    const unsigned int n_elements = body.n_elements();
    const auto         contribution_of = [&](const unsigned int e, ElementMatrix &matrix) {
      matrix = current_contribution(e);
    };

    if (threshold == 0)
      {
        // Every element is updated: exact corotation, assembled and factored in full.
        stopwatch.restart();
        system.assemble(contribution_of);
        statistics.t_assembly += stopwatch.seconds();
        statistics.elements_updated = n_elements;
        record_updates(true);
        factorize(statistics);
        return;
      }
    if (std::isinf(threshold))
      {
        // Nothing is ever updated: stiffness warping.
        record_updates(false);
        return;
      }

    stopwatch.restart();
    const std::vector<unsigned int> update = elements_to_update(positions, velocities);
    statistics.t_error_estimate += stopwatch.seconds();
    record_updates(update);
    statistics.elements_updated = update.size();
    if (update.empty())
      return;

    stopwatch.restart();
    const std::vector<Index> changed_columns = system.reassemble(update, contribution_of);
    statistics.t_assembly += stopwatch.seconds();
    if (!changed_columns.empty())
      refactorize(changed_columns, statistics);
  }

  void WarpCancelingModel::add_elastic_forces(const std::vector<Vector3> &positions,
                                              std::vector<Vector3>       &forces) const
  {
    body.add_elastic_forces(positions, &element_rotations, forces);
  }
} // namespace warpchol::fem
