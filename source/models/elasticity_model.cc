#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/models/elasticity_model.h>
#include <warpchol/models/forecast_solver_control.h>
#include <warpchol/models/model_type.h>

#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/vector.h>

#include <algorithm>
#include <cmath>

namespace warpchol::fem
{
  double StepStatistics::t_rotations() const
  {
    return stages.seconds(stage::rotations) + stages.seconds(stage::elastic_forces);
  }

  double StepStatistics::t_error_estimate() const
  {
    return stages.seconds(stage::error_estimate);
  }

  double StepStatistics::t_assembly() const
  {
    return stages.seconds(stage::assembly);
  }

  double StepStatistics::t_factor() const
  {
    return stages.seconds(stage::factorization);
  }

  double StepStatistics::t_solve() const
  {
    return stages.seconds(stage::solve);
  }

  double StepStatistics::t_iterations() const
  {
    return stages.seconds(stage::cg_iterations);
  }

  bool SystemChange::empty() const
  {
    return elements.empty() && vertices.empty();
  }

  double StepStatistics::strategy_seconds() const
  {
    double seconds = 0;
    for (const char *name : {stage::change, stage::error_estimate, stage::assembly, stage::refresh_choice, stage::factorization,
                             stage::background_refresh, stage::solve, stage::cg_iterations})
      seconds += stages.seconds(name);
    return seconds;
  }

  ElasticityModel::StrategyReport ElasticityModel::strategy_report() const
  {
    return {};
  }

  std::string to_string(const StepChoice choice)
  {
    return name_of(step_choice_names, choice);
  }

  StepChoice iterating_choice(const cholesky::Refresh refresh)
  {
    switch (refresh)
      {
        case cholesky::Refresh::all:
          return StepChoice::refresh_all;
        case cholesky::Refresh::below_top:
          return StepChoice::refresh_below_top;
        default:
          return StepChoice::refresh_none;
      }
  }

  void StepStatistics::add_phase_times(const StepStatistics &step)
  {
    stages.add(step.stages);
  }

  ElasticityModel::ElasticityModel(const ElasticBody &body, const SystemCoefficients &coefficients,
                                   const cholesky::SparseCholesky::Settings &solver_settings,
                                   std::unique_ptr<backends::LinearSolver>   peer)
    : body(body)
    , coefficients(coefficients)
    , system(body, coefficients)
    , cholesky_solver(solver_settings)
    , peer_solver(std::move(peer))
  {
    if (body.n_unknowns() == 0)
      throw InputError("every vertex is fixed: nothing to simulate");
    record.rerotated.assign(body.n_elements(), 0);
    record.steps_since_rerotation.assign(body.n_elements(), 0);
  }

  void ElasticityModel::add_elastic_forces(const std::vector<Vector3> &,
                                           std::vector<Vector3> &forces) const
  {
    for (std::size_t v = 0; v < forces.size(); ++v)
      forces[v] += elastic_state.forces[v];
  }

  void ElasticityModel::evaluate_elastic_state(const std::vector<Vector3> &positions,
                                               const ElasticBody::Rotations rotations,
                                               StepStatistics             &statistics)
  {
    StageTimer timer(statistics.stages, rotations == ElasticBody::Rotations::none ? stage::elastic_forces :
                                                                                      stage::rotations);
    body.evaluate(positions, rotations, elastic_state);
    statistics.rotation_paths += elastic_state.rotation_paths;
  }

  bool ElasticityModel::solves_iteratively() const
  {
    // A step whose factor is that of the target matrix solves directly (WCC's exact steps).
    return peer_solver ? peer_solver->is_iterative() : strategy.iterates() && !factor_solves_target();
  }

  bool ElasticityModel::uses_rotations() const
  {
    return true;
  }

  unsigned int ElasticityModel::step_threads() const
  {
    return 0;
  }

