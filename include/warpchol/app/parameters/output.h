#pragma once

#include <warpchol/app/parameters/parameter_file.h>

#include <deal.II/base/parameter_handler.h>

#include <string>

/**
 * @file
 * The subsection of what a run writes and prints ("Output").
 */
namespace warpchol::app
{
  namespace parameters
  {
    /** Subsection "Output". */
    struct Output
    {
      std::string  directory = "output";
      /** The scene's name: the folder under directory; empty for the parameter file's name. */
      std::string  scene;
      /** Write a VTU file every this many steps (and the initial state); 0: none. */
      unsigned int vtu_interval = 0;
      /** "float32" (deal.II's DataOut) or "float64" (every value with its 17 digits). */
      std::string  vtu_precision = "float32";
      bool         write_log    = true;
      bool         print_timings = true;
      /** "auto" (when standard error is a terminal), "on" or "off" (true/yes, false/no in the file). */
      std::string  progress = "auto";
      /** Run the exact corotational model alongside and log the trajectory error. */
      bool         compare_with_corotational = false;
      /**
       * > 0: after the run, time this many steps of the exact corotational model (from
       * rest, on this machine) and print what exact corotation would have cost, the
       * speed-up, and WCC's per-step velocity error against it (measured every step).
       */
      unsigned int exact_steps_timed = 0;
      /**
       * Write the state of the run to SCENE/checkpoint.bin every this many steps (0:
       * never), from which "warpchol FILE --resume" goes on.
       */
      unsigned int checkpoint_interval = 0;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };
  } // namespace parameters
} // namespace warpchol::app
