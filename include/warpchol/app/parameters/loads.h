#pragma once

#include <warpchol/app/parameters/entries.h>
#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/app/path_file.h>
#include <warpchol/fem/small_dense.h>

#include <deal.II/base/parameter_handler.h>

/**
 * @file
 * The subsections of what acts on the body: its initial state ("Initial state"), the
 * fixed vertices ("Fixed vertices"), the loads ("Gravity", "Region force") and the tool
 * that pulls a region ("Tool").
 */
namespace warpchol::app
{
  namespace parameters
  {
    /** Subsection "Initial state": a rigid motion to start from (rest by default). */
    struct InitialState
    {
      fem::Vector3 linear_velocity{0, 0, 0};
      /** rad/s, about the rest centre of mass. */
      fem::Vector3 angular_velocity{0, 0, 0};

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Fixed vertices". */
    struct FixedVertices
    {
      RegionParameters region;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Gravity". */
    struct Gravity
    {
      fem::Vector3 acceleration{0, 0, 0};

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Region force": a constant total force on a region, shared by mass. */
    struct RegionForce
    {
      RegionParameters region;
      fem::Vector3     total_force{0, 0, 0};

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /**
     * Subsection "Tool": a region pulled by springs towards targets that move, with a
     * velocity or along a path file (time, x, y, z: they move as it does from time 0).
     */
    struct Tool
    {
      RegionParameters region;
      double           spring_stiffness = 0;
      fem::Vector3     velocity{0, 0, 0};
      double           duration = 0;
      PathFile         path;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };
  } // namespace parameters
} // namespace warpchol::app