  void ElasticityModel::checked(const std::function<void()> &factor)
  {
    try
      {
        factor();
      }
    catch (const NotPositiveDefinite &failure)
      {
        const unsigned int vertex = body.vertex_of_unknown(failure.column);
        throw MatrixError("the Cholesky factorization failed at column " +
                          std::to_string(failure.column) + " (vertex " + std::to_string(vertex) +
                          ", component " + "xyz"[failure.column % 3] +
                          "): pivot " + format_number(failure.pivot) +
                          ", the system matrix is not positive definite");
      }
  }

  void ElasticityModel::set_up_rest_system()
  {
    Stopwatch stopwatch;
    system.assemble(contribution_frames());
    StepStatistics setup;
    factorize(setup);
    setup_time = stopwatch.seconds();
  }

  const backends::LinearSolver *ElasticityModel::linear_solver() const
  {
    return peer_solver.get();
  }

  std::size_t ElasticityModel::factor_memory_bytes() const
  {
    return peer_solver ? peer_solver->memory_bytes() : cholesky_solver.statistics().factor_bytes;
  }

  void ElasticityModel::save_state(BinaryWriter &writer) const
  {
    writer.section("model " + name());
    // The vertex diagonal changes with grasps (apply_change()).
    writer.write(coefficients.vertex_diagonal);
    writer.write(matrix_carries_over());
    if (matrix_carries_over())
      {
        system.save(writer);
        // A peer's factor is that of A, factored again on loading; warpchol's may be partly
        // refreshed, the factor of no matrix: its values are written.
        if (!peer_solver)
          cholesky_solver.save_numeric(writer);
      }
    writer.write(record.rerotated);
    writer.write(record.steps_since_rerotation);
    writer.write(record.error_estimate);
    writer.write(last_cg_iterations);
    writer.write(last_cg_seconds);
    writer.write(last_velocity_error);
    writer.write(last_refresh);
    save_model_state(writer);
  }

  void ElasticityModel::load_state(BinaryReader &reader)
  {
    reader.expect_section("model " + name());
    reader.read(coefficients.vertex_diagonal);
    if (!coefficients.vertex_diagonal.empty() && coefficients.vertex_diagonal.size() != body.n_vertices())
      reader.fail("the vertex diagonal does not have one value per vertex");
    for (std::size_t v = 0; v < coefficients.vertex_diagonal.size(); ++v)
      system.set_vertex_diagonal(v, coefficients.vertex_diagonal[v]);
    if (reader.get<bool>() != matrix_carries_over())
      reader.fail("was written by a model whose matrix carries over differently");
    if (matrix_carries_over())
      {
        system.load(reader);
        if (peer_solver)
          checked([&]() { peer_solver->factorize(system.matrix(), system.csc()); });
        else
          cholesky_solver.load_numeric(reader);
      }
    reader.read(record.rerotated);
    reader.read(record.steps_since_rerotation);
    reader.read(record.error_estimate);
    const std::size_t n_elements = body.n_elements();
    if (record.rerotated.size() != n_elements || record.steps_since_rerotation.size() != n_elements ||
        (!record.error_estimate.empty() && record.error_estimate.size() != n_elements))
      reader.fail("the update record does not have one entry per element (" +
                  std::to_string(n_elements) + ")");
    reader.read(last_cg_iterations);
    reader.read(last_cg_seconds);
    reader.read(last_velocity_error);
    reader.read(last_refresh);
    if (last_refresh != cholesky::Refresh::all && last_refresh != cholesky::Refresh::below_top &&
        last_refresh != cholesky::Refresh::none)
      reader.fail("the last refresh is not one of all, below_top, none (corrupt)");
    load_model_state(reader);
  }

  bool ElasticityModel::matrix_carries_over() const
  {
    return false;
  }

  bool ElasticityModel::refresh_after_failed_solve(StepStatistics &statistics)
  {
    if (cholesky_solver.factor_is_exact())
      return false;
    refactorize({}, statistics, cholesky::Refresh::all);
    return true;
  }

