#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/fem/warp_canceling_model.h>

#include <deal.II/base/parallel.h>

#include <cmath>
#include <limits>

namespace warpchol::fem
{
  ElementErrorEstimate estimate_element_error(const ElasticBody &body, const SystemCoefficients &coefficients,
                                              const unsigned int e, const std::vector<Vector3> &velocities,
                                              const std::vector<Vector3> &nodal_velocities,
                                              const std::vector<Matrix3> &nodal_rotations,
                                              const Matrix3 &element_rotation,
                                              const std::array<Matrix3, 4> &frames, const double force_norm)
  {
    const bool     lumped   = body.mass_matrix_type() == MassMatrix::lumped;
    const auto    &vertices = body.element_vertices(e);
    const Matrix3 &rotation = element_rotation;
    const auto    &mass     = body.element_mass(e);
    // Exact, in the world frame: c_K R_e K_e R_e^T v_e (+ c_M M_e v_e).
    const Matrix3 exact_stiffness =
      coefficients.stiffness *
      (rotation * body.stiffness_forces(e, rotation.transpose() * body.field_gradient(e, velocities)));
    // Stored, in the nodal frames: c_K T_a K_e T_b^T z_b; the gradient of
    // y_b = T_b^T z_b is [y1-y0, y2-y0, y3-y0] Dm^-1.
    std::array<Vector3, 4> y;
    for (unsigned int b = 0; b < 4; ++b)
      y[b] = frames[b].transpose() * nodal_velocities[vertices[b]];
    const Matrix3 stored_stiffness =
      coefficients.stiffness * body.stiffness_forces(e, body.field_gradient(e, y));

    double error_squared = 0, exact_squared = 0;
    for (unsigned int a = 0; a < 4; ++a)
      {
        const Vector3 world_stiffness =
          a == 0 ? Vector3(-exact_stiffness.rowwise().sum()) : Vector3(exact_stiffness.col(a - 1));
        const Vector3 local_stiffness =
          a == 0 ? Vector3(-stored_stiffness.rowwise().sum()) : Vector3(stored_stiffness.col(a - 1));
        const Matrix3 &nodal = nodal_rotations[vertices[a]];
        if (lumped)
          {
            // A lumped mass is the same in every frame: its parts cancel exactly in
            // the difference, and the norm of the exact part needs no rotation.
            exact_squared +=
              (world_stiffness + (coefficients.mass * mass(a, a)) * velocities[vertices[a]]).squaredNorm();
            error_squared += (nodal.transpose() * world_stiffness - frames[a] * local_stiffness).squaredNorm();
            continue;
          }
        Vector3 world_mass  = Vector3::Zero();
        Vector3 stored_mass = Vector3::Zero();
        for (unsigned int b = 0; b < 4; ++b)
          {
            world_mass += (coefficients.mass * mass(a, b)) * velocities[vertices[b]];
            stored_mass += (coefficients.mass * mass(a, b)) * y[b];
          }
        const Vector3 exact = nodal.transpose() * (world_stiffness + world_mass);
        exact_squared += exact.squaredNorm();
        error_squared += (exact - frames[a] * (local_stiffness + stored_mass)).squaredNorm();
      }
    return {std::sqrt(error_squared), std::sqrt(exact_squared) + coefficients.time_step * force_norm};
  }

  ElementMatrix updated_contribution(const ElasticBody &body, const SystemCoefficients &coefficients,
                                     const unsigned int e, const std::vector<Matrix3> &nodal_rotations,
                                     const Matrix3 &element_rotation, std::array<Matrix3, 4> &frames)
  {
    const auto            &vertices = body.element_vertices(e);
    std::array<Matrix3, 4> vertex_rotations;
    for (unsigned int a = 0; a < 4; ++a)
      {
        vertex_rotations[a] = nodal_rotations[vertices[a]];
        // What the contribution is made with, as warped_element_matrix() forms it.
        frames[a] = vertex_rotations[a].transpose() * element_rotation;
      }
    return warped_element_matrix(body, e, coefficients, vertex_rotations, element_rotation);
  }

