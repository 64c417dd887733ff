#include <warpchol/app/parameters/contact.h>
#include <warpchol/app/parameters/entries.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <cmath>

namespace warpchol::app
{
  namespace parameters
  {
    void Contact::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      prm.declare_entry("Method", "constraints", Patterns::Selection("constraints|penalty"),
                        "constraints: SOFA's way (impulses by projected Gauss-Seidel with the friction cone "
                        "on W = H A^-1 H^T, one correcting solve); penalty: a spring per penetrating "
                        "vertex carried in A and its factor (updates and downdates as contacts come and go)");
      prm.declare_entry("Penalty stiffness", "1e5", Patterns::Double(0),
                        "Method = penalty: the spring's stiffness (N/m); a resting vertex sinks its "
                        "share of the load over this, and the spring drags it along the obstacle as a "
                        "viscous friction of dt times this (the obstacles' Friction is not used)");
      prm.declare_entry("Alarm distance", "0.001", Patterns::Double(0),
                        "A surface vertex closer than this (m) to an obstacle, besides how far it moves in "
                        "a step, is a contact (SOFA's alarmDistance)");
      prm.declare_entry("Contact distance", "1e-4", Patterns::Double(0),
                        "The penetration (m) a step may leave (SOFA's contactDistance); each step's "
                        "largest is in log.csv");
      prm.declare_entry("Max iterations", "200", Patterns::Integer(1),
                        "Sweeps of projected Gauss-Seidel at most (SOFA's maxIterations); if it "
                        "stops short of the tolerance, a warning says so and the run goes on");
      prm.declare_entry("Tolerance", "1e-9", Patterns::Double(0),
                        "Gauss-Seidel stops when a sweep changes no contact velocity by more (m/s)");
      prm.declare_entry("Max contacts", "2000", Patterns::Integer(1),
                        "More contacts in a step stop the run with an error (W is m x m, m = 3 contacts)");
      prm.declare_entry("Compliance", "paths", Patterns::Selection("paths|full solves"),
                        "How W = H A^-1 H^T is built from the factor: forward solves on the contacts' "
                        "elimination-tree paths, or SOFA's way (a full forward solve per row)");
      prm.declare_entry("Compliance lag", "false", Patterns::Bool(),
                        "Compliance = paths, direct solves: true, the kept columns of A^-1 outlive the "
                        "factor's changes, W lagging behind the factor (as an asynchronously refreshed "
                        "factor gives it), Gauss-Seidel stopping at Contact distance / (40 dt) if that "
                        "is above Tolerance; a step whose contacts end more than a quarter of Contact "
                        "distance from where Gauss-Seidel aimed them is solved again from there, and W "
                        "is renewed (in single precision, which the same check covers) after six such "
                        "rounds. Faster steps, penetrations within a quarter "
                        "of Contact distance instead of the exact compliance's. false: W renewed at "
                        "every change of the factor");
      prm.leave_subsection();
    }

