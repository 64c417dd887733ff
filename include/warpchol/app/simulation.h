#pragma once

#include <warpchol/app/output.h>
#include <warpchol/app/parameters.h>
#include <warpchol/app/scene.h>
#include <warpchol/app/trajectory_error.h>
#include <warpchol/dynamics/energy_balance.h>

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The driver: builds a scene from its parameters, runs its time steps, writes what was
 * asked for and prints a summary.
 */
namespace warpchol::app
{
  /**
   * The stages of a run besides those of its steps (fem::stage), each only when asked for
   * in the parameters.
   */
  namespace stage
  {
    /** The exact corotational run alongside, and the trajectory error against it. */
    constexpr const char *reference_run = "reference run (error)";
    /** The energy the body holds against what was put in (the divergence detector). */
    constexpr const char *energy_balance = "energy balance";
    /** A row of log.csv, with the elastic energy it needs. */
    constexpr const char *log = "log";
    /**
     * What the run waits for of a VTU file: the copy of the state and the end of the file
     * before (the files are written in the background).
     */
    constexpr const char *vtu_output = "VTU output";
    /** Writing the state to the checkpoint file (Output/Checkpoint interval). */
    constexpr const char *checkpoint = "checkpoint";
  } // namespace stage

  /** Totals over the steps of a run, for the summary. */
  struct RunTotals
  {
    unsigned int steps                  = 0;
    double       elements_rerotated       = 0;
    /** Elements re-rotated in the last step (the progress line shows it). */
    double       last_elements_rerotated  = 0;
    double       max_elements_rerotated   = 0;
    unsigned int steps_with_rerotations     = 0;
    unsigned int trailing_steps_without_rerotation = 0;
    unsigned int refactorizations       = 0;
    double       columns_recomputed_pct = 0;
    double       flops_recomputed_pct   = 0;
    /** Iterations of preconditioned CG, summed over the steps. */
    unsigned int cg_iterations          = 0;
    /** WCC: the re-rotation threshold of the steps (adapted to a target error, or fixed). */
    double       threshold_sum = 0;
    double       min_threshold = std::numeric_limits<double>::infinity();
    double       max_threshold = 0;
    /** The steps' measured velocity error against exact corotation (with a target error). */
    double       velocity_error_sum = 0;
    double       max_velocity_error = 0;
    /** Steps per refresh of the factor (fem::StepStatistics::refresh): "full", "all", "below_top", "none", "background". */
    std::map<std::string, unsigned int> refreshes;
    /** Steps per choice of the automatic strategy ("exact", "fallback", "all", ...; fem::StepStatistics::choice). */
    std::map<std::string, unsigned int> choices;
    /** Factorizations per way they took their changes ("update", "partial", "full"; fem::StepStatistics::factorization). */
    std::map<std::string, unsigned int> factor_methods;
    /**
     * Cuts, grasps, material changes: elements cut and changed, vertices grasped and
     * released, the steps with a change and, summed over them, the share of the columns and
     * of a full factorization's flops the change touched.
     */
    unsigned int elements_cut = 0, elements_changed = 0, vertices_grasped = 0, vertices_released = 0;
    unsigned int change_steps = 0;
    double       change_columns_pct = 0, change_flops_pct = 0;
    /** The paths the element rotations took, over the steps. */
    fem::RotationPaths rotation_paths;
    /** The age of the factor in steps (background refreshes), summed over the steps that report it. */
    double       factor_lag_sum   = 0;
    unsigned int factor_lag_steps = 0;
    /** The stages that ran: the steps' (fem::stage) and the run's own (app::stage). */
    StageTimes   stages;
    double       step_seconds = 0;
    /** The whole run: steps, log, VTU files (the initial one included). */
    double       run_seconds = 0;
    /** Sum over updates of the rest distance of the element's centre to the tool's centre. */
    double       rerotated_distance_to_tool = 0;
    /** Trajectory error against the corotational run (worst vertex and RMS per step). */
    TrajectoryError error_vs_corotational;

    /** Count the step whose statistics are @p step and which took @p step_seconds. */
    void add_step(const fem::StepStatistics &step, double step_seconds);
  };

  /**
   * One body of a run: its scene, the exact corotational run of the same scene beside it
   * (when the trajectory error is asked), its totals and its log.
   */
  struct SimulatedBody
  {
    std::unique_ptr<Scene>     scene;
    std::unique_ptr<Scene>     reference;
    RunTotals                  totals;
    std::unique_ptr<StepLog>   log;
    /** Where the VTU series shows it: its index times Bodies/Spacing. */
    fem::Vector3               offset = fem::Vector3::Zero();
    /** What the body put in and holds, for the divergence detector and the log. */
    std::unique_ptr<fem::EnergyBalance> energy_balance;
    /**
     * Why the body stopped (a scene of several bodies: its energy ran away, the others go
     * on); empty while it runs.
     */
    std::string                stopped;
    /** Whether a Gauss-Seidel that stopped short of its tolerance was reported. */
    bool                       warned_gauss_seidel = false;
    /** Penalty contact past Contact/Contact distance: said once a run. */
    bool                       warned_penetration = false;
    /** "body 2 (warp_canceling, threshold 0.3)" when the scene has several, else "". */
    std::string                label;
    double                     setup_seconds = 0;
    /** Seconds of a step of exact corotation, timed after the run (Output/Exact steps timed); < 0: not timed. */
    double                     exact_step_seconds = -1;
    /** Rest centre of every element, and of the tool (if any). */
    std::vector<fem::Vector3>  element_centres;
    fem::Vector3               tool_centre = fem::Vector3::Zero();
  };

