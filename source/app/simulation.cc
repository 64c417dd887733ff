#include <warpchol/app/run_summary.h>
#include <warpchol/app/simulation.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/dynamics/energy_balance.h>
#include <warpchol/models/warp_canceling_model.h>

#include <deal.II/base/exceptions.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace warpchol::app
{
  namespace
  {
    /**
     * The seconds of a step of exact corotation for @p parameters on this machine: @p steps
     * steps of the exact corotational model from rest, output off (every element rotated
     * and assembled, a full factorization, a direct solve: a step costs that whatever the
     * state, so the first steps stand for the run's).
     */
    double time_exact_steps(const AllParameters &parameters, const unsigned int steps)
    {
      Scene           exact{parameters.exact_corotational()};
      const Stopwatch stopwatch;
      for (unsigned int step = 0; step < steps; ++step)
        {
          fem::StepStatistics statistics;
          exact.integrator().advance(statistics);
        }
      return stopwatch.seconds() / steps;
    }

    /** "body 2 (warp_canceling, threshold 0.3)": how messages and the summary name a body. */
    std::string body_label(const AllParameters &body_parameters, const unsigned int index)
    {
      std::string label = "body " + std::to_string(index + 1) + " (" + fem::to_string(body_parameters.model.type);
      if (body_parameters.model.type == fem::ModelType::warp_canceling)
        label += ", threshold " + format_number(body_parameters.model.rerotation_threshold);
      return label + ")";
    }

    /** The first section of a checkpoint: its kind and the version of its layout. */
    /**
     * 2: the body's plastic strains, the changes' energy (issue 29). 3: WCC's target-error
     * controller and its step history each written as one object. 4: in WCC's step
     * history, whether auto's last step was the exact path's and A is in its frames. 5:
     * the fall-back's count of losing steps in its window. 6: WCC's step cost model
     * without a flop rate of its own (it reads the solver's). 8: the parameters it was
     * written with name Model/Rerotation threshold and Bodies/Rerotation thresholds (once
     * Update threshold(s)), which a resume compares entry by entry.
     */
    constexpr const char *checkpoint_format = "warpchol checkpoint 12";

    /** "Model/Type" of the entry "Model/Type = corotational". */
    std::string entry_name(const std::string &entry)
    {
      return entry.substr(0, entry.find(" = "));
    }

    /**
     * Whether entry @p name may differ between the run that wrote a checkpoint and the
     * one that resumes from it: the number of steps (a stopped run may be extended) and what
     * only says where and how the results are shown, which changes no step. Not the log or
     * the corotational reference, whose rows and state the checkpoint holds.
     */
    bool may_differ_on_resume(const std::string &name)
    {
      for (const char *entry : {"Time stepping/Number of steps", "Output/Directory", "Output/Scene",
                                "Output/VTU interval", "Output/VTU precision", "Output/Print timings",
                                "Output/Progress", "Output/Checkpoint interval"})
        if (name == entry)
          return true;
      return false;
    }

    /**
     * Apply @p io to every field of @p totals that a checkpoint keeps (all but the run's
     * seconds, kept apart): one list for writing and reading.
     */
    template <typename Totals, typename IO>
    void for_each_checkpointed_total(Totals &totals, const IO &io)
    {
      io(totals.steps);
      io(totals.elements_rerotated);
      io(totals.last_elements_rerotated);
      io(totals.max_elements_rerotated);
      io(totals.steps_with_rerotations);
      io(totals.trailing_steps_without_rerotation);
      io(totals.refactorizations);
      io(totals.columns_recomputed_pct);
      io(totals.flops_recomputed_pct);
      io(totals.cg_iterations);
      io(totals.threshold_sum);
      io(totals.min_threshold);
      io(totals.max_threshold);
      io(totals.velocity_error_sum);
      io(totals.max_velocity_error);
      io(totals.step_seconds);
      io(totals.rerotated_distance_to_tool);
      io(totals.error_vs_corotational);
      io(totals.factor_lag_sum);
      io(totals.factor_lag_steps);
      io(totals.elements_cut);
      io(totals.elements_changed);
      io(totals.vertices_grasped);
      io(totals.vertices_released);
      io(totals.change_steps);
      io(totals.change_columns_pct);
      io(totals.change_flops_pct);
      io(totals.rotation_paths.lanes);
      io(totals.rotation_paths.newton);
      io(totals.rotation_paths.svd);
    }

    void save_totals(BinaryWriter &writer, const RunTotals &totals)
    {
      writer.section("totals");
      for_each_checkpointed_total(totals, [&](const auto &value) { writer.write(value); });
      std::vector<std::string>  names;
      std::vector<unsigned int> counts;
      for (const auto *counted : {&totals.refreshes, &totals.choices, &totals.factor_methods})
        {
          names.clear();
          counts.clear();
          for (const auto &[name, count] : *counted)
            {
              names.push_back(name);
              counts.push_back(count);
            }
          writer.write(names);
          writer.write(counts);
        }
      std::vector<double> seconds;
      names.clear();
      counts.clear();
      for (const auto &stage : totals.stages.stages())
        {
          names.push_back(stage.name);
          seconds.push_back(stage.seconds);
          counts.push_back(stage.runs);
        }
      writer.write(names);
      writer.write(seconds);
      writer.write(counts);
    }

    void load_totals(BinaryReader &reader, RunTotals &totals)
    {
      reader.expect_section("totals");
      totals = RunTotals();
      for_each_checkpointed_total(totals, [&](auto &value) { reader.read(value); });
      std::vector<std::string>  names;
      std::vector<unsigned int> counts;
      std::vector<double>       seconds;
      for (auto *counted : {&totals.refreshes, &totals.choices, &totals.factor_methods})
        {
          reader.read(names);
          reader.read(counts);
          if (names.size() != counts.size())
            reader.fail("the refresh or choice counts do not match their names");
          for (std::size_t i = 0; i < names.size(); ++i)
            (*counted)[names[i]] = counts[i];
        }
      reader.read(names);
      reader.read(seconds);
      reader.read(counts);
      if (names.size() != seconds.size() || names.size() != counts.size())
        reader.fail("the stage times do not match their names");
      for (std::size_t i = 0; i < names.size(); ++i)
        totals.stages.add(names[i], seconds[i], counts[i]);
    }
  } // namespace

  Simulation::Simulation(const AllParameters &parameters)
    : parameters(parameters)
  {
    directory = parameters.output.directory + "/" + parameters.scene_name();
    // Before any computation: a run of hours must not end unable to write its results.
    if (parameters.output.write_log || parameters.output.vtu_interval > 0 ||
        parameters.output.checkpoint_interval > 0)
      create_directory(directory);
    const unsigned int n_bodies = parameters.bodies.count;
    bodies.resize(n_bodies);
    for (unsigned int i = 0; i < n_bodies; ++i)
      {
        SimulatedBody      &simulated        = bodies[i];
        const AllParameters body_parameters  = parameters.body(i);
        Stopwatch           stopwatch;
        try
          {
            simulated.scene = std::make_unique<Scene>(body_parameters);
          }
        catch (const MatrixError &error)
          {
            if (n_bodies == 1)
              throw;
            throw MatrixError(body_label(body_parameters, i) + ": " + error.what());
          }
        simulated.setup_seconds = stopwatch.seconds();
        simulated.energy_balance = std::make_unique<fem::EnergyBalance>(simulated.scene->body());
        simulated.energy_balance->record(simulated.scene->integrator());
        simulated.offset        = static_cast<double>(i) * parameters.bodies.spacing;
        if (n_bodies > 1)
          simulated.label = body_label(body_parameters, i);
        if (parameters.output.compare_with_corotational)
          {
            simulated.reference = std::make_unique<Scene>(body_parameters.exact_corotational());
          }
        // What the summary compares with exact corotation: each step's velocity error,
        // estimated by WCC's own factor (a peer has none).
        if (parameters.output.exact_steps_timed > 0 &&
            dynamic_cast<const fem::WarpCancelingModel *>(&simulated.scene->model()) &&
            !simulated.scene->model().linear_solver())
          simulated.scene->model().measure_velocity_errors();

        const auto &body = simulated.scene->body();
        simulated.element_centres.resize(body.n_elements(), fem::Vector3::Zero());
        for (unsigned int e = 0; e < body.n_elements(); ++e)
          for (const unsigned int v : body.element_vertices(e))
            simulated.element_centres[e] += 0.25 * body.rest_positions()[v];
        const auto &tool = simulated.scene->loads().tool.vertices;
        for (const unsigned int v : tool)
          simulated.tool_centre += body.rest_positions()[v] / static_cast<double>(tool.size());
      }
  }

  void Simulation::add_vtu_seconds(const double seconds, const unsigned int runs)
  {
    // One file holds every body: each body's share of the output stage is its part.
    for (auto &simulated : bodies)
      simulated.totals.stages.add(stage::vtu_output, seconds / bodies.size(), runs);
  }

  void Simulation::write_vtu(const unsigned int step)
  {
    const Stopwatch stopwatch;
    std::vector<BodySnapshot> snapshots;
    for (const auto &simulated : bodies)
      {
        const auto &integrator = simulated.scene->integrator();
        BodySnapshot snapshot;
        snapshot.body          = &simulated.scene->body();
        snapshot.offset        = simulated.offset;
        snapshot.displacements = integrator.displacements();
        snapshot.velocities    = integrator.velocities();
        snapshot.record        = simulated.scene->model().rerotation_record();
        snapshots.push_back(std::move(snapshot));
        const fem::Surgery &surgery = integrator.surgery();
        if (surgery.active())
          {
            const auto &body             = simulated.scene->body();
            snapshots.back().cut_steps = surgery.cut_steps();
            snapshots.back().cut_steps.resize(body.n_elements(), -1);
            snapshots.back().grasped = surgery.grasped_vertices(body.n_vertices());
          }
        if (const fem::ContactConstraints *contact = integrator.contact())
          {
            const auto  &body     = simulated.scene->body();
            BodySnapshot &snapshot = snapshots.back();
            snapshot.contact_forces = contact->vertex_forces();
            snapshot.contact_gaps   = contact->vertex_gaps();
            snapshot.contact_forces.resize(body.n_vertices(), fem::Vector3::Zero());
            snapshot.contact_gaps.resize(body.n_vertices(), contact->settings().margin);
            // A plane is drawn as a square twice the body's size around its point.
            fem::Vector3 lower = body.rest_positions()[0], upper = lower;
            for (const fem::Vector3 &x : body.rest_positions())
              {
                lower = lower.cwiseMin(x);
                upper = upper.cwiseMax(x);
              }
            for (const fem::Obstacle &obstacle : contact->obstacles())
              snapshot.obstacles.push_back(obstacle.boundary(integrator.time(), 2 * (upper - lower).norm()));
          }
      }
    vtu_series->write(step, bodies[0].scene->integrator().time(), std::move(snapshots));
    add_vtu_seconds(stopwatch.seconds(), 1);
  }

  void RunTotals::add_step(const fem::StepStatistics &step, const double step_seconds)
  {
    ++steps;
    elements_rerotated += step.elements_rerotated;
    last_elements_rerotated = step.elements_rerotated;
    max_elements_rerotated =
      std::max(max_elements_rerotated, static_cast<double>(step.elements_rerotated));
    if (step.elements_rerotated > 0)
      {
        ++steps_with_rerotations;
        trailing_steps_without_rerotation = 0;
      }
    else
      ++trailing_steps_without_rerotation;
    if (step.refactorized)
      {
        ++refactorizations;
        ++factor_methods[cholesky::to_string(step.factorization.method)];
        columns_recomputed_pct += 100.0 * step.columns_recomputed / step.n_columns;
        flops_recomputed_pct += 100.0 * step.flops_recomputed / step.flops_full;
      }
    stages.add(step.stages);
    cg_iterations += step.cg_iterations;
    rotation_paths += step.rotation_paths;
    if (step.rerotation_threshold >= 0)
      {
        threshold_sum += step.rerotation_threshold;
        min_threshold = std::min(min_threshold, step.rerotation_threshold);
        max_threshold = std::max(max_threshold, step.rerotation_threshold);
      }
    if (step.velocity_error >= 0)
      {
        velocity_error_sum += step.velocity_error;
        max_velocity_error = std::max(max_velocity_error, step.velocity_error);
      }
    if (!step.refresh.empty())
      ++refreshes[step.refresh];
    if (step.choice != fem::StepChoice::not_chosen)
      ++choices[fem::to_string(step.choice)];
    if (step.factor_lag >= 0)
      {
        factor_lag_sum += step.factor_lag;
        ++factor_lag_steps;
      }
    elements_cut += step.elements_cut;
    elements_changed += step.elements_changed;
    vertices_grasped += step.vertices_grasped;
    vertices_released += step.vertices_released;
    if (step.change_columns > 0)
      {
        ++change_steps;
        change_columns_pct += 100.0 * step.change_columns / step.n_columns;
        if (step.flops_full > 0)
          change_flops_pct += 100.0 * step.change_flops / step.flops_full;
      }
    this->step_seconds += step_seconds;
  }

  void Simulation::advance(SimulatedBody &simulated, const unsigned int step)
  {
    auto       &integrator = simulated.scene->integrator();
    auto       &model      = simulated.scene->model();
    const auto &body       = simulated.scene->body();

    fem::StepStatistics statistics;
    Stopwatch           stopwatch;
    integrator.advance(statistics);
    const double step_seconds = stopwatch.seconds();

    // Gauss-Seidel short of its tolerance: said once a run (with the residual), the run goes on.
    if (const fem::ContactConstraints *contact = integrator.contact();
        contact && !contact->last_step().gauss_seidel.converged && !simulated.warned_gauss_seidel)
      {
        const auto &settings = contact->settings();
        std::cerr << "warpchol: warning: " << settings.max_iterations_origin << " = "
                  << settings.gauss_seidel.max_iterations << ": Gauss-Seidel stopped at step " << step
                  << " with residual " << format_number(contact->last_step().gauss_seidel.residual, 3)
                  << " m/s, above Contact/Tolerance = " << format_number(settings.gauss_seidel.tolerance, 3)
                  << " (later steps not reported); the run goes on" << std::endl;
        simulated.warned_gauss_seidel = true;
      }
    // Penalty springs yield: a penetration past the tolerance is said once a run, the run goes on.
    if (const fem::ContactConstraints *contact = integrator.contact();
        contact && contact->settings().method == fem::ContactMethod::penalty &&
        contact->last_step().largest_penetration > contact->settings().tolerance && !simulated.warned_penetration)
      {
        std::cerr << "warpchol: warning: " << contact->settings().tolerance_origin << " = "
                  << format_number(contact->settings().tolerance, 3) << ": the penalty springs left "
                  << format_number(contact->last_step().largest_penetration, 3) << " m of penetration at step "
                  << step << " (later steps not reported); a stiffer Contact/Penalty stiffness or "
                  << "Contact/Method = constraints holds it; the run goes on" << std::endl;
        simulated.warned_penetration = true;
      }

    auto &t = simulated.totals;
    t.add_step(statistics, step_seconds);
    if (!simulated.scene->loads().tool.vertices.empty())
      {
        const auto &rerotated = model.rerotation_record().rerotated;
        for (unsigned int e = 0; e < rerotated.size(); ++e)
          if (rerotated[e])
            t.rerotated_distance_to_tool += (simulated.element_centres[e] - simulated.tool_centre).norm();
      }

    double error_vs_corotational = -1, rms_error_vs_corotational = -1;
    if (simulated.reference)
      {
        StageTimer          timer(t.stages, stage::reference_run);
        fem::StepStatistics reference_statistics;
        try
          {
            simulated.reference->integrator().advance(reference_statistics);
          }
        catch (const MatrixError &error)
          {
            throw MatrixError(std::string("the corotational reference run: ") + error.what());
          }
        const PositionError error = position_error(
          integrator.positions(), simulated.reference->integrator().positions(), body.rest_positions());
        error_vs_corotational     = error.max;
        rms_error_vs_corotational = error.rms;
        t.error_vs_corotational.add(error);
      }

    // The balance of the detector takes the elastic energy the step computed (one step
    // late); the log, which shows it, the current one (a pass over the elements).
    const bool track_energy = parameters.time_stepping.energy_growth_limit > 0 || simulated.log;
    if (track_energy)
      {
        StageTimer timer(t.stages, stage::energy_balance);
        simulated.energy_balance->record(integrator, simulated.log ?
                                                       fem::EnergyBalance::ElasticEnergy::current :
                                                       fem::EnergyBalance::ElasticEnergy::at_step_start);
      }
    if (simulated.log)
      {
        StageTimer timer(t.stages, stage::log);
        StepLogRow row;
        row.step           = step;
        row.time           = integrator.time();
        row.statistics     = statistics;
        row.n_elements     = body.n_elements();
        row.step_seconds   = step_seconds;
        row.kinetic_energy = integrator.kinetic_energy();
        row.elastic_energy = integrator.elastic_energy();
        row.potential_energy  = integrator.potential_energy();
        row.tool_energy       = integrator.tool_energy();
        row.total_energy      = integrator.total_energy();
        row.external_work     = integrator.external_work();
        row.change_energy     = integrator.change_energy();
        row.tool_work_on_body = integrator.tool_work_on_body();
        row.energy_ratio      = simulated.energy_balance->ratio();
        row.error_vs_corotational     = error_vs_corotational;
        row.rms_error_vs_corotational = rms_error_vs_corotational;
        if (const fem::ContactConstraints *contact = integrator.contact())
          {
            row.contact              = contact->last_step();
            row.contact_work         = contact->work_on_body();
            row.friction_dissipation = contact->friction_dissipation();
          }
        simulated.log->add(row);
      }
    if (track_energy)
      check_energy(simulated, step);
  }

  std::string Simulation::checkpoint_file() const
  {
    return directory + "/checkpoint.bin";
  }

  void Simulation::resume()
  {
    resuming = true;
  }

  void Simulation::write_checkpoint(const unsigned int step, const double run_seconds)
  {
    // The VTU files the checkpoint lists must be whole before it says they are.
    if (vtu_series)
      vtu_series->finish();
    write_file_atomically(checkpoint_file(), [&](std::ostream &out) {
      BinaryWriter writer(out);
      writer.section(checkpoint_format);
      writer.write(parameters.entries);
      writer.write(step);
      writer.write(seconds_before_resume + run_seconds);
      writer.write(static_cast<std::uint64_t>(bodies.size()));
      for (const auto &simulated : bodies)
        {
          writer.section("body");
          simulated.scene->integrator().save_state(writer);
          writer.write(simulated.reference != nullptr);
          if (simulated.reference)
            simulated.reference->integrator().save_state(writer);
          simulated.energy_balance->save(writer);
          save_totals(writer, simulated.totals);
          writer.write(simulated.stopped);
          writer.write(simulated.log != nullptr);
          if (simulated.log)
            simulated.log->save(writer);
        }
      writer.write(vtu_series != nullptr);
      if (vtu_series)
        vtu_series->save(writer);
      writer.section("end");
    });
  }

  void Simulation::read_checkpoint()
  {
    const std::string file = checkpoint_file();
    std::error_code   error;
    if (!std::filesystem::exists(file, error))
      throw InputError(file + ": no checkpoint to resume from (Output/Checkpoint interval = N "
                              "writes one every N steps)");
    std::ifstream in   = open_input_file(file, "checkpoint");
    const auto    size = std::filesystem::file_size(file, error);
    if (error)
      throw InputError(file + ": cannot read the checkpoint's size: " + error.message());
    BinaryReader reader(in, file, size);
    reader.expect_section(checkpoint_format);

    // The parameters must be those that wrote it, but for what changes no result.
    std::vector<std::string> written_with;
    reader.read(written_with);
    std::map<std::string, std::string> written;
    for (const auto &entry : written_with)
      written[entry_name(entry)] = entry;
    for (const auto &entry : parameters.entries)
      {
        const std::string name = entry_name(entry);
        if (may_differ_on_resume(name))
          continue;
        const auto found = written.find(name);
        if (found == written.end())
          throw InputError(file + ": was written without the entry " + name +
                           " (another version of warpchol): cannot resume from it");
        if (found->second != entry)
          throw InputError(file + ": was written with " + found->second + ", the parameter file has " +
                           entry + ": resume with the parameters that wrote it");
      }

    const auto step = reader.get<unsigned int>();
    if (step > parameters.time_stepping.n_steps)
      throw InputError(file + ": the checkpoint is at step " + std::to_string(step) +
                       ", past Time stepping/Number of steps = " +
                       std::to_string(parameters.time_stepping.n_steps));
    reader.read(seconds_before_resume);
    if (reader.get<std::uint64_t>() != bodies.size())
      reader.fail("holds another number of bodies");
    for (auto &simulated : bodies)
      {
        reader.expect_section("body");
        simulated.scene->integrator().load_state(reader);
        if (reader.get<bool>() != (simulated.reference != nullptr))
          reader.fail("the corotational reference run differs");
        if (simulated.reference)
          simulated.reference->integrator().load_state(reader);
        simulated.energy_balance->load(reader);
        load_totals(reader, simulated.totals);
        reader.read(simulated.stopped);
        if (reader.get<bool>() != (simulated.log != nullptr))
          reader.fail("the log differs");
        if (simulated.log)
          simulated.log->load(reader);
      }
    // The files the run wrote so far: listed on in the series, or read past by a run that
    // writes none now (VTU interval = 0); one that did not write any starts its series here.
    if (reader.get<bool>())
      {
        VtuSeries not_written_now(directory, parameters.scene_name(), parameters.output.vtu_precision);
        (vtu_series ? *vtu_series : not_written_now).load(reader);
      }
    reader.expect_section("end");
    first_step = step + 1;
  }

  bool Simulation::advance_bodies(const unsigned int step)
  {
    bool all_at_rest = step > 1;
    for (auto &simulated : bodies)
      {
        if (!simulated.stopped.empty())
          continue;
        try
          {
            advance(simulated, step);
          }
        catch (const SimulationError &error)
          {
            if (simulated.label.empty())
              {
                keep_what_was_written();
                throw;
              }
            if (simulated.log)
              simulated.log->flush();
            // One body of several diverged: it stays where it was (the report's
            // side-by-side pictures show it), the others go on.
            simulated.stopped = error.what();
            std::cerr << "warpchol: " << simulated.label << ": " << simulated.stopped
                      << "; it stops there, the other bodies go on" << std::endl;
          }
        catch (const Error &error)
          {
            keep_what_was_written();
            if (simulated.label.empty())
              throw;
            // The same kind of error, naming the body.
            const std::string message = simulated.label + ": " + error.what();
            if (dynamic_cast<const InputError *>(&error))
              throw InputError(message);
            if (dynamic_cast<const OutputError *>(&error))
              throw OutputError(message);
            if (dynamic_cast<const MatrixError *>(&error))
              throw MatrixError(message);
            throw Error(message);
          }
        all_at_rest = all_at_rest && (!simulated.stopped.empty() ||
                                      simulated.scene->integrator().kinetic_energy() <
                                        parameters.time_stepping.rest_kinetic_energy);
      }
    return all_at_rest;
  }

  void Simulation::print_progress(const unsigned int step, const double seconds_per_step) const
  {
    const unsigned int n_steps = parameters.time_stepping.n_steps;
    const auto &first = bodies[0];
    std::cerr << "\rstep " << step << "/" << n_steps << "  t = "
              << format_number(first.scene->integrator().time(), 4) << " s";
    if (bodies.size() == 1)
      std::cerr << "  re-rotated "
                << format_number(100.0 * first.totals.last_elements_rerotated /
                                   first.scene->body().n_elements(), 3)
                << " %";
    std::cerr << "  " << format_number(seconds_per_step, 3)
              << " s/step   " << std::flush;
  }

  void Simulation::run(std::ostream &out)
  {
    // End to end: the initial VTU file and the log's creation count as part of the run.
    const Stopwatch run_stopwatch;
    const auto &settings = parameters.output;
    for (unsigned int i = 0; i < bodies.size(); ++i)
      if (settings.write_log)
        bodies[i].log = std::make_unique<StepLog>(
          directory + (bodies.size() == 1 ? "/log.csv" : "/log_body" + std::to_string(i + 1) + ".csv"),
          bodies[i].reference != nullptr, bodies[i].scene->integrator().contact() != nullptr);
    if (settings.vtu_interval > 0)
      vtu_series = std::make_unique<VtuSeries>(directory, parameters.scene_name(), settings.vtu_precision);
    const bool show_progress =
      settings.progress == "on" || (settings.progress == "auto" && isatty(fileno(stderr)));
    if (resuming)
      {
        read_checkpoint();
        if (show_progress)
          std::cerr << "resuming from " << checkpoint_file() << " at step " << first_step << " of "
                    << parameters.time_stepping.n_steps << std::endl;
      }
    else if (vtu_series)
      write_vtu(0);

    Stopwatch since_progress;
    const unsigned int n_steps = parameters.time_stepping.n_steps;
    for (unsigned int step = first_step; step <= n_steps; ++step)
      {
        const bool all_at_rest = advance_bodies(step);
        if (vtu_series && step % settings.vtu_interval == 0)
          write_vtu(step);
        if (settings.checkpoint_interval > 0 && step % settings.checkpoint_interval == 0)
          {
            const Stopwatch stopwatch;
            write_checkpoint(step, run_stopwatch.seconds());
            for (auto &simulated : bodies)
              simulated.totals.stages.add(stage::checkpoint, stopwatch.seconds() / bodies.size());
          }
        if (show_progress && (since_progress.seconds() > 0.5 || step == n_steps))
          {
            print_progress(step, run_stopwatch.seconds() / (step + 1 - first_step));
            since_progress.restart();
          }
        if (parameters.time_stepping.rest_kinetic_energy > 0 && all_at_rest)
          break;
      }
    if (show_progress)
      std::cerr << std::endl;
    if (vtu_series)
      {
        // Waiting for the last file ends that file's run.
        const Stopwatch stopwatch;
        vtu_series->finish();
        add_vtu_seconds(stopwatch.seconds(), 0);
      }
    for (auto &simulated : bodies)
      if (simulated.log)
        {
          StageTimer timer(simulated.totals.stages, stage::log);
          simulated.log->flush();
        }
    const double run_seconds = seconds_before_resume + run_stopwatch.seconds();
    for (auto &simulated : bodies)
      simulated.totals.run_seconds = run_seconds;
    // After the run, not during it: the exact steps do not slow the run they are compared with.
    for (unsigned int i = 0; i < bodies.size(); ++i)
      if (parameters.output.exact_steps_timed > 0 && bodies[i].scene->parameters().model.type != fem::ModelType::corotational)
        bodies[i].exact_step_seconds = time_exact_steps(parameters.body(i), parameters.output.exact_steps_timed);
    print_summary(out);
  }

  void Simulation::keep_what_was_written() noexcept
  {
    // The error being reported comes first: one that these writes meet (the disk that
    // filled up) is not reported on top of it.
    for (auto &body : bodies)
      if (body.log)
        try
          {
            body.log->flush();
          }
        catch (...)
          {}
    if (vtu_series)
      try
        {
          vtu_series->finish();
        }
      catch (...)
        {}
  }

  void Simulation::check_energy(const SimulatedBody &simulated, const unsigned int step)
  {
    const auto  &balance    = *simulated.energy_balance;
    const double limit      = parameters.time_stepping.energy_growth_limit;
    const bool   not_finite = !balance.all_finite();
    if (!not_finite && !(limit > 0 && balance.ratio() > limit))
      return;
    // Stop before writing the runaway state; what earlier steps wrote stays complete.
    keep_what_was_written();
    const auto       &integrator = simulated.scene->integrator();
    const std::string where = "step " + std::to_string(step) + ": the energy of " +
                              simulated.scene->model().name();
    if (not_finite)
      throw SimulationError(where + " is not finite: the simulation diverged");
    // What the changes of the body put in is named where there are any.
    const bool   changes = integrator.surgery().active();
    const double change  = integrator.change_energy();
    throw SimulationError(where + " grew to " + format_number(balance.held_energy(), 3) +
                          " J (start " + format_number(integrator.initial_energy(), 3) +
                          " J, work of the external loads " +
                          format_number(balance.energy_put_in() - integrator.initial_energy() - change, 3) +
                          (changes ? " J, changes of the body " + format_number(change, 3) : std::string()) +
                          " J), over Time stepping/Energy growth limit = " + format_number(limit) +
                          " times what was put in: the simulation diverged");
  }

  void Simulation::print_summary(std::ostream &out) const
  {
    const auto &scene = *bodies[0].scene;
    const auto &body  = scene.body();
    out << "scene " << parameters.scene_name() << ": " << scene.mesh_description();
    if (bodies.size() > 1)
      out << ", " << bodies.size() << " bodies side by side";
    out << "\n";
    out << "  mesh: " << body.n_vertices() << " vertices, " << body.n_elements() << " tets, "
        << scene.fixed_vertices().size() << " fixed vertices, " << body.n_unknowns()
        << " unknowns, mass " << format_number(body.total_mass(), 3) << " kg";
    if (bodies.size() > 1)
      out << " (each body)";
    out << "\n";
    for (const auto &simulated : bodies)
      {
        if (!simulated.label.empty())
          out << simulated.label << ", shown shifted by " << format_number(simulated.offset[0]) << ", "
              << format_number(simulated.offset[1]) << ", " << format_number(simulated.offset[2])
              << " m:\n";
        print_body_summary(out, simulated, parameters);
      }
    if (vtu_series)
      out << "  VTU: " << vtu_series->n_files() << " files, series " << vtu_series->pvd_file() << "\n";
    out << std::flush;
  }

  unsigned int Simulation::n_bodies() const
  {
    return bodies.size();
  }

  const Scene &Simulation::scene(const unsigned int index) const
  {
    return *bodies.at(index).scene;
  }

  const RunTotals &Simulation::totals(const unsigned int index) const
  {
    return bodies.at(index).totals;
  }

  const std::string &Simulation::output_directory() const
  {
    return directory;
  }

  void run_parameter_file(const std::string &parameter_file, std::ostream &out, std::ostream &err,
                          const bool resume)
  {
    const AllParameters parameters(parameter_file);
    parameters.print_warnings(err);
    Simulation          simulation(parameters);
    if (resume)
      simulation.resume();
    simulation.run(out);
  }

  namespace
  {
    const char *usage = "usage: warpchol PARAMS.prm          run the scene of a parameter file\n"
                        "       warpchol PARAMS.prm --resume go on from its last checkpoint\n"
                        "       mpirun -np N warpchol PARAMS.prm\n"
                        "       warpchol PARAMS.prm --distributed\n"
                        "                                    run it distributed (MPI, Trilinos,\n"
                        "                                    PETSc), on N ranks or on one\n"
                        "       warpchol --print-parameters [FILE]\n"
                        "                                    write the documented defaults\n"
                        "                                    (to FILE, which must not exist, or\n"
                        "                                    standard output)";
  }

  int report_errors(std::ostream &err, const std::function<void()> &action, const bool print)
  {
    const auto report = [&](const std::string &message, const int status) {
      if (print)
        err << "warpchol: error: " << message << std::endl;
      return status;
    };
    try
      {
        action();
        return 0;
      }
    catch (const InputError &error)
      {
        return report(error.what(), 2);
      }
    catch (const OutputError &error)
      {
        return report(error.what(), 3);
      }
    catch (const Error &error)
      {
        return report(error.what(), 1);
      }
    catch (const std::exception &error)
      {
        // deal.II and the standard library: keep their message on one line.
        std::string message = error.what();
        for (auto &c : message)
          if (c == '\n')
            c = ' ';
        return report(message, 1);
      }
  }

  int main(const int argc, const char *const *argv, std::ostream &out, std::ostream &err)
  {
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    return report_errors(err, [&] {
      if (arguments.size() == 1 && (arguments[0] == "--help" || arguments[0] == "-h"))
        {
          out << usage << std::endl;
          return;
        }
      if (!arguments.empty() && arguments[0] == "--print-parameters")
        {
          if (arguments.size() > 2)
            throw InputError("--print-parameters takes at most one file name");
          if (arguments.size() == 2)
            {
              // It replaced a scene once: a file that exists is left alone (standard
              // output, redirected, replaces one on purpose).
              std::error_code error;
              if (std::filesystem::exists(arguments[1], error))
                throw InputError(arguments[1] + ": exists already: --print-parameters writes a new file only "
                                                "(warpchol --print-parameters > FILE replaces one)");
              write_file_atomically(arguments[1], [](std::ostream &file) { AllParameters::print_defaults(file); });
            }
          else
            AllParameters::print_defaults(out);
          return;
        }
      const bool resume = arguments.size() == 2 && arguments[1] == "--resume";
      if ((arguments.size() != 1 && !resume) || arguments[0].empty() || arguments[0][0] == '-')
        throw InputError(arguments.empty() ? "no parameter file given" : "unexpected arguments (see warpchol --help)");
      // What was printed stays before the error line.
      try
        {
          run_parameter_file(arguments[0], out, err, resume);
        }
      catch (...)
        {
          out << std::flush;
          throw;
        }
    });
  }
} // namespace warpchol::app
