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
#include <functional>
#include <unordered_map>

namespace warpchol::fem
{
  namespace
  {
    /** A contact's impulse in world coordinates from its 3 rows (normal, tangents). */
    Vector3 world_impulse(const Contact &c, const double *rows)
    {
      return rows[0] * c.normal + rows[1] * c.tangent_1 + rows[2] * c.tangent_2;
    }
  } // namespace

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

    /**
     * The point of the triangle @p a, @p b, @p c closest to @p p, as barycentric
     * coordinates (Ericson, Real-Time Collision Detection, 5.1.5).
     */
    std::array<double, 3> closest_in_triangle(const Vector3 &p, const Vector3 &a, const Vector3 &b, const Vector3 &c)
    {
      const Vector3 ab = b - a, ac = c - a, ap = p - a;
      const double  d1 = ab.dot(ap), d2 = ac.dot(ap);
      if (d1 <= 0 && d2 <= 0)
        return {{1, 0, 0}};
      const Vector3 bp = p - b;
      const double  d3 = ab.dot(bp), d4 = ac.dot(bp);
      if (d3 >= 0 && d4 <= d3)
        return {{0, 1, 0}};
      const double vc = d1 * d4 - d3 * d2;
      if (vc <= 0 && d1 >= 0 && d3 <= 0)
        {
          const double v = d1 / (d1 - d3);
          return {{1 - v, v, 0}};
        }
      const Vector3 cp = p - c;
      const double  d5 = ab.dot(cp), d6 = ac.dot(cp);
      if (d6 >= 0 && d5 <= d6)
        return {{0, 0, 1}};
      const double vb = d5 * d2 - d1 * d6;
      if (vb <= 0 && d2 >= 0 && d6 <= 0)
        {
          const double w = d2 / (d2 - d6);
          return {{1 - w, 0, w}};
        }
      const double va = d3 * d6 - d5 * d4;
      if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        {
          const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
          return {{0, 1 - w, w}};
        }
      const double denominator = 1 / (va + vb + vc);
      const double v = vb * denominator, w = vc * denominator;
      return {{1 - v - w, v, w}};
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
    , penalty(settings.penalty_stiffness, settings.margin)
  {}

  std::vector<std::array<unsigned int, 3>> surface_triangles(const ElasticBody &body)
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
    std::vector<std::array<unsigned int, 3>> surface;
    for (std::size_t k = 0; k < faces.size();)
      {
        std::size_t same = k + 1;
        while (same < faces.size() && faces[same] == faces[k])
          ++same;
        if (same == k + 1)
          surface.push_back(faces[k]);
        k = same;
      }
    return surface;
  }

  std::vector<unsigned int> surface_vertices(const ElasticBody &body)
  {
    std::vector<char> on_surface(body.n_vertices(), 0);
    for (const auto &face : surface_triangles(body))
      for (const unsigned int v : face)
        on_surface[v] = 1;
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
        triangles = surface_triangles(body);
        std::vector<char> on_surface(body.n_vertices(), 0);
        for (const auto &face : triangles)
          for (const unsigned int v : face)
            on_surface[v] = 1;
        surface.clear();
        for (unsigned int v = 0; v < body.n_vertices(); ++v)
          if (on_surface[v])
            surface.push_back(v);
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
    detect_tips(body, positions, velocities, time, time_step, found);
    return found;
  }