  class Simulation
  {
  public:
    /** Build the scene: every body (mesh, model and its first factorization). */
    explicit Simulation(const AllParameters &parameters);

    /**
     * Run the steps, writing the log and VTU files if asked, and print the summary to
     * @p out. If a step fails, what earlier steps wrote stays and the error (naming the
     * step, and the body when there are several) propagates: MatrixError for a
     * factorization that fails, SimulationError for a run whose energy grows past Time
     * stepping/Energy growth limit (logged, not written as VTU) or stops being finite. In a
     * scene of several bodies a body whose energy runs away stops alone (one line on
     * standard error, its summary says why) and the others go on.
     */
    void run(std::ostream &out);

    /**
     * Go on from the checkpoint SCENE/checkpoint.bin that an earlier run of the same
     * parameters wrote (Output/Checkpoint interval): the next run() continues with the
     * step after it, its log and VTU series, and ends as the run that wrote it would
     * have, to the bit. Only Time stepping/Number of steps and the Output entries that do
     * not change the results (Checkpoint interval, Progress, Print timings) may differ.
     * Throws InputError naming the file and what does not match. Before run().
     */
    void resume();

    /** SCENE/checkpoint.bin: where checkpoints go and resume() reads. */
    std::string checkpoint_file() const;

    /** The bodies (Bodies/Number of bodies, 1 by default). */
    unsigned int n_bodies() const;
    /** The scene of body @p index (the only one by default). */
    const Scene     &scene(unsigned int index = 0) const;
    const RunTotals &totals(unsigned int index = 0) const;
    /** Where the results go: DIRECTORY/SCENE. */
    const std::string &output_directory() const;

  private:
    /** Advance @p body by one step and account for it in its totals and log. */
    void advance(SimulatedBody &body, unsigned int step);

    /**
     * Step @p step of every body still running; a body of several that diverges stops
     * there and the others go on. Returns whether every body is at rest (none in the first step).
     */
    bool advance_bodies(unsigned int step);

    /** The progress line on standard error: the step, the time, the last re-rotations, seconds per step. */
    void print_progress(unsigned int step, double seconds_per_step) const;
    /** Write the VTU file of @p step, every body in it. */
    void write_vtu(unsigned int step);
    /** Account @p seconds of VTU output (@p runs files) to the bodies, in equal parts. */
    void add_vtu_seconds(double seconds, unsigned int runs);

    void print_summary(std::ostream &out) const;

    /**
     * After step @p step: throw SimulationError naming the step, the model and the energies
     * if an energy is not finite or the body holds more than Time stepping/Energy growth
     * limit times the energy put into it, once the VTU files written so far are complete.
     */
    void check_energy(const SimulatedBody &body, unsigned int step);

    /**
     * Write the state after step @p step to checkpoint_file(), atomically; @p run_seconds:
     * the run's seconds so far.
     */
    void write_checkpoint(unsigned int step, double run_seconds);
    /** Read checkpoint_file() into the bodies (resume()); the logs and series after run() made them. */
    void read_checkpoint();

    /**
     * Before an error is reported: write every log's rows and wait for the VTU file being
     * written, ignoring the errors these meet (the error reported comes first).
     */
    void keep_what_was_written() noexcept;

    AllParameters                 parameters;
    std::vector<SimulatedBody>    bodies;
    std::string                   directory;
    std::unique_ptr<VtuSeries>    vtu_series;
    /** resume(): go on from the checkpoint, after its step. */
    bool                          resuming = false;
    unsigned int                  first_step = 1;
    /** The seconds the run had taken up to the checkpoint it resumed from. */
    double                        seconds_before_resume = 0;
  };

  /**
   * Read @p parameter_file, print its warnings (AllParameters::warnings) on @p err, run it
   * (from its checkpoint if @p resume) and print the summary on @p out. Throws
   * warpchol::Error.
   */
  void run_parameter_file(const std::string &parameter_file, std::ostream &out, std::ostream &err,
                          bool resume = false);

  /**
   * Run @p action and turn what it throws into warpchol's exit status: 2 for InputError, 3
   * for OutputError, 1 for any other exception, 0 if it throws nothing; the error's
   * message goes on one line "warpchol: error: MESSAGE" to @p err, if @p print.
   */
  int report_errors(std::ostream &err, const std::function<void()> &action, bool print = true);

  /**
   * The warpchol program's serial runs: "warpchol PARAMS.prm", "warpchol --print-parameters
   * [FILE]", "warpchol --help" (the distributed run, distributed::run_distributed(), is
   * chosen before by programs/warpchol.cc: app/ knows nothing of distributed/, which builds
   * on it). Prints a one-line error on @p err and returns 2 for bad input
   * (InputError: parameters, mesh files), 3 for results that cannot be written
   * (OutputError: an output directory that cannot be written, a full disk), 1 for another
   * failure (a factorization that fails, a diverging simulation), 0 on success: the
   * convention of the other programs.
   */
  int main(int argc, const char *const *argv, std::ostream &out, std::ostream &err);
} // namespace warpchol::app
