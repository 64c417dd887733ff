#pragma once

#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/fem/energy_balance.h>

#include <map>
#include <memory>
#include <ostream>
#include <string>

/**
 * @file
 * The driver: builds a scene from its parameters, runs its time steps, writes what was
 * asked for and prints a summary.
 */
namespace warpchol::app
{
  /** Totals over the steps of a run, for the summary. */
  struct RunTotals
  {
    unsigned int steps                  = 0;
    double       elements_updated       = 0;
    double       max_elements_updated   = 0;
    unsigned int steps_with_updates     = 0;
    unsigned int trailing_steps_without_update = 0;
    unsigned int refactorizations       = 0;
    double       columns_recomputed_pct = 0;
    double       flops_recomputed_pct   = 0;
    /** Iterations of preconditioned CG, summed over the steps. */
    unsigned int cg_iterations          = 0;
    /** Steps per refresh of the factor: "full", "all", "below_top", "none". */
    std::map<std::string, unsigned int> refreshes;
    fem::StepStatistics seconds;
    double       step_seconds = 0;
    /** The whole run: steps, log, VTU files (the initial one included). */
    double       run_seconds = 0;
    /** Sum over updates of the rest distance of the element's centre to the tool's centre. */
    double       updated_distance_to_tool = 0;
    /** Trajectory error against the corotational run: largest over the steps, and last. */
    double       max_error_vs_corotational  = 0;
    double       last_error_vs_corotational = 0;
  };

  class Simulation
  {
  public:
    /** Build the scene (mesh, body, model and its first factorization). */
    explicit Simulation(const AllParameters &parameters);

    /**
     * Run the steps, writing the log and VTU files if asked, and print the summary to
     * @p out. If a step fails, what earlier steps wrote stays and the error (naming the
     * step) propagates: MatrixError for a factorization that fails, SimulationError for a
     * run whose energy grows past Time stepping/Energy growth limit (logged, not written
     * as VTU) or stops being finite.
     */
    void run(std::ostream &out);

    const Scene     &scene() const;
    const RunTotals &totals() const;
    /** Where the results go: DIRECTORY/SCENE. */
    const std::string &output_directory() const;

  private:
    void print_summary(std::ostream &out) const;

    /**
     * After step @p step: throw SimulationError naming the step, the model and the energies
     * if an energy is not finite or the body holds more than Time stepping/Energy growth
     * limit times the energy put into it, once the VTU files written so far are complete.
     */
    void check_energy(const fem::EnergyBalance &balance, unsigned int step);

    AllParameters                 parameters;
    std::unique_ptr<Scene>        simulated_scene;
    /** The exact corotational run of the same scene, when the error against it is asked. */
    std::unique_ptr<Scene>        reference_scene;
    std::string                   directory;
    RunTotals                     run_totals;
    std::unique_ptr<VtuSeries>    vtu_series;
    std::unique_ptr<StepLog>      step_log;
    double                        setup_seconds = 0;
    /** Rest centre of every element, and of the tool (if any). */
    std::vector<fem::Vector3>     element_centres;
    fem::Vector3                  tool_centre = fem::Vector3::Zero();
  };

  /** Read @p parameter_file, run it and print the summary on @p out. Throws warpchol::Error. */
  void run_parameter_file(const std::string &parameter_file, std::ostream &out);

  /**
   * The warpchol program: "warpchol PARAMS.prm", "warpchol --print-parameters [FILE]",
   * "warpchol --help". Prints a one-line error on @p err and returns 2 for bad input
   * (InputError: parameters, mesh files), 1 for another failure (a factorization that
   * fails, a diverging simulation), 0 on success: the convention of the other programs.
   */
  int main(int argc, const char *const *argv, std::ostream &out, std::ostream &err);
} // namespace warpchol::app