  void ContactConstraints::detect_tips(const ElasticBody &body, const std::vector<Vector3> &positions,
                                       const std::vector<Vector3> &velocities, const double time,
                                       const double time_step, std::vector<Contact> &found) const
  {
    // A tip or an edge smaller than the mesh's spacing passes between the vertices: where
    // the point of a surface triangle deepest in the obstacle lies inside the triangle,
    // that point is a contact. The deepest point is the one nearest the obstacle's core
    // (a sphere's centre, a capsule's axis) or one of its sharp edges (a box's, a triangle
    // surface's). Triangles with a vertex in contact with the same obstacle already are
    // left out.
    std::vector<char> touching(body.n_vertices(), 0);
    for (unsigned int o = 0; o < obstacle_list.size(); ++o)
      {
        const Obstacle     &obstacle = obstacle_list[o];
        const ObstacleShape shape    = obstacle.shape();
        const bool          cored    = shape == ObstacleShape::sphere || shape == ObstacleShape::capsule;
        const std::vector<Obstacle::Segment> edges =
          cored ? std::vector<Obstacle::Segment>() : obstacle.sharp_edges(time + time_step);
        if (!cored && edges.empty())
          continue;
        std::fill(touching.begin(), touching.end(), 0);
        for (const Contact &contact : found)
          if (contact.obstacle == o)
            touching[contact.vertex] = 1;
        for (const auto &face : triangles)
          {
            if (touching[face[0]] || touching[face[1]] || touching[face[2]] ||
                (body.is_fixed(face[0]) && body.is_fixed(face[1]) && body.is_fixed(face[2])))
              continue;
            const Vector3 &a = positions[face[0]], &b = positions[face[1]], &c = positions[face[2]];
            // The obstacle's proximity at the triangle's centroid first: a cheap rejection.
            const Vector3 centroid = (a + b + c) / 3;
            const double  size     = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
            double        speed    = 0;
            for (const unsigned int v : face)
              speed = std::max(speed, velocities[v].norm());
            const double reach = contact_settings.margin + time_step * speed;
            if (obstacle.proximity(centroid, time + time_step).distance >= reach + size)
              continue;
            // The triangle's point nearest a core, by alternating the two nearest-point
            // projections (which converge for two convex sets; one pass for a point).
            const auto nearest_to = [&](const auto &core, const unsigned int passes) {
              Vector3               point = centroid;
              std::array<double, 3> weights{};
              for (unsigned int pass = 0; pass < passes; ++pass)
                {
                  weights = closest_in_triangle(core(point), a, b, c);
                  point   = weights[0] * a + weights[1] * b + weights[2] * c;
                }
              return weights;
            };
            std::array<double, 3> weights{};
            Proximity             proximity;
            proximity.distance = reach;
            const auto keep_if_deeper = [&](const std::array<double, 3> &candidate) {
              if (std::min({candidate[0], candidate[1], candidate[2]}) <= 1e-3)
                return; // on an edge or at a vertex: the vertices' own contacts cover it
              const Proximity here =
                obstacle.proximity(candidate[0] * a + candidate[1] * b + candidate[2] * c, time + time_step);
              if (here.distance < proximity.distance)
                {
                  proximity = here;
                  weights   = candidate;
                }
            };
            if (cored)
              keep_if_deeper(nearest_to([&](const Vector3 &p) { return obstacle.core_point(p, time + time_step); },
                                        shape == ObstacleShape::sphere ? 1 : 4));
            else
              for (const Obstacle::Segment &edge : edges)
                {
                  const Vector3 axis = edge[1] - edge[0];
                  const auto on_edge = [&](const Vector3 &p) {
                    const double along = std::clamp((p - edge[0]).dot(axis) / axis.squaredNorm(), 0., 1.);
                    return Vector3(edge[0] + along * axis);
                  };
                  // An edge farther from the centroid than the triangle's size and the reach misses it.
                  if ((on_edge(centroid) - centroid).norm() < size + reach)
                    keep_if_deeper(nearest_to(on_edge, 4));
                }
            if (!(proximity.distance < reach))
              continue;
            Contact contact;
            contact.vertex     = face[0];
            contact.obstacle   = o;
            contact.n_vertices = 3;
            contact.vertices   = face;
            contact.weights    = weights;
            contact.normal     = proximity.normal;
            contact.tangent_1  = proximity.normal.unitOrthogonal();
            contact.tangent_2  = proximity.normal.cross(contact.tangent_1);
            contact.gap        = proximity.distance;
            found.push_back(contact);
          }
      }
  }

  sparse::CSCMatrix ContactConstraints::constraint_columns(const ElasticBody &body, const std::vector<Contact> &contacts,
                                                           const std::vector<Matrix3> *rotations)
  {
    const Index       m  = 3 * static_cast<Index>(contacts.size());
    sparse::CSCMatrix ht = sparse::CSCMatrix::zero(body.n_unknowns(), m);
    for (std::size_t j = 0; j < contacts.size(); ++j)
      {
        const Contact &contact = contacts[j];
        for (int d = 0; d < 3; ++d)
          {
            const Vector3 &direction = d == 0 ? contact.normal : d == 1 ? contact.tangent_1 : contact.tangent_2;
            for (unsigned int k = 0; k < contact.n_vertices; ++k)
              {
                const unsigned int v     = contact.vertex_of(k);
                const Index        first = body.first_unknown(v);
                if (first < 0)
                  continue; // a fixed vertex of a triangle: its velocity is zero
                // The row h on v is the row R^T h on the unknowns y (v = R y).
                const Vector3 rotated =
                  contact.weights[k] * (rotations ? Vector3((*rotations)[v].transpose() * direction) : direction);
                for (int c = 0; c < 3; ++c)
                  {
                    ht.row_index.push_back(first + c);
                    ht.values.push_back(rotated[c]);
                  }
              }
            ht.column_start[3 * j + d + 1] = static_cast<Index>(ht.row_index.size());
          }
      }
    return ht;
  }