  WarpCancelingModel::WarpCancelingModel(const ElasticBody &body,
                                         const SystemCoefficients &coefficients,
                                         const cholesky::SparseCholesky::Settings &solver_settings,
                                         const double update_threshold,
                                         const StepStrategy &step_strategy,
                                         const double        target_error,
                                         std::unique_ptr<backends::LinearSolver> peer)
    : ElasticityModel(body, coefficients, solver_settings, std::move(peer))
    , threshold(update_threshold)
    , target(target_error)
    , adapted_threshold(update_threshold)
  {
    strategy = step_strategy;
    if (strategy.kind == StepStrategy::Kind::delayed_top || strategy.kind == StepStrategy::Kind::automatic)
      if (solver_settings.method != cholesky::FactorizationMethod::supernodal)
        throw InputError("the step strategy " + to_string(strategy.kind) +
                         " needs the supernodal method (Solver/Method = supernodal)");
    if (!(update_threshold >= 0))
      throw InputError("the WCC update threshold must be >= 0 (or inf), got " +
                       format_number(update_threshold));
    if (!(target_error >= 0))
      throw InputError("the WCC target error must be >= 0, got " + format_number(target_error));
    if (target_error > 0)
      {
        if (!(update_threshold > 0) || std::isinf(update_threshold))
          throw InputError("a WCC target error adapts the update threshold, which must then "
                           "start finite and > 0, got " + format_number(update_threshold));
        if (strategy.iterates() && strategy.iterate_on == StepStrategy::Target::corotational)
          throw InputError("a WCC target error needs a step that solves the WCC system "
                           "(Strategy = partial, or Iterate on = warp_canceling): CG on the "
                           "corotational matrix is already exact to the CG tolerance");
        measure_velocity_error = true;
      }
    // At rest every rotation is the identity: A is the rest matrix.
    set_up_rest_system();
    solve_frame = &elastic_state.nodal_rotations;
    // At rest every frame is the identity.
    stored_frames.assign(body.n_elements(), {{Matrix3::Identity(), Matrix3::Identity(),
                                               Matrix3::Identity(), Matrix3::Identity()}});
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

  double WarpCancelingModel::current_update_threshold() const
  {
    return adapted_threshold;
  }

  double WarpCancelingModel::target_error() const
  {
    return target;
  }

  const StepStrategy &WarpCancelingModel::step_strategy() const
  {
    return strategy;
  }

  std::vector<unsigned int>
  WarpCancelingModel::elements_to_update(const std::vector<Vector3> &velocities)
  {
    const unsigned int  n_elements        = body.n_elements();
    const auto         &element_rotations = elastic_state.element_rotations;
    const auto         &nodal_rotations   = elastic_state.nodal_rotations;
    std::vector<double> error(n_elements);
    std::vector<double> impulse(n_elements);
    // z_v = R_v^T v_v, the velocities in the nodal frames, once per vertex.
    nodal_velocities.resize(body.n_vertices());
    dealii::parallel::apply_to_subranges(
      0u, body.n_vertices(),
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int v = begin; v < end; ++v)
          nodal_velocities[v] = nodal_rotations[v].transpose() * velocities[v];
      },
      1024);
    // Independent per element (threads as deal.II's MultithreadInfo allows); the sum of
    // the impulses follows, in element order, so the result does not depend on threads.
    // Everything is matrix-free: the stiffness K_e is applied through the strain of a
    // gradient (ElasticBody::stiffness_forces), the stored contribution through the
    // frames T_a = S_a^T Q_e it was made with.
    dealii::parallel::apply_to_subranges(
      0u, n_elements,
      [&](const unsigned int begin, const unsigned int end) {
        for (unsigned int e = begin; e < end; ++e)
          {
            const ElementErrorEstimate estimate =
              estimate_element_error(body, coefficients, e, velocities, nodal_velocities, nodal_rotations,
                                     element_rotations[e], stored_frames[e],
                                     elastic_state.element_force_norms[e]);
            error[e]   = estimate.error;
            impulse[e] = estimate.impulse;
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
        if (error[e] > adapted_threshold * scale || !std::isfinite(error[e]))
          update.push_back(e);
      }
    return update;
  }

  bool WarpCancelingModel::matrix_carries_over() const
  {
    return threshold > 0 && !std::isinf(threshold);
  }

  void WarpCancelingModel::save_model_state(BinaryWriter &writer) const
  {
    writer.write(stored_frames);
    writer.write(adapted_threshold);
    writer.write(steps_since_top_refresh);
    cost_model.save(writer);
  }

  void WarpCancelingModel::load_model_state(BinaryReader &reader)
  {
    const std::size_t n_frames = stored_frames.size();
    reader.read(stored_frames);
    if (stored_frames.size() != n_frames)
      reader.fail("holds the frames of " + std::to_string(stored_frames.size()) +
                  " elements, the model keeps " + std::to_string(n_frames));
    reader.read(adapted_threshold);
    reader.read(steps_since_top_refresh);
    cost_model.load(reader);
  }

  ElementMatrix WarpCancelingModel::current_contribution(const unsigned int e)
  {
    return updated_contribution(body, coefficients, e, elastic_state.nodal_rotations, elastic_state.element_rotations[e],
                                stored_frames[e]);
  }

  void WarpCancelingModel::prepare_step(const std::vector<Vector3> &positions,
                                        const std::vector<Vector3> &velocities,
                                        StepStatistics             &statistics)
  {
    // What the last step's solve measured calibrates the cost model.
    if (last_cg_iterations > 0)
      cost_model.record_iterations(last_refresh, last_cg_iterations, last_cg_seconds);
    last_refresh = cholesky::Refresh::none;
    if (target > 0 && last_velocity_error >= 0)
      {
        // The last step's error against exact corotation steers this step's threshold
        // (in logarithms, a gain of 0.7 on an error that grows like the threshold to a
        // power of 0.6 to 1.1). It falls fast (to 1/8 per step) and rises slowly (2x), and
        // stays below 100, above which hardly an element is ever updated: a body that
        // rested (error 0, the threshold rising) and moves again is caught within steps.
        const double goal   = target / 2;
        const double factor = last_velocity_error > 0 ?
                                std::clamp(std::pow(goal / last_velocity_error, 0.7), 0.125, 2.0) :
                                2.0;
        adapted_threshold = std::clamp(adapted_threshold * factor, 1e-6, 100.0);
      }
    statistics.update_threshold = adapted_threshold;

    evaluate_elastic_state(positions, ElasticBody::Rotations::elements_and_vertices, statistics);
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
        {
          StageTimer timer(statistics.stages, stage::assembly);
          system.assemble(contribution_of);
        }
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

    StageTimer estimate_timer(statistics.stages, stage::error_estimate);
    const std::vector<unsigned int> update = elements_to_update(velocities);
    estimate_timer.stop();
    record_updates(update);
    statistics.elements_updated = update.size();

    std::vector<Index> changed_columns;
    if (!update.empty())
      {
        StageTimer timer(statistics.stages, stage::assembly);
        changed_columns = system.reassemble(update, contribution_of);
      }
    // Nothing changed and nothing is left stale: the factor is that of A.
    if (changed_columns.empty() && factor_is_exact())
      return;
    const cholesky::Refresh refresh = choose_refresh(changed_columns, statistics);
    refactorize(changed_columns, statistics, refresh);
    cost_model.record_factorization(statistics.flops_recomputed, statistics.t_factor());
  }

  cholesky::Refresh WarpCancelingModel::choose_refresh(const std::vector<Index> &changed_columns,
                                                       StepStatistics           &statistics)
  {
    using cholesky::Refresh;
    switch (strategy.kind)
      {
        case StepStrategy::Kind::partial:
        case StepStrategy::Kind::preconditioned:
          return Refresh::all;
        case StepStrategy::Kind::delayed_top:
          // The top when it is due, or when the last solve showed the factor has become a
          // poor preconditioner (the change the top has accumulated, measured by its effect).
          if (++steps_since_top_refresh >= strategy.refresh_interval ||
              last_cg_iterations > strategy.refresh_iterations)
            {
              steps_since_top_refresh = 0;
              return Refresh::all;
            }
          return Refresh::below_top;
        case StepStrategy::Kind::automatic:
          {
            if (!cost_model.calibrated())
              return Refresh::all;
            // Predicting the flops of each refresh walks the elimination tree three times.
            StageTimer timer(statistics.stages, stage::refresh_choice);
            Refresh cheapest      = Refresh::all;
            double  least_seconds = std::numeric_limits<double>::infinity();
            for (const Refresh refresh : {Refresh::all, Refresh::below_top, Refresh::none})
              {
                const double seconds = cost_model.predicted_seconds(
                  refresh, cholesky_solver.predicted_flops(changed_columns, refresh));
                if (seconds < least_seconds)
                  {
                    least_seconds = seconds;
                    cheapest      = refresh;
                  }
              }
            return cheapest;
          }
      }
    return Refresh::all;
  }

} // namespace warpchol::fem
