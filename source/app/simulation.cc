#include <warpchol/app/simulation.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/fem/energy_balance.h>
#include <warpchol/fem/warp_canceling_model.h>

#include <deal.II/base/exceptions.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace warpchol::app
{
  Simulation::Simulation(const AllParameters &parameters)
    : parameters(parameters)
  {
    Stopwatch stopwatch;
    simulated_scene = std::make_unique<Scene>(parameters);
    setup_seconds   = stopwatch.seconds();
    directory       = parameters.output.directory + "/" + parameters.scene_name();
    if (parameters.output.compare_with_corotational)
      {
        AllParameters reference = parameters;
        reference.model.type    = "corotational";
        reference_scene         = std::make_unique<Scene>(reference);
      }

    const auto &body = simulated_scene->body();
    element_centres.resize(body.n_elements(), fem::Vector3::Zero());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      for (const unsigned int v : body.element_vertices(e))
        element_centres[e] += 0.25 * body.rest_positions()[v];
    const auto &tool = simulated_scene->loads().tool.vertices;
    for (const unsigned int v : tool)
      tool_centre += body.rest_positions()[v] / static_cast<double>(tool.size());
  }

  void Simulation::run(std::ostream &out)
  {
    const auto &settings = parameters.output;
    if (settings.write_log || settings.vtu_interval > 0)
      create_directory(directory);
    if (settings.write_log)
      step_log = std::make_unique<StepLog>(directory + "/log.csv", reference_scene != nullptr);
    if (settings.vtu_interval > 0)
      vtu_series = std::make_unique<VtuSeries>(directory, parameters.scene_name());

    auto       &integrator = simulated_scene->integrator();
    auto       &model      = simulated_scene->model();
    const auto &body       = simulated_scene->body();
    if (vtu_series)
      vtu_series->write(0, 0, body, integrator.displacements(), integrator.velocities(),
                        model.update_record());

    // The balance needs the elastic energy, a pass over the elements per step: only when
    // the detector or the log uses it.
    const bool         track_energy = parameters.time_stepping.energy_growth_limit > 0 || step_log;
    fem::EnergyBalance energy_balance(body);
    energy_balance.record(integrator);

    const bool show_progress =
      settings.progress == "on" || (settings.progress == "auto" && isatty(fileno(stderr)));
    Stopwatch since_progress;
    const Stopwatch run_stopwatch;
    const unsigned int n_steps = parameters.time_stepping.n_steps;
    for (unsigned int step = 1; step <= n_steps; ++step)
      {
        fem::StepStatistics statistics;
        Stopwatch           stopwatch;
        integrator.advance(statistics);
        const double step_seconds = stopwatch.seconds();

        auto &t = run_totals;
        ++t.steps;
        t.elements_updated += statistics.elements_updated;
        t.max_elements_updated =
          std::max(t.max_elements_updated, static_cast<double>(statistics.elements_updated));
        if (statistics.elements_updated > 0)
          {
            ++t.steps_with_updates;
            t.trailing_steps_without_update = 0;
          }
        else
          ++t.trailing_steps_without_update;
        if (statistics.refactorized)
          {
            ++t.refactorizations;
            t.columns_recomputed_pct += 100.0 * statistics.columns_recomputed / statistics.n_columns;
            t.flops_recomputed_pct += 100.0 * statistics.flops_recomputed / statistics.flops_full;
          }
        t.seconds.add_phase_times(statistics);
        t.cg_iterations += statistics.cg_iterations;
        if (!statistics.refresh.empty())
          ++t.refreshes[statistics.refresh];
        t.step_seconds += step_seconds;
        if (!simulated_scene->loads().tool.vertices.empty())
          {
            const auto &updated = model.update_record().updated;
            for (unsigned int e = 0; e < updated.size(); ++e)
              if (updated[e])
                t.updated_distance_to_tool += (element_centres[e] - tool_centre).norm();
          }

        double error_vs_corotational = -1;
        if (reference_scene)
          {
            fem::StepStatistics reference_statistics;
            try
              {
                reference_scene->integrator().advance(reference_statistics);
              }
            catch (const MatrixError &error)
              {
                throw MatrixError(std::string("the corotational reference run: ") + error.what());
              }
            const auto &x         = integrator.positions();
            const auto &reference = reference_scene->integrator().positions();
            double      difference = 0, motion = 0;
            for (unsigned int v = 0; v < x.size(); ++v)
              {
                difference = std::max(difference, (x[v] - reference[v]).norm());
                motion     = std::max(motion, (reference[v] - body.rest_positions()[v]).norm());
              }
            error_vs_corotational = motion > 0 ? difference / motion : difference;
            t.max_error_vs_corotational = std::max(t.max_error_vs_corotational, error_vs_corotational);
            t.last_error_vs_corotational = error_vs_corotational;
          }

        const double kinetic_energy = integrator.kinetic_energy();
        if (track_energy)
          energy_balance.record(integrator);
        if (step_log)
          {
            StepLogRow row;
            row.step           = step;
            row.time           = integrator.time();
            row.statistics     = statistics;
            row.n_elements     = body.n_elements();
            row.step_seconds   = step_seconds;
            row.kinetic_energy = kinetic_energy;
            row.elastic_energy = integrator.elastic_energy();
            row.potential_energy  = integrator.potential_energy();
            row.tool_energy       = integrator.tool_energy();
            row.total_energy      = integrator.total_energy();
            row.external_work     = integrator.external_work();
            row.tool_work_on_body = integrator.tool_work_on_body();
            row.energy_ratio      = energy_balance.ratio();
            row.error_vs_corotational = error_vs_corotational;
            step_log->add(row);
          }
        if (track_energy)
          check_energy(energy_balance, step);
        if (vtu_series && step % settings.vtu_interval == 0)
          vtu_series->write(step, integrator.time(), body, integrator.displacements(),
                            integrator.velocities(), model.update_record());
        if (show_progress && (since_progress.seconds() > 0.5 || step == n_steps))
          {
            std::cerr << "\rstep " << step << "/" << n_steps << "  t = "
                      << format_number(integrator.time(), 4) << " s  updated "
                      << format_number(100.0 * statistics.elements_updated / body.n_elements(), 3)
                      << " %  " << format_number(step_seconds, 3) << " s/step   " << std::flush;
            since_progress.restart();
          }
        if (parameters.time_stepping.rest_kinetic_energy > 0 && step > 1 &&
            kinetic_energy < parameters.time_stepping.rest_kinetic_energy)
          break;
      }
    if (show_progress)
      std::cerr << std::endl;
    if (vtu_series)
      vtu_series->finish();
    run_totals.run_seconds = run_stopwatch.seconds();
    print_summary(out);
  }

  void Simulation::check_energy(const fem::EnergyBalance &balance, const unsigned int step)
  {
    const double limit      = parameters.time_stepping.energy_growth_limit;
    const bool   not_finite = !balance.all_finite();
    if (!not_finite && !(limit > 0 && balance.ratio() > limit))
      return;
    // Stop before writing the runaway state; what earlier steps wrote stays complete.
    if (vtu_series)
      vtu_series->finish();
    const auto       &integrator = simulated_scene->integrator();
    const std::string where = "step " + std::to_string(step) + ": the energy of " +
                              simulated_scene->model().name();
    if (not_finite)
      throw SimulationError(where + " is not finite: the simulation diverged");
    throw SimulationError(where + " grew to " + format_number(balance.held_energy(), 3) +
                          " J (start " + format_number(integrator.initial_energy(), 3) +
                          " J, work of the external loads " +
                          format_number(balance.energy_put_in() - integrator.initial_energy(), 3) +
                          " J), over Time stepping/Energy growth limit = " + format_number(limit) +
                          " times what was put in: the simulation diverged");
  }

  void Simulation::print_summary(std::ostream &out) const
  {
    const auto &scene      = *simulated_scene;
    const auto &body       = scene.body();
    const auto &model      = scene.model();
    const auto &integrator = scene.integrator();
    const auto &t          = run_totals;
    const bool  timings    = parameters.output.print_timings;
    const auto  n          = [](const double value, const int digits = 3) {
      return format_number(value, digits);
    };
    const double n_elements = body.n_elements();

    out << "scene " << parameters.scene_name() << ": " << scene.mesh_description() << "\n";
    out << "  mesh: " << body.n_vertices() << " vertices, " << body.n_elements() << " tets, "
        << scene.fixed_vertices().size() << " fixed vertices, " << body.n_unknowns()
        << " unknowns, mass " << n(body.total_mass()) << " kg\n";
    out << "  model: " << model.name();
    if (const auto *wcc = dynamic_cast<const fem::WarpCancelingModel *>(&model))
      out << ", update threshold " << n(wcc->update_threshold());
    const auto &solver = model.solver();
    out << "; solver: " << cholesky::to_string(solver.settings().ordering.method) << " ordering, "
        << cholesky::to_string(solver.settings().method);
    if (timings)
      out << ", fill " << n(solver.statistics().fill());
    out << "\n";
    out << "  steps: " << t.steps << ", simulated time " << n(integrator.time(), 4) << " s\n";
    if (model.uses_rotations())
      {
        out << "  elements updated per step: mean " << n(100 * t.elements_updated / n_elements / t.steps)
            << " %, max " << n(100 * t.max_elements_updated / n_elements) << " %; steps with "
            << "updates: " << t.steps_with_updates << ", without update at the end: "
            << t.trailing_steps_without_update << "\n";
        out << "  refactorizations: " << t.refactorizations;
        if (timings && t.refactorizations > 0)
          out << ", columns recomputed mean " << n(t.columns_recomputed_pct / t.refactorizations)
              << " %, flops recomputed mean " << n(t.flops_recomputed_pct / t.refactorizations)
              << " %";
        out << "\n";
        if (const auto *wcc = dynamic_cast<const fem::WarpCancelingModel *>(&model))
          {
            const auto &strategy = wcc->step_strategy();
            out << "  strategy: " << fem::to_string(strategy.kind);
            if (strategy.iterates())
              out << ", CG on the " << fem::to_string(strategy.iterate_on) << " matrix to "
                  << n(strategy.cg_tolerance, 2) << ", iterations per step mean "
                  << n(static_cast<double>(t.cg_iterations) / std::max(1u, t.steps));
            out << "; factor refreshes:";
            if (t.refreshes.empty())
              out << " 0";
            for (const auto &[refresh, count] : t.refreshes)
              out << " " << refresh << " " << count;
            out << "\n";
          }
        if (!scene.loads().tool.vertices.empty() && t.elements_updated > 0)
          {
            double all_distance = 0;
            for (const auto &centre : element_centres)
              all_distance += (centre - tool_centre).norm();
            out << "  updated elements lie " << n(t.updated_distance_to_tool / t.elements_updated, 2)
                << " m from the tool on average (all elements: " << n(all_distance / n_elements, 2)
                << " m)\n";
          }
      }
    if (reference_scene)
      out << "  trajectory error against corotational: max " << n(t.max_error_vs_corotational, 2)
          << ", at the end " << n(t.last_error_vs_corotational, 2) << "\n";
    // An energy below 1e-12 of the total is rounding (a translated body's elastic energy):
    // printed as such, not as digits that change with the order of the operations.
    const double kinetic_energy = integrator.kinetic_energy();
    const double elastic_energy = integrator.elastic_energy();
    const auto   energy = [&](const double value) {
      return value <= 1e-12 * (kinetic_energy + elastic_energy) ? std::string("0 (rounding)") :
                                                                  n(value) + " J";
    };
    out << "  energy at the end: kinetic " << energy(kinetic_energy) << ", elastic "
        << energy(elastic_energy) << "\n";
    if (timings)
      {
        const double steps = std::max(1u, t.steps);
        out << "  seconds per step: rotations " << n(t.seconds.t_rotations / steps)
            << ", error estimate " << n(t.seconds.t_error_estimate / steps) << ", assembly "
            << n(t.seconds.t_assembly / steps) << ", factor " << n(t.seconds.t_factor / steps)
            << ", solve " << n(t.seconds.t_solve / steps) << ", iterations "
            << n(t.seconds.t_iterations / steps) << ", step " << n(t.step_seconds / steps)
            << "\n";
        out << "  set-up " << n(setup_seconds) << " s (model " << n(model.setup_seconds())
            << " s), time steps " << n(t.step_seconds) << " s; end to end (output included) "
            << n(t.run_seconds) << " s, " << n(t.steps / std::max(t.run_seconds, 1e-9)) << " steps/s\n";
      }
    if (step_log)
      out << "  log: " << step_log->filename() << "\n";
    if (vtu_series)
      out << "  VTU: " << vtu_series->n_files() << " files, series " << vtu_series->pvd_file() << "\n";
    out << std::flush;
  }

  const Scene &Simulation::scene() const
  {
    return *simulated_scene;
  }

  const RunTotals &Simulation::totals() const
  {
    return run_totals;
  }

  const std::string &Simulation::output_directory() const
  {
    return directory;
  }

  void run_parameter_file(const std::string &parameter_file, std::ostream &out)
  {
    const AllParameters parameters(parameter_file);
    Simulation          simulation(parameters);
    simulation.run(out);
  }

  namespace
  {
    const char *usage = "usage: warpchol PARAMS.prm          run the scene of a parameter file\n"
                        "       warpchol --print-parameters [FILE]\n"
                        "                                    write the documented defaults\n"
                        "                                    (to FILE, or standard output)";
  }

  int main(const int argc, const char *const *argv, std::ostream &out, std::ostream &err)
  {
    try
      {
        const std::vector<std::string> arguments(argv + 1, argv + argc);
        if (arguments.size() == 1 && (arguments[0] == "--help" || arguments[0] == "-h"))
          {
            out << usage << std::endl;
            return 0;
          }
        if (!arguments.empty() && arguments[0] == "--print-parameters")
          {
            if (arguments.size() > 2)
              throw InputError("--print-parameters takes at most one file name");
            if (arguments.size() == 2)
              write_file_atomically(arguments[1], [](std::ostream &file) {
                AllParameters::print_defaults(file);
              });
            else
              AllParameters::print_defaults(out);
            return 0;
          }
        if (arguments.size() != 1 || arguments[0].empty() || arguments[0][0] == '-')
          throw InputError(arguments.empty() ? "no parameter file given" :
                                               "unexpected arguments (see warpchol --help)");
        run_parameter_file(arguments[0], out);
        return 0;
      }
    catch (const InputError &error)
      {
        out << std::flush;
        err << "warpchol: error: " << error.what() << std::endl;
        return 2;
      }
    catch (const Error &error)
      {
        out << std::flush;
        err << "warpchol: error: " << error.what() << std::endl;
        return 1;
      }
    catch (const std::exception &error)
      {
        // deal.II and the standard library: keep their message on one line.
        std::string message = error.what();
        for (auto &c : message)
          if (c == '\n')
            c = ' ';
        out << std::flush;
        err << "warpchol: error: " << message << std::endl;
        return 1;
      }
  }
} // namespace warpchol::app
