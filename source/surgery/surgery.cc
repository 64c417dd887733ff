#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/surgery/surgery.h>

#include <algorithm>

namespace warpchol::fem
{
  Vector3 Grasp::closing_centre() const
  {
    return path.empty() ? centre : path.position(grasp_time);
  }

  Vector3 Grasp::offset(const double time) const
  {
    if (!path.empty())
      return path.position(std::clamp(time, grasp_time, release_time)) - path.position(grasp_time);
    return std::clamp(time - grasp_time, 0., duration) * velocity;
  }

  Surgery::Surgery(std::vector<Blade> blades, std::vector<Grasp> grasps, std::vector<MaterialChange> material_changes)
    : blades(std::move(blades))
    , grasps(std::move(grasps))
    , material_changes(std::move(material_changes))
    , material_changed(this->material_changes.size(), false)
    , holds(this->grasps.size())
  {}

  bool Surgery::active() const
  {
    return !blades.empty() || !grasps.empty() || !material_changes.empty();
  }

  namespace
  {
    /** Whether an event at @p when falls at the start of the step that starts at @p time. */
    bool due(const double when, const double time, const double time_step)
    {
      // The first step that starts at or after it, up to rounding of the summed times.
      return time + 1e-9 * time_step >= when;
    }
  } // namespace

  double ChangeEnergy::total() const
  {
    return material_changes + cuts + grasps;
  }

  SystemChange Surgery::changes_of_step(ElasticBody &body, const std::vector<Vector3> &positions,
                                        const std::vector<Vector3> &velocities, const bool rotated,
                                        const unsigned int step, const double time, const double time_step,
                                        const std::vector<double> &tool_diagonal, StepStatistics &statistics)
  {
    SystemChange change;
    if (cut_step.empty())
      cut_step.assign(body.n_elements(), -1);
    reached_time = time + time_step;
    if (!blades.empty())
      cut_elements(body, positions, velocities, rotated, step, time, time_step, change, statistics);
    change_materials(body, positions, rotated, time, time_step, change, statistics);
    grasp_and_release(body, positions, time, time_step, tool_diagonal, change, statistics);
    return change;
  }

  void Surgery::cut_elements(ElasticBody &body, const std::vector<Vector3> &positions,
                             const std::vector<Vector3> &velocities, const bool rotated, const unsigned int step,
                             const double time, const double time_step, SystemChange &change,
                             StepStatistics &statistics)
  {
    std::vector<bool> is_cut(body.n_elements());
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      is_cut[e] = body.element_is_cut(e);
    for (const Blade &blade : blades)
      {
        const std::vector<unsigned int> crossed =
          elements_crossed(body, positions, blade, time, time + time_step, is_cut);
        if (crossed.empty())
          continue;
        // The removed elements take their elastic energy and their mass's share of
        // the kinetic energy with them.
        double removed = body.kinetic_energy(velocities);
        for (const unsigned int e : crossed)
          {
            removed += body.element_energy(e, body.displacement_gradient(e, positions, rotated));
            body.cut_element(e);
            is_cut[e]   = true;
            cut_step[e] = static_cast<int>(step);
            change.elements.push_back(e);
          }
        energy_of_changes.cuts -= removed - body.kinetic_energy(velocities);
      }
    statistics.elements_cut = change.elements.size();
    change.topology         = !change.elements.empty();
  }

  void Surgery::change_materials(ElasticBody &body, const std::vector<Vector3> &positions, const bool rotated,
                                 const double time, const double time_step, SystemChange &change,
                                 StepStatistics &statistics)
  {
    for (std::size_t k = 0; k < material_changes.size(); ++k)
      {
        const MaterialChange &material_change = material_changes[k];
        if (material_changed[k] || !due(material_change.time, time, time_step))
          continue;
        double added = 0;
        for (const unsigned int e : material_change.elements)
          if (!body.element_is_cut(e))
            {
              const Matrix3 gradient = body.displacement_gradient(e, positions, rotated);
              added -= body.element_energy(e, gradient);
              if (material_change.keep_stress)
                body.scale_element_stiffness_keeping_stress(e, material_change.factor, gradient);
              else
                body.scale_element_stiffness(e, material_change.factor);
              added += body.element_energy(e, gradient);
              change.elements.push_back(e);
              ++statistics.elements_changed;
            }
        energy_of_changes.material_changes += added;
        material_changed[k] = true;
      }
  }

