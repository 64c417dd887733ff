#include <warpchol/contact/penalty_springs.h>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace warpchol::fem
{
  namespace
  {
    /** The keys of @p contacts (contact_key()). */
    std::unordered_set<std::uint64_t> keys_of(const std::vector<Contact> &contacts)
    {
      std::unordered_set<std::uint64_t> keys;
      for (const Contact &contact : contacts)
        keys.insert(contact_key(contact));
      return keys;
    }
  } // namespace

  PenaltySprings::PenaltySprings(const double stiffness, const double margin)
    : stiffness(stiffness)
    , margin(margin)
  {}

  PenaltySprings::Change PenaltySprings::tie(const std::vector<Contact> &contacts, const std::vector<Obstacle> &obstacles,
                                             const std::vector<Vector3> &positions,
                                             const std::vector<Vector3> &velocities, const unsigned int n_vertices,
                                             const double time, const double step)
  {
    time_step                                    = step;
    const std::unordered_set<std::uint64_t> held = keys_of(springs);
    springs.clear();
    drag_velocity.clear();
    // A point that would be inside its obstacle at the step's end, at its velocity, ties a
    // spring (its drag stops it short); one tied keeps it within the alarm distance. The
    // gap is already to where the obstacle is at the step's end.
    for (const Contact &c : contacts)
      if (c.gap + time_step * c.normal.dot(point_value(c, velocities)) < 0 ||
          (c.gap < margin && held.count(contact_key(c)) > 0))
        tie_spring(c, point_value(c, positions), obstacles[c.obstacle], time, time_step);
    if (spring_diagonal.size() != n_vertices)
      spring_diagonal.assign(n_vertices, 0.);
    return diagonal_change();
  }

  PenaltySprings::Change PenaltySprings::tie_entering(const std::vector<Contact>  &contacts,
                                                      const std::vector<Obstacle> &obstacles,
                                                      const std::vector<Vector3>  &positions,
                                                      const std::vector<Vector3> &velocities, const double time,
                                                      const double step)
  {
    const std::unordered_set<std::uint64_t> held = keys_of(springs);
    bool                                     tied = false;
    for (const Contact &c : contacts)
      if (held.count(contact_key(c)) == 0)
        {
          const Vector3 next = point_value(c, positions) + step * point_value(c, velocities);
          if (obstacles[c.obstacle].proximity(next, time + step).distance < 0)
            {
              tie_spring(c, point_value(c, positions), obstacles[c.obstacle], time, step);
              tied = true;
            }
        }
    return tied ? diagonal_change() : Change();
  }

  void PenaltySprings::tie_spring(const Contact &contact, const Vector3 &point, const Obstacle &obstacle,
                                  const double time, const double step)
  {
    // The gap is to the obstacle where it is at the step's end: along the normal the drag
    // holds the point where it is; along the tangents it moves with the obstacle.
    const Vector3 velocity = obstacle.velocity(point, time, time + step);
    springs.push_back(contact);
    drag_velocity.push_back(velocity - velocity.dot(contact.normal) * contact.normal);
  }

  PenaltySprings::Change PenaltySprings::diagonal_change()
  {
    std::vector<double> diagonal(spring_diagonal.size(), 0.);
    const double        spring = time_step * time_step * stiffness;
    for (const Contact &c : springs)
      for (unsigned int k = 0; k < c.n_vertices; ++k)
        diagonal[c.vertex_of(k)] += spring * c.weights[k];
    Change change;
    for (std::size_t v = 0; v < diagonal.size(); ++v)
      if (diagonal[v] != spring_diagonal[v])
        {
          change.vertices.push_back(static_cast<unsigned int>(v));
          change.old_diagonal.push_back(spring_diagonal[v]);
          change.new_diagonal.push_back(diagonal[v]);
        }
    spring_diagonal = std::move(diagonal);
    return change;
  }

  Vector3 PenaltySprings::pushing_force(const Contact &spring) const
  {
    return stiffness * std::max(0., -spring.gap) * spring.normal;
  }

  double PenaltySprings::diagonal(const unsigned int vertex) const
  {
    return vertex < spring_diagonal.size() ? spring_diagonal[vertex] : 0.;
  }

  void PenaltySprings::add_forces(std::vector<Vector3> &forces) const
  {
    for (std::size_t j = 0; j < springs.size(); ++j)
      {
        const Contact &c = springs[j];
        const Vector3  force = pushing_force(c) + time_step * stiffness * drag_velocity[j];
        for (unsigned int a = 0; a < c.n_vertices; ++a)
          forces[c.vertex_of(a)] += c.weights[a] * force;
      }
  }

  void PenaltySprings::record(const std::vector<Vector3> &velocities, const double step,
                              std::vector<Vector3> &forces, ContactStepReport &report) const
  {
    const double drag = step * stiffness;
    for (std::size_t j = 0; j < springs.size(); ++j)
      {
        const Contact &c      = springs[j];
        const Vector3  normal = pushing_force(c);
        Vector3        total  = Vector3::Zero();
        for (unsigned int a = 0; a < c.n_vertices; ++a)
          {
            // The vertex's share of the normal force and of the drag.
            const Vector3 relative = velocities[c.vertex_of(a)] - drag_velocity[j];
            const Vector3 force    = c.weights[a] * (normal - drag * relative);
            const Vector3 sliding  = relative - relative.dot(c.normal) * c.normal;
            forces[c.vertex_of(a)] += force;
            total += force;
            report.work_on_body += step * force.dot(velocities[c.vertex_of(a)]);
            report.friction_dissipation += step * drag * c.weights[a] * sliding.squaredNorm();
          }
        report.total_force += total;
        report.normal_force += std::abs(total.dot(c.normal));
        report.friction_force += (total - total.dot(c.normal) * c.normal).norm();
      }
  }

  void PenaltySprings::save(BinaryWriter &writer) const
  {
    write_contact_keys(writer, springs);
    writer.write(spring_diagonal);
  }

  void PenaltySprings::load(BinaryReader &reader, const std::size_t n_obstacles)
  {
    springs = read_contact_keys(reader, n_obstacles, "penalty spring");
    reader.read(spring_diagonal);
  }
} // namespace warpchol::fem
