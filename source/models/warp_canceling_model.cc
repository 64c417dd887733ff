#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/models/warp_canceling_model.h>
#include <warpchol/models/model_type.h>

#include <deal.II/base/parallel.h>

#include <algorithm>
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

  ElementMatrix rerotated_contribution(const ElasticBody &body, const SystemCoefficients &coefficients,
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

  std::optional<SettingConflict> wcc_setting_conflict(const double rerotation_threshold, const double target_error,
                                                      const StepStrategy                 &strategy,
                                                      const cholesky::FactorizationMethod method)
  {
    using Rule = SettingConflict::Rule;
    using Kind = StepStrategy::Kind;
    if (!(rerotation_threshold >= 0))
      return SettingConflict{Rule::threshold_range, "Model", "Rerotation threshold", "must be a number >= 0 or inf"};
    if (!(target_error >= 0))
      return SettingConflict{Rule::target_range, "Model", "Target error", "must be >= 0"};
    if (target_error > 0 && (!(rerotation_threshold > 0) || std::isinf(rerotation_threshold)))
      return SettingConflict{Rule::target_needs_finite_threshold, "Model", "Target error",
                             "adapts the re-rotation threshold, which must then start finite and > 0 (Rerotation threshold = " +
                               format_number(rerotation_threshold) + ")"};
    if (target_error > 0 && strategy.iterates() && strategy.iterate_on == StepStrategy::Target::corotational)
      return SettingConflict{Rule::target_needs_wcc_system, "Model", "Target error",
                             "needs a step that solves the WCC system (Strategy = partial, or Iterate on = "
                             "warp_canceling): CG on the corotational matrix is exact to the CG tolerance"};
    if (strategy.kind == Kind::background && strategy.iterate_on != StepStrategy::Target::corotational)
      return SettingConflict{Rule::background_iterates_on_corotational, "Model", "Iterate on",
                             "must be corotational with Strategy = background: a refresh re-rotates every element, "
                             "which makes the WCC matrix the corotational one"};
    if ((strategy.kind == Kind::delayed_top || strategy.kind == Kind::automatic) &&
        method != cholesky::FactorizationMethod::supernodal)
      return SettingConflict{Rule::top_needs_supernodes, "Model", "Strategy",
                             "refreshes the factor below the top of its tree, which needs Solver/Method = supernodal (not " +
                               cholesky::to_string(method) + ")"};
    return std::nullopt;
  }

  WarpCancelingModel::WarpCancelingModel(const ElasticBody &body,
                                         const SystemCoefficients &coefficients,
                                         const cholesky::SparseCholesky::Settings &solver_settings,
                                         const double rerotation_threshold,
                                         const StepStrategy &step_strategy,
                                         const double        target_error,
                                         std::unique_ptr<backends::LinearSolver> peer)
    : ElasticityModel(body, coefficients, solver_settings, std::move(peer))
    , threshold(rerotation_threshold)
    , target_control(target_error, rerotation_threshold)
    , warp_frames(body.n_elements())
    , given_threads(std::max(1u, solver_settings.n_threads))
    , step_thread_count(given_threads)
  {
    strategy = step_strategy;
    if (const auto conflict = wcc_setting_conflict(rerotation_threshold, target_error, strategy, solver_settings.method))
      throw InputError(conflict->subsection + "/" + conflict->entry + ": " + conflict->message);
    measure_velocity_error = target_error > 0;
    // At rest every rotation is the identity: A is the rest matrix, assembled in these
    // frames (warp_frames at rest), as re-assembly will (a grasp's columns then change on
    // their diagonal only).
    set_up_rest_system();
    // That is also the exact corotational matrix at rest, factored: what the set-up spent
    // on it (all but the analysis) stands for an exact step's cost until one is measured,
    // so that auto's first step, whose factor is exact already, is not made exact again
    // (a full factorization for nothing: on a short run, a large share of it).
    // (Its flop rate is the solver's, which timed the factorization itself.)
    if (strategy.kind == StepStrategy::Kind::automatic)
      {
        const auto &factor_statistics = cholesky_solver.statistics();
        cost_model.record_setup(setup_seconds() - factor_statistics.analyze_seconds,
                                factor_statistics.factorize_seconds);
      }
    solve_frame = &elastic_state.nodal_rotations;
    // Estimates exist only between the two limits (0: all re-rotated, inf: none); at rest
    // they are 0. The background refresh estimates nothing.
    if (rerotation_threshold > 0 && !std::isinf(rerotation_threshold) && strategy.kind != StepStrategy::Kind::background)
      record.error_estimate.assign(body.n_elements(), 0.0);
    // The background refresh: asked for, or the automatic strategy's with a thread to spare.
    if (strategy.kind == StepStrategy::Kind::background ||
        (automatic_on_corotational() && solver_settings.n_threads > 1))
      background = std::make_unique<BackgroundRefresh>(body, coefficients, cholesky_solver);
  }

  std::string WarpCancelingModel::name() const
  {
    return to_string(ModelType::warp_canceling);
  }

  unsigned int WarpCancelingModel::step_threads() const
  {
    return background && background->in_flight() && given_threads > 1 ? given_threads - 1 : 0;
  }

  const RefreshPlacement &WarpCancelingModel::refresh_placement() const
  {
    return placement;
  }

  const ExactFallback &WarpCancelingModel::exact_fallback() const
  {
    return fallback;
  }

  bool WarpCancelingModel::refreshes_beside_the_steps() const
  {
    // While auto's steps run exact, no refresh beside them: each step makes the factor exact.
    return background && (strategy.kind == StepStrategy::Kind::background ||
                          (placement.current() == RefreshPlacement::Where::beside_the_steps && !fallback.runs_exact()));
  }

  double WarpCancelingModel::rerotation_threshold() const
  {
    return threshold;
  }

  double WarpCancelingModel::current_rerotation_threshold() const
  {
    return target_control.threshold();
  }

  double WarpCancelingModel::target_error() const
  {
    return target_control.target();
  }

  const std::string &WarpCancelingModel::target_note() const
  {
    return target_control.why_given_up();
  }

  ElasticityModel::StrategyReport WarpCancelingModel::strategy_report() const
  {
    StrategyReport report;
    report.has_strategy            = true;
    report.rerotation_threshold        = threshold;
    report.target_error            = target_control.target();
    report.target_note             = target_control.why_given_up();
    report.strategy                = strategy;
    report.steps_refreshing_beside = placement.steps_in(RefreshPlacement::Where::beside_the_steps);
    report.steps_refreshing_in     = placement.steps_in(RefreshPlacement::Where::in_the_steps);
    report.exact_fallback_steps    = fallback.exact_steps();
    report.fallbacks               = fallback.fallbacks();
    report.fallbacks_ended         = fallback.stretches_ended();
    return report;
  }

  void WarpCancelingModel::give_up_target()
  {
    strategy.kind          = StepStrategy::Kind::preconditioned;
    strategy.iterate_on    = StepStrategy::Target::corotational;
    measure_velocity_error = false;
    last_velocity_error    = -1;
  }

  const StepStrategy &WarpCancelingModel::step_strategy() const
  {
    return strategy;
  }

  std::vector<unsigned int>
  WarpCancelingModel::elements_to_rerotate(const std::vector<Vector3> &velocities)
  {
    const unsigned int  n_elements        = body.n_elements();
    const auto         &element_rotations = elastic_state.element_rotations;
    const auto         &nodal_rotations   = warp_frames.solve_rotations();
    std::vector<double> error(n_elements);
    std::vector<double> impulse(n_elements);
    // z_v = S_v^T v_v, the velocities in the solve's frames, once per vertex.
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
                                     element_rotations[e], warp_frames.of(e),
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
    std::vector<unsigned int> rerotate;
    for (unsigned int e = 0; e < n_elements; ++e)
      {
        // A body at rest has scale 0 and errors 0: no re-rotation (strict inequality).
        const double relative_error = scale > 0 ? error[e] / scale : 0.0;
        record.error_estimate[e]    = relative_error;
        if (error[e] > target_control.threshold() * scale || !std::isfinite(error[e]))
          rerotate.push_back(e);
      }
    return rerotate;
  }

  bool WarpCancelingModel::matrix_carries_over() const
  {
    return (threshold > 0 && !std::isinf(threshold)) || background;
  }

  ElementFrames WarpCancelingModel::contribution_frames() const
  {
    return warp_frames.element_frames();
  }

  void WarpCancelingModel::apply_change(const SystemChange &change, StepStatistics &statistics)
  {
    if (change.empty())
      return;
    if (background && background->in_flight())
      {
        StageTimer timer(statistics.stages, stage::background_refresh);
        const unsigned int started = background->started_step();
        checked([&]() { background->take(system, warp_frames, cholesky_solver); });
        history.factor_step = started;
      }
    ElasticityModel::apply_change(change, statistics);
    change_pending = true;
  }

  bool WarpCancelingModel::factor_solves_target() const
  {
    return exact_this_step && cholesky_solver.factor_is_exact();
  }

  bool WarpCancelingModel::refresh_after_failed_solve(StepStatistics &statistics)
  {
    history.solve_failed = true;
    // auto's CG stopped at an exact step's worth of iterations: the exact step now, not a
    // refresh of the stale columns first, after which CG would spend as much again.
    if (!cholesky_solver.factor_is_exact() && (exact_this_step || !automatic_on_corotational()))
      return ElasticityModel::refresh_after_failed_solve(statistics);
    if (exact_this_step)
      return false;
    exact_step(statistics);
    return true;
  }

  bool WarpCancelingModel::automatic_on_corotational() const
  {
    return strategy.kind == StepStrategy::Kind::automatic &&
           strategy.iterate_on == StepStrategy::Target::corotational;
  }

  unsigned int WarpCancelingModel::cg_iteration_limit() const
  {
    if (cg_bounded_by_exact_step())
      return std::min(strategy.max_cg_iterations, cost_model.affordable_iterations());
    return strategy.max_cg_iterations;
  }

  bool WarpCancelingModel::cg_gives_up_on_forecast() const
  {
    return cg_bounded_by_exact_step();
  }

  bool WarpCancelingModel::cg_bounded_by_exact_step() const
  {
    return automatic_on_corotational() && cost_model.affordable_iterations() > 0;
  }

  void WarpCancelingModel::save_model_state(BinaryWriter &writer) const
  {
    warp_frames.save(writer);
    write_object(writer, target_control);
    write_object(writer, history);
    cost_model.save(writer);
    placement.save(writer);
    fallback.save(writer);
    if (background)
      background->save(writer);
  }

  void WarpCancelingModel::load_model_state(BinaryReader &reader)
  {
    warp_frames.load(reader);
    read_object(reader, target_control);
    if (!target_control.why_given_up().empty())
      give_up_target();
    read_object(reader, history);
    cost_model.load(reader);
    placement.load(reader);
    fallback.load(reader);
    if (background)
      background->load(reader);
  }

  void WarpCancelingModel::rerotate_frames(const unsigned int e)
  {
    warp_frames.rerotate(e, body.element_vertices(e), elastic_state.element_rotations[e]);
  }

  void WarpCancelingModel::prepare_step(const std::vector<Vector3> &positions,
                                        const std::vector<Vector3> &velocities,
                                        StepStatistics             &statistics)
  {
    const Stopwatch whole_step;
    const bool      automatic = strategy.kind == StepStrategy::Kind::automatic;
    // What the last step measured calibrates the cost model, unless it ran beside a
    // refresh, on fewer threads than the steps in which the model's refreshes run, was
    // the exact path's (the fall-back's: below, as an exact step only) or failed its solve
    // and was made exact in it: the model foresees auto's own steps.
    const bool last_beside_refresh = step_thread_count < given_threads;
    const bool last_solve_failed   = history.solve_failed;
    const bool last_measures_own   = history.step_count > 0 && !history.last_step_fell_back && !last_solve_failed;
    history.solve_failed           = false;
    if (last_measures_own && !last_beside_refresh)
      {
        const double last_seconds = history.last_prepare_seconds + last_solve_seconds;
        if (history.last_step_exact)
          cost_model.record_exact_step(last_seconds, history.cycle_length);
        else if (!history.last_step_changed)
          cost_model.record_iterating_step(history.last_staleness, last_seconds, last_cg_iterations);
        else
          // A step that refreshed a cut's or a grasp's columns paid for that too: its
          // seconds would make exact steps look due in the middle of an incision. Its
          // iterations are the staleness's (the change is in the factor), and where a flap
          // swings away from the factor's rotations they tell that an exact step pays in
          // the incision's middle.
          cost_model.record_iterations_at(history.last_staleness, last_cg_iterations);
      }
    // A step of the fall-back is an exact step, measured as auto's own are (the element
    // pass aside): without it a model that the set-up's cold factorization made rate exact
    // steps dear would never run one of its own, however dear its iterating steps.
    if (history.step_count > 0 && history.last_step_fell_back && !last_beside_refresh)
      cost_model.record_exact_step(history.last_prepare_seconds + last_solve_seconds, 0);
    if (history.step_count > 0 && !history.last_step_fell_back)
      cost_model.record_own_step(history.last_step_exact);
    if (last_cg_iterations > 0 && !last_beside_refresh)
      cost_model.record_iterations(last_refresh, last_cg_iterations, last_cg_seconds);
    // auto with a refresh beside the steps: where its refreshes go is measured on whole
    // steps of its own.
    if (last_measures_own && background && automatic)
      placement.record_step(last_step_prepare_seconds + last_solve_seconds);
    // auto against the exact path, on whole steps too. Until an exact step of the
    // fall-back is measured, the smaller of the set-up's factorization (a part of one) and
    // auto's own exact steps (which do more) stands for one.
    const bool may_fall_back = automatic_on_corotational();
    if (history.step_count > 0 && may_fall_back)
      {
        const double factorization = cost_model.setup_factorization_seconds();
        const double own_exact     = cost_model.predicted_exact_seconds();
        fallback.set_exact_estimate(factorization > 0 && own_exact > 0 ? std::min(factorization, own_exact) :
                                                                          std::max(factorization, own_exact));
        fallback.record_step(last_step_prepare_seconds + last_solve_seconds,
                             last_solve_failed,
                             history.last_step_changed);
      }
    // The step runs on the threads the integrator gave it: so do the solver and the assembly.
    const unsigned int limited = step_threads();
    step_thread_count          = limited > 0 ? limited : given_threads;
    cholesky_solver.set_thread_count(step_thread_count);
    system.set_thread_count(step_thread_count);
    last_refresh = cholesky::Refresh::none;
    // The last step's error against exact corotation steers this step's threshold
    // (TargetErrorController), until no threshold holds the target with few re-rotations: the
    // steps then iterate on the exact corotational matrix instead (the preconditioned
    // strategy: the same updates and refactorizations, CG to its tolerance).
    if (target_control.steering() && last_velocity_error >= 0)
      {
        const double rerotated =
          static_cast<double>(std::count(record.rerotated.begin(), record.rerotated.end(), 1)) / body.n_elements();
        if (target_control.steer(history.step_count + 1, last_velocity_error, rerotated))
          give_up_target();
      }
    statistics.rerotation_threshold = target_control.threshold();
    ++history.step_count;
    exact_this_step = false;

    Stopwatch stopwatch;
    // The last exact step's element rotations, before this step's overwrite them.
    warp_frames.keep_rotations(elastic_state.element_rotations);
    history.last_step_fell_back = may_fall_back && fallback.runs_exact();
    double element_pass_seconds = 0;
    if (history.last_step_fell_back)
      {
        corotational_step(positions, statistics);
        element_pass_seconds = statistics.stages.seconds(stage::rotations);
      }
    else
      {
        evaluate_elastic_state(positions, ElasticBody::Rotations::elements_and_vertices, statistics);
        warp_frames.update_solve_rotations(body, elastic_state.nodal_rotations);
        record_no_refactorization(statistics);
        stopwatch.restart();
        prepare_factor(velocities, statistics);
      }
    // A y = S^T rhs with the solve rotations S (ContributionFrames); an exact step's S = I:
    // it solves in the world frame, as the exact path does.
    solve_frame = exact_this_step ? nullptr : &warp_frames.solve_rotations();
    history.last_step_changed = change_pending;
    change_pending    = false;
    history.last_prepare_seconds = stopwatch.seconds() - element_pass_seconds;
    // The cycle an exact step ends: how stale the factor had grown before it.
    history.cycle_length         = exact_this_step ? history.last_staleness : history.cycle_length;
    history.last_step_exact      = exact_this_step;
    history.last_staleness       = history.step_count - history.factor_step;
    if (background)
      statistics.factor_lag = static_cast<int>(history.last_staleness);
    last_step_prepare_seconds = whole_step.seconds();
  }

  void WarpCancelingModel::corotational_step(const std::vector<Vector3> &positions, StepStatistics &statistics)
  {
    // A refresh beside the steps that finished is taken only to be replaced: the next
    // one waits for auto's own steps.
    if (background)
      take_background_refresh(statistics);
    corotational_exact_step(positions, statistics);
    warp_frames.reset(elastic_state.element_rotations, nullptr);
    history.factor_step = history.step_count;
    exact_this_step     = true;
    statistics.choice                = StepChoice::fallback;
    statistics.predicted_seconds     = fallback.exact_step_seconds();
  }

  void WarpCancelingModel::exact_step(StepStatistics &statistics)
  {
    {
      StageTimer timer(statistics.stages, stage::assembly);
      // A in the elements' frames, of reference the nodal rotations of this step: the
      // exact path's assembly, with no frame per vertex to write.
      system.assemble(ElementFrames::rotated(elastic_state.element_rotations));
      warp_frames.reset(elastic_state.element_rotations, &elastic_state.nodal_rotations);
      // S = R P^T = I: the exact path's solve, in the world frame.
      solve_frame = nullptr;
    }
    statistics.elements_rerotated = body.n_elements();
    record_rerotations(true);
    factorize(statistics);
    history.factor_step = history.step_count;
    exact_this_step     = true;
  }

  void WarpCancelingModel::prepare_factor(const std::vector<Vector3> &velocities, StepStatistics &statistics)
  {
    const bool automatic = strategy.kind == StepStrategy::Kind::automatic;
    if (background)
      {
        const bool took = take_background_refresh(statistics);
        if (strategy.kind == StepStrategy::Kind::background)
          {
            statistics.choice = took ? StepChoice::background : StepChoice::refresh_none;
            if (!took)
              record_rerotations(false);
            return;
          }
        if (took)
          {
            // A factor exact for the rotations of a few steps ago: iterate on it.
            statistics.choice            = StepChoice::background;
            statistics.predicted_seconds = cost_model.predicted_iterating_seconds(history.step_count - history.factor_step);
            return;
          }
      }

    if (threshold == 0)
      {
        // Every element is re-rotated: exact corotation, assembled and factored in full.
        exact_step(statistics);
        return;
      }
    // Exact steps change A to the corotational matrix: only where CG iterates on that one
    // (on the WCC matrix they would change the system being solved).
    const unsigned int staleness = history.step_count - history.factor_step;
    // With the refreshes beside the steps the factor is made exact there, never here.
    const unsigned int steps_left = run_length >= history.step_count ? run_length - history.step_count + 1 : 0;
    if (automatic_on_corotational() && !refreshes_beside_the_steps() &&
        cost_model.exact_step_is_due(staleness, steps_left))
      {
        // Iterating on would cost more than the least average of a cycle that starts now.
        statistics.choice            = StepChoice::exact;
        statistics.predicted_seconds = cost_model.predicted_exact_seconds();
        exact_step(statistics);
        return;
      }
    if (automatic)
      statistics.predicted_seconds = cost_model.predicted_iterating_seconds(staleness);
    // Nothing is ever re-rotated at an infinite threshold: stiffness warping, or the automatic
    // strategy's factor between its exact steps; only changes of the system (a cut, a
    // grasp) may be pending.
    std::vector<unsigned int> rerotate;
    if (!std::isinf(threshold))
      {
        StageTimer estimate_timer(statistics.stages, stage::error_estimate);
        rerotate = elements_to_rerotate(velocities);
      }
    record_rerotations(rerotate);
    statistics.elements_rerotated = rerotate.size();

    std::vector<Index> changed_columns;
    if (!rerotate.empty())
      {
        StageTimer timer(statistics.stages, stage::assembly);
        for (const unsigned int e : rerotate)
          rerotate_frames(e);
        changed_columns = system.reassemble(rerotate, warp_frames.element_frames());
      }
    // Nothing changed and nothing is left stale: the factor is that of A.
    if (changed_columns.empty() && factor_is_exact())
      {
        statistics.choice = automatic ? StepChoice::refresh_none : StepChoice::not_chosen;
        return;
      }
    const cholesky::Refresh refresh = choose_refresh(changed_columns, statistics);
    if (automatic)
      statistics.choice = iterating_choice(refresh);
    refactorize(changed_columns, statistics, refresh);
  }

  bool WarpCancelingModel::take_background_refresh(StepStatistics &statistics)
  {
    StageTimer timer(statistics.stages, stage::background_refresh);
    // Deterministic (lag N > 0): the refresh of step k at step k + N, waiting if need be.
    // Otherwise the one that has finished, if any.
    const unsigned int lag = strategy.kind == StepStrategy::Kind::background ? strategy.background_lag : 0;
    const bool due = background->in_flight() &&
                     (lag > 0 ? history.step_count - background->started_step() >= lag : background->done());
    if (due)
      {
        const unsigned int started = background->started_step();
        checked([&]() { background->take(system, warp_frames, cholesky_solver); });
        history.factor_step = started;
        last_refresh        = cholesky::Refresh::all;
        statistics.refresh = "background";
        record_rerotations(true);
        statistics.elements_rerotated = body.n_elements();
      }
    if (!background->in_flight() && refreshes_beside_the_steps())
      background->start(history.step_count, elastic_state.element_rotations, elastic_state.nodal_rotations);
    return due;
  }

  cholesky::Refresh WarpCancelingModel::choose_refresh(const std::vector<Index> &changed_columns,
                                                       StepStatistics           &statistics)
  {
    using cholesky::Refresh;
    switch (strategy.kind)
      {
        case StepStrategy::Kind::partial:
        case StepStrategy::Kind::preconditioned:
        case StepStrategy::Kind::background:
          return Refresh::all;
        case StepStrategy::Kind::delayed_top:
          // The top when it is due, or when the last solve showed the factor has become a
          // poor preconditioner (the change the top has accumulated, measured by its effect).
          if (++history.steps_since_top_refresh >= strategy.refresh_interval ||
              last_cg_iterations > strategy.refresh_iterations)
            {
              history.steps_since_top_refresh = 0;
              return Refresh::all;
            }
          return Refresh::below_top;
        case StepStrategy::Kind::automatic:
          {
            if (!cost_model.calibrated(cholesky_solver.cost_model()))
              return Refresh::all;
            // Predicting the cost of each refresh walks the elimination tree three times.
            StageTimer timer(statistics.stages, stage::refresh_choice);
            Refresh cheapest      = Refresh::all;
            double  least_seconds = std::numeric_limits<double>::infinity();
            // Where the exact factor can take the step's changes as an update, refreshing
            // below the top would give that up: the top left stale blocks every later
            // update until a recomputation of the top (most of a factorization's flops)
            // makes the factor exact again, a cost a single step's prediction cannot see.
            cholesky::RefactorizationMethod all_method = cholesky::RefactorizationMethod::none;
            const double all_seconds = cholesky_solver.predicted_seconds(changed_columns, Refresh::all, &all_method);
            for (const Refresh refresh : {Refresh::all, Refresh::below_top, Refresh::none})
              {
                // A change of the system (a cut) left out of the factor makes CG iterate
                // far more than the last steps foretell: it is refreshed, at least below
                // the top, in the step it comes.
                if (refresh == Refresh::none && change_pending)
                  continue;
                if (refresh == Refresh::below_top && all_method == cholesky::RefactorizationMethod::update)
                  continue;
                const double seconds = cost_model.predicted_seconds(
                  refresh, refresh == Refresh::all ? all_seconds : cholesky_solver.predicted_seconds(changed_columns, refresh));
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
