#include <warpchol/app/parameters.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>
#include <warpchol/models/warp_canceling_model.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace warpchol::app
{
  using dealii::ParameterHandler;
  using parameters::numbered_events;
  using parameters::parameter_handler_message;
  using parameters::refuse_binary;
  using parameters::trim;

  void AllParameters::declare_parameters(ParameterHandler &prm)
  {
    parameters::Mesh::declare_parameters(prm);
    parameters::Material::declare_parameters(prm);
    parameters::TimeStepping::declare_parameters(prm);
    parameters::Model::declare_parameters(prm);
    parameters::Solver::declare_parameters(prm);
    parameters::InitialState::declare_parameters(prm);
    parameters::FixedVertices::declare_parameters(prm);
    parameters::Gravity::declare_parameters(prm);
    parameters::RegionForce::declare_parameters(prm);
    parameters::Tool::declare_parameters(prm);
    parameters::Cut::declare_parameters(prm);
    parameters::Grasp::declare_parameters(prm);
    parameters::MaterialChange::declare_parameters(prm);
    parameters::Contact::declare_parameters(prm);
    parameters::Obstacle::declare_parameters(prm);
    // The numbered events ("Cut 2", ...) are declared where a file holds them (the constructor).
    parameters::Bodies::declare_parameters(prm);
    parameters::Output::declare_parameters(prm);
    parameters::Distributed::declare_parameters(prm);
    // Not deprecated in deal.II's sense, which prints its own warning to std::cerr at the
    // line of the text with its includes written out: ours names the file and line.
    for (const RenamedEntry &renamed : renamed_entries)
      {
        prm.enter_subsection(renamed.subsection);
        prm.declare_alias(renamed.new_name, renamed.old_name, false);
        prm.leave_subsection();
      }
  }

  void AllParameters::parse_parameters(ParameterHandler &prm)
  {
    mesh.parse_parameters(prm, file);
    material.parse_parameters(prm, file);
    time_stepping.parse_parameters(prm, file);
    model.parse_parameters(prm, file);
    solver.parse_parameters(prm, file);
    initial_state.parse_parameters(prm, file);
    fixed_vertices.parse_parameters(prm, file);
    gravity.parse_parameters(prm, file);
    region_force.parse_parameters(prm, file);
    tool.parse_parameters(prm, file);
    cuts.assign(1, {});
    grasps.assign(1, {});
    material_changes.assign(1, {});
    cuts[0].parse_parameters(prm, file);
    grasps[0].parse_parameters(prm, file);
    material_changes[0].parse_parameters(prm, file);
    for (const auto &name : numbered_events(file.text(), "Cut"))
      cuts.emplace_back().parse_parameters(prm, file, name);
    for (const auto &name : numbered_events(file.text(), "Grasp"))
      grasps.emplace_back().parse_parameters(prm, file, name);
    for (const auto &name : numbered_events(file.text(), "Material change"))
      material_changes.emplace_back().parse_parameters(prm, file, name);
    contact.parse_parameters(prm, file);
    obstacles.assign(1, {});
    obstacles[0].parse_parameters(prm, file);
    for (const auto &name : numbered_events(file.text(), "Obstacle"))
      obstacles.emplace_back().parse_parameters(prm, file, name);
    bodies.parse_parameters(prm, file);
    output.parse_parameters(prm, file);
    distributed.parse_parameters(prm, file);
    // What one entry allows only with another (WCC's rules, fem::wcc_setting_conflict):
    // said at the entry that asks for it; a body's own threshold at Bodies/Rerotation thresholds.
    const std::size_t n_bodies =
      std::max<std::size_t>({1, bodies.rerotation_thresholds.size(), bodies.model_types.size()});
    for (std::size_t i = 0; i < n_bodies; ++i)
      {
        const auto  &type      = bodies.model_types.empty() ? model.type : bodies.model_types[i];
        const bool   own       = !bodies.rerotation_thresholds.empty();
        const double threshold = own ? bodies.rerotation_thresholds[i] : model.rerotation_threshold;
        if (type != fem::ModelType::warp_canceling)
          continue;
        const auto conflict =
          fem::wcc_setting_conflict(threshold, model.target_error, model.strategy, solver.settings.method);
        if (!conflict)
          continue;
        if (own && conflict->rule == fem::SettingConflict::Rule::target_needs_finite_threshold)
          {
            prm.enter_subsection("Bodies");
            file.fail(prm, "Bodies", "Rerotation thresholds",
                      "with Model/Target error each body's threshold is where its adaptation "
                      "starts: finite and > 0 (got " + format_number(threshold) + ")");
          }
        prm.enter_subsection(conflict->subsection);
        file.fail(prm, conflict->subsection, conflict->entry, conflict->message);
      }
    check_backend(prm);
    const bool touches = std::any_of(obstacles.begin(), obstacles.end(), [](const auto &o) { return o.active(); });
    if (touches && solver.settings.method != cholesky::FactorizationMethod::supernodal)
      {
        prm.enter_subsection("Solver");
        file.fail(prm, "Solver", "Method",
                  "contact builds W = H A^-1 H^T from the supernodal factor's panels: needs Method = supernodal");
      }
    // CG's relative tolerance, set against the step's momentum, stops before it sees the
    // springs' stiff terms: penalty contact needs the step's direct solve.
    if (touches && contact.settings.method == fem::ContactMethod::penalty && model.strategy.iterates())
      for (const fem::ModelType type : model_types())
        if (type == fem::ModelType::warp_canceling)
          {
            prm.enter_subsection("Contact");
            file.fail(prm, "Contact", "Method",
                      "penalty springs need a direct solve, and Model/Strategy = " +
                        fem::to_string(model.strategy.kind) +
                        " iterates (CG stops before it sees their stiff terms): use Strategy = partial, or "
                        "Method = constraints");
          }
    read_paths();
    warn_about_ignored_entries(prm);
    warn_about_old_names();
  }

  void AllParameters::warn_about_old_names()
  {
    for (const auto &[where, renamed] : file.old_names())
      warnings.push_back(where + ": " + renamed.subsection + "/" + renamed.old_name + ": the old name of " +
                         renamed.subsection + "/" + renamed.new_name + ", read as it");
  }

  void AllParameters::warn_about_ignored_entries(ParameterHandler &prm)
  {
    warnings.clear();
    warn_about_mesh_and_material(prm);
    warn_about_model_and_solver(prm);
    warn_about_instruments(prm);
    warn_about_obstacles_and_output(prm);
    warn_about_run_kind(prm);
  }

  void AllParameters::warn_if_set(ParameterHandler &prm, const std::string &subsection,
                                  const std::vector<std::string> &entries, const std::string &choice)
  {
    for (const std::string &entry : entries)
      if (file.sets(subsection, entry))
        {
          // Each entry once, with the first choice that ignores it.
          const std::string where = file.where(subsection, entry) + " = ";
          if (std::any_of(warnings.begin(), warnings.end(),
                          [&](const std::string &warning) { return warning.rfind(where, 0) == 0; }))
            continue;
          prm.enter_subsection(subsection);
          warnings.push_back(where + excerpt(trim(prm.get(entry)), 60) + ": ignored with " + choice);
          prm.leave_subsection();
        }
  }

  void AllParameters::warn_about_region(ParameterHandler &prm, const RegionParameters &region,
                                        const std::string              &subsection,
                                        const std::vector<std::string> &what_it_moves)
  {
    const std::string choice = "Region = " + region.kind;
    if (region.kind != "box")
      warn_if_set(prm, subsection, {"Box lower corner", "Box upper corner"}, choice);
    if (region.kind != "sphere")
      warn_if_set(prm, subsection, {"Sphere center", "Sphere radius"}, choice);
    if (region.kind != "ids")
      warn_if_set(prm, subsection, {"Vertex ids"}, choice);
    if (region.kind == "none")
      warn_if_set(prm, subsection, what_it_moves, choice);
  }

  void AllParameters::warn_about_mesh_and_material(ParameterHandler &prm)
  {
    const std::string source = "Source = " + mesh.source;
    const std::vector<std::pair<std::string, std::vector<std::string>>> source_entries = {
      {"file", {"File", "Scale", "Refinements"}},
      {"torus", {"Torus major radius", "Torus minor radius", "Torus toroidal cells", "Torus refinements"}},
      {"box", {"Box lower corner", "Box upper corner", "Box subdivisions", "Box grading", "Box sliver flattening"}},
      {"cylinder", {"Cylinder radius", "Cylinder length", "Cylinder axial cells", "Cylinder refinements"}},
      {"tube",
       {"Tube inner radius", "Tube outer radius", "Tube length", "Tube circumferential cells", "Tube axial cells",
        "Tube refinements"}}};
    for (const auto &[other, entries] : source_entries)
      if (mesh.source != other)
        warn_if_set(prm, "Mesh", entries, source);
    if (material.total_mass > 0)
      warn_if_set(prm, "Material", {"Density"}, "Total mass = " + format_number(material.total_mass));
  }

  void AllParameters::warn_about_model_and_solver(ParameterHandler &prm)
  {
    const std::vector<std::string> wcc_entries = {"Rerotation threshold", "Target error", "Strategy",
                                                  "Iterate on", "CG tolerance", "Max CG iterations",
                                                  "Refresh interval", "Refresh iterations", "Background lag"};
    // A distributed run ignores Solver as a whole (warn_about_run_kind()).
    const bool        serial  = run == RunKind::serial;
    const auto        backend = solver.backend.backend;
    const std::string backend_choice = "Backend = " + backends::to_string(backend);
    // Model: WCC's entries, unless some body is WCC; then each strategy's own. A body's
    // own model and threshold (Bodies) stand for Model's.
    const std::vector<fem::ModelType> types = model_types();
    const bool any_wcc = std::find(types.begin(), types.end(), fem::ModelType::warp_canceling) != types.end();
    std::string model_list;
    for (const fem::ModelType type : bodies.model_types)
      model_list += (model_list.empty() ? "" : ", ") + fem::to_string(type);
    const std::string models = "Bodies/Models = " + excerpt(model_list, 60);
    if (!bodies.model_types.empty())
      warn_if_set(prm, "Model", {"Type"}, models);
    if (!any_wcc)
      {
        const std::string choice = bodies.model_types.empty() ? "Type = " + fem::to_string(model.type) : models;
        warn_if_set(prm, "Model", wcc_entries, choice);
        warn_if_set(prm, "Bodies", {"Rerotation thresholds"}, (bodies.model_types.empty() ? "Model/" : "") + choice);
      }
    else
      {
        const auto        kind     = model.strategy.kind;
        const std::string strategy = "Strategy = " + fem::to_string(kind);
        // The background refresh re-rotates every element; the steps re-rotate none.
        if (kind == fem::StepStrategy::Kind::background)
          warn_if_set(prm, "Model", {"Rerotation threshold"}, strategy);
        else if (!bodies.rerotation_thresholds.empty())
          warn_if_set(prm, "Model", {"Rerotation threshold"}, "Bodies/Rerotation thresholds");
        if (!model.strategy.iterates())
          warn_if_set(prm, "Model", {"Iterate on", "CG tolerance", "Max CG iterations"}, strategy);
        if (kind != fem::StepStrategy::Kind::delayed_top)
          warn_if_set(prm, "Model", {"Refresh interval", "Refresh iterations"}, strategy);
        if (kind != fem::StepStrategy::Kind::background)
          warn_if_set(prm, "Model", {"Background lag"}, strategy);
        if (serial && kind != fem::StepStrategy::Kind::delayed_top &&
            kind != fem::StepStrategy::Kind::automatic)
          warn_if_set(prm, "Solver", {"Top flops fraction"}, "Model/" + strategy);
        if (serial && !model.strategy.iterates())
          warn_if_set(prm, "Solver", {"Preconditioner precision"}, "Model/" + strategy);
      }
    if (!serial)
      return;
    if (!backends::iterates(backend))
      warn_if_set(prm, "Solver", {"Tolerance", "Max iterations"}, backend_choice);
    // A peer factors the matrix itself, in full, whenever it changes
    // (ElasticityModel::factorize_with_peer()); warpchol's ordering still counts the flops.
    // SOFA's warp preconditioner keeps the rest factor in double precision, never changed
    // (app::create_model()).
    if (backend == backends::Backend::warp_preconditioned_cg)
      warn_if_set(prm, "Solver", {"Change method", "Top flops fraction", "Preconditioner precision"},
                  backend_choice + " (its rest factor, in double precision, never changes)");
    else if (backends::replaces_factor(backend))
      warn_if_set(prm, "Solver", {"Method", "Change method", "Preconditioner precision"},
                  backend_choice + " (it factors the matrix itself)");
    // Only the supernodal factor takes a change by an update (SparseCholesky::may_update()).
    else if (solver.settings.method != cholesky::FactorizationMethod::supernodal)
      warn_if_set(prm, "Solver", {"Change method"}, "Method = " + cholesky::to_string(solver.settings.method));
  }

  void AllParameters::warn_about_instruments(ParameterHandler &prm)
  {
    warn_about_region(prm, fixed_vertices.region, "Fixed vertices", {});
    warn_about_region(prm, region_force.region, "Region force", {"Total force"});
    warn_about_region(prm, tool.region, "Tool", {"Spring stiffness", "Velocity", "Duration", "Path file"});
    // A path moves the targets for the whole run (fem::PullingTool::target_offset()).
    if (tool.region.kind != "none" && !tool.path.file_name.empty())
      warn_if_set(prm, "Tool", {"Duration"}, "Path file = " + tool.path.file_name);
    for (const auto &cut : cuts)
      if (cut.duration == 0)
        warn_if_set(prm, cut.subsection, {"Blade start", "Blade end", "Velocity", "Start time", "Path file"},
                    "Duration = 0 (no cut)");
      else if (!cut.path.file_name.empty())
        warn_if_set(prm, cut.subsection, {"Blade start", "Blade end"}, "Path file = " + cut.path.file_name);
    for (const auto &grasp : grasps)
      if (!grasp.active())
        warn_if_set(prm, grasp.subsection,
                    {"Sphere center", "Velocity", "Duration", "Grasp time", "Release time", "Spring stiffness",
                     "Path file"},
                    "Sphere radius = 0 (no grasp)");
      else if (!grasp.path.file_name.empty())
        warn_if_set(prm, grasp.subsection, {"Sphere center", "Duration"}, "Path file = " + grasp.path.file_name);
    for (const auto &change : material_changes)
      warn_about_region(prm, change.region, change.subsection, {"Time", "Stiffness factor", "Stress"});
    if (bodies.count == 1)
      warn_if_set(prm, "Bodies", {"Spacing"}, "Number of bodies = 1");
  }

  void AllParameters::warn_about_obstacles_and_output(ParameterHandler &prm)
  {
    // Each shape reads its own entries (Obstacle::build()); contact needs an obstacle.
    const std::vector<std::string> shape_entries = {"Point", "Normal", "End", "Radius", "Size", "File"};
    const std::vector<std::pair<std::string, std::vector<std::string>>> used_by_shape = {
      {"plane", {"Point", "Normal"}},
      {"sphere", {"Point", "Radius"}},
      {"capsule", {"Point", "End", "Radius"}},
      {"box", {"Point", "Size"}},
      {"surface", {"File"}}};
    for (const auto &obstacle : obstacles)
      if (!obstacle.active())
        {
          std::vector<std::string> entries = shape_entries;
          entries.insert(entries.end(), {"Friction", "Path file"});
          warn_if_set(prm, obstacle.subsection, entries, "Type = none");
        }
      else
        for (const auto &[shape, used] : used_by_shape)
          if (shape == obstacle.type)
            {
              std::vector<std::string> unused;
              for (const std::string &entry : shape_entries)
                if (std::find(used.begin(), used.end(), entry) == used.end())
                  unused.push_back(entry);
              warn_if_set(prm, obstacle.subsection, unused, "Type = " + obstacle.type);
            }
    if (std::none_of(obstacles.begin(), obstacles.end(), [](const auto &o) { return o.active(); }))
      warn_if_set(prm, "Contact",
                  {"Method", "Penalty stiffness", "Alarm distance", "Contact distance", "Max iterations", "Tolerance",
                   "Max contacts", "Compliance", "Compliance lag"},
                  "no obstacle (Obstacle/Type = none)");
    else if (contact.settings.method == fem::ContactMethod::penalty)
      {
        warn_if_set(prm, "Contact", {"Max iterations", "Tolerance", "Compliance", "Compliance lag"},
                    "Contact/Method = penalty");
        for (const auto &obstacle : obstacles)
          if (obstacle.active())
            warn_if_set(prm, obstacle.subsection, {"Friction"}, "Contact/Method = penalty");
      }
    else
      {
        warn_if_set(prm, "Contact", {"Penalty stiffness"}, "Contact/Method = constraints");
        if (contact.settings.compliance != cholesky::ComplianceMethod::paths)
          warn_if_set(prm, "Contact", {"Compliance lag"}, "Contact/Compliance = full solves");
        // The lag is checked by the correction's direct solve: a strategy that always
        // iterates (auto solves directly in its exact steps) never uses it.
        const auto types          = model_types();
        const bool always_iterate = model.strategy.iterates() && model.strategy.kind != fem::StepStrategy::Kind::automatic &&
                                    std::all_of(types.begin(), types.end(), [](const fem::ModelType type) {
                                      return type == fem::ModelType::warp_canceling;
                                    });
        if (always_iterate)
          warn_if_set(prm, "Contact", {"Compliance lag"}, "Model/Strategy = " + fem::to_string(model.strategy.kind));
      }
    if (output.vtu_interval == 0)
      warn_if_set(prm, "Output", {"VTU precision"}, "VTU interval = 0");
  }

  void AllParameters::warn_about_run_kind(ParameterHandler &prm)
  {
    // One kind of run reads Distributed, the other Solver (DistributedSimulation solves by
    // Distributed/Linear solver alone).
    if (run == RunKind::serial)
      {
        warn_if_set(prm, "Distributed", {"Linear solver", "Tolerance", "Max iterations"},
                    "a serial run (distributed: mpirun -np N with N > 1, or --distributed)");
        return;
      }
    warn_if_set(prm, "Solver",
                {"Ordering", "Method", "Threads", "Top flops fraction", "Backend", "Tolerance", "Max iterations",
                 "Change method", "Preconditioner precision"},
                "a distributed run (it solves by Distributed/Linear solver)");
    // DistributedSimulation has no instruments, no contact, no reference run and writes
    // its VTU pieces with deal.II's DataOut (float32).
    const std::string distributed_run = "a distributed run";
    for (const auto &cut : cuts)
      if (cut.active())
        warn_if_set(prm, cut.subsection, {"Duration"}, distributed_run + " (no cuts)");
    for (const auto &grasp : grasps)
      if (grasp.active())
        warn_if_set(prm, grasp.subsection, {"Sphere radius"}, distributed_run + " (no grasps)");
    for (const auto &change : material_changes)
      if (change.region.kind != "none")
        warn_if_set(prm, change.subsection, {"Region", "Stiffness factor"}, distributed_run + " (no material changes)");
    for (const auto &obstacle : obstacles)
      if (obstacle.active())
        warn_if_set(prm, obstacle.subsection, {"Type"}, distributed_run + " (no contact)");
    warn_if_set(prm, "Output", {"Exact steps timed"}, distributed_run);
    if (output.vtu_interval > 0)
      warn_if_set(prm, "Output", {"VTU precision"}, distributed_run + " (float32)");
    if (distributed.linear_solver == "mumps")
      warn_if_set(prm, "Distributed", {"Tolerance", "Max iterations"}, "Linear solver = mumps");
  }

  void AllParameters::print_warnings(std::ostream &err) const
  {
    for (const std::string &warning : warnings)
      err << "warpchol: warning: " << warning << "\n";
  }

  void AllParameters::check_backend(ParameterHandler &prm) const
  {
    const backends::Backend backend = solver.backend.backend;
    if (backend == backends::Backend::warpchol)
      return;
    const std::string name = backends::to_string(backend);
    if (std::any_of(obstacles.begin(), obstacles.end(), [](const auto &obstacle) { return obstacle.active(); }))
      {
        prm.enter_subsection("Solver");
        file.fail(prm, "Solver", "Backend",
                  "contact builds W = H A^-1 H^T from warpchol's own factor: needs Backend = warpchol, not " + name);
      }
    const auto        fail = [&](const std::string &message) {
      prm.enter_subsection("Solver");
      file.fail(prm, "Solver", "Backend", message);
    };
    for (const fem::ModelType type : model_types())
      {
        if (backend == backends::Backend::warp_preconditioned_cg && type != fem::ModelType::corotational)
          fail("solves the exact corotational system (CG preconditioned by the rotated rest "
               "factor): needs Model/Type = corotational, not " + fem::to_string(type));
        if (type == fem::ModelType::warp_canceling && model.strategy.kind != fem::StepStrategy::Kind::partial)
          fail(name + " factors in full and solves by itself: needs Model/Strategy = partial, not " +
               fem::to_string(model.strategy.kind));
        if (type == fem::ModelType::warp_canceling && model.target_error > 0)
          fail(name + " has no factor of warpchol's to measure a step's error with: needs "
                      "Model/Target error = 0");
      }
  }

  void AllParameters::read_paths()
  {
    const double end_of_run = time_stepping.n_steps * time_stepping.time_step;
    // A relative path is taken relative to the file that sets it, as a mesh file is.
    const auto read = [&](PathFile &path, const std::string &subsection, const unsigned int n_values,
                          const std::string &columns, const unsigned int optional_values = 0) {
      if (path.file_name.empty())
        return;
      const std::string name =
        path.file_name[0] == '/' ? path.file_name : file.directory_of(subsection, "Path file") + path.file_name;
      path = PathFile::read(name, n_values, columns, optional_values);
    };
    read(tool.path, "Tool", 3, "time, x, y, z");
    if (!tool.path.file_name.empty() && tool.region.kind != "none")
      tool.path.check_covers(0, end_of_run, "the run (Tool/Path file)");
    for (auto &cut : cuts)
      {
        read(cut.path, cut.subsection, 6, "time, start x, y, z, end x, y, z");
        if (!cut.path.file_name.empty() && cut.duration > 0 && cut.start_time < end_of_run)
          cut.path.check_covers(cut.start_time, std::min(cut.start_time + cut.duration, end_of_run),
                                cut.subsection + " (Start time to Start time + Duration)");
      }
    for (auto &obstacle : obstacles)
      {
        read(obstacle.path, obstacle.subsection, 3, "time, x, y, z[, rx, ry, rz]", 3);
        if (!obstacle.path.file_name.empty() && obstacle.active())
          obstacle.path.check_covers(0, end_of_run, obstacle.subsection + " (the run)");
      }
    for (auto &grasp : grasps)
      {
        read(grasp.path, grasp.subsection, 3, "time, x, y, z");
        if (!grasp.path.file_name.empty() && grasp.active() && grasp.grasp_time < end_of_run)
          grasp.path.check_covers(grasp.grasp_time, std::min(grasp.release_time, end_of_run),
                                  grasp.subsection + " (Grasp time to Release time)");
      }
  }

  AllParameters AllParameters::exact_corotational() const
  {
    AllParameters exact          = *this;
    exact.model.type             = fem::ModelType::corotational;
    exact.solver.backend.backend = backends::Backend::warpchol;
    return exact;
  }

  namespace
  {
    /** Every entry of @p prm as "Subsection/Entry = value", from its short PRM form. */
    std::vector<std::string> entry_list(const ParameterHandler &prm)
    {
      std::ostringstream text;
      prm.print_parameters(text, ParameterHandler::ShortPRM);
      std::istringstream       lines(text.str());
      std::vector<std::string> path, entries;
      for (std::string line; std::getline(lines, line);)
        {
          line = trim(line);
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(trim(line.substr(11)));
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0)
            {
              std::string prefix;
              for (const auto &name : path)
                prefix += name + "/";
              // "set Entry    = value": the alignment is not part of it.
              const std::string assignment = line.substr(4);
              const auto        equals     = assignment.find('=');
              entries.push_back(prefix + trim(assignment.substr(0, equals)) + " = " +
                                (equals == std::string::npos ? "" : trim(assignment.substr(equals + 1))));
            }
        }
      return entries;
    }
  } // namespace

  AllParameters::AllParameters()
  {
    ParameterHandler prm;
    declare_parameters(prm);
    parse_parameters(prm);
    entries = entry_list(prm);
  }

  AllParameters::AllParameters(const std::string &filename, const RunKind run_kind)
    : run(run_kind)
  {
    check_input_file(filename, "parameter file");
    refuse_binary(filename, filename);
    file = ParameterFileLocator(filename);
    ParameterHandler prm;
    declare_parameters(prm);
    for (const auto &name : numbered_events(file.text(), "Cut"))
      parameters::Cut::declare_parameters(prm, name);
    for (const auto &name : numbered_events(file.text(), "Grasp"))
      parameters::Grasp::declare_parameters(prm, name);
    for (const auto &name : numbered_events(file.text(), "Material change"))
      parameters::MaterialChange::declare_parameters(prm, name);
    for (const auto &name : numbered_events(file.text(), "Obstacle"))
      parameters::Obstacle::declare_parameters(prm, name);
    try
      {
        // deal.II reads .xml and .json files as such; a .prm file it is given as the
        // locator wrote it out, its includes in place (their paths resolved as ours).
        std::string extension = filename.substr(filename.find_last_of('.') + 1);
        std::transform(extension.begin(), extension.end(), extension.begin(),
                       [](const unsigned char c) { return std::tolower(c); });
        if (extension == "prm")
          {
            std::istringstream text(file.text());
            prm.parse_input(text, filename);
          }
        else
          prm.parse_input(filename);
      }
    catch (const dealii::ExceptionBase &error)
      {
        throw InputError(parameter_handler_message(error, file));
      }
    parse_parameters(prm);
    entries = entry_list(prm);
  }

  void AllParameters::print_defaults(std::ostream &out)
  {
    ParameterHandler prm;
    declare_parameters(prm);
    out << "# warpchol scene parameters (defaults). Run: warpchol FILE.prm\n";
    prm.print_parameters(out, ParameterHandler::PRM);
  }

  std::string AllParameters::scene_name() const
  {
    if (!output.scene.empty())
      return output.scene;
    std::string name = file.filename();
    const auto  slash = name.find_last_of('/');
    if (slash != std::string::npos)
      name = name.substr(slash + 1);
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".prm") == 0)
      name.resize(name.size() - 4);
    return name.empty() ? "scene" : name;
  }

  AllParameters AllParameters::body(const unsigned int index) const
  {
    AllParameters one = *this;
    if (!bodies.model_types.empty())
      one.model.type = bodies.model_types.at(index);
    if (!bodies.rerotation_thresholds.empty())
      one.model.rerotation_threshold = bodies.rerotation_thresholds.at(index);
    one.bodies = parameters::Bodies();
    return one;
  }

  std::vector<fem::ModelType> AllParameters::model_types() const
  {
    return bodies.model_types.empty() ? std::vector<fem::ModelType>{model.type} : bodies.model_types;
  }

  std::string AllParameters::mesh_file_path() const
  {
    if (mesh.file_name.empty() || mesh.file_name[0] == '/')
      return mesh.file_name;
    return file.directory_of("Mesh", "File") + mesh.file_name;
  }
} // namespace warpchol::app
