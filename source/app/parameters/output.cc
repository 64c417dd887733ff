#include <warpchol/app/parameters/output.h>

namespace warpchol::app
{
  namespace parameters
  {
    void Output::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Directory", "output", Patterns::Anything(),
                        "Results go to DIRECTORY/SCENE/ (relative to the working directory)");
      prm.declare_entry("Scene", "", Patterns::Anything(),
                        "The scene's name; empty: the parameter file's name without .prm");
      prm.declare_entry("VTU interval", "0", Patterns::Integer(0),
                        "Write a VTU file (and the PVD series) every this many steps, and the "
                        "initial state; 0: none");
      prm.declare_entry("VTU precision", "float32", Patterns::Selection("float32|float64"),
                        "The numbers of the VTU files: float32 (deal.II's DataOut, about 7 "
                        "digits, the smaller files) or float64 (17 digits, for comparing "
                        "trajectories with a reference beyond 1e-7; the files are about twice "
                        "as large)");
      prm.declare_entry("Write log", "false", Patterns::Bool(),
                        "Write the per-step CSV log SCENE/log.csv");
      prm.declare_entry("Print timings", "true", Patterns::Bool(),
                        "Print run times and the solver's figures (fill, columns and flops "
                        "recomputed) in the summary, with a table of the stages that ran (runs, "
                        "seconds per step, share of the run); false leaves what depends on the "
                        "model alone, the same from run to run and from solver to solver, and "
                        "lists the stages by name");
      prm.declare_entry("Progress", "auto", Patterns::Selection("auto|on|off|true|false|yes|no"),
                        "A progress line on standard error: auto shows it on a terminal; on "
                        "(or true, yes) always, off (or false, no) never");
      prm.declare_entry("Compare with corotational", "false", Patterns::Bool(),
                        "Also run the exact corotational model, in step (not timed), and report "
                        "the trajectory error max_i |x_i - x_i(corotational)| and the RMS error "
                        "sqrt(mean_i |x_i - x_i(corotational)|^2), both over "
                        "max_i |x_i(corotational) - X_i|, in the log and the summary");
      prm.declare_entry("Exact steps timed", "0", Patterns::Integer(0, 1000),
                        "After the run, time this many steps of the exact corotational model (from "
                        "rest, output off) and print what exact corotation costs a step on this "
                        "machine and the run's speed-up over it; WCC then also estimates each "
                        "step's velocity error against exact corotation (|A^-1 (b - B v)| / |v|, "
                        "B the exact matrix, A the factor's: one product and one solve a step). 0: "
                        "none");
      prm.declare_entry("Checkpoint interval", "0", Patterns::Integer(0),
                        "Write the whole state of the run (positions, velocities, the model's "
                        "matrix, stored rotations and factor, the tool, the log so far) to "
                        "SCENE/checkpoint.bin every this many steps, replacing the last one "
                        "atomically; 'warpchol FILE.prm --resume' goes on from it and gives the "
                        "same trajectory, to the bit, as a run never stopped. 0: none");
      prm.leave_subsection();
    }

    void Output::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &)
    {
      prm.enter_subsection("Output");
      directory     = prm.get("Directory");
      scene         = trim(prm.get("Scene"));
      vtu_interval  = prm.get_integer("VTU interval");
      vtu_precision = prm.get("VTU precision");
      write_log     = prm.get_bool("Write log");
      print_timings = prm.get_bool("Print timings");
      // The words of a Bool entry mean on and off, as in the other switches.
      progress = prm.get("Progress");
      if (progress == "true" || progress == "yes")
        progress = "on";
      else if (progress == "false" || progress == "no")
        progress = "off";
      compare_with_corotational = prm.get_bool("Compare with corotational");
      exact_steps_timed         = prm.get_integer("Exact steps timed");
      checkpoint_interval       = prm.get_integer("Checkpoint interval");
      prm.leave_subsection();
    }
  } // namespace parameters
} // namespace warpchol::app
