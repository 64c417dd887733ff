#include <warpchol/app/parameters/events.h>
#include <warpchol/base/format.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdlib>

namespace warpchol::app
{
  namespace parameters
  {
    bool Cut::active() const
    {
      return duration > 0 && (velocity.norm() > 0 || !path.file_name.empty());
    }

    void Cut::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      prm.declare_entry("Blade start", "0, 0, 0", vector_pattern(),
                        "One end of the blade's cutting edge (m) at Start time");
      prm.declare_entry("Blade end", "0, 0, 0", vector_pattern(), "The other end of the cutting edge (m)");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern(),
                        "Velocity (m/s) of the edge: every tetrahedron the area it sweeps in a step "
                        "crosses is cut at that step (its stiffness and mass leave A)");
      prm.declare_entry("Start time", "0", Patterns::Double(0), "When the blade starts moving (s)");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "How long it moves (s); 0: no cut");
      declare_path_file(prm, "lines of time, start x, y, z, end x, y, z: the edge follows it from Start "
                             "time for Duration, instead of Blade start, Blade end and Velocity");
      prm.leave_subsection();
    }

    void Cut::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file, const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      blade_start    = get_vector(prm, "Blade start");
      blade_end      = get_vector(prm, "Blade end");
      velocity       = get_vector(prm, "Velocity");
      start_time     = prm.get_double("Start time");
      duration       = prm.get_double("Duration");
      path.file_name = parse_path_file(prm, file, subsection, velocity);
      if (path.file_name.empty())
        {
          if (duration > 0 && !((blade_end - blade_start).norm() > 0))
            file.fail(prm, subsection, "Blade end", "must differ from Blade start: the edge has no length");
          if (duration > 0 && !(velocity.norm() > 0))
            file.fail(prm, subsection, "Velocity", "must not be zero while the blade cuts (Duration > 0)");
          if (duration > 0 && velocity.cross(blade_end - blade_start).norm() <=
                                1e-12 * velocity.norm() * (blade_end - blade_start).norm())
            file.fail(prm, subsection, "Velocity", "runs along the edge: the blade would sweep no area");
        }
      prm.leave_subsection();
    }

    bool Grasp::active() const
    {
      return sphere_radius > 0;
    }

    void Grasp::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      prm.declare_entry("Sphere center", "0, 0, 0", vector_pattern(), "Centre of the jaws at time 0 (m)");
      prm.declare_entry("Sphere radius", "0", Patterns::Double(0),
                        "Radius of the jaws (m): at Grasp time the free vertices within it are "
                        "grasped; 0: no grasp");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern(),
                        "Velocity (m/s) of the jaws from the grasp on, for Duration: the grasped "
                        "vertices are pulled along");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "How long after the grasp the jaws move (s), then hold");
      prm.declare_entry("Grasp time", "0", Patterns::Double(0), "When the jaws close (s)");
      prm.declare_entry("Release time", "inf", Patterns::Anything(),
                        "When they open and let the vertices go (s, after Grasp time), or inf: never");
      prm.declare_entry("Spring stiffness", "0", Patterns::Double(0),
                        "Stiffness (N/m) of the spring tying each grasped vertex to the jaws; 0: "
                        "a penalty spring, 1e6 times the vertex's mass over dt^2, which holds it to "
                        "the jaws within a millionth of its motion");
      declare_path_file(prm, "lines of time, x, y, z of the jaws' centre: they close around its position "
                             "at Grasp time and follow it until Release time, instead of Sphere center "
                             "and Velocity");
      prm.leave_subsection();
    }

    void Grasp::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                 const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      sphere_center    = get_vector(prm, "Sphere center");
      sphere_radius    = prm.get_double("Sphere radius");
      velocity         = get_vector(prm, "Velocity");
      duration         = prm.get_double("Duration");
      grasp_time       = prm.get_double("Grasp time");
      spring_stiffness = prm.get_double("Spring stiffness");
      if (!parse_threshold(prm.get("Release time"), release_time))
        file.fail(prm, subsection, "Release time", "must be a time >= 0 (s) or inf");
      if (active() && !(release_time > grasp_time))
        file.fail(prm, subsection, "Release time", "must come after Grasp time (" + format_number(grasp_time) + " s)");
      path.file_name = parse_path_file(prm, file, subsection, velocity);
      prm.leave_subsection();
    }

    void MaterialChange::declare_parameters(ParameterHandler &prm, const std::string &subsection)
    {
      prm.enter_subsection(subsection);
      RegionParameters::declare_parameters(prm, "whose elements (all their vertices in it) change");
      prm.declare_entry("Time", "0", Patterns::Double(0), "When the material changes (s)");
      prm.declare_entry("Stiffness factor", "1", Patterns::Anything(),
                        "The Young's modulus of the region's elements is multiplied by this (> 0): "
                        "cauterized tissue stiffens (> 1), torn tissue softens (< 1)");
      prm.declare_entry("Stress", "continuous", Patterns::Selection("continuous|reset"),
                        "continuous: the changed elements keep their stress at the change (a plastic "
                        "strain takes up the rest), stiffened tissue holds its shape; reset: they keep "
                        "their rest shape, a strained element's stress is multiplied by the factor");
      prm.leave_subsection();
    }

    void MaterialChange::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file,
                                          const std::string &subsection)
    {
      this->subsection = subsection;
      prm.enter_subsection(subsection);
      region.parse_parameters(prm, file, subsection);
      time = prm.get_double("Time");
      const std::string factor = trim(prm.get("Stiffness factor"));
      char             *end    = nullptr;
      stiffness_factor         = std::strtod(factor.c_str(), &end);
      if (factor.empty() || *end != '\0' || !std::isfinite(stiffness_factor))
        file.fail(prm, subsection, "Stiffness factor", "must be a number > 0");
      if (!(stiffness_factor > 0))
        file.fail(prm, subsection, "Stiffness factor",
                  "must be > 0: a Young's modulus E <= 0 has no stiffness (a cut removes elements)");
      keep_stress = prm.get("Stress") == "continuous";
      prm.leave_subsection();
    }
  } // namespace parameters
} // namespace warpchol::app