  unsigned int ElasticityModel::cg_iteration_limit() const
  {
    return strategy.max_cg_iterations;
  }

  bool ElasticityModel::cg_gives_up_on_forecast() const
  {
    return false;
  }

  ElementFrames ElasticityModel::contribution_frames() const
  {
    return ElementFrames::rest();
  }

  bool ElasticityModel::assembles_every_step() const
  {
    return false;
  }

  double ElasticityModel::vertex_diagonal(const unsigned int vertex) const
  {
    return coefficients.vertex_diagonal.empty() ? 0. : coefficients.vertex_diagonal[vertex];
  }

  void ElasticityModel::apply_change(const SystemChange &change, StepStatistics &statistics)
  {
    load_change(change, false, statistics);
  }

  void ElasticityModel::change_within_step(const SystemChange &change, StepStatistics &statistics)
  {
    load_change(change, true, statistics);
  }

  void ElasticityModel::load_change(const SystemChange &change, const bool within_step, StepStatistics &statistics)
  {
    if (change.empty())
      return;
    StageTimer timer(statistics.stages, stage::change);
    if (change.vertex_diagonal.size() != change.vertices.size())
      throw Error("apply_change(): one diagonal value per vertex is needed");
    if (coefficients.vertex_diagonal.empty())
      coefficients.vertex_diagonal.assign(body.n_vertices(), 0.);
    for (std::size_t k = 0; k < change.vertices.size(); ++k)
      {
        coefficients.vertex_diagonal[change.vertices[k]] = change.vertex_diagonal[k];
        system.set_vertex_diagonal(change.vertices[k], change.vertex_diagonal[k]);
      }
    std::vector<unsigned int> vertices = change.vertices;
    for (const unsigned int e : change.elements)
      for (const unsigned int v : body.element_vertices(e))
        vertices.push_back(v);
    // The columns the change touches; a model that assembles all of A in its next step
    // only needs them counted.
    std::vector<Index> columns;
    for (const unsigned int v : vertices)
      if (body.first_unknown(v) >= 0)
        for (Index c = 0; c < 3; ++c)
          columns.push_back(body.first_unknown(v) + c);
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    statistics.change_columns += static_cast<Index>(columns.size());
    if (peer_solver)
      {
        if (change.topology)
          peer_solver->topology_changed();
        if (within_step || !assembles_every_step())
          {
            system.reassemble_vertices(vertices, contribution_frames());
            peer_factor_stale = true;
          }
        return;
      }
    statistics.change_flops += cholesky_solver.predicted_flops(columns, cholesky::Refresh::all);
    if (!within_step && assembles_every_step())
      return;
    system.reassemble_vertices(vertices, contribution_frames());
    refactorize_solver(columns, cholesky::Refresh::none);
  }

  bool ElasticityModel::factor_solves_target() const
  {
    return false;
  }

  void ElasticityModel::save_model_state(BinaryWriter &) const
  {}

  void ElasticityModel::load_model_state(BinaryReader &)
  {}

  void ElasticityModel::corotational_exact_step(const std::vector<Vector3> &positions, StepStatistics &statistics)
  {
    evaluate_elastic_state(positions, rotations_of(ModelType::corotational), statistics);
    {
      StageTimer timer(statistics.stages, stage::assembly);
      system.assemble(ElementFrames::rotated(elastic_state.element_rotations));
    }
    statistics.elements_rerotated = body.n_elements();
    record_rerotations(true);
    factorize(statistics);
  }

  void ElasticityModel::factorize(StepStatistics &statistics)
  {
    StageTimer timer(statistics.stages, stage::factorization);
    if (peer_solver)
      {
        factorize_with_peer(statistics);
        return;
      }
    checked([&]() {
      if (cholesky_solver.statistics().n == 0)
        cholesky_solver.analyze(system.lower());
      cholesky_solver.factorize(system.lower());
      whole_changes_read = system.n_whole_changes();
    });
    statistics.refresh = "full";
    last_refresh       = cholesky::Refresh::all;
    record_refactorization(statistics);
  }

