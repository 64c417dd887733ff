#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/dynamics/implicit_euler.h>

#include <Eigen/Geometry>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace warpchol::fem
{
  Vector3 PullingTool::target_offset(const double time) const
  {
    if (!path.empty())
      return path.position(time) - path.position(0);
    return velocity * std::min(time, duration);
  }

  bool Loads::has_static_load() const
  {
    if (gravity.norm() > 0)
      return true;
    return std::any_of(vertex_forces.begin(), vertex_forces.end(),
                       [](const Vector3 &force) { return force.norm() > 0; });
  }

  std::vector<Vector3> rigid_body_velocities(const ElasticBody &body, const Vector3 &linear,
                                             const Vector3 &angular)
  {
    Vector3 centre = Vector3::Zero();
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      centre += body.vertex_mass(i) * body.rest_positions()[i];
    centre /= body.total_mass();
    std::vector<Vector3> velocities(body.n_vertices());
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      velocities[i] = linear + angular.cross(body.rest_positions()[i] - centre);
    return velocities;
  }

  std::vector<std::vector<double>> rigid_body_modes(const ElasticBody &body)
  {
    std::vector<std::vector<double>> modes;
    for (unsigned int k = 0; k < 6; ++k)
      {
        const Vector3              unit      = Vector3::Unit(k % 3);
        const std::vector<Vector3> velocities = k < 3 ? rigid_body_velocities(body, unit, Vector3::Zero()) :
                                                         rigid_body_velocities(body, Vector3::Zero(), unit);
        std::vector<double> mode(body.n_unknowns());
        for (unsigned int v = 0; v < body.n_vertices(); ++v)
          if (const Index first = body.first_unknown(v); first >= 0)
            for (unsigned int c = 0; c < 3; ++c)
              mode[first + c] = velocities[v][c];
        modes.push_back(std::move(mode));
      }
    return modes;
  }

  SystemCoefficients ImplicitEuler::coefficients(const ElasticBody &body, const double time_step,
                                                 const double rayleigh_mass,
                                                 const double rayleigh_stiffness,
                                                 const Loads &loads)
  {
    SystemCoefficients result =
      SystemCoefficients::implicit_euler(time_step, rayleigh_mass, rayleigh_stiffness);
    if (!loads.tool.vertices.empty() && loads.tool.stiffness > 0)
      {
        result.vertex_diagonal.assign(body.n_vertices(), 0.0);
        for (const unsigned int v : loads.tool.vertices)
          result.vertex_diagonal[v] = time_step * time_step * loads.tool.stiffness;
      }
    return result;
  }

  ImplicitEuler::ImplicitEuler(ElasticBody &body, ElasticityModel &model, const Loads &loads,
                               const double time_step, Surgery surgery)
    : body(body)
    , model(model)
    , loads(loads)
    , operations(std::move(surgery))
    , time_step(time_step)
    , x(body.rest_positions())
    , v(body.n_vertices(), Vector3::Zero())
    , constant_forces(body.n_vertices(), Vector3::Zero())
  {
    if (!(time_step > 0))
      throw InputError("the time step must be > 0, got " + format_number(time_step));
    if (!loads.vertex_forces.empty() && loads.vertex_forces.size() != body.n_vertices())
      throw InputError("vertex forces: " + std::to_string(loads.vertex_forces.size()) +
                       " given for " + std::to_string(body.n_vertices()) + " vertices");
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      constant_forces[i] = constant_force(i);
    if (!loads.tool.vertices.empty() && loads.tool.stiffness > 0)
      {
        tool_diagonal.assign(body.n_vertices(), 0.);
        for (const unsigned int i : loads.tool.vertices)
          tool_diagonal[i] = time_step * time_step * loads.tool.stiffness;
      }
  }

  Vector3 ImplicitEuler::constant_force(const unsigned int i) const
  {
    Vector3 force = body.vertex_mass(i) * loads.gravity;
    if (!loads.vertex_forces.empty())
      force += loads.vertex_forces[i];
    return force;
  }

  const Surgery &ImplicitEuler::surgery() const
  {
    return operations;
  }

  void ImplicitEuler::set_surgery(Surgery surgery)
  {
    if (steps_done > 0)
      throw InputError("the cuts, grasps and material changes can only be set before the first step");
    operations = std::move(surgery);
  }

  void ImplicitEuler::check_initial_field(const std::string &what, const std::size_t size) const
  {
    if (steps_done > 0)
      throw InputError("the initial " + what + " can only be set before the first step");
    if (size != body.n_vertices())
      throw InputError("initial " + what + ": " + std::to_string(size) + " given for " +
                       std::to_string(body.n_vertices()) + " vertices");
  }

  void ImplicitEuler::set_initial_velocities(const std::vector<Vector3> &velocities)
  {
    check_initial_field("velocities", velocities.size());
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      v[i] = body.is_fixed(i) ? Vector3::Zero() : velocities[i];
    start_energy = total_energy();
  }

  void ImplicitEuler::set_initial_positions(const std::vector<Vector3> &positions)
  {
    check_initial_field("positions", positions.size());
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      x[i] = body.is_fixed(i) ? body.rest_positions()[i] : positions[i];
    cached_elastic_step = static_cast<unsigned int>(-1);
    start_energy        = total_energy();
  }

  void ImplicitEuler::advance(StepStatistics &statistics)
  {
    const unsigned int threads = model.step_threads();
    if (threads == 0)
      {
        advance_step(statistics);
        return;
      }
    // Every parallel loop of the step (deal.II's, TBB's) runs in this arena: no more
    // threads than the model allows.
    if (!step_arena || step_arena->max_concurrency() != static_cast<int>(threads))
      step_arena = std::make_shared<tbb::task_arena>(static_cast<int>(threads));
    step_arena->execute([&] { advance_step(statistics); });
  }

  std::vector<Vector3> ImplicitEuler::right_hand_side(const double new_time, StepStatistics &statistics) const
  {
    std::vector<Vector3> tool_forces;
    if (!loads.tool.vertices.empty())
      {
        StageTimer    timer(statistics.stages, stage::tool_springs);
        const Vector3 offset = loads.tool.target_offset(new_time);
        for (const unsigned int i : loads.tool.vertices)
          tool_forces.push_back(loads.tool.stiffness * (body.rest_positions()[i] + offset - x[i]));
      }
    StageTimer           timer(statistics.stages, stage::right_hand_side);
    std::vector<Vector3> result(body.n_vertices(), Vector3::Zero());
    std::vector<Vector3> forces = constant_forces;
    model.add_elastic_forces(x, forces);
    for (std::size_t k = 0; k < tool_forces.size(); ++k)
      forces[loads.tool.vertices[k]] += tool_forces[k];
    operations.add_spring_forces(x, new_time, forces);
    if (penalty_contact())
      contact_constraints->add_penalty_forces(forces);
    body.add_mass_times(v, result);
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      result[i] += time_step * forces[i];
    return result;
  }

  bool ImplicitEuler::penalty_contact() const
  {
    return contact_constraints && contact_constraints->settings().method == ContactMethod::penalty;
  }

  void ImplicitEuler::solve_again_with_entering_springs(std::vector<Vector3> &new_velocities, const double new_time,
                                                        StepStatistics &statistics)
  {
    // A few rounds at most: each ties only what enters. Only where the solve is direct:
    // CG's tolerance would not see the new springs.
    for (unsigned int round = 0; round < max_penalty_rounds && !model.solves_iteratively(); ++round)
      {
        SystemChange entering;
        join_penalty_change(
          contact_constraints->tie_entering_springs(x, new_velocities, current_time, time_step, statistics), entering);
        if (entering.empty())
          break;
        model.change_within_step(entering, statistics);
        model.solve_again(right_hand_side(new_time, statistics), new_velocities, statistics);
      }
  }

  void ImplicitEuler::add_penalty_springs(SystemChange &change, StepStatistics &statistics)
  {
    join_penalty_change(contact_constraints->tie_penalty_springs(body, x, v, current_time, time_step, statistics),
                        change);
  }

  void ImplicitEuler::join_penalty_change(const PenaltySprings::Change &springs, SystemChange &change) const
  {
    std::vector<char> listed(body.n_vertices(), 0);
    for (std::size_t k = 0; k < change.vertices.size(); ++k)
      {
        listed[change.vertices[k]] = 1;
        change.vertex_diagonal[k] += contact_constraints->penalty_diagonal(change.vertices[k]);
      }
    for (std::size_t k = 0; k < springs.vertices.size(); ++k)
      if (!listed[springs.vertices[k]])
        {
          const unsigned int vertex = springs.vertices[k];
          change.vertices.push_back(vertex);
          change.vertex_diagonal.push_back(model.vertex_diagonal(vertex) - springs.old_diagonal[k] +
                                           springs.new_diagonal[k]);
        }
  }

  std::vector<Vector3> ImplicitEuler::initial_guess(StepStatistics &statistics) const
  {
    std::vector<Vector3> guess;
    if (model.solves_iteratively())
      {
        StageTimer timer(statistics.stages, stage::initial_guess);
        guess = v;
        if (!previous_v.empty())
          for (unsigned int i = 0; i < body.n_vertices(); ++i)
            guess[i] += v[i] - previous_v[i];
      }
    return guess;
  }

  void ImplicitEuler::advance_step(StepStatistics &statistics)
  {
    const unsigned int step     = steps_done + 1;
    const double       new_time = current_time + time_step;
    try
      {
        // What happens to the body in this step (a cut, a grasp, a material change), told
        // to the model before it prepares the step: the change's columns of A are then
        // refactorized with the step's own.
        SystemChange change;
        if (operations.active())
          change = operations.changes_of_step(body, x, v, model.uses_rotations(), step, current_time, time_step,
                                              tool_diagonal, statistics);
        if (penalty_contact())
          add_penalty_springs(change, statistics);
        model.apply_change(change, statistics);
        // A cut moves mass: gravity follows it.
        for (const unsigned int e : change.elements)
          for (const unsigned int i : body.element_vertices(e))
            constant_forces[i] = constant_force(i);
        model.prepare_step(x, v, statistics);
      }
    catch (const MatrixError &error)
      {
        throw MatrixError("step " + std::to_string(step) + ": " + error.what());
      }

    const std::vector<Vector3> rhs            = right_hand_side(new_time, statistics);
    std::vector<Vector3>       new_velocities = initial_guess(statistics);
    try
      {
        model.solve(rhs, new_velocities, statistics);
        // The free motion's velocities corrected by the contacts' impulses.
        if (penalty_contact())
          {
            solve_again_with_entering_springs(new_velocities, new_time, statistics);
            contact_constraints->finish_penalty_step(x, new_velocities, current_time, time_step, statistics);
          }
        else if (contact_constraints)
          contact_constraints->correct(body, model, x, new_velocities, current_time, time_step, statistics);
      }
    catch (const MatrixError &error)
      {
        throw MatrixError("step " + std::to_string(step) + ": " + error.what());
      }

    StageTimer timer(statistics.stages, stage::position_update);
    // A velocity whose square overflows (|v| > 1e154 m/s) has long left physics: the
    // simulation diverged (stiffness warping can, as the report found).
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      if (!std::isfinite(new_velocities[i].squaredNorm()))
        throw MatrixError("step " + std::to_string(step) + ": the velocity of vertex " +
                          std::to_string(i) + " is not finite: the simulation diverged");

    // The tool's work: the springs' energy gained by moving the targets at x(t) (see
    // external_work()).
    if (!loads.tool.vertices.empty())
      {
        const Vector3 old_offset = loads.tool.target_offset(current_time);
        const Vector3 new_offset = loads.tool.target_offset(new_time);
        for (const unsigned int i : loads.tool.vertices)
          {
            const Vector3 &rest = body.rest_positions()[i];
            tool_work += 0.5 * loads.tool.stiffness *
                         ((rest + new_offset - x[i]).squaredNorm() -
                          (rest + old_offset - x[i]).squaredNorm());
          }
      }

    tool_work += operations.spring_work(x, current_time, new_time);

    previous_v = std::move(v);
    v          = std::move(new_velocities);
    const std::vector<Vector3> old_x = operations.active() ? x : std::vector<Vector3>();
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      x[i] += time_step * v[i];
    if (operations.active())
      tool_work_on_body_sum += operations.spring_work_on_body(old_x, x, new_time);
    // The work of the springs on the body: the implicit force k (target(t+dt) - x(t+dt))
    // the step applied, times the displacement.
    if (!loads.tool.vertices.empty())
      {
        const Vector3 new_offset = loads.tool.target_offset(new_time);
        for (const unsigned int i : loads.tool.vertices)
          tool_work_on_body_sum += loads.tool.stiffness *
                               (body.rest_positions()[i] + new_offset - x[i]).dot(time_step * v[i]);
      }
    current_time = new_time;
    steps_done   = step;
  }

  const std::vector<Vector3> &ImplicitEuler::positions() const
  {
    return x;
  }

  const std::vector<Vector3> &ImplicitEuler::velocities() const
  {
    return v;
  }

  std::vector<Vector3> ImplicitEuler::displacements() const
  {
    std::vector<Vector3> result(x.size());
    for (unsigned int i = 0; i < x.size(); ++i)
      result[i] = x[i] - body.rest_positions()[i];
    return result;
  }

  double ImplicitEuler::time() const
  {
    return current_time;
  }

  unsigned int ImplicitEuler::step_number() const
  {
    return steps_done;
  }

  double ImplicitEuler::kinetic_energy() const
  {
    return body.kinetic_energy(v);
  }

  double ImplicitEuler::elastic_energy_at_step_start() const
  {
    return steps_done == 0 ? elastic_energy() : model.elastic_energy_at_last_evaluation();
  }

  double ImplicitEuler::elastic_energy() const
  {
    if (cached_elastic_step == steps_done)
      return cached_elastic_energy;
    if (!model.uses_rotations())
      cached_elastic_energy = body.elastic_energy(x, nullptr);
    else
      {
        std::vector<Matrix3> rotations;
        body.compute_element_rotations(x, rotations);
        cached_elastic_energy = body.elastic_energy(x, &rotations);
      }
    cached_elastic_step = steps_done;
    return cached_elastic_energy;
  }

  double ImplicitEuler::potential_energy() const
  {
    double energy = 0;
    for (unsigned int i = 0; i < body.n_vertices(); ++i)
      energy -= constant_forces[i].dot(x[i] - body.rest_positions()[i]);
    return energy;
  }

  double ImplicitEuler::tool_energy() const
  {
    const Vector3 offset = loads.tool.target_offset(current_time);
    double        energy = 0;
    for (const unsigned int i : loads.tool.vertices)
      energy += 0.5 * loads.tool.stiffness *
                (body.rest_positions()[i] + offset - x[i]).squaredNorm();
    return energy + operations.spring_energy(x, current_time);
  }

  double ImplicitEuler::total_energy() const
  {
    return kinetic_energy() + elastic_energy() + potential_energy() + tool_energy();
  }

  double ImplicitEuler::initial_energy() const
  {
    return start_energy;
  }

  double ImplicitEuler::external_work() const
  {
    return tool_work;
  }

  double ImplicitEuler::contact_work() const
  {
    return contact_constraints ? contact_constraints->work_on_body() : 0.;
  }

  void ImplicitEuler::set_contact(ContactConstraints contact)
  {
    if (steps_done > 0)
      throw InputError("the obstacles can only be set before the first step");
    contact.check_start(body, x);
    contact_constraints = std::move(contact);
  }

  const ContactConstraints *ImplicitEuler::contact() const
  {
    return contact_constraints ? &*contact_constraints : nullptr;
  }

  double ImplicitEuler::change_energy() const
  {
    return operations.change_energy().total();
  }

  double ImplicitEuler::tool_work_on_body() const
  {
    return tool_work_on_body_sum;
  }
  void ImplicitEuler::save_state(BinaryWriter &writer) const
  {
    writer.section("time integrator");
    writer.write(current_time);
    writer.write(steps_done);
    writer.write(x);
    writer.write(v);
    writer.write(previous_v);
    writer.write(start_energy);
    writer.write(tool_work);
    writer.write(tool_work_on_body_sum);
    writer.write(operations.active());
    if (operations.active())
      {
        body.save_changes(writer);
        operations.save(writer);
      }
    model.save_state(writer);
    writer.write(contact_constraints.has_value());
    if (contact_constraints)
      contact_constraints->save(writer);
  }

  void ImplicitEuler::load_state(BinaryReader &reader)
  {
    reader.expect_section("time integrator");
    reader.read(current_time);
    reader.read(steps_done);
    reader.read(x);
    reader.read(v);
    reader.read(previous_v);
    if (x.size() != body.n_vertices() || v.size() != body.n_vertices() ||
        (!previous_v.empty() && previous_v.size() != body.n_vertices()))
      reader.fail("holds " + std::to_string(x.size()) + " positions, the body has " +
                  std::to_string(body.n_vertices()) + " vertices");
    reader.read(start_energy);
    reader.read(tool_work);
    reader.read(tool_work_on_body_sum);
    if (reader.get<bool>() != operations.active())
      reader.fail("was written by a run with other cuts, grasps or material changes");
    if (operations.active())
      {
        body.load_changes(reader);
        operations.load(reader);
        for (unsigned int i = 0; i < body.n_vertices(); ++i)
          constant_forces[i] = constant_force(i);
      }
    cached_elastic_step = static_cast<unsigned int>(-1);
    model.load_state(reader);
    if (reader.get<bool>() != contact_constraints.has_value())
      reader.fail("was written by a run " + std::string(contact_constraints ? "without" : "with") + " contact");
    if (contact_constraints)
      contact_constraints->load(reader);
  }
} // namespace warpchol::fem
