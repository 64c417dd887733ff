#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/stage_times.h>
#include <warpchol/contact/contact_constraints.h>

#include <Eigen/Geometry>

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace warpchol::fem
{
  namespace
  {
    /** Whether @p point lies in the tetrahedron @p corners (barycentric coordinates all >= 0). */
    bool in_tetrahedron(const Vector3 &point, const std::array<Vector3, 4> &corners)
    {
      Matrix3 edges;
      for (int a = 0; a < 3; ++a)
        edges.col(a) = corners[a + 1] - corners[0];
      const Vector3 local = edges.fullPivLu().solve(point - corners[0]);
      return local.minCoeff() >= 0 && local.sum() <= 1;
    }

    /** The obstacle's reference point, which must not be inside the body at the start. */
    Vector3 reference_point(const Obstacle &obstacle)
    {
      const TriangleSurface boundary = obstacle.boundary(0);
      Vector3               centre   = Vector3::Zero();
      for (const Vector3 &point : boundary.points)
        centre += point;
      return centre / static_cast<double>(boundary.points.size());
    }
  } // namespace

  ContactConstraints::ContactConstraints(std::vector<Obstacle> obstacles, const ContactSettings &settings)
    : obstacle_list(std::move(obstacles))
    , contact_settings(settings)
  {}

  std::uint64_t ContactConstraints::contact_key(const Contact &contact)
  {
    return (static_cast<std::uint64_t>(contact.vertex) << 32) | contact.obstacle;
  }

  std::vector<unsigned int> surface_vertices(const ElasticBody &body)
  {
    // A face of one element only (of those not cut) is on the surface.
    std::vector<std::array<unsigned int, 3>> faces;
    faces.reserve(4 * static_cast<std::size_t>(body.n_elements()));
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      if (!body.element_is_cut(e))
        {
          const auto &v = body.element_vertices(e);
          for (unsigned int skip = 0; skip < 4; ++skip)
            {
              std::array<unsigned int, 3> face{};
              for (unsigned int a = 0, k = 0; a < 4; ++a)
                if (a != skip)
                  face[k++] = v[a];
              std::sort(face.begin(), face.end());
              faces.push_back(face);
            }
        }
    std::sort(faces.begin(), faces.end());
    std::vector<char> on_surface(body.n_vertices(), 0);
    for (std::size_t k = 0; k < faces.size();)
      {
        std::size_t same = k + 1;
        while (same < faces.size() && faces[same] == faces[k])
          ++same;
        if (same == k + 1)
          for (const unsigned int v : faces[k])
            on_surface[v] = 1;
        k = same;
      }
    std::vector<unsigned int> vertices;
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      if (on_surface[v])
        vertices.push_back(v);
    return vertices;
  }

  const std::vector<unsigned int> &ContactConstraints::current_surface(const ElasticBody &body)
  {
    unsigned int n_cut = 0;
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      n_cut += body.element_is_cut(e) ? 1 : 0;
    if (n_cut != surface_of_cut_count)
      {
        surface              = surface_vertices(body);
        surface_of_cut_count = n_cut;
      }
    return surface;
  }

  std::string obstacle_inside_body(const Obstacle &obstacle, const ElasticBody &body,
                                   const std::vector<Vector3> &positions, const double tolerance)
  {
    for (const unsigned int v : surface_vertices(body))
      {
        const double distance = obstacle.proximity(positions[v], 0).distance;
        if (distance < -tolerance)
          return "the obstacle is inside the body at the start: vertex " + std::to_string(v) + " lies " +
                 format_number(-distance) + " m inside it (more than the tolerance " + format_number(tolerance) +
                 " m)";
      }
    if (obstacle.shape() == ObstacleShape::plane)
      return "";
    const Vector3 point = reference_point(obstacle);
    for (unsigned int e = 0; e < body.n_elements(); ++e)
      {
        if (body.element_is_cut(e))
          continue;
        const auto &v = body.element_vertices(e);
        if (in_tetrahedron(point, {{positions[v[0]], positions[v[1]], positions[v[2]], positions[v[3]]}}))
          return "the obstacle is inside the body at the start: its centre lies in element " + std::to_string(e);
      }
    return "";
  }

  void ContactConstraints::check_start(const ElasticBody &body, const std::vector<Vector3> &positions) const
  {
    for (std::size_t o = 0; o < obstacle_list.size(); ++o)
      {
        const std::string why = obstacle_inside_body(obstacle_list[o], body, positions, contact_settings.tolerance);
        if (!why.empty())
          throw InputError("obstacle " + std::to_string(o + 1) + ": " + why);
      }
  }

  std::vector<Contact> ContactConstraints::detect(const ElasticBody &body, const std::vector<Vector3> &positions,
                                                  const std::vector<Vector3> &velocities, const double time,
                                                  const double time_step)
  {
    std::vector<Contact> found;
    for (const unsigned int v : current_surface(body))
      {
        if (body.is_fixed(v))
          continue;
        // A vertex may reach an obstacle from as far as it moves in the step.
        const double reach = contact_settings.margin + time_step * velocities[v].norm();
        for (unsigned int o = 0; o < obstacle_list.size(); ++o)
          {
            const Proximity proximity = obstacle_list[o].proximity(positions[v], time + time_step);
            if (proximity.distance >= reach)
              continue;
            Contact contact;
            contact.vertex    = v;
            contact.obstacle  = o;
            contact.normal    = proximity.normal;
            contact.tangent_1 = proximity.normal.unitOrthogonal();
            contact.tangent_2 = proximity.normal.cross(contact.tangent_1);
            contact.gap       = proximity.distance;
            found.push_back(contact);
          }
      }
    return found;
  }

  sparse::CSCMatrix ContactConstraints::constraint_columns(const ElasticBody &body, const std::vector<Contact> &contacts,
                                                           const std::vector<Matrix3> *rotations)
  {
    const Index       m  = 3 * static_cast<Index>(contacts.size());
    sparse::CSCMatrix ht = sparse::CSCMatrix::zero(body.n_unknowns(), m);
    for (std::size_t j = 0; j < contacts.size(); ++j)
      {
        const Contact &contact = contacts[j];
        const Index    first   = body.first_unknown(contact.vertex);
        for (int d = 0; d < 3; ++d)
          {
            const Vector3 &direction = d == 0 ? contact.normal : d == 1 ? contact.tangent_1 : contact.tangent_2;
            // The row h on v is the row R^T h on the unknowns y (v = R y).
            const Vector3 rotated = rotations ? Vector3((*rotations)[contact.vertex].transpose() * direction) : direction;
            for (int c = 0; c < 3; ++c)
              {
                ht.row_index.push_back(first + c);
                ht.values.push_back(rotated[c]);
              }
            ht.column_start[3 * j + d + 1] = static_cast<Index>(ht.row_index.size());
          }
      }
    return ht;
  }

  void ContactConstraints::correct(const ElasticBody &body, ElasticityModel &model,
                                   const std::vector<Vector3> &positions, std::vector<Vector3> &velocities,
                                   const double time, const double time_step, StepStatistics &statistics)
  {
    report            = ContactStepReport();
    previous_contacts = std::move(step_contacts);
    forces.assign(body.n_vertices(), Vector3::Zero());
    gaps.assign(body.n_vertices(), contact_settings.margin);
    {
      StageTimer timer(statistics.stages, stage::contact_detection);
      step_contacts = detect(body, positions, velocities, time, time_step);
    }
    const std::size_t n_contacts = step_contacts.size();
    report.n_contacts            = static_cast<unsigned int>(n_contacts);
    report.contacts_per_obstacle.assign(obstacle_list.size(), 0);
    for (const Contact &contact : step_contacts)
      ++report.contacts_per_obstacle[contact.obstacle];
    if (n_contacts > contact_settings.max_contacts)
      throw InputError(contact_settings.max_contacts_origin + " = " + std::to_string(contact_settings.max_contacts) +
                       ": " + std::to_string(n_contacts) + " contacts at time " + format_number(time + time_step) +
                       " s exceed the cap");
    if (n_contacts == 0)
      {
        lambda.clear();
        return;
      }
    if (model.solver().state() != cholesky::SparseCholesky::State::factorized)
      throw InputError("contact needs warpchol's own factor of A, not a peer's (Solver/Backend)");

    std::vector<double> w;
    {
      StageTimer timer(statistics.stages, stage::contact_compliance);
      w = model.solver().compliance(constraint_columns(body, step_contacts, model.solve_rotations()),
                                    contact_settings.compliance);
    }

    // u = H v_free + the targets: u_n >= 0 keeps the next position out of the obstacle,
    // u_t is the sliding velocity relative to the obstacle.
    std::vector<double> free_velocity(3 * n_contacts), friction(n_contacts);
    std::vector<Vector3> obstacle_velocity(n_contacts);
    for (std::size_t j = 0; j < n_contacts; ++j)
      {
        const Contact  &c = step_contacts[j];
        const Obstacle &o = obstacle_list[c.obstacle];
        obstacle_velocity[j]     = o.velocity(time, time + time_step);
        const Vector3 relative   = velocities[c.vertex] - obstacle_velocity[j];
        free_velocity[3 * j]     = c.normal.dot(velocities[c.vertex]) + c.gap / time_step;
        free_velocity[3 * j + 1] = c.tangent_1.dot(relative);
        free_velocity[3 * j + 2] = c.tangent_2.dot(relative);
        friction[j]              = o.friction();
      }
    {
      StageTimer timer(statistics.stages, stage::contact_gauss_seidel);
      // Warm start: a contact that persists (same vertex, same obstacle) starts from its
      // impulses of the step before, as SOFA's solver starts from the last forces.
      std::unordered_map<std::uint64_t, std::size_t> previous;
      for (std::size_t j = 0; j < previous_contacts.size(); ++j)
        previous[contact_key(previous_contacts[j])] = j;
      std::vector<double> start(3 * n_contacts, 0.);
      for (std::size_t j = 0; j < n_contacts; ++j)
        if (const auto found = previous.find(contact_key(step_contacts[j])); found != previous.end())
          for (std::size_t d = 0; d < 3; ++d)
            start[3 * j + d] = lambda[3 * found->second + d];
      lambda              = std::move(start);
      report.gauss_seidel = solve_friction_cone(w, free_velocity, friction, contact_settings.gauss_seidel, lambda);
    }

    // v += A~^-1 H^T lambda: the impulses as forces on the vertices, one solve.
    std::vector<Vector3> impulses(body.n_vertices(), Vector3::Zero());
    for (std::size_t j = 0; j < n_contacts; ++j)
      {
        const Contact &c = step_contacts[j];
        impulses[c.vertex] += lambda[3 * j] * c.normal + lambda[3 * j + 1] * c.tangent_1 + lambda[3 * j + 2] * c.tangent_2;
      }
    {
      StageTimer           timer(statistics.stages, stage::contact_correction);
      std::vector<Vector3> change;
      model.solve(impulses, change, statistics);
      for (unsigned int v = 0; v < body.n_vertices(); ++v)
        velocities[v] += change[v];
    }

    for (std::size_t j = 0; j < n_contacts; ++j)
      {
        const Contact &c        = step_contacts[j];
        const Vector3  impulse  = lambda[3 * j] * c.normal + lambda[3 * j + 1] * c.tangent_1 + lambda[3 * j + 2] * c.tangent_2;
        const Vector3  relative = velocities[c.vertex] - obstacle_velocity[j];
        const double   sliding  = -(lambda[3 * j + 1] * c.tangent_1.dot(relative) + lambda[3 * j + 2] * c.tangent_2.dot(relative));
        forces[c.vertex] += impulse / time_step;
        report.total_force += impulse / time_step;
        report.normal_force += std::abs(lambda[3 * j]) / time_step;
        report.friction_force += std::hypot(lambda[3 * j + 1], lambda[3 * j + 2]) / time_step;
        report.work_on_body += impulse.dot(velocities[c.vertex]);
        report.friction_dissipation += std::max(0., sliding);
        const Vector3 next = positions[c.vertex] + time_step * velocities[c.vertex];
        const double  gap  = obstacle_list[c.obstacle].proximity(next, time + time_step).distance;
        gaps[c.vertex]     = std::min(gaps[c.vertex], gap);
        report.largest_penetration = std::max(report.largest_penetration, -gap);
      }
    total_work += report.work_on_body;
    total_dissipation += report.friction_dissipation;
  }

  const std::vector<Obstacle> &ContactConstraints::obstacles() const
  {
    return obstacle_list;
  }

  const ContactSettings &ContactConstraints::settings() const
  {
    return contact_settings;
  }

  const ContactStepReport &ContactConstraints::last_step() const
  {
    return report;
  }

  double ContactConstraints::work_on_body() const
  {
    return total_work;
  }

  double ContactConstraints::friction_dissipation() const
  {
    return total_dissipation;
  }

  const std::vector<Vector3> &ContactConstraints::vertex_forces() const
  {
    return forces;
  }

  const std::vector<double> &ContactConstraints::vertex_gaps() const
  {
    return gaps;
  }

  const std::vector<Contact> &ContactConstraints::contacts() const
  {
    return step_contacts;
  }
} // namespace warpchol::fem
