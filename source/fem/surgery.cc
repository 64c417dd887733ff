#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/fem/surgery.h>

#include <algorithm>

namespace warpchol::fem
{
  Vector3 Grasp::offset(const double time) const
  {
    return std::clamp(time - grasp_time, 0., duration) * velocity;
  }

  Surgery::Surgery(std::optional<Blade> blade, std::optional<Grasp> grasp,
                   std::optional<MaterialChange> material_change)
    : blade(std::move(blade))
    , grasp(std::move(grasp))
    , material_change(std::move(material_change))
  {}

  bool Surgery::active() const
  {
    return blade || grasp || material_change;
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
    reached_time    = time + time_step;
    const auto tool = [&](const unsigned int v) { return tool_diagonal.empty() ? 0. : tool_diagonal[v]; };
    const auto elastic_energy = [&](const unsigned int e) {
      return body.element_energy(e, body.displacement_gradient(e, positions, rotated));
    };

    if (blade)
      {
        std::vector<bool> is_cut(body.n_elements());
        for (unsigned int e = 0; e < body.n_elements(); ++e)
          is_cut[e] = body.element_is_cut(e);
        const std::vector<unsigned int> crossed =
          elements_crossed(body, positions, *blade, time, time + time_step, is_cut);
        if (!crossed.empty())
          {
            // The removed elements take their elastic energy and their mass's share of
            // the kinetic energy with them.
            double removed = body.kinetic_energy(velocities);
            for (const unsigned int e : crossed)
              {
                removed += elastic_energy(e);
                body.cut_element(e);
                cut_step[e] = static_cast<int>(step);
                change.elements.push_back(e);
              }
            energy_of_changes.cuts -= removed - body.kinetic_energy(velocities);
          }
        statistics.elements_cut = change.elements.size();
        change.topology         = !change.elements.empty();
      }

    if (material_change && !material_changed && due(material_change->time, time, time_step))
      {
        double added = 0;
        for (const unsigned int e : material_change->elements)
          if (!body.element_is_cut(e))
            {
              const Matrix3 gradient = body.displacement_gradient(e, positions, rotated);
              added -= body.element_energy(e, gradient);
              if (material_change->keep_stress)
                body.scale_element_stiffness_keeping_stress(e, material_change->factor, gradient);
              else
                body.scale_element_stiffness(e, material_change->factor);
              added += body.element_energy(e, gradient);
              change.elements.push_back(e);
              ++statistics.elements_changed;
            }
        energy_of_changes.material_changes += added;
        material_changed = true;
      }

    // A grasp ties the vertices where they are (no energy), a release lets the springs'
    // go: counted alike, as the springs' energy after minus before.
    const double springs_before = spring_energy(positions, time);

    if (grasp && !closed && due(grasp->grasp_time, time, time_step))
      {
        unsigned int fixed_within = 0;
        for (unsigned int v = 0; v < body.n_vertices(); ++v)
          if ((positions[v] - grasp->centre).norm() <= grasp->radius)
            {
              if (body.is_fixed(v))
                {
                  ++fixed_within;
                  continue;
                }
              held.push_back(v);
              anchors.push_back(positions[v]);
              stiffness.push_back(grasp->stiffness > 0 ? grasp->stiffness :
                                                         1e6 * body.vertex_mass(v) / (time_step * time_step));
              change.vertices.push_back(v);
              change.vertex_diagonal.push_back(tool(v) + time_step * time_step * stiffness.back());
            }
        if (held.empty())
          throw InputError("Grasp at " + format_number(time) + " s: " +
                           (fixed_within > 0 ? "the jaws hold only fixed vertices (" + std::to_string(fixed_within) +
                                                 "), which nothing can move" :
                                               std::string("no vertex lies within the jaws")) +
                           " (sphere at " + format_number(grasp->centre[0]) + ", " + format_number(grasp->centre[1]) +
                           ", " + format_number(grasp->centre[2]) + ", radius " + format_number(grasp->radius) + ")");
        closed                      = true;
        statistics.vertices_grasped = held.size();
      }
    else if (grasp && closed && !released && due(grasp->release_time, time, time_step))
      {
        for (const unsigned int v : held)
          {
            change.vertices.push_back(v);
            change.vertex_diagonal.push_back(tool(v));
          }
        statistics.vertices_released = held.size();
        held.clear();
        anchors.clear();
        stiffness.clear();
        released = true;
      }
    energy_of_changes.grasps += spring_energy(positions, time) - springs_before;
    return change;
  }