  void Surgery::grasp_and_release(ElasticBody &body, const std::vector<Vector3> &positions, const double time,
                                  const double time_step, const std::vector<double> &tool_diagonal,
                                  SystemChange &change, StepStatistics &statistics)
  {
    const auto tool = [&](const unsigned int v) { return tool_diagonal.empty() ? 0. : tool_diagonal[v]; };
    // A grasp ties the vertices where they are (no energy), a release lets the springs'
    // go: counted alike, as the springs' energy after minus before.
    const double springs_before = spring_energy(positions, time);

    // The vertices whose springs change: their diagonals are set once all grasps acted.
    std::vector<unsigned int> spring_changed;
    for (std::size_t k = 0; k < grasps.size(); ++k)
      {
        const Grasp &grasp = grasps[k];
        Hold        &hold  = holds[k];
        if (!hold.closed && due(grasp.grasp_time, time, time_step))
          {
            const Vector3 centre       = grasp.closing_centre();
            unsigned int  fixed_within = 0;
            for (unsigned int v = 0; v < body.n_vertices(); ++v)
              if ((positions[v] - centre).norm() <= grasp.radius)
                {
                  if (body.is_fixed(v))
                    {
                      ++fixed_within;
                      continue;
                    }
                  hold.held.push_back(v);
                  hold.anchors.push_back(positions[v]);
                  hold.stiffness.push_back(grasp.stiffness > 0 ? grasp.stiffness :
                                                                 1e6 * body.vertex_mass(v) / (time_step * time_step));
                  spring_changed.push_back(v);
                }
            if (hold.held.empty())
              throw InputError(grasp.name + " at " + format_number(time) + " s: " +
                               (fixed_within > 0 ? "the jaws hold only fixed vertices (" + std::to_string(fixed_within) +
                                                     "), which nothing can move" :
                                                   std::string("no vertex lies within the jaws")) +
                               " (sphere at " + format_number(centre[0]) + ", " + format_number(centre[1]) + ", " +
                               format_number(centre[2]) + ", radius " + format_number(grasp.radius) + ")");
            hold.closed = true;
            statistics.vertices_grasped += hold.held.size();
          }
        else if (hold.closed && !hold.released && due(grasp.release_time, time, time_step))
          {
            spring_changed.insert(spring_changed.end(), hold.held.begin(), hold.held.end());
            statistics.vertices_released += hold.held.size();
            hold.held.clear();
            hold.anchors.clear();
            hold.stiffness.clear();
            hold.released = true;
          }
      }
    if (!spring_changed.empty())
      {
        // Each vertex once, in the order it first changed, with the springs of every grasp
        // that holds it now (one grasp: its spring alone, as before there were several).
        std::vector<double> spring(body.n_vertices(), 0.);
        std::vector<char>   listed(body.n_vertices(), 0);
        for (const Hold &hold : holds)
          for (std::size_t j = 0; j < hold.held.size(); ++j)
            spring[hold.held[j]] += hold.stiffness[j];
        for (const unsigned int v : spring_changed)
          if (!listed[v])
            {
              listed[v] = 1;
              change.vertices.push_back(v);
              change.vertex_diagonal.push_back(tool(v) + time_step * time_step * spring[v]);
            }
      }
    energy_of_changes.grasps += spring_energy(positions, time) - springs_before;
  }

  const ChangeEnergy &Surgery::change_energy() const
  {
    return energy_of_changes;
  }

  std::vector<std::string> Surgery::events_not_reached() const
  {
    std::vector<std::string> events;
    for (std::size_t k = 0; k < material_changes.size(); ++k)
      if (!material_changed[k])
        events.push_back("the material change at " + format_number(material_changes[k].time) + " s");
    for (const Blade &blade : blades)
      if (blade.duration > 0 && !(reached_time > blade.begin))
        events.push_back("the cut from " + format_number(blade.begin) + " s");
    for (std::size_t k = 0; k < grasps.size(); ++k)
      if (!holds[k].closed)
        events.push_back("the grasp at " + format_number(grasps[k].grasp_time) + " s");
    return events;
  }

  namespace
  {
    /**
     * f(v, k, anchor, from_anchor) for each spring of each grasp that holds vertices: vertex
     * v, its stiffness k, its anchor at @p time and at @p other_time (the jaws move with the
     * grasp's offset).
     */
    template <typename Holds, typename Grasps, typename Function>
    void for_each_spring(const Holds &holds, const Grasps &grasps, const double time, const double other_time,
                         const Function &f)
    {
      for (std::size_t g = 0; g < grasps.size(); ++g)
        {
          const auto &hold = holds[g];
          if (hold.held.empty())
            continue;
          const Vector3 offset = grasps[g].offset(time), other_offset = grasps[g].offset(other_time);
          for (std::size_t k = 0; k < hold.held.size(); ++k)
            f(hold.held[k], hold.stiffness[k], Vector3(hold.anchors[k] + offset),
              Vector3(hold.anchors[k] + other_offset));
        }
    }
  } // namespace