    void Contact::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Contact");
      settings.method = prm.get("Method") == "penalty" ? fem::ContactMethod::penalty : fem::ContactMethod::constraints;
      settings.penalty_stiffness = prm.get_double("Penalty stiffness");
      if (!(settings.penalty_stiffness > 0))
        file.fail(prm, "Contact", "Penalty stiffness", "must be > 0");
      settings.margin                      = prm.get_double("Alarm distance");
      settings.tolerance                   = prm.get_double("Contact distance");
      settings.gauss_seidel.max_iterations = static_cast<unsigned int>(prm.get_integer("Max iterations"));
      settings.gauss_seidel.tolerance      = prm.get_double("Tolerance");
      settings.max_contacts                = static_cast<unsigned int>(prm.get_integer("Max contacts"));
      settings.compliance = prm.get("Compliance") == "paths" ? cholesky::ComplianceMethod::paths :
                                                                cholesky::ComplianceMethod::full_solves;
      settings.keep_compliance_across_factor_changes = prm.get_bool("Compliance lag");
      settings.max_contacts_origin   = file.where("Contact", "Max contacts");
      settings.max_iterations_origin = file.where("Contact", "Max iterations");
      settings.tolerance_origin      = file.where("Contact", "Contact distance");
      prm.leave_subsection();
    }

    bool Obstacle::active() const
    {
      return type != "none";
    }

    fem::Obstacle Obstacle::build() const
    {
      fem::Obstacle obstacle = type == "plane"   ? fem::Obstacle::plane(point, normal) :
                               type == "sphere"  ? fem::Obstacle::sphere(point, radius) :
                               type == "capsule" ? fem::Obstacle::capsule(point, end, radius) :
                               type == "box"     ? fem::Obstacle::box(point, size) :
                                                   fem::Obstacle::surface(surface);
      obstacle.set_friction(friction);
      if (!path.file_name.empty())
        obstacle.set_path(path.path);
      return obstacle;
    }

    void Obstacle::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      prm.declare_entry("Type", "none", Patterns::Selection("none|" + selection_of(fem::obstacle_shape_names)),
                        "none, or the obstacle's shape: plane (Point, Normal), sphere (Point, Radius), "
                        "capsule (Point to End, Radius), box (Point, Size) or surface (File)");
      prm.declare_entry("Point", "0, 0, 0", vector_pattern(),
                        "A plane's point, a sphere's or a box's centre, a capsule's first end (m)");
      prm.declare_entry("Normal", "0, 0, 1", vector_pattern(), "A plane's outward normal (the solid is behind it)");
      prm.declare_entry("End", "0, 0, 0", vector_pattern(), "A capsule's other end (m)");
      prm.declare_entry("Radius", "0", Patterns::Double(0), "A sphere's or a capsule's radius (m)");
      prm.declare_entry("Size", "0, 0, 0", vector_pattern(), "A box's edge lengths along x, y, z (m)");
      prm.declare_entry("File", "", Patterns::Anything(),
                        "A surface's triangles: STL (ASCII or binary), OBJ or legacy VTK polydata, in "
                        "metres, relative to this file; the inside is behind the triangles' normals");
      prm.declare_entry("Friction", "0", Patterns::Anything(),
                        "Coulomb's friction coefficient against the body (static = dynamic), >= 0");
      declare_path_file(prm, "lines of time, x, y, z: the obstacle is translated by the path's "
                             "displacement from its first sample, which must cover the run");
      prm.leave_subsection();
    }

    void Obstacle::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                    const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      type   = prm.get("Type");
      point  = get_vector(prm, "Point");
      normal = get_vector(prm, "Normal");
      end    = get_vector(prm, "End");
      radius = prm.get_double("Radius");
      size   = get_vector(prm, "Size");
      {
        const std::string text  = trim(prm.get("Friction"));
        char             *stop  = nullptr;
        friction                = std::strtod(text.c_str(), &stop);
        if (text.empty() || *stop != '\0' || !(friction >= 0) || !std::isfinite(friction))
          file.fail(prm, subsection, "Friction", "must be a number >= 0");
      }
      path.file_name = parse_path_file(prm, file, subsection, fem::Vector3::Zero());
      file_name      = trim(prm.get("File"));
      if (type == "plane" && !(normal.norm() > 0))
        file.fail(prm, subsection, "Normal", "must not be zero");
      if ((type == "sphere" || type == "capsule") && !(radius > 0))
        file.fail(prm, subsection, "Radius", "must be > 0 for a " + type);
      if (type == "box" && !(size.minCoeff() > 0))
        file.fail(prm, subsection, "Size", "every edge of a box must be > 0");
      if (type == "surface")
        {
          if (file_name.empty())
            file.fail(prm, subsection, "File", "a surface needs a file of triangles");
          const std::string name =
            file_name[0] == '/' ? file_name : file.directory_of(subsection, "File") + file_name;
          try
            {
              surface = fem::read_triangle_surface(name);
            }
          catch (const InputError &error)
            {
              file.fail(prm, subsection, "File", error.what());
            }
        }
      prm.leave_subsection();
    }
  } // namespace parameters
} // namespace warpchol::app
