#pragma once

#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/app/path_file.h>
#include <warpchol/contact/contact_constraints.h>
#include <warpchol/contact/triangle_surface.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

/**
 * @file
 * The subsections of contact: "Contact" (how contacts are found and solved) and the
 * obstacles, "Obstacle", "Obstacle 2", ... (numbered as the events are), with the names a
 * SOFA user knows from its collision pipeline and GenericConstraintSolver: Alarm distance
 * (the margin), Contact distance (the tolerance), Max iterations, Tolerance, Friction.
 */
namespace warpchol::app
{
  namespace parameters
  {
    /** Subsection "Contact". */
    struct Contact
    {
      /** With the cap's origin "FILE:LINE: Contact/Max contacts" for the message of a step that exceeds it. */
      fem::ContactSettings settings;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /**
     * Subsection "Obstacle": a rigid obstacle or instrument of Type plane (Point, Normal),
     * sphere (Point: centre, Radius), capsule (Point to End, Radius), box (Point: centre,
     * Size) or surface (File: STL, OBJ or legacy VTK, in metres), with a Friction
     * coefficient; fixed, or translated along a Path file (time, x, y, z) from its first
     * sample. "Obstacle 2", ... are more.
     */
    struct Obstacle
    {
      std::string  subsection = "Obstacle";
      /** "none" or an fem::obstacle_shape_names name. */
      std::string  type       = "none";
      fem::Vector3 point{0, 0, 0};
      fem::Vector3 normal{0, 0, 1};
      fem::Vector3 end{0, 0, 0};
      double       radius   = 0;
      fem::Vector3 size{0, 0, 0};
      double       friction = 0;
      /** The surface file as given, and its triangles (read while parsing). */
      std::string          file_name;
      fem::TriangleSurface surface;
      PathFile             path;

      bool active() const;

      /** The obstacle, without its path (set once the path file is read). */
      fem::Obstacle build() const;

      static void declare_parameters(dealii::ParameterHandler &prm, const std::string &subsection = "Obstacle");
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                   const std::string &subsection = "Obstacle");
    };
  } // namespace parameters
} // namespace warpchol::app
