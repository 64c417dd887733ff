#include <warpchol/app/run_summary.h>
#include <warpchol/base/format.h>
#include <warpchol/base/simd.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/dynamics/energy_balance.h>
#include <warpchol/models/elasticity_model.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace warpchol::app
{
  namespace
  {
    /**
     * The summary's stages: with Print timings, a table of their runs, seconds per step and
     * shares of the run; without, their names only (the same in every run).
     */
    void print_stages(std::ostream &out, const SimulatedBody &body, const AllParameters &parameters)
    {
      const auto &t = body.totals;
      if (!parameters.output.print_timings)
        {
          // The names alone: what ran does not change from run to run, its seconds do.
          out << "  stages: " << t.stages.names() << "\n";
          return;
        }
      // Per stage: its runs, its seconds per step and its share of the run, end to end; what
      // no stage holds (the run's bookkeeping, the progress line) is "other".
      const double steps = std::max(1u, t.steps);
      const double run   = std::max(t.run_seconds, 1e-12);
      const auto   share = [&](const double seconds) {
        std::ostringstream text;
        text << std::fixed << std::setprecision(1) << 100 * seconds / run;
        return text.str();
      };
      const auto row = [&](const std::string &name, const std::string &runs, const double seconds) {
        out << "    " << std::left << std::setw(22) << name << std::right << std::setw(6) << runs
            << std::setw(12) << format_number(seconds / steps, 3) << std::setw(8) << share(seconds) << " %\n";
      };
      out << "  stages: " << std::left << std::setw(16) << "" << std::right << std::setw(6) << "runs"
          << std::setw(12) << "s per step" << std::setw(10) << "share" << "\n";
      for (const auto &stage : t.stages.stages())
        row(stage.name, std::to_string(stage.runs), stage.seconds);
      row("other", "", std::max(0.0, t.run_seconds - t.stages.total_seconds()));
      out << "    " << std::left << std::setw(22) << "time steps" << std::right << std::setw(6) << t.steps
          << std::setw(12) << format_number(t.step_seconds / steps, 3) << std::setw(8)
          << share(t.step_seconds) << " %\n";
    }

    std::string figure(const double value, const int digits = 3)
    {
      return format_number(value, digits);
    }

    double iterations_per_step(const RunTotals &t)
    {
      return static_cast<double>(t.cg_iterations) / std::max(1u, t.steps);
    }

    /** "model: ...; solver: ...": the model, its threshold or target, who factors and solves. */
    void print_model(std::ostream &out, const SimulatedBody &simulated, const bool timings)
    {
      const Scene                &scene  = *simulated.scene;
      const fem::ElasticityModel &model  = scene.model();
      const auto                  report = model.strategy_report();
      out << "  model: " << model.name();
      if (report.has_strategy && report.target_error > 0)
        out << ", target error " << figure(report.target_error) << " (re-rotation threshold from "
            << figure(report.rerotation_threshold) << ")";
      else if (report.has_strategy)
        out << ", re-rotation threshold " << figure(report.rerotation_threshold);
      const auto &solver  = model.solver();
      const auto &backend = scene.parameters().solver.backend;
      if (const auto *peer = model.linear_solver())
        {
          out << "; solver: " << peer->name();
          if (peer->is_iterative())
            out << ", to " << figure(backend.tolerance, 2) << ", iterations per step mean "
                << figure(iterations_per_step(simulated.totals));
        }
      else
        {
          out << "; solver: " << cholesky::to_string(solver.settings().ordering.method) << " ordering, "
              << cholesky::to_string(solver.settings().method);
          if (timings)
            out << ", fill " << figure(solver.statistics().fill());
          if (backend.backend == backends::Backend::warp_preconditioned_cg)
            out << ", its rest factor rotated as CG's preconditioner (warp_preconditioned_cg)";
        }
      if (timings)
        out << ", factor memory " << figure(model.factor_memory_bytes() / 1048576.) << " MiB";
      out << "\n";
    }

    /** Elements re-rotated, the rotations' paths, the refactorizations and an adapted threshold. */
    void print_updates(std::ostream &out, const SimulatedBody &simulated, const bool timings)
    {
      const RunTotals &t          = simulated.totals;
      const double     n_elements = simulated.scene->body().n_elements();
      const auto       report     = simulated.scene->model().strategy_report();
      out << "  elements re-rotated per step: mean " << figure(100 * t.elements_rerotated / n_elements / t.steps)
          << " %, max " << figure(100 * t.max_elements_rerotated / n_elements) << " %; steps with "
          << "re-rotations: " << t.steps_with_rerotations << ", without re-rotation at the end: "
          << t.trailing_steps_without_rerotation << "\n";
      // Where the batched polar decompositions left the SIMD lanes, and why.
      const fem::RotationPaths &paths = t.rotation_paths;
      if (paths.total() > 0)
        out << "  rotations: " << paths.total() << " over the run; " << figure(100.0 * paths.lanes / paths.total())
            << " % in the SIMD lanes, " << paths.newton << " by the scalar Newton iteration (strain too large for the "
            << "lanes' 12 steps), " << paths.svd << " by the SVD (inverted or flat)\n";
      out << "  refactorizations: " << t.refactorizations;
      if (timings && t.refactorizations > 0)
        out << ", columns recomputed mean " << figure(t.columns_recomputed_pct / t.refactorizations)
            << " %, flops recomputed mean " << figure(t.flops_recomputed_pct / t.refactorizations) << " %";
      // How the factorizations took their changes: by updating the factor or recomputing
      // (chosen by measured times: shown with them).
      if (timings && t.refactorizations > 0)
        {
          out << "; taken by";
          for (const auto &[method, count] : t.factor_methods)
            out << " " << method << " " << count;
        }
      out << "\n";
      if (report.target_error > 0 && t.steps > 0)
        out << "  adapted re-rotation threshold: mean " << figure(t.threshold_sum / t.steps) << ", from "
            << figure(t.min_threshold) << " to " << figure(t.max_threshold)
            << "; velocity error against exact corotation per step: mean "
            << figure(t.velocity_error_sum / t.steps, 2) << ", max " << figure(t.max_velocity_error, 2) << "\n";
      if (!report.target_note.empty())
        out << "  " << report.target_note << "\n";
    }

    /** "strategy: ...": how WCC's steps kept their factor and solved, and what auto chose. */
    void print_strategy(std::ostream &out, const SimulatedBody &simulated, const bool timings)
    {
      const fem::ElasticityModel &model    = simulated.scene->model();
      const RunTotals            &t        = simulated.totals;
      const auto                  report   = model.strategy_report();
      const auto                 &strategy = report.strategy;
      out << "  strategy: " << fem::to_string(strategy.kind);
      if (strategy.iterates())
        out << ", CG on the " << fem::to_string(strategy.iterate_on) << " matrix to "
            << figure(strategy.cg_tolerance, 2) << ", iterations per step mean " << figure(iterations_per_step(t));
      // What an iteration moves and how fast: the iterating step is memory-bound.
      if (timings && model.cg_bytes_per_second() > 0)
        {
          const auto bytes = model.cg_iteration_bytes();
          out << " (an iteration moves " << figure(bytes.total() * 1e-6) << " MB: factor read twice "
              << figure(bytes.preconditioner * 1e-6) << ", product " << figure(bytes.product * 1e-6) << ", vectors "
              << figure(bytes.vectors * 1e-6) << "; at " << figure(model.cg_bytes_per_second() * 1e-9) << " GB/s)";
        }
      out << "; factor refreshes:";
      if (t.refreshes.empty())
        out << " 0";
      for (const auto &[refresh, count] : t.refreshes)
        out << " " << refresh << " " << count;
      if (!t.choices.empty())
        {
          out << "; choices:";
          for (const auto &[choice, count] : t.choices)
            out << " " << choice << " " << count;
        }
      if (t.factor_lag_steps > 0)
        out << "; factor age mean " << figure(t.factor_lag_sum / t.factor_lag_steps) << " steps";
      const unsigned int beside = report.steps_refreshing_beside;
      if (strategy.kind == fem::StepStrategy::Kind::automatic && beside > 0)
        out << "; refreshes beside the steps (one thread less for them) in " << beside << " of "
            << beside + report.steps_refreshing_in << " steps";
      if (strategy.kind == fem::StepStrategy::Kind::automatic && report.exact_fallback_steps > 0)
        {
          out << "; exact in " << report.exact_fallback_steps << " steps where its own had cost more ("
              << report.fallbacks << " times";
          if (report.fallbacks_ended > 0)
            out << ", " << report.fallbacks_ended << " ended early: the machine had slowed down";
          out << ")";
        }
      out << "\n";
    }

    /** What the instruments did, and where the re-rotated elements lie from the tool. */
    void print_surgery(std::ostream &out, const SimulatedBody &simulated)
    {
      const Scene     &scene      = *simulated.scene;
      const RunTotals &t          = simulated.totals;
      const double     n_elements = scene.body().n_elements();
      if (scene.integrator().surgery().active())
        {
          out << "  surgery: " << t.elements_cut << " elements cut";
          const auto &cuts = scene.parameters().cuts;
          if (t.elements_cut == 0 &&
              std::any_of(cuts.begin(), cuts.end(), [](const parameters::Cut &cut) { return cut.active(); }))
            out << (cuts.size() > 1 ? " (the blades crossed no element)" : " (the blade crossed no element)");
          out << ", " << t.vertices_grasped << " vertices grasped, " << t.vertices_released << " released, "
              << t.elements_changed << " elements of changed material";
          // Penalty springs that come and go change A's diagonal too, and count with it.
          const fem::ContactConstraints *contact = scene.integrator().contact();
          const bool springs = contact && contact->settings().method == fem::ContactMethod::penalty;
          if (t.change_steps > 0)
            out << "; " << t.change_steps
                << (springs ? " steps with a change of A (the surgery's or the penalty springs')" : " steps with a change")
                << ", each touching "
                << figure(t.change_columns_pct / t.change_steps) << " % of the columns and "
                << figure(t.change_flops_pct / t.change_steps) << " % of a full factorization's flops (mean)";
          out << "\n";
        }
      if (!scene.loads().tool.vertices.empty() && t.elements_rerotated > 0)
        {
          double all_distance = 0;
          for (const auto &centre : simulated.element_centres)
            all_distance += (centre - simulated.tool_centre).norm();
          out << "  re-rotated elements lie " << figure(t.rerotated_distance_to_tool / t.elements_rerotated, 2)
              << " m from the tool on average (all elements: " << figure(all_distance / n_elements, 2) << " m)\n";
        }
    }

    /** The error against a reference run, the energies at the end and those of the changes. */
    void print_error_and_energy(std::ostream &out, const SimulatedBody &simulated)
    {
      const fem::ImplicitEuler &integrator = simulated.scene->integrator();
      if (simulated.reference)
        {
          const auto &error = simulated.totals.error_vs_corotational;
          out << "  trajectory error against corotational: max " << figure(error.max_error(), 2) << ", mean "
              << figure(error.mean_error(), 2) << ", at the end " << figure(error.last_error(), 2) << "; RMS max "
              << figure(error.max_rms_error(), 2) << ", mean " << figure(error.mean_rms_error(), 2) << "\n";
        }
      // An energy below 1e-12 of the total is rounding (a translated body's elastic energy):
      // printed as such, not as digits that change with the order of the operations.
      const double kinetic_energy = integrator.kinetic_energy();
      const double elastic_energy = integrator.elastic_energy();
      const auto   energy         = [&](const double value) {
        return value <= 1e-12 * (kinetic_energy + elastic_energy) ? std::string("0 (rounding)") :
                                                                    figure(value) + " J";
      };
      out << "  energy at the end: kinetic " << energy(kinetic_energy) << ", elastic " << energy(elastic_energy)
          << "\n";
      if (!integrator.surgery().active())
        return;
      // What the changes put in or took out, which the energy balance counts.
      const fem::ChangeEnergy &change = integrator.surgery().change_energy();
      out << "  energy of the changes: " << figure(change.total()) << " J (material change "
          << figure(change.material_changes) << " J, cuts " << figure(change.cuts) << " J, grasps and releases "
          << figure(change.grasps) << " J)\n";
      const std::vector<std::string> missed = integrator.surgery().events_not_reached();
      if (!missed.empty() && simulated.stopped.empty())
        {
          out << "  warning: ";
          for (std::size_t k = 0; k < missed.size(); ++k)
            out << (k == 0 ? "" : k + 1 == missed.size() ? " and " : ", ") << missed[k];
          out << (missed.size() == 1 ? " falls" : " fall") << " after the run's end (" << figure(integrator.time(), 4)
              << " s): " << (missed.size() == 1 ? "it" : "they") << " never happened\n";
        }
    }

    /** The set-up and run times, and the run against exact corotation timed after it. */
    void print_times(std::ostream &out, const SimulatedBody &simulated, const AllParameters &parameters)
    {
      const RunTotals &t       = simulated.totals;
      const bool       timings = parameters.output.print_timings;
      if (timings)
        out << "  set-up " << figure(simulated.setup_seconds) << " s (model "
            << figure(simulated.scene->model().setup_seconds()) << " s), time steps " << figure(t.step_seconds)
            << " s; end to end (output included) " << figure(t.run_seconds) << " s, "
            << figure(t.steps / std::max(t.run_seconds, 1e-9)) << " steps/s; SIMD target " << simd::current_target()
            << "\n";
      if (simulated.exact_step_seconds < 0 || t.steps == 0)
        return;
      // The run's steps without the error estimate, which only the comparison asks for.
      const double own = (t.step_seconds - t.stages.seconds(fem::stage::velocity_error)) / t.steps;
      if (timings)
        out << "  exact corotation: " << figure(1e3 * simulated.exact_step_seconds) << " ms a step on this machine ("
            << parameters.output.exact_steps_timed
            << " exact steps timed after the run: every element rotated and assembled, a full factorization, "
               "a direct solve); this run "
            << figure(1e3 * own) << " ms a step: " << figure(simulated.exact_step_seconds / own) << "x faster\n";
      if (t.velocity_error_sum > 0 || t.max_velocity_error > 0)
        out << "  error against exact corotation, estimated every step (no reference run: |A^-1 (b - B v)| / |v|, "
               "B the exact corotational matrix, A the step's factor): velocity error mean "
            << figure(t.velocity_error_sum / t.steps, 2) << ", max " << figure(t.max_velocity_error, 2) << "\n";
    }
  } // namespace

  void print_body_summary(std::ostream &out, const SimulatedBody &simulated, const AllParameters &parameters)
  {
    const bool                  timings = parameters.output.print_timings;
    const fem::ElasticityModel &model   = simulated.scene->model();
    print_model(out, simulated, timings);
    out << "  steps: " << simulated.totals.steps << ", simulated time "
        << figure(simulated.scene->integrator().time(), 4) << " s\n";
    if (model.uses_rotations())
      {
        print_updates(out, simulated, timings);
        if (model.strategy_report().has_strategy)
          print_strategy(out, simulated, timings);
        print_surgery(out, simulated);
      }
    print_error_and_energy(out, simulated);
    print_stages(out, simulated, parameters);
    print_times(out, simulated, parameters);
    if (!simulated.stopped.empty())
      out << "  stopped: " << simulated.stopped << "\n";
    if (simulated.log)
      out << "  log: " << simulated.log->filename() << "\n";
  }
} // namespace warpchol::app
