#include <warpchol/app/output.h>
#include <warpchol/app/scene_mesh.h>
#include <warpchol/app/simulation.h>
#include <warpchol/base/atomic_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/distributed/distributed_simulation.h>
#include <warpchol/dynamics/implicit_euler.h>
#include <warpchol/models/elasticity_model.h>
#include <warpchol/models/warp_canceling_model.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/numerics/data_out.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

#include <unistd.h>

namespace warpchol::distributed
{
  namespace
  {
    using fem::Matrix3;
    using fem::Vector3;

    /** How the tool's targets move: with its velocity, or along its path file. */
    fem::PullingTool tool_motion(const app::AllParameters &all)
    {
      return fem::PullingTool{{}, 0, all.tool.velocity, all.tool.duration, all.tool.path.path};
    }

    const std::array<Matrix3, 4> identity_frames{
      {Matrix3::Identity(), Matrix3::Identity(), Matrix3::Identity(), Matrix3::Identity()}};

    /** Whether WCC re-assembles the elements its error estimate picks (models/model_type.h). */
    bool reassembles_by_error_estimate(const app::parameters::Model &model)
    {
      return fem::reassembles_by_error_estimate(model.type, model.rerotation_threshold);
    }
  } // namespace

  bool launched_on_several_ranks()
  {
    for (const char *name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MPI_LOCALNRANKS"})
      if (const char *value = std::getenv(name); value != nullptr && std::atoi(value) > 1)
        return true;
    return false;
  }

  void DistributedSimulation::check_supported(app::AllParameters &parameters)
  {
    const auto &file   = parameters.file;
    const auto  refuse = [&](const std::string &subsection, const std::string &entry,
                            const std::string &value, const std::string &why) {
      throw InputError(file.where(subsection, entry) + " = " + value + ": " + why);
    };
    if (parameters.bodies.count > 1)
      refuse("Bodies", "Number of bodies", std::to_string(parameters.bodies.count),
             "a distributed run (mpirun, --distributed) simulates one body");
    if (parameters.output.checkpoint_interval > 0)
      refuse("Output", "Checkpoint interval", std::to_string(parameters.output.checkpoint_interval),
             "distributed runs write no checkpoint");
    if (parameters.output.compare_with_corotational)
      refuse("Output", "Compare with corotational", "true",
             "a distributed run does not run the corotational reference alongside");
    if (parameters.model.target_error > 0)
      refuse("Model", "Target error", format_number(parameters.model.target_error),
             "a distributed run keeps the re-rotation threshold fixed (its solver is not warpchol's factor)");
    // auto chooses among warpchol's own factor's refreshes: what the distributed engine
    // has of them is the exact WCC system, solved by Distributed/Linear solver.
    if (parameters.model.type == fem::ModelType::warp_canceling &&
        parameters.model.strategy.kind == fem::StepStrategy::Kind::automatic)
      {
        parameters.warnings.push_back(file.where("Model", "Strategy") +
                                      " = auto: a distributed run takes partial (the WCC system "
                                      "solved by Distributed/Linear solver)");
        parameters.model.strategy.kind = fem::StepStrategy::Kind::partial;
      }
    if (parameters.model.type == fem::ModelType::warp_canceling &&
        parameters.model.strategy.kind != fem::StepStrategy::Kind::partial)
      refuse("Model", "Strategy", to_string(parameters.model.strategy.kind),
             "a distributed run solves the WCC system with Distributed/Linear solver (Strategy = partial)");
    if (parameters.time_stepping.rest_kinetic_energy > 0)
      refuse("Time stepping", "Rest kinetic energy", format_number(parameters.time_stepping.rest_kinetic_energy),
             "a distributed run takes Number of steps steps");
    if (parameters.output.write_log || parameters.output.vtu_interval > 0)
      app::create_directory(parameters.output.directory + "/" + parameters.scene_name());
  }

  DistributedSimulation::DistributedSimulation(const app::AllParameters &parameters, app::SceneMesh &mesh,
                                               const MPI_Comm communicator)
    : all(parameters)
    , directory(parameters.output.directory + "/" + parameters.scene_name())
  {
    Stopwatch stopwatch;
    mesh_text        = mesh.description();
    distributed_body = std::make_unique<DistributedBody>(
      mesh, mesh.material(), all.material.mass_matrix,
      mesh.marks(mesh.select_vertices(all.fixed_vertices.region, "Fixed vertices")), communicator);
    set_up_loads(mesh);

    solver = create_distributed_solver(all.distributed, *distributed_body, rigid_body_modes());
    // At rest every rotation is the identity: every model starts from the rest matrix.
    reset_matrix();
    for (const unsigned int e : distributed_body->owned_elements())
      add_element(e, identity_frames, Matrix3::Identity(), 1);
    solver->compress();

    const fem::ElasticBody &body = distributed_body->local_body();
    if (reassembles_by_error_estimate(all.model))
      {
        stored_frames.assign(body.n_elements(), identity_frames);
        last_estimate.reinit(distributed_body->triangulation().n_active_cells());
        last_rerotated.reinit(distributed_body->triangulation().n_active_cells());
      }
    const std::size_t n_owned_rows = distributed_body->locally_owned_dofs().n_elements();
    rhs.assign(n_owned_rows, 0.0);
    owned_field.reinit(distributed_body->locally_owned_dofs(), communicator);
    ghosted_field.reinit(distributed_body->locally_owned_dofs(), distributed_body->locally_relevant_dofs(),
                         communicator);
    setup_seconds = stopwatch.seconds();
  }

  void DistributedSimulation::set_up_loads(const app::SceneMesh &mesh)
  {
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    const unsigned int      n_vertices  = body.n_vertices();
    x = body.rest_positions();
    v.assign(n_vertices, Vector3::Zero());

    // The mesh's vertices of each region, as a lookup by mesh vertex.
    const auto marks = [&](const app::RegionParameters &region, const std::string &subsection) {
      const std::vector<bool>    in_region = mesh.marks(mesh.select_vertices(region, subsection));
      std::vector<unsigned char> local(n_vertices, 0);
      for (unsigned int i = 0; i < n_vertices; ++i)
        local[i] = in_region[distributed.mesh_vertex(i)];
      return local;
    };

    constant_forces.assign(n_vertices, Vector3::Zero());
    for (unsigned int i = 0; i < n_vertices; ++i)
      constant_forces[i] = body.vertex_mass(i) * all.gravity.acceleration;
    if (all.region_force.region.kind != "none" && all.region_force.total_force.norm() > 0)
      {
        // As the serial Scene: shared in proportion to the vertices' masses.
        const auto in_region   = marks(all.region_force.region, "Region force");
        double     region_mass = 0;
        for (const unsigned int i : distributed.owned_vertices())
          if (in_region[i])
            region_mass += body.vertex_mass(i);
        region_mass = distributed.sum(region_mass);
        for (unsigned int i = 0; i < n_vertices; ++i)
          if (in_region[i])
            constant_forces[i] += all.region_force.total_force * (body.vertex_mass(i) / region_mass);
      }
    is_tool_vertex.assign(n_vertices, 0);
    if (all.tool.region.kind != "none")
      is_tool_vertex = marks(all.tool.region, "Tool");

    coefficients = fem::SystemCoefficients::implicit_euler(all.time_stepping.time_step, all.time_stepping.rayleigh_mass,
                                                           all.time_stepping.rayleigh_stiffness);

    const auto &initial = all.initial_state;
    if (initial.linear_velocity.norm() > 0 || initial.angular_velocity.norm() > 0)
      {
        // v = linear + angular x (X - c), c the rest centre of mass (lumped masses).
        Vector3 moment = Vector3::Zero();
        double  mass   = 0;
        for (const unsigned int i : distributed.owned_vertices())
          {
            moment += body.vertex_mass(i) * body.rest_positions()[i];
            mass += body.vertex_mass(i);
          }
        Vector3 centre;
        for (unsigned int c = 0; c < 3; ++c)
          centre[c] = distributed.sum(moment[c]) / distributed.sum(mass);
        for (unsigned int i = 0; i < n_vertices; ++i)
          if (!body.is_fixed(i))
            v[i] = initial.linear_velocity + initial.angular_velocity.cross(body.rest_positions()[i] - centre);
      }
  }

  std::vector<double> DistributedSimulation::rigid_body_modes() const
  {
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    const std::size_t       n_rows      = distributed.locally_owned_dofs().n_elements();
    // Rotations about the origin span the same space as about the centre of mass.
    std::vector<double> modes(6 * n_rows, 0.0);
    for (const unsigned int i : distributed.owned_vertices())
      {
        if (body.is_fixed(i))
          continue;
        const int      row = distributed.first_owned_row(i);
        const Vector3 &X   = body.rest_positions()[i];
        for (unsigned int k = 0; k < 3; ++k)
          {
            modes[k * n_rows + row + k] = 1;
            const Vector3 rotation = Vector3::Unit(k).cross(X);
            for (unsigned int c = 0; c < 3; ++c)
              modes[(3 + k) * n_rows + row + c] = rotation[c];
          }
      }
    return modes;
  }

  void DistributedSimulation::element_dofs(const unsigned int e, std::array<dealii::types::global_dof_index, 12> &dofs,
                                           std::array<bool, 12> &free) const
  {
    const fem::ElasticBody &body = distributed_body->local_body();
    for (unsigned int a = 0; a < 4; ++a)
      {
        const unsigned int vertex = body.element_vertices(e)[a];
        for (unsigned int c = 0; c < 3; ++c)
          {
            dofs[3 * a + c] = distributed_body->dofs_of_vertex(vertex)[c];
            free[3 * a + c] = !body.is_fixed(vertex);
          }
      }
  }

  void DistributedSimulation::reset_matrix()
  {
    const fem::ElasticBody &body = distributed_body->local_body();
    solver->set_zero();
    const double spring = all.time_stepping.time_step * all.time_stepping.time_step * all.tool.spring_stiffness;
    for (const unsigned int i : distributed_body->owned_vertices())
      for (unsigned int c = 0; c < 3; ++c)
        {
          const auto dof = distributed_body->dofs_of_vertex(i)[c];
          if (body.is_fixed(i))
            solver->add_diagonal(dof, 1.0);
          else if (is_tool_vertex[i] && spring > 0)
            solver->add_diagonal(dof, spring);
        }
  }

  void DistributedSimulation::add_element(const unsigned int e, const std::array<Matrix3, 4> &nodal_rotations,
                                          const Matrix3 &element_rotation, const double factor)
  {
    add_element(e,
                fem::warped_element_matrix(distributed_body->local_body(), e, coefficients, nodal_rotations,
                                           element_rotation),
                factor);
  }

  void DistributedSimulation::add_element(const unsigned int e, const fem::ElementMatrix &matrix, const double factor)
  {
    std::array<dealii::types::global_dof_index, 12> dofs;
    std::array<bool, 12>                            free;
    element_dofs(e, dofs, free);
    solver->add(dofs, free, matrix, factor);
  }

  std::vector<unsigned int> DistributedSimulation::elements_to_rerotate(StageTimes &stages)
  {
    StageTimer              timer(stages, fem::stage::error_estimate);
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    std::vector<Vector3>    nodal_velocities(body.n_vertices());
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      nodal_velocities[i] = state.nodal_rotations[i].transpose() * v[i];
    const auto         &owned = distributed.owned_elements();
    std::vector<double> error(owned.size());
    double              impulse_sum = 0;
    for (std::size_t k = 0; k < owned.size(); ++k)
      {
        const unsigned int               e = owned[k];
        const fem::ElementErrorEstimate estimate =
          fem::estimate_element_error(body, coefficients, e, v, nodal_velocities, state.nodal_rotations,
                                      state.element_rotations[e], stored_frames[e], state.element_force_norms[e]);
        error[k] = estimate.error;
        impulse_sum += estimate.impulse;
      }
    // The impulse scale of the whole body: the same threshold means the same on every rank.
    const double scale = distributed.sum(impulse_sum) / distributed.n_global_elements();
    std::vector<unsigned int> rerotate;
    for (std::size_t k = 0; k < owned.size(); ++k)
      {
        const unsigned int e        = owned[k];
        const double       relative = scale > 0 ? error[k] / scale : 0.0;
        last_estimate[distributed.active_cell_index(e)] = relative;
        last_rerotated[distributed.active_cell_index(e)]  = 0;
        if (error[k] > all.model.rerotation_threshold * scale || !std::isfinite(error[k]))
          rerotate.push_back(e);
      }
    return rerotate;
  }

  void DistributedSimulation::advance(DistributedStep &step)
  {
    Stopwatch              stopwatch;
    const fem::ElasticBody &body = distributed_body->local_body();
    {
      const auto rotations = fem::rotations_of(all.model.type);
      StageTimer timer(step.stages, rotations == fem::ElasticBody::Rotations::none ? fem::stage::elastic_forces :
                                                                                      fem::stage::rotations);
      body.evaluate(x, rotations, state);
    }
    step.elements_rerotated = dealii::Utilities::MPI::sum(reassemble(step.stages), distributed_body->communicator());
    assemble_right_hand_side(step.stages);
    set_initial_guess(step.stages);
    solve(step);
    update_state(step.stages);
    step.seconds = stopwatch.seconds();
  }

  unsigned long DistributedSimulation::reassemble(StageTimes &stages)
  {
    // The matrix: in full (corotation), the elements over the threshold (WCC), or as it is.
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    if (fem::reassembles_every_step(all.model.type, all.model.rerotation_threshold))
      {
        StageTimer timer(stages, fem::stage::assembly);
        reset_matrix();
        const bool in_frames = fem::solves_in_nodal_frames(all.model.type);
        for (const unsigned int e : distributed.owned_elements())
          {
            std::array<Matrix3, 4> nodal = identity_frames;
            if (in_frames)
              for (unsigned int a = 0; a < 4; ++a)
                nodal[a] = state.nodal_rotations[body.element_vertices(e)[a]];
            add_element(e, nodal, state.element_rotations[e], 1);
          }
        solver->compress();
        return distributed.owned_elements().size();
      }
    if (!reassembles_by_error_estimate(all.model))
      return 0;
    const std::vector<unsigned int> rerotate = elements_to_rerotate(stages);
    StageTimer                      timer(stages, fem::stage::assembly);
    for (const unsigned int e : rerotate)
      {
        // Take the stored contribution out (its frames T_a stand for S_a^T Q with Q = I),
        // put the current one in.
        std::array<Matrix3, 4> old_nodal;
        for (unsigned int a = 0; a < 4; ++a)
          old_nodal[a] = stored_frames[e][a].transpose();
        add_element(e, old_nodal, Matrix3::Identity(), -1);
        add_element(e,
                    fem::rerotated_contribution(body, coefficients, e, state.nodal_rotations, state.element_rotations[e],
                                              stored_frames[e]),
                    1);
        last_rerotated[distributed.active_cell_index(e)] = 1;
      }
    // Collective: every rank, with or without re-rotations of its own.
    solver->compress();
    return rerotate.size();
  }

  void DistributedSimulation::assemble_right_hand_side(StageTimes &stages)
  {
    // rhs = M v + dt (f_ext + f_el(x) + k (target(t + dt) - x)), on the owned vertices.
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    const double            dt          = all.time_stepping.time_step;
    const bool              in_frames   = fem::solves_in_nodal_frames(all.model.type);
    StageTimer              timer(stages, fem::stage::right_hand_side);
    std::vector<Vector3>    momentum;
    if (body.mass_matrix_type() == fem::MassMatrix::consistent)
      {
        momentum.assign(body.n_vertices(), Vector3::Zero());
        body.add_mass_times(v, momentum);
      }
    const Vector3 offset = tool_motion(all).target_offset(time + dt);
    for (const unsigned int i : distributed.owned_vertices())
      {
        const int row = distributed.first_owned_row(i);
        if (body.is_fixed(i))
          {
            for (unsigned int c = 0; c < 3; ++c)
              rhs[row + c] = 0;
            continue;
          }
        Vector3 force = constant_forces[i] + state.forces[i];
        if (is_tool_vertex[i])
          force += all.tool.spring_stiffness * (body.rest_positions()[i] + offset - x[i]);
        Vector3 value = (momentum.empty() ? Vector3(body.vertex_mass(i) * v[i]) : momentum[i]) + dt * force;
        if (in_frames)
          value = state.nodal_rotations[i].transpose() * value;
        for (unsigned int c = 0; c < 3; ++c)
          rhs[row + c] = value[c];
      }
  }

  void DistributedSimulation::set_initial_guess(StageTimes &stages)
  {
    // CG's initial guess: the velocities extrapolated from the last two steps.
    const fem::ElasticBody &body      = distributed_body->local_body();
    const bool              in_frames = fem::solves_in_nodal_frames(all.model.type);
    StageTimer              timer(stages, fem::stage::initial_guess);
    solution.assign(rhs.size(), 0.0);
    for (const unsigned int i : distributed_body->owned_vertices())
      {
        if (body.is_fixed(i))
          continue;
        Vector3 guess = previous_v.empty() ? v[i] : Vector3(2 * v[i] - previous_v[i]);
        if (in_frames)
          guess = state.nodal_rotations[i].transpose() * guess;
        const int row = distributed_body->first_owned_row(i);
        for (unsigned int c = 0; c < 3; ++c)
          solution[row + c] = guess[c];
      }
  }

  void DistributedSimulation::solve(DistributedStep &step)
  {
    Stopwatch solve_watch;
    try
      {
        solver->solve(rhs, solution);
      }
    catch (const MatrixError &error)
      {
        throw MatrixError("step " + std::to_string(steps_done + 1) + ": " + error.what());
      }
    const double total = solve_watch.seconds();
    // The AMG hierarchy or MUMPS' factorization, when the solve made one.
    if (solver->last_setup_seconds() > 0)
      step.stages.add(fem::stage::factorization, solver->last_setup_seconds());
    step.stages.add(fem::stage::solve, total - solver->last_setup_seconds());
    step.cg_iterations = solver->last_iterations();
  }

  void DistributedSimulation::update_state(StageTimes &stages)
  {
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    const double            dt          = all.time_stepping.time_step;
    const bool              in_frames   = fem::solves_in_nodal_frames(all.model.type);
    StageTimer              timer(stages, fem::stage::position_update);
    // v = S y on the owned vertices, then everywhere through the ghosts.
    std::vector<Vector3> new_v(body.n_vertices(), Vector3::Zero());
    bool                 finite = true;
    for (const unsigned int i : distributed.owned_vertices())
      {
        const int row = distributed.first_owned_row(i);
        Vector3   value(solution[row], solution[row + 1], solution[row + 2]);
        if (in_frames)
          value = state.nodal_rotations[i] * value;
        new_v[i] = body.is_fixed(i) ? Vector3::Zero() : value;
        finite   = finite && std::isfinite(new_v[i].squaredNorm());
      }
    if (dealii::Utilities::MPI::logical_or(!finite, distributed.communicator()))
      throw MatrixError("step " + std::to_string(steps_done + 1) +
                        ": a velocity is not finite: the simulation diverged");
    to_dof_vector(new_v, ghosted_field);
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      for (unsigned int c = 0; c < 3; ++c)
        new_v[i][c] = ghosted_field[distributed.dofs_of_vertex(i)[c]];
    previous_v = std::move(v);
    v          = std::move(new_v);
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      x[i] += dt * v[i];
    time += dt;
    ++steps_done;
  }

  void DistributedSimulation::to_dof_vector(const std::vector<Vector3> &values,
                                            dealii::TrilinosWrappers::MPI::Vector &field) const
  {
    for (const unsigned int i : distributed_body->owned_vertices())
      {
        const int row = distributed_body->first_owned_row(i);
        for (unsigned int c = 0; c < 3; ++c)
          owned_field.begin()[row + c] = values[i][c];
      }
    field = owned_field;
  }

  double DistributedSimulation::kinetic_energy() const
  {
    const fem::ElasticBody &body = distributed_body->local_body();
    double                  sum  = 0;
    if (body.mass_matrix_type() == fem::MassMatrix::consistent)
      {
        std::vector<Vector3> momentum(body.n_vertices(), Vector3::Zero());
        body.add_mass_times(v, momentum);
        for (const unsigned int i : distributed_body->owned_vertices())
          sum += 0.5 * v[i].dot(momentum[i]);
      }
    else
      for (const unsigned int i : distributed_body->owned_vertices())
        sum += 0.5 * body.vertex_mass(i) * v[i].squaredNorm();
    return distributed_body->sum(sum);
  }

  double DistributedSimulation::elastic_energy() const
  {
    // The serial kernel on the local body (ghosts included), summed over the owned elements.
    const fem::ElasticBody &body = distributed_body->local_body();
    std::vector<Matrix3>    rotations;
    if (fem::rotations_of(all.model.type) != fem::ElasticBody::Rotations::none)
      body.compute_element_rotations(x, rotations);
    const std::vector<double> energies = body.element_energies(x, rotations.empty() ? nullptr : &rotations);
    double                    sum      = 0;
    for (const unsigned int e : distributed_body->owned_elements())
      sum += energies[e];
    return distributed_body->sum(sum);
  }

  double DistributedSimulation::potential_energy() const
  {
    const fem::ElasticBody &body = distributed_body->local_body();
    double                  sum  = 0;
    for (const unsigned int i : distributed_body->owned_vertices())
      sum -= constant_forces[i].dot(x[i] - body.rest_positions()[i]);
    return distributed_body->sum(sum);
  }

  double DistributedSimulation::tool_energy() const
  {
    const fem::ElasticBody &body   = distributed_body->local_body();
    const Vector3           offset = tool_motion(all).target_offset(time);
    double                  sum    = 0;
    for (const unsigned int i : distributed_body->owned_vertices())
      if (is_tool_vertex[i])
        sum += 0.5 * all.tool.spring_stiffness * (body.rest_positions()[i] + offset - x[i]).squaredNorm();
    return distributed_body->sum(sum);
  }

  void DistributedSimulation::write_vtu(const unsigned int step)
  {
    const DistributedBody  &distributed = *distributed_body;
    const fem::ElasticBody &body        = distributed.local_body();
    std::vector<Vector3>    displacement(body.n_vertices());
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      displacement[i] = x[i] - body.rest_positions()[i];
    dealii::TrilinosWrappers::MPI::Vector displacement_field(ghosted_field);
    dealii::TrilinosWrappers::MPI::Vector velocity_field(ghosted_field);
    to_dof_vector(displacement, displacement_field);
    to_dof_vector(v, velocity_field);

    dealii::Vector<float> rank(distributed.triangulation().n_active_cells());
    rank = static_cast<float>(distributed.rank());
    dealii::DataOut<3> data_out;
    data_out.attach_dof_handler(distributed.dof_handler());
    const std::vector<dealii::DataComponentInterpretation::DataComponentInterpretation> vector_field(
      3, dealii::DataComponentInterpretation::component_is_part_of_vector);
    data_out.add_data_vector(displacement_field, std::vector<std::string>(3, "displacement"),
                             dealii::DataOut<3>::type_dof_data, vector_field);
    data_out.add_data_vector(velocity_field, std::vector<std::string>(3, "velocity"),
                             dealii::DataOut<3>::type_dof_data, vector_field);
    data_out.add_data_vector(rank, "rank", dealii::DataOut<3>::type_cell_data);
    if (last_estimate.size() > 0)
      {
        data_out.add_data_vector(last_estimate, "error_estimate", dealii::DataOut<3>::type_cell_data);
        data_out.add_data_vector(last_rerotated, "rerotated", dealii::DataOut<3>::type_cell_data);
      }
    data_out.build_patches(distributed.mapping());
    // Without the writing time in its header, a step's file is the same bytes on every run.
    dealii::DataOutBase::VtkFlags flags;
    flags.print_date_and_time = false;
    data_out.set_flags(flags);

    std::ostringstream base;
    base << all.scene_name() << "-" << std::setw(5) << std::setfill('0') << step;
    const auto piece = [&](const unsigned int r) { return base.str() + "." + std::to_string(r) + ".vtu"; };
    write_file_atomically(directory + "/" + piece(distributed.rank()),
                          [&](std::ostream &out) { data_out.write_vtu(out); });
    // The record names the pieces once they are all written.
    MPI_Barrier(distributed.communicator());
    pvtu_records.emplace_back(time, base.str() + ".pvtu");
    if (distributed.rank() == 0)
      {
        std::vector<std::string> pieces;
        for (unsigned int r = 0; r < distributed.n_ranks(); ++r)
          pieces.push_back(piece(r));
        write_file_atomically(directory + "/" + base.str() + ".pvtu",
                              [&](std::ostream &out) { data_out.write_pvtu_record(out, pieces); });
        write_file_atomically(directory + "/" + all.scene_name() + ".pvd",
                              [&](std::ostream &out) { dealii::DataOutBase::write_pvd_record(out, pvtu_records); });
      }
  }

  void DistributedSimulation::run(std::ostream &out)
  {
    Stopwatch          run_watch;
    DistributedBody   &distributed = *distributed_body;
    const bool         root        = distributed.rank() == 0;
    const unsigned int n_steps     = all.time_stepping.n_steps;
    const bool         progress    = root && (all.output.progress == "on" ||
                                       (all.output.progress == "auto" && ::isatty(STDERR_FILENO)));
    const auto log_row = [&](const DistributedStep &step) {
      // The slowest rank's seconds: what the step waited for.
      const auto slowest = [&](const std::string &name) { return distributed.max(step.stages.seconds(name)); };
      const double t_rotations  = slowest(fem::stage::rotations) + slowest(fem::stage::elastic_forces);
      const double t_estimate   = slowest(fem::stage::error_estimate);
      const double t_assembly   = slowest(fem::stage::assembly);
      const double t_factor     = slowest(fem::stage::factorization);
      const double t_solve      = slowest(fem::stage::solve);
      const double t_step       = distributed.max(step.seconds);
      const double kinetic      = kinetic_energy();
      const double elastic      = elastic_energy();
      const double potential    = potential_energy();
      const double tool         = tool_energy();
      std::ostringstream line;
      line << std::setprecision(6) << steps_done << "," << time << "," << step.elements_rerotated << ","
           << step.cg_iterations << "," << t_rotations << "," << t_estimate << "," << t_assembly << ","
           << t_factor << "," << t_solve << "," << t_step << "," << std::setprecision(10) << kinetic << ","
           << elastic << "," << potential << "," << tool << "," << kinetic + elastic + potential + tool;
      log_rows.push_back(line.str());
    };

    if (all.output.vtu_interval > 0)
      write_vtu(0);
    for (unsigned int k = 1; k <= n_steps; ++k)
      {
        DistributedStep step;
        advance(step);
        stage_totals.add(step.stages);
        step_seconds += step.seconds;
        elements_rerotated += step.elements_rerotated;
        cg_iterations += step.cg_iterations;
        if (all.output.write_log)
          {
            StageTimer timer(stage_totals, app::stage::log);
            log_row(step);
          }
        if (all.output.vtu_interval > 0 && k % all.output.vtu_interval == 0)
          {
            StageTimer timer(stage_totals, app::stage::vtu_output);
            write_vtu(k);
          }
        if (progress)
          std::cerr << "\rstep " << k << "/" << n_steps << std::flush;
      }
    if (progress)
      std::cerr << "\r" << std::string(40, ' ') << "\r" << std::flush;
    if (all.output.write_log && root)
      write_file_atomically(directory + "/log.csv", [&](std::ostream &file) {
        file << "step,time,elements_rerotated,cg_iterations,t_rotations,t_error_estimate,t_assembly,t_factor,"
                "t_solve,t_step,kinetic_energy,elastic_energy,potential_energy,tool_energy,total_energy\n";
        for (const std::string &row : log_rows)
          file << row << "\n";
      });
    print_summary(out, run_watch.seconds());
  }

  void DistributedSimulation::print_summary(std::ostream &out, const double run_seconds) const
  {
    const DistributedBody &distributed = *distributed_body;
    const MPI_Comm         comm        = distributed.communicator();
    const unsigned int     n_ranks     = distributed.n_ranks();
    const auto             range       = [&](const double value) {
      const auto minmax = dealii::Utilities::MPI::min_max_avg(value, comm);
      return std::array<double, 3>{{minmax.min, minmax.avg, minmax.max}};
    };
    const auto owned_cells = range(distributed.owned_elements().size());
    const auto local_cells = range(distributed.local_body().n_elements());
    const double kinetic   = kinetic_energy();
    const double elastic   = elastic_energy();
    const double potential = potential_energy();
    const double tool      = tool_energy();
    // Every stage that ran on rank 0 (all ranks run the same stages), min/mean/max per step.
    std::vector<std::pair<std::string, std::array<double, 3>>> stage_rows;
    for (const auto &stage : stage_totals.stages())
      stage_rows.emplace_back(stage.name, range(stage.seconds / std::max(1u, steps_done)));
    const auto step_range  = range(step_seconds / std::max(1u, steps_done));
    const auto setup_range = range(setup_seconds);
    if (distributed.rank() != 0)
      return;

    const bool timings = all.output.print_timings;
    out << "scene " << all.scene_name() << ": " << mesh_text << ", distributed over " << n_ranks
        << (n_ranks == 1 ? " rank" : " ranks") << "\n";
    out << "  " << distributed.n_global_elements() << " tetrahedra, " << distributed.n_global_vertices()
        << " vertices, " << distributed.n_global_unknowns() << " unknowns; tetrahedra per rank "
        << static_cast<unsigned long>(owned_cells[0]) << " to " << static_cast<unsigned long>(owned_cells[2])
        << " owned, " << static_cast<unsigned long>(local_cells[0]) << " to "
        << static_cast<unsigned long>(local_cells[2]) << " with ghosts\n";
    out << "  model " << fem::to_string(all.model.type);
    if (all.model.type == fem::ModelType::warp_canceling)
      out << " (re-rotation threshold " << format_number(all.model.rerotation_threshold) << ")";
    out << ", linear solver "
        << (solver->name() == "mumps" ? "MUMPS (PETSc, direct)" :
                                         "Trilinos CG + ML AMG (tolerance " + format_number(all.distributed.tolerance) + ")")
        << "\n";
    out << "  steps " << steps_done << ", time " << format_number(time);
    if (solver->name() == "amg_cg")
      out << ", mean CG iterations " << std::fixed << std::setprecision(1)
          << static_cast<double>(cg_iterations) / std::max(1u, steps_done) << std::defaultfloat;
    if (reassembles_by_error_estimate(all.model))
      out << ", elements re-rotated per step " << std::fixed << std::setprecision(2)
          << 100.0 * elements_rerotated / std::max(1u, steps_done) / distributed.n_global_elements() << " %"
          << std::defaultfloat;
    out << "\n";
    out << std::setprecision(8) << "  final energies: kinetic " << kinetic << ", elastic " << elastic
        << ", potential " << potential << ", tool " << tool << std::setprecision(6) << "\n";
    if (timings)
      {
        out << std::fixed << std::setprecision(4);
        out << "  set-up " << setup_range[2] << " s, run " << run_seconds << " s, per step "
            << step_range[0] << " / " << step_range[1] << " / " << step_range[2] << " s (min / mean / max over ranks)\n";
        out << "  seconds per step by stage, min / mean / max over ranks:\n";
        for (const auto &[name, seconds] : stage_rows)
          out << "    " << std::left << std::setw(22) << name << std::right << std::setw(10) << seconds[0]
              << std::setw(10) << seconds[1] << std::setw(10) << seconds[2] << "\n";
        out << std::defaultfloat << std::setprecision(6);
      }
    else
      {
        out << "  stages:";
        for (const auto &[name, seconds] : stage_rows)
          out << " " << name << ";";
        out << "\n";
      }
    if (all.output.write_log || all.output.vtu_interval > 0)
      {
        out << "  results in " << directory << "/:";
        if (all.output.write_log)
          out << " log.csv";
        if (all.output.vtu_interval > 0)
          out << " " << all.scene_name() << ".pvd (" << pvtu_records.size() << " steps, " << n_ranks
              << (n_ranks == 1 ? " piece" : " pieces") << " each)";
        out << "\n";
      }
    out << std::flush;
  }

  const DistributedBody &DistributedSimulation::body() const
  {
    return *distributed_body;
  }

  int run_distributed(const int argc, const char *const *argv, const std::string &parameter_file,
                      std::ostream &out, std::ostream &err)
  {
    // MPI and PETSc read no option of ours: they get the program's name alone.
    int                     mpi_argc   = 1;
    std::string             program    = argc > 0 ? argv[0] : "warpchol";
    std::array<char *, 2>   mpi_args   = {{program.data(), nullptr}};
    char                  **mpi_argv   = mpi_args.data();
    dealii::Utilities::MPI::MPI_InitFinalize mpi(mpi_argc, mpi_argv, 1);
    const bool root = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

    // What every rank does alike: an error there is the same everywhere, said once.
    std::unique_ptr<app::AllParameters> parameters;
    std::unique_ptr<app::SceneMesh>     mesh;
    int status = app::report_errors(root ? err : std::cerr, [&] {
      parameters = std::make_unique<app::AllParameters>(parameter_file, app::RunKind::distributed);
      DistributedSimulation::check_supported(*parameters);
      if (root)
        parameters->print_warnings(err);
      mesh = std::make_unique<app::SceneMesh>(*parameters);
    }, root);
    if (status != 0)
      return status;

    // Collective: a rank that fails alone would leave the others waiting.
    status = app::report_errors(err, [&] {
      std::ostringstream    silent;
      DistributedSimulation simulation(*parameters, *mesh, MPI_COMM_WORLD);
      mesh.reset();
      simulation.run(root ? out : silent);
    });
    if (status != 0 && dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
      MPI_Abort(MPI_COMM_WORLD, status);
    return status;
  }
} // namespace warpchol::distributed