  ContactCompliance ContactConstraints::compliance_from_kept_columns(const ElasticBody     &body,
                                                                     const ElasticityModel &model,
                                                                     const bool             lag)
  {
    // The contacts' vertices that have unknowns, each once: S, 3 unknowns per vertex.
    const std::vector<Matrix3>                  *rotations = model.solve_rotations();
    std::unordered_map<unsigned int, Index>      slot_of_vertex;
    std::vector<Index>                           unknowns;
    std::vector<ContactCompliance::ContactRows> rows(step_contacts.size());
    for (std::size_t j = 0; j < step_contacts.size(); ++j)
      {
        const Contact &contact = step_contacts[j];
        Matrix3        directions;
        directions << contact.normal, contact.tangent_1, contact.tangent_2;
        for (unsigned int k = 0; k < contact.n_vertices; ++k)
          {
            const unsigned int v     = contact.vertex_of(k);
            const Index        first = body.first_unknown(v);
            if (first < 0)
              continue; // a fixed vertex of a triangle: its velocity is zero
            const auto [place, added] = slot_of_vertex.emplace(v, static_cast<Index>(unknowns.size() / 3));
            if (added)
              for (Index c = 0; c < 3; ++c)
                unknowns.push_back(first + c);
            ContactCompliance::VertexRows &part = rows[j].parts[rows[j].n_parts++];
            part.slot                           = place->second; // its place among S, until G places it
            part.rows = contact.weights[k] * (rotations ? Matrix3((*rotations)[v].transpose() * directions) : directions);
          }
      }
    kept_columns.outlive_factor_changes = lag;
    kept_columns.group                  = 3;
    model.solver().inverse_block(unknowns, kept_columns);
    report.kept_columns   = static_cast<unsigned int>(kept_columns.kept);
    report.solved_columns = static_cast<unsigned int>(kept_columns.solved);
    // Each vertex's slot in G: where its three unknowns were placed.
    for (ContactCompliance::ContactRows &contact : rows)
      for (unsigned int k = 0; k < contact.n_parts; ++k)
        contact.parts[k].slot = kept_columns.places[3 * contact.parts[k].slot] / 3;
    return ContactCompliance::factored(kept_columns.gram, std::move(rows));
  }

