#pragma once

#include <warpchol/app/parameters/entries.h>
#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/app/path_file.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/parameter_handler.h>

#include <limits>
#include <string>

/**
 * @file
 * The subsections of the events of a run, each also numbered ("Cut 2", ...): the cuts
 * ("Cut"), the grasps ("Grasp") and the changes of the material ("Material change").
 */
namespace warpchol::app
{
  namespace parameters
  {
    /**
     * Subsection "Cut": a scalpel. Its edge, the segment from Blade start to Blade end,
     * moves with Velocity from Start time for Duration; every tetrahedron the area it sweeps
     * in a step crosses is cut (its stiffness and mass leave A) at that step. With a Path
     * file (time, both ends of the edge) the edge follows it instead. "Cut 2", "Cut 3", ...
     * are more blades, each with its own entries.
     */
    struct Cut
    {
      /** "Cut", "Cut 2", ...: the subsection it was read from. */
      std::string  subsection = "Cut";
      fem::Vector3 blade_start{0, 0, 0};
      fem::Vector3 blade_end{0, 0, 0};
      fem::Vector3 velocity{0, 0, 0};
      double       start_time = 0;
      double       duration   = 0;
      PathFile     path;

      /** Whether there is a cut: a blade that moves for some time. */
      bool active() const;

      static void declare_parameters(dealii::ParameterHandler &prm, const std::string &subsection = "Cut");
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                   const std::string &subsection = "Cut");
    };

    /**
     * Subsection "Grasp": a grasping instrument's jaws, a sphere that moves with Velocity
     * (from the grasp until Duration after it); at Grasp time the free vertices within it
     * are tied to it by stiff springs, at Release time they are let go. With a Path file
     * (time, centre) the jaws follow it instead. "Grasp 2", ... are more grasps.
     */
    struct Grasp
    {
      /** "Grasp", "Grasp 2", ...: the subsection it was read from. */
      std::string  subsection = "Grasp";
      fem::Vector3 sphere_center{0, 0, 0};
      double       sphere_radius = 0;
      fem::Vector3 velocity{0, 0, 0};
      double       duration     = 0;
      double       grasp_time   = 0;
      double       release_time = std::numeric_limits<double>::infinity();
      /** N/m; 0: a penalty spring 1e6 times each vertex's mass over dt^2. */
      double       spring_stiffness = 0;
      PathFile     path;

      /** Whether there is a grasp (a sphere of positive radius). */
      bool active() const;

      static void declare_parameters(dealii::ParameterHandler &prm, const std::string &subsection = "Grasp");
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                   const std::string &subsection = "Grasp");
    };

    /**
     * Subsection "Material change": at Time the Young's modulus of the elements whose
     * vertices all lie in Region is multiplied by Stiffness factor (cauterized tissue
     * stiffens, torn tissue softens). Stress: continuous keeps their stress at the change
     * (a plastic strain takes up the rest), reset keeps their rest shape (the stress scales
     * with the stiffness). "Material change 2", ... are more changes.
     */
    struct MaterialChange
    {
      /** "Material change", "Material change 2", ...: the subsection it was read from. */
      std::string      subsection = "Material change";
      RegionParameters region;
      double           time             = 0;
      double           stiffness_factor = 1;
      bool             keep_stress      = true;

      static void declare_parameters(dealii::ParameterHandler &prm,
                                     const std::string        &subsection = "Material change");
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                   const std::string &subsection = "Material change");
    };
  } // namespace parameters
} // namespace warpchol::app