  void ElasticityModel::refactorize(const std::vector<Index> &changed_columns,
                                    StepStatistics &statistics, const cholesky::Refresh refresh)
  {
    StageTimer timer(statistics.stages, stage::factorization);
    if (peer_solver)
      {
        // The peers have no partial refactorization: in full.
        factorize_with_peer(statistics);
        return;
      }
    refactorize_solver(changed_columns, refresh);
    statistics.refresh = to_string(refresh);
    last_refresh       = refresh;
    record_refactorization(statistics);
  }

  void ElasticityModel::refactorize_solver(const std::vector<Index> &changed_columns, const cholesky::Refresh refresh)
  {
    checked([&]() {
      const cholesky::ChangeListing listing = system.n_whole_changes() == whole_changes_read ?
                                                cholesky::ChangeListing::complete :
                                                cholesky::ChangeListing::searched;
      cholesky_solver.refactorize(system.lower(), changed_columns, refresh, listing);
      whole_changes_read = system.n_whole_changes();
    });
  }

  bool ElasticityModel::factor_is_exact() const
  {
    // A peer factors A in full whenever it changed.
    return peer_solver || cholesky_solver.factor_is_exact();
  }

  void ElasticityModel::factorize_with_peer(StepStatistics &statistics)
  {
    peer_factor_stale = false;
    // warpchol's solver analyzes A only: the flops of a full factorization, the unit of the
    // statistics, without a numeric factor beside the peer's.
    if (cholesky_solver.statistics().n == 0)
      cholesky_solver.analyze(system.csc());
    checked([&]() { peer_solver->factorize(system.matrix(), system.csc()); });
    statistics.refresh            = "full";
    statistics.refactorized       = true;
    statistics.columns_recomputed = body.n_unknowns();
    record_no_refactorization(statistics);
    // warpchol's count of a full factorization's flops: the peers' own counts differ.
    statistics.flops_recomputed = statistics.flops_full;
  }

  void ElasticityModel::record_refactorization(StepStatistics &statistics) const
  {
    // After a full factorization the solver reports every column and the full flops.
    const auto &solver_statistics = cholesky_solver.statistics();
    statistics.refactorized       = true;
    statistics.columns_recomputed = solver_statistics.columns_recomputed;
    statistics.flops_recomputed   = solver_statistics.flops_recomputed;
    // The last factorization of the step is the one that counts, with what it weighed.
    statistics.factorization = solver_statistics;
    record_no_refactorization(statistics);
  }

  void ElasticityModel::record_no_refactorization(StepStatistics &statistics) const
  {
    statistics.n_columns  = body.n_unknowns();
    statistics.flops_full = cholesky_solver.statistics().flops;
  }

  void ElasticityModel::solve(const std::vector<Vector3> &right_hand_side,
                              std::vector<Vector3> &velocities, StepStatistics &statistics)
  {
    const Stopwatch stopwatch;
    solve_in_frame(right_hand_side, velocities, statistics);
    last_solve_seconds = stopwatch.seconds();
  }

  void ElasticityModel::set_run_length(const unsigned int steps)
  {
    run_length = steps;
  }

  void ElasticityModel::solve_again(const std::vector<Vector3> &right_hand_side,
                                    std::vector<Vector3> &velocities, StepStatistics &statistics)
  {
    const unsigned int iterations = last_cg_iterations;
    const double       cg_seconds = last_cg_seconds, solve_seconds = last_solve_seconds;
    solve(right_hand_side, velocities, statistics);
    last_cg_iterations += iterations;
    last_cg_seconds += cg_seconds;
    last_solve_seconds += solve_seconds;
  }

