#include <warpchol/app/parameters/loads.h>

namespace warpchol::app
{
  namespace parameters
  {
    void InitialState::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Initial state");
      prm.declare_entry("Linear velocity", "0, 0, 0", vector_pattern(),
                        "Initial velocity (m/s) of every vertex that is not fixed");
      prm.declare_entry("Angular velocity", "0, 0, 0", vector_pattern(),
                        "Initial angular velocity (rad/s, a vector along the axis) about the "
                        "rest centre of mass, added to the linear velocity: a spinning body");
      prm.leave_subsection();
    }

    void InitialState::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Initial state");
      linear_velocity  = get_vector(prm, "Linear velocity");
      angular_velocity = get_vector(prm, "Angular velocity");
      prm.leave_subsection();
    }

    void FixedVertices::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Fixed vertices");
      RegionParameters::declare_parameters(prm, "held at rest (their dofs are not unknowns)");
      prm.leave_subsection();
    }

    void FixedVertices::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Fixed vertices");
      region.parse_parameters(prm, file, "Fixed vertices");
      prm.leave_subsection();
    }

    void Gravity::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Gravity");
      prm.declare_entry("Acceleration", "0, 0, 0", vector_pattern(),
                        "Gravitational acceleration (m/s^2), e.g. 0, -9.81, 0");
      prm.leave_subsection();
    }

    void Gravity::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Gravity");
      acceleration = get_vector(prm, "Acceleration");
      prm.leave_subsection();
    }

    void RegionForce::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Region force");
      RegionParameters::declare_parameters(prm, "that carry the force");
      prm.declare_entry("Total force", "0, 0, 0", vector_pattern(),
                        "A constant force (N) on the region, shared by its vertices in proportion to "
                        "their masses (a body force)");
      prm.leave_subsection();
    }

    void RegionForce::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Region force");
      region.parse_parameters(prm, file, "Region force");
      total_force = get_vector(prm, "Total force");
      prm.leave_subsection();
    }

    void Tool::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Tool");
      RegionParameters::declare_parameters(prm, "the tool grabs");
      prm.declare_entry("Spring stiffness", "0", Patterns::Double(0),
                        "Stiffness (N/m) of the spring tying each grabbed vertex to its target");
      prm.declare_entry("Velocity", "0, 0, 0", vector_pattern(),
                        "Velocity (m/s) of the targets, which start at the grabbed vertices' "
                        "rest positions");
      prm.declare_entry("Duration", "0", Patterns::Double(0),
                        "Time (s) after which the targets stop and hold");
      declare_path_file(prm, "the targets move as its positions do from time 0 (its samples must "
                             "cover the run), instead of with Velocity");
      prm.leave_subsection();
    }

    void Tool::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Tool");
      region.parse_parameters(prm, file, "Tool");
      spring_stiffness = prm.get_double("Spring stiffness");
      velocity         = get_vector(prm, "Velocity");
      duration         = prm.get_double("Duration");
      if (region.kind != "none")
        require_positive(prm, file, "Tool", "Spring stiffness");
      path.file_name = parse_path_file(prm, file, "Tool", velocity);
      prm.leave_subsection();
    }
  } // namespace parameters
} // namespace warpchol::app