  const ChangeEnergy &Surgery::change_energy() const
  {
    return energy_of_changes;
  }

  std::vector<std::string> Surgery::events_not_reached() const
  {
    std::vector<std::string> events;
    if (material_change && !material_changed)
      events.push_back("the material change at " + format_number(material_change->time) + " s");
    if (blade && blade->duration > 0 && !(reached_time > blade->begin))
      events.push_back("the cut from " + format_number(blade->begin) + " s");
    if (grasp && !closed)
      events.push_back("the grasp at " + format_number(grasp->grasp_time) + " s");
    return events;
  }

  void Surgery::add_spring_forces(const std::vector<Vector3> &positions, const double time,
                                  std::vector<Vector3> &forces) const
  {
    if (held.empty())
      return;
    const Vector3 offset = grasp->offset(time);
    for (std::size_t k = 0; k < held.size(); ++k)
      forces[held[k]] += stiffness[k] * (anchors[k] + offset - positions[held[k]]);
  }

  double Surgery::spring_energy(const std::vector<Vector3> &positions, const double time) const
  {
    double energy = 0;
    if (held.empty())
      return energy;
    const Vector3 offset = grasp->offset(time);
    for (std::size_t k = 0; k < held.size(); ++k)
      energy += 0.5 * stiffness[k] * (anchors[k] + offset - positions[held[k]]).squaredNorm();
    return energy;
  }

  double Surgery::spring_work(const std::vector<Vector3> &positions, const double from, const double to) const
  {
    double work = 0;
    if (held.empty())
      return work;
    const Vector3 old_offset = grasp->offset(from), new_offset = grasp->offset(to);
    for (std::size_t k = 0; k < held.size(); ++k)
      {
        const Vector3 &x = positions[held[k]];
        work += 0.5 * stiffness[k] * ((anchors[k] + new_offset - x).squaredNorm() - (anchors[k] + old_offset - x).squaredNorm());
      }
    return work;
  }

  double Surgery::spring_work_on_body(const std::vector<Vector3> &old_positions,
                                      const std::vector<Vector3> &new_positions, const double time) const
  {
    double work = 0;
    if (held.empty())
      return work;
    const Vector3 offset = grasp->offset(time);
    for (std::size_t k = 0; k < held.size(); ++k)
      {
        const unsigned int v = held[k];
        work += stiffness[k] * (anchors[k] + offset - new_positions[v]).dot(new_positions[v] - old_positions[v]);
      }
    return work;
  }

  const std::vector<int> &Surgery::cut_steps() const
  {
    return cut_step;
  }

  std::vector<char> Surgery::grasped_vertices(const unsigned int n_vertices) const
  {
    std::vector<char> grasped(n_vertices, 0);
    for (const unsigned int v : held)
      grasped[v] = 1;
    return grasped;
  }

  unsigned int Surgery::n_cut() const
  {
    return static_cast<unsigned int>(std::count_if(cut_step.begin(), cut_step.end(), [](const int s) { return s >= 0; }));
  }

  void Surgery::save(BinaryWriter &writer) const
  {
    writer.section("surgery");
    writer.write(cut_step);
    writer.write(held);
    writer.write(anchors);
    writer.write(stiffness);
    writer.write(closed);
    writer.write(released);
    writer.write(material_changed);
    writer.write(reached_time);
    for (const double energy : {energy_of_changes.material_changes, energy_of_changes.cuts, energy_of_changes.grasps})
      writer.write(energy);
  }

  void Surgery::load(BinaryReader &reader)
  {
    reader.expect_section("surgery");
    reader.read(cut_step);
    reader.read(held);
    reader.read(anchors);
    reader.read(stiffness);
    reader.read(closed);
    reader.read(released);
    reader.read(material_changed);
    reader.read(reached_time);
    for (double *energy : {&energy_of_changes.material_changes, &energy_of_changes.cuts, &energy_of_changes.grasps})
      reader.read(*energy);
    if (anchors.size() != held.size() || stiffness.size() != held.size())
      reader.fail("the grasped vertices do not match their anchors (corrupt)");
  }
} // namespace warpchol::fem