  void ElasticityModel::solve_in_frame(const std::vector<Vector3> &right_hand_side,
                                       std::vector<Vector3> &velocities, StepStatistics &statistics)
  {
    // A y = R^T rhs, then v = R y: the nodal rotations stand for the updates A lacks.
    std::vector<double> rotated(body.n_unknowns());
    to_solve_frame(right_hand_side, rotated.data());
    // The initial guess of CG: the velocities given on entry, in the solve frame.
    std::vector<double> solution(body.n_unknowns(), 0.);
    if (solves_iteratively() && velocities.size() == body.n_vertices())
      to_solve_frame(velocities, solution.data());
    last_cg_iterations = 0;
    last_cg_seconds    = 0;
    if (peer_solver)
      {
        // A change since the peer's last factorization: it factors A again first.
        if (peer_factor_stale)
          {
            StageTimer timer(statistics.stages, stage::factorization);
            factorize_with_peer(statistics);
          }
        // An iterating peer's iterations and preconditioner all count as its solve.
        StageTimer timer(statistics.stages, stage::solve);
        peer_solver->solve(rotated, solution);
        last_cg_iterations = peer_solver->last_iterations();
        statistics.cg_iterations += last_cg_iterations;
      }
    else if (!strategy.iterates() || factor_solves_target())
      {
        // A direct solve needs the exact factor: changes still pending are taken first.
        if (!cholesky_solver.factor_is_exact())
          refactorize({}, statistics, cholesky::Refresh::all);
        StageTimer timer(statistics.stages, stage::solve);
        cholesky_solver.solve(rotated, solution);
      }
    else
      {
        try
          {
            solve_by_cg(rotated, solution, statistics);
          }
        catch (const dealii::SolverControl::NoConvergence &)
          {
            // A factor that has become a poor preconditioner: refresh it and retry (from
            // the same initial guess: velocities is untouched so far).
            if (!refresh_after_failed_solve(statistics))
              throw MatrixError("preconditioned CG did not reach the tolerance " +
                                format_number(strategy.cg_tolerance) + " in " +
                                std::to_string(cg_iteration_limit()) + " iterations");
            solve_in_frame(right_hand_side, velocities, statistics);
            return;
          }
      }
    if (measure_velocity_error)
      {
        StageTimer timer(statistics.stages, stage::velocity_error);
        last_velocity_error       = relative_velocity_error(rotated, solution);
        statistics.velocity_error = last_velocity_error;
      }
    from_solve_frame(solution.data(), velocities);
  }

  void ElasticityModel::measure_velocity_errors()
  {
    measure_velocity_error = true;
  }

  double ElasticityModel::relative_velocity_error(const std::vector<double> &b, const std::vector<double> &y)
  {
    // The exact corotational system B y* = b: B (y* - y) = b - B y, and with the factor of
    // A, close to B, y* - y ~ A^-1 (b - B y).
    dealii::Vector<double> solution(y.begin(), y.end()), product(y.size());
    corotational_times(solution, product);
    std::vector<double> residual(y.size()), correction(y.size());
    for (std::size_t i = 0; i < residual.size(); ++i)
      residual[i] = b[i] - product[i];
    if (strategy.iterates())
      cholesky_solver.apply_preconditioner(residual.data(), correction.data());
    else
      cholesky_solver.solve(residual, correction);
    // Per vertex (3 unknowns each): the norms do not depend on the solve frame.
    double largest_correction = 0, largest_velocity = 0;
    for (std::size_t i = 0; i + 2 < y.size(); i += 3)
      {
        largest_correction =
          std::max(largest_correction, std::hypot(correction[i], correction[i + 1], correction[i + 2]));
        largest_velocity = std::max(largest_velocity, std::hypot(y[i], y[i + 1], y[i + 2]));
      }
    return largest_velocity > 0 ? largest_correction / largest_velocity : 0.0;
  }