  void Surgery::add_spring_forces(const std::vector<Vector3> &positions, const double time,
                                  std::vector<Vector3> &forces) const
  {
    for_each_spring(holds, grasps, time, time, [&](const unsigned int v, const double k, const Vector3 &anchor, const Vector3 &) {
      forces[v] += k * (anchor - positions[v]);
    });
  }

  double Surgery::spring_energy(const std::vector<Vector3> &positions, const double time) const
  {
    double energy = 0;
    for_each_spring(holds, grasps, time, time, [&](const unsigned int v, const double k, const Vector3 &anchor, const Vector3 &) {
      energy += 0.5 * k * (anchor - positions[v]).squaredNorm();
    });
    return energy;
  }

  double Surgery::spring_work(const std::vector<Vector3> &positions, const double from, const double to) const
  {
    double work = 0;
    for_each_spring(holds, grasps, to, from,
                    [&](const unsigned int v, const double k, const Vector3 &new_anchor, const Vector3 &old_anchor) {
                      const Vector3 &x = positions[v];
                      work += 0.5 * k * ((new_anchor - x).squaredNorm() - (old_anchor - x).squaredNorm());
                    });
    return work;
  }

  double Surgery::spring_work_on_body(const std::vector<Vector3> &old_positions,
                                      const std::vector<Vector3> &new_positions, const double time) const
  {
    double work = 0;
    for_each_spring(holds, grasps, time, time, [&](const unsigned int v, const double k, const Vector3 &anchor, const Vector3 &) {
      work += k * (anchor - new_positions[v]).dot(new_positions[v] - old_positions[v]);
    });
    return work;
  }

  const std::vector<int> &Surgery::cut_steps() const
  {
    return cut_step;
  }

  std::vector<char> Surgery::grasped_vertices(const unsigned int n_vertices) const
  {
    std::vector<char> grasped(n_vertices, 0);
    for (const Hold &hold : holds)
      for (const unsigned int v : hold.held)
        grasped[v] = 1;
    return grasped;
  }

  unsigned int Surgery::n_cut() const
  {
    return static_cast<unsigned int>(std::count_if(cut_step.begin(), cut_step.end(), [](const int s) { return s >= 0; }));
  }

  void Surgery::save_hold(BinaryWriter &writer, const Hold &hold) const
  {
    writer.write(hold.held);
    writer.write(hold.anchors);
    writer.write(hold.stiffness);
    writer.write(hold.closed);
    writer.write(hold.released);
  }

  void Surgery::load_hold(BinaryReader &reader, Hold &hold)
  {
    reader.read(hold.held);
    reader.read(hold.anchors);
    reader.read(hold.stiffness);
    reader.read(hold.closed);
    reader.read(hold.released);
    if (hold.anchors.size() != hold.held.size() || hold.stiffness.size() != hold.held.size())
      reader.fail("the grasped vertices do not match their anchors (corrupt)");
  }

  // The first grasp and material change where a scene of one of each kept them, so that
  // such a checkpoint reads as before there were several; the others after them.
  void Surgery::save(BinaryWriter &writer) const
  {
    writer.section("surgery");
    writer.write(cut_step);
    save_hold(writer, holds.empty() ? Hold() : holds[0]);
    writer.write(!material_changed.empty() && material_changed[0]);
    writer.write(reached_time);
    for (const double energy : {energy_of_changes.material_changes, energy_of_changes.cuts, energy_of_changes.grasps})
      writer.write(energy);
    for (std::size_t k = 1; k < holds.size(); ++k)
      save_hold(writer, holds[k]);
    for (std::size_t k = 1; k < material_changed.size(); ++k)
      writer.write(static_cast<bool>(material_changed[k]));
  }

  void Surgery::load(BinaryReader &reader)
  {
    reader.expect_section("surgery");
    reader.read(cut_step);
    Hold first;
    load_hold(reader, first);
    if (!holds.empty())
      holds[0] = std::move(first);
    bool changed = false;
    reader.read(changed);
    if (!material_changed.empty())
      material_changed[0] = changed;
    reader.read(reached_time);
    for (double *energy : {&energy_of_changes.material_changes, &energy_of_changes.cuts, &energy_of_changes.grasps})
      reader.read(*energy);
    for (std::size_t k = 1; k < holds.size(); ++k)
      load_hold(reader, holds[k]);
    for (std::size_t k = 1; k < material_changed.size(); ++k)
      {
        reader.read(changed);
        material_changed[k] = changed;
      }
  }
} // namespace warpchol::fem