  void ContactConstraints::correct(const ElasticBody &body, ElasticityModel &model,
                                   const std::vector<Vector3> &positions, std::vector<Vector3> &velocities,
                                   const double time, const double time_step, StepStatistics &statistics)
  {
    previous_contacts = std::move(step_contacts);
    detect_for_step(body, positions, velocities, time, time_step, statistics);
    const std::size_t n_contacts = step_contacts.size();
    if (n_contacts == 0)
      {
        lambda.clear();
        return;
      }
    if (model.solver().state() != cholesky::SparseCholesky::State::factorized)
      throw InputError("contact needs warpchol's own factor of A, not a peer's (Solver/Backend)");

    std::vector<double>  friction(n_contacts);
    std::vector<Vector3> obstacle_velocity(n_contacts);
    for (std::size_t j = 0; j < n_contacts; ++j)
      {
        const Obstacle &o    = obstacle_list[step_contacts[j].obstacle];
        obstacle_velocity[j] = o.velocity(point_value(step_contacts[j], positions), time, time + time_step);
        friction[j]          = o.friction();
      }
    // A lagged W is checked by the correction's direct solve; CG's own tolerance would blur
    // that check, so an iterating step renews W at every change of the factor.
    const bool by_paths = contact_settings.compliance == cholesky::ComplianceMethod::paths;
    const bool may_lag  = by_paths && contact_settings.keep_compliance_across_factor_changes &&
                         !model.solves_iteratively();
    // A factored W reads the kept columns' G: renewing them (dropping what was kept)
    // comes with a new W.
    const auto compliance = [&](const bool renew) {
      StageTimer timer(statistics.stages, stage::contact_compliance);
      if (renew)
        {
          kept_columns         = cholesky::KeptInverseColumns();
          rounds_since_renewal = 0;
        }
      if (by_paths)
        return compliance_from_kept_columns(body, model, may_lag);
      const sparse::CSCMatrix ht = constraint_columns(body, step_contacts, model.solve_rotations());
      return ContactCompliance::whole(model.solver().compliance(ht, contact_settings.compliance));
    };
    ContactCompliance w = compliance(renew_compliance);
    renew_compliance    = false;
    report.compliance_lag = by_paths ? kept_columns.factor_changes_behind : 0;
    // A lagged W, or one renewed in single precision, is checked by the correction's
    // direct solve.
    const bool checked = report.compliance_lag > 0 || (by_paths && kept_columns.single_precision);

    // u = free + W lambda is where Gauss-Seidel aims the contacts (u_n >= 0 keeps the next
    // position out of the obstacle, u_t is the sliding velocity relative to it).
    std::vector<double> free_velocity = contact_velocities(velocities, obstacle_velocity, time_step);
    // Gauss-Seidel need not resolve a lagged W finer than the check lets its correction
    // miss: a tenth of that, or Tolerance if larger.
    GaussSeidelSettings gauss_seidel = contact_settings.gauss_seidel;
    if (checked)
      gauss_seidel.tolerance = std::max(gauss_seidel.tolerance, contact_settings.tolerance / (40 * time_step));
    std::optional<ContactCompliance::Product> w_lambda;
    solve_for_impulses(w, free_velocity, friction, gauss_seidel, w_lambda, statistics);
    apply_impulses(body, model, lambda, velocities, statistics);
    // A W exactly as the factor has it aims where the direct solve goes: any other is checked.
    if (checked)
      aim_again(body, model, compliance, w, w_lambda, free_velocity, friction, gauss_seidel, obstacle_velocity,
                time_step, velocities, statistics);

    record_forces_and_gaps(positions, velocities, obstacle_velocity, time, time_step);
  }

  void ContactConstraints::aim_again(const ElasticBody &body, ElasticityModel &model,
                                     const std::function<ContactCompliance(bool)> &compliance,
                                     ContactCompliance &w, std::optional<ContactCompliance::Product> &product,
                                     std::vector<double> free_velocity,
                                     const std::vector<double> &friction, const GaussSeidelSettings &gauss_seidel,
                                     const std::vector<Vector3> &obstacle_velocity, const double time_step,
                                     std::vector<Vector3> &velocities, StepStatistics &statistics)
  {
    // The miss: reached - (free + W lambda), largest over the rows; u = reached - W lambda
    // are then the free velocities that aim from where the correction left the contacts.
    std::vector<double> reached, w_lambda;
    const auto          measure_miss = [&]() {
      StageTimer timer(statistics.stages, stage::contact_correction);
      reached          = contact_velocities(velocities, obstacle_velocity, time_step);
      w_lambda         = product->values();
      report.aim_error = 0;
      for (std::size_t i = 0; i < reached.size(); ++i)
        report.aim_error = std::max(report.aim_error, std::abs(reached[i] - free_velocity[i] - w_lambda[i]));
    };
    measure_miss();
    // Each round with the same W cuts the miss by about W's relative error; the third
    // renews W.
    constexpr unsigned int rounds_with_lagged_w = 2;
    unsigned int           round = 0;
    bool                   renewed = false;
    for (; report.aim_error * time_step > contact_settings.tolerance / 4; ++round)
      {
        if (round == rounds_with_lagged_w)
          {
            w = compliance(true);
            product.emplace(w, lambda);
            w_lambda              = product->values();
            report.compliance_lag = 0;
            renewed               = true;
          }
        const std::size_t m = reached.size();
        for (std::size_t i = 0; i < m; ++i)
          free_velocity[i] = reached[i] - w_lambda[i];
        const std::vector<double> before     = lambda;
        const unsigned int        iterations = report.gauss_seidel.iterations;
        {
          StageTimer timer(statistics.stages, stage::contact_gauss_seidel);
          report.gauss_seidel = solve_friction_cone(
            w, free_velocity, friction, renewed ? contact_settings.gauss_seidel : gauss_seidel, lambda, *product);
        }
        report.gauss_seidel.iterations += iterations;
        std::vector<double> change(m);
        for (std::size_t i = 0; i < m; ++i)
          change[i] = lambda[i] - before[i];
        apply_impulses(body, model, change, velocities, statistics);
        measure_miss();
      }
    // Once the rounds since W was renewed have cost about what a renewal does, the next
    // step renews it.
    rounds_since_renewal += renewed ? 0 : round;
    renew_compliance = rounds_since_renewal >= rounds_worth_a_renewal;
  }