  void ElasticityModel::to_solve_frame(const std::vector<Vector3> &field, double *unknowns) const
  {
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        const Index first = body.first_unknown(v);
        if (first < 0)
          continue;
        const Vector3 local = solve_frame ? Vector3((*solve_frame)[v].transpose() * field[v]) : field[v];
        for (unsigned int c = 0; c < 3; ++c)
          unknowns[first + c] = local[c];
      }
  }

  void ElasticityModel::from_solve_frame(const double *unknowns, std::vector<Vector3> &field) const
  {
    field.resize(body.n_vertices());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        const Index first = body.first_unknown(v);
        if (first < 0)
          {
            field[v].setZero();
            continue;
          }
        const Vector3 local(unknowns[first], unknowns[first + 1], unknowns[first + 2]);
        field[v] = solve_frame ? Vector3((*solve_frame)[v] * local) : local;
      }
  }

  namespace
  {
    /** A matrix or preconditioner for deal.II's SolverCG: vmult through a function. */
    class FunctionOperator
    {
    public:
      using Function = std::function<void(const dealii::Vector<double> &, dealii::Vector<double> &)>;

      explicit FunctionOperator(Function apply)
        : apply(std::move(apply))
      {}

      void vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const
      {
        apply(src, dst);
      }

    private:
      Function apply;
    };
  } // namespace

  unsigned int ElasticityModel::solve_by_cg(const std::vector<double> &b, std::vector<double> &y,
                                            StepStatistics &statistics)
  {
    Stopwatch    stopwatch;
    double       solve_seconds = 0;
    const FunctionOperator target([this](const dealii::Vector<double> &in, dealii::Vector<double> &out) {
      target_times(in, out);
    });
    const FunctionOperator preconditioner([&](const dealii::Vector<double> &in, dealii::Vector<double> &out) {
      Stopwatch solve_stopwatch;
      cholesky_solver.apply_preconditioner(in.begin(), out.begin());
      solve_seconds += solve_stopwatch.seconds();
    });
    dealii::Vector<double> right_hand_side(b.begin(), b.end());
    dealii::Vector<double> solution(y.begin(), y.end());
    // |b - B y| <= tolerance |b|: relative to the right-hand side, not to the residual of
    // the initial guess, so that a good guess saves iterations.
    const double          tolerance = strategy.cg_tolerance * right_hand_side.l2_norm();
    const unsigned int    limit     = cg_iteration_limit();
    dealii::SolverControl plain_control(limit, tolerance, false, false);
    ForecastSolverControl forecast_control(limit, tolerance);
    dealii::SolverControl &control = cg_gives_up_on_forecast() ? forecast_control : plain_control;
    dealii::SolverCG<dealii::Vector<double>> cg(control);
    const auto record = [&]() {
      last_cg_iterations = control.last_step();
      last_cg_seconds    = stopwatch.seconds();
      total_cg_iterations += control.last_step();
      total_cg_seconds += last_cg_seconds;
      statistics.cg_iterations += control.last_step();
      statistics.stages.add(stage::solve, solve_seconds);
      statistics.stages.add(stage::cg_iterations, last_cg_seconds - solve_seconds);
    };
    try
      {
        cg.solve(target, solution, right_hand_side, preconditioner);
      }
    catch (...)
      {
        record();
        throw;
      }
    record();
    y.assign(solution.begin(), solution.end());
    return control.last_step();
  }

  double ElasticityModel::IterationBytes::total() const
  {
    return preconditioner + product + vectors;
  }

  ElasticityModel::IterationBytes ElasticityModel::cg_iteration_bytes() const
  {
    IterationBytes bytes;
    const auto    &settings = cholesky_solver.settings();
    if (settings.method == cholesky::FactorizationMethod::supernodal)
      {
        const auto  &structure = cholesky_solver.supernodal_symbolic();
        const double value   = settings.preconditioner_precision == cholesky::PreconditionerPrecision::half   ? 2 :
                               settings.preconditioner_precision == cholesky::PreconditionerPrecision::single ? 4 :
                                                                                                               8;
        bytes.preconditioner = 2. * (static_cast<double>(structure.n_stored_values()) * value +
                                     static_cast<double>(structure.row_index.size()) * sizeof(Index));
      }
    else
      bytes.preconditioner =
        2. * static_cast<double>(cholesky_solver.statistics().nnz_l) * (sizeof(double) + sizeof(Index));
    const double n = static_cast<double>(body.n_unknowns());
    if (strategy.iterate_on == StepStrategy::Target::warp_canceling)
      bytes.product = static_cast<double>(system.lower().values.size()) * (sizeof(double) + sizeof(Index)) +
                      2 * n * sizeof(double);
    else
      // The forces are summed on the vertices as the elements give them (no array of the
      // elements' forces written and read back).
      bytes.product = static_cast<double>(body.n_elements()) *
                        (2 * sizeof(Matrix3) + sizeof(double) + 4 * sizeof(unsigned int) + 4 * sizeof(Vector3)) +
                      static_cast<double>(body.n_vertices()) * 2 * sizeof(unsigned int) + n * sizeof(double);
    bytes.vectors = 10 * n * sizeof(double);
    return bytes;
  }

  double ElasticityModel::cg_bytes_per_second() const
  {
    return total_cg_iterations > 0 && total_cg_seconds > 0 ?
             cg_iteration_bytes().total() * static_cast<double>(total_cg_iterations) / total_cg_seconds :
             0.;
  }

  void ElasticityModel::target_times(const dealii::Vector<double> &y, dealii::Vector<double> &out) const
  {
    if (strategy.iterate_on == StepStrategy::Target::warp_canceling)
      {
        // A itself: the symmetric product with its lower triangle.
        system.lower().vmult(y.begin(), out.begin());
        return;
      }
    corotational_times(y, out);
  }

  void ElasticityModel::corotational_times(const dealii::Vector<double> &y, dealii::Vector<double> &out) const
  {
    // R^T (c_M M + c_K sum_e R_e K_e R_e^T + tool springs) R y, matrix-free over the
    // elements; fixed vertices have no velocity.
    from_solve_frame(y.begin(), vertex_work);
    body.corotated_stiffness_times(&elastic_state.element_rotations, vertex_work, vertex_product, element_work);
    mass_product.assign(body.n_vertices(), Vector3::Zero());
    body.add_mass_times(vertex_work, mass_product);
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      {
        vertex_product[v] = coefficients.stiffness * vertex_product[v] + coefficients.mass * mass_product[v];
        if (!coefficients.vertex_diagonal.empty())
          vertex_product[v] += coefficients.vertex_diagonal[v] * vertex_work[v];
      }
    to_solve_frame(vertex_product, out.begin());
  }

  void ElasticityModel::record_rerotations(const std::vector<unsigned int> &rerotated)
  {
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        record.rerotated[e] = 0;
        ++record.steps_since_rerotation[e];
      }
    for (const unsigned int e : rerotated)
      {
        record.rerotated[e]              = 1;
        record.steps_since_rerotation[e] = 0;
      }
  }

  void ElasticityModel::record_rerotations(const bool all)
  {
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        record.rerotated[e]              = all ? 1 : 0;
        record.steps_since_rerotation[e] = all ? 0 : record.steps_since_rerotation[e] + 1;
      }
  }

  double ElasticityModel::elastic_energy_at_last_evaluation() const
  {
    return elastic_state.elastic_energy;
  }

  const ElementRerotationRecord &ElasticityModel::rerotation_record() const
  {
    return record;
  }

  const SystemMatrix &ElasticityModel::system_matrix() const
  {
    return system;
  }

  const cholesky::SparseCholesky &ElasticityModel::solver() const
  {
    return cholesky_solver;
  }

  double ElasticityModel::setup_seconds() const
  {
    return setup_time;
  }
} // namespace warpchol::fem