  std::vector<double> ContactConstraints::contact_velocities(const std::vector<Vector3> &velocities,
                                                             const std::vector<Vector3> &obstacle_velocity,
                                                             const double                time_step) const
  {
    std::vector<double> u(3 * step_contacts.size());
    for (std::size_t j = 0; j < step_contacts.size(); ++j)
      {
        const Contact &c        = step_contacts[j];
        const Vector3  velocity = point_value(c, velocities);
        const Vector3  relative = velocity - obstacle_velocity[j];
        u[3 * j]                = c.normal.dot(velocity) + c.gap / time_step;
        u[3 * j + 1]            = c.tangent_1.dot(relative);
        u[3 * j + 2]            = c.tangent_2.dot(relative);
      }
    return u;
  }

  void ContactConstraints::apply_impulses(const ElasticBody &body, ElasticityModel &model,
                                          const std::vector<double> &impulses, std::vector<Vector3> &velocities,
                                          StepStatistics &statistics) const
  {
    // The impulses as forces on the vertices, one solve.
    std::vector<Vector3> on_vertices(body.n_vertices(), Vector3::Zero());
    for (std::size_t j = 0; j < step_contacts.size(); ++j)
      {
        const Contact &c       = step_contacts[j];
        const Vector3  impulse = world_impulse(c, impulses.data() + 3 * j);
        for (unsigned int k = 0; k < c.n_vertices; ++k)
          on_vertices[c.vertex_of(k)] += c.weights[k] * impulse;
      }
    StageTimer           timer(statistics.stages, stage::contact_correction);
    std::vector<Vector3> change;
    model.solve_again(on_vertices, change, statistics);
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      velocities[v] += change[v];
  }

  void ContactConstraints::detect_for_step(const ElasticBody &body, const std::vector<Vector3> &positions,
                                           const std::vector<Vector3> &velocities, const double time,
                                           const double time_step, StepStatistics &statistics)
  {
    report = ContactStepReport();
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
  }

  PenaltySprings::Change ContactConstraints::tie_penalty_springs(const ElasticBody          &body,
                                                                 const std::vector<Vector3> &positions,
                                                                 const std::vector<Vector3> &velocities,
                                                                 const double time, const double time_step,
                                                                 StepStatistics &statistics)
  {
    detect_for_step(body, positions, velocities, time, time_step, statistics);
    StageTimer timer(statistics.stages, stage::contact_penalty);
    return penalty.tie(step_contacts, obstacle_list, positions, velocities, body.n_vertices(), time, time_step);
  }

  PenaltySprings::Change ContactConstraints::tie_entering_springs(const std::vector<Vector3> &positions,
                                                                  const std::vector<Vector3> &velocities,
                                                                  const double time, const double time_step,
                                                                  StepStatistics &statistics)
  {
    StageTimer timer(statistics.stages, stage::contact_penalty);
    return penalty.tie_entering(step_contacts, obstacle_list, positions, velocities, time, time_step);
  }

  double ContactConstraints::penalty_diagonal(const unsigned int vertex) const
  {
    return penalty.diagonal(vertex);
  }

  void ContactConstraints::add_penalty_forces(std::vector<Vector3> &body_forces) const
  {
    penalty.add_forces(body_forces);
  }

  void ContactConstraints::finish_penalty_step(const std::vector<Vector3> &positions,
                                               const std::vector<Vector3> &velocities, const double time,
                                               const double time_step, StepStatistics &statistics)
  {
    StageTimer timer(statistics.stages, stage::contact_penalty);
    penalty.record(velocities, time_step, forces, report);
    record_gaps_and_totals(positions, velocities, time, time_step);
  }

  void ContactConstraints::solve_for_impulses(const ContactCompliance &w, const std::vector<double> &free_velocity,
                                              const std::vector<double> &friction, const GaussSeidelSettings &settings,
                                              std::optional<ContactCompliance::Product> &w_lambda,
                                              StepStatistics &statistics)
  {
    const std::size_t n_contacts = step_contacts.size();
    StageTimer timer(statistics.stages, stage::contact_gauss_seidel);
    // As SOFA's solver starts from the last forces.
    std::unordered_map<std::uint64_t, std::size_t> previous;
    for (std::size_t j = 0; j < previous_contacts.size(); ++j)
      previous[contact_key(previous_contacts[j])] = j;
    std::vector<double> start(3 * n_contacts, 0.);
    for (std::size_t j = 0; j < n_contacts; ++j)
      if (const auto found = previous.find(contact_key(step_contacts[j])); found != previous.end())
        for (std::size_t d = 0; d < 3; ++d)
          start[3 * j + d] = lambda[3 * found->second + d];
    lambda = std::move(start);
    w_lambda.emplace(w, lambda);
    report.gauss_seidel = solve_friction_cone(w, free_velocity, friction, settings, lambda, *w_lambda);
  }

  void ContactConstraints::record_forces_and_gaps(const std::vector<Vector3> &positions,
                                                  const std::vector<Vector3> &velocities,
                                                  const std::vector<Vector3> &obstacle_velocity, const double time,
                                                  const double time_step)
  {
    const std::size_t n_contacts = step_contacts.size();
    for (std::size_t j = 0; j < n_contacts; ++j)
      {
        const Contact &c        = step_contacts[j];
        const Vector3  impulse  = impulse_of(j);
        const Vector3  velocity = point_value(c, velocities);
        const Vector3  relative = velocity - obstacle_velocity[j];
        const double   sliding  = -(lambda[3 * j + 1] * c.tangent_1.dot(relative) + lambda[3 * j + 2] * c.tangent_2.dot(relative));
        for (unsigned int k = 0; k < c.n_vertices; ++k)
          forces[c.vertex_of(k)] += c.weights[k] * impulse / time_step;
        report.total_force += impulse / time_step;
        report.normal_force += std::abs(lambda[3 * j]) / time_step;
        report.friction_force += std::hypot(lambda[3 * j + 1], lambda[3 * j + 2]) / time_step;
        report.work_on_body += impulse.dot(velocity);
        report.friction_dissipation += std::max(0., sliding);
      }
    record_gaps_and_totals(positions, velocities, time, time_step);
  }

  void ContactConstraints::record_gaps_and_totals(const std::vector<Vector3> &positions,
                                                  const std::vector<Vector3> &velocities, const double time,
                                                  const double time_step)
  {
    // The penetration after the step, of every contact found (with a spring or not).
    for (const Contact &c : step_contacts)
      {
        const Vector3 next = point_value(c, positions) + time_step * point_value(c, velocities);
        const double  gap  = obstacle_list[c.obstacle].proximity(next, time + time_step).distance;
        for (unsigned int k = 0; k < c.n_vertices; ++k)
          gaps[c.vertex_of(k)] = std::min(gaps[c.vertex_of(k)], gap);
        report.largest_penetration = std::max(report.largest_penetration, -gap);
      }
    total_work += report.work_on_body;
    total_dissipation += report.friction_dissipation;
  }

  Vector3 ContactConstraints::impulse_of(const std::size_t j) const
  {
    return world_impulse(step_contacts[j], lambda.data() + 3 * j);
  }

  void ContactConstraints::save(BinaryWriter &writer) const
  {
    // A resumed run solves the columns of A^-1 anew: so does this one at its next step,
    // and the two go on alike (a lagged W would differ).
    kept_columns         = cholesky::KeptInverseColumns();
    renew_compliance     = false;
    rounds_since_renewal = 0;
    writer.section("contact");
    // The last step's contacts as their warm start finds them again (contact_key()), their
    // impulses; penalty contact has no impulses to start from.
    const bool warm_start = contact_settings.method == ContactMethod::constraints;
    write_contact_keys(writer, warm_start ? step_contacts : std::vector<Contact>());
    writer.write(lambda);
    writer.write(total_work);
    writer.write(total_dissipation);
    penalty.save(writer);
  }

  void ContactConstraints::load(BinaryReader &reader)
  {
    reader.expect_section("contact");
    step_contacts = read_contact_keys(reader, obstacle_list.size(), "contact");
    reader.read(lambda);
    if (lambda.size() != 3 * step_contacts.size())
      reader.fail("holds " + std::to_string(step_contacts.size()) + " contacts and " + std::to_string(lambda.size()) +
                  " impulses (3 per contact)");
    reader.read(total_work);
    reader.read(total_dissipation);
    penalty.load(reader, obstacle_list.size());
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
