#pragma once

#include <warpchol/base/binary_io.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/contact/contact_constraints.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/models/elasticity_model.h>

#include <future>
#include <string>
#include <utility>
#include <vector>

/**
 * @file
 * What a run leaves on disk, in output/SCENE/: VTU files with a PVD time series, and the
 * per-step CSV log. Every file is written under a temporary name and renamed into place,
 * so that a reader (ParaView, a plotting script, an interrupted run) never meets a
 * half-written file, and what earlier steps wrote stays.
 */
namespace warpchol::app
{
  /**
   * Create @p directory and its parents and check that a file can be created in it (the
   * run checks before it computes anything); throws OutputError naming it otherwise.
   * Removes the temporary files that killed runs left in it (remove_stale_temporaries()).
   */
  void create_directory(const std::string &directory);

  /**
   * What a VTU file shows of one body, copied so that the file is written while the run
   * goes on.
   */
  struct BodySnapshot
  {
    const fem::ElasticBody   *body = nullptr;
    /** The shift of the body in the picture (several bodies side by side). */
    fem::Vector3              offset = fem::Vector3::Zero();
    std::vector<fem::Vector3> displacements;
    std::vector<fem::Vector3> velocities;
    fem::ElementRerotationRecord  record;
    /**
     * With cuts, grasps or material changes (empty otherwise): per element the step it was
     * cut at (-1: not cut), per vertex 1 while it is grasped.
     */
    std::vector<int>          cut_steps;
    std::vector<char>         grasped;
    /**
     * With obstacles (empty otherwise): per vertex the contact force (N) and the gap to the
     * nearest obstacle (m, up to Contact/Alarm distance), and the obstacles' surfaces where
     * they are, written to a VTU file of their own beside the body's.
     */
    std::vector<fem::Vector3>         contact_forces;
    std::vector<double>               contact_gaps;
    std::vector<fem::TriangleSurface> obstacles;
  };

  /**
   * VTU files SCENE-NNNNN.vtu with the displacement and velocity per vertex and, per cell,
   * whether the element was re-rotated in the step, its error estimate (WCC) and the steps
   * since its last update; SCENE.pvd lists them with their times. A scene of several
   * bodies writes them all into each file, shifted side by side, with the cell field
   * "body" (0, 1, ...) telling them apart. A scene with cuts or grasps adds the cell fields
   * "removed" (1 for a cut element: ParaView's Threshold filter on removed < 0.5 hides them)
   * and "cut_step" (the step it was cut at, -1 if not), and the vertex field "grasped".
   * A scene with obstacles adds the vertex fields "contact_force" and "contact_gap", and
   * writes the obstacles' triangles to SCENE-obstacles-NNNNN.vtu (cell field "obstacle":
   * 1, 2, ...), listed in the PVD as part 1 of each time beside the body's part 0.
   */
  class VtuSeries
  {
  public:
    /**
     * @p precision: "float32", the files deal.II's DataOut writes (Float32, the vertices
     * of each cell repeated, the cell fields as point data), or "float64": every number in
     * double precision, each vertex once, the cell fields as cell data (written here:
     * deal.II 9.4 writes VTU in single precision only).
     */
    VtuSeries(const std::string &directory, const std::string &scene,
              const std::string &precision = "float32");

    /** Waits for the file being written. */
    ~VtuSeries();

    /**
     * Write the state after step @p step at time @p time and rewrite the PVD file. The
     * state is copied and written in the background (building deal.II's patches and
     * compressing them costs about as much as a few steps): the call returns at once, after
     * waiting for the previous file, whose error, if any, it throws. A process allowed
     * one core only writes at once instead: there the background would take the core of
     * the steps, and the steps it slowed would be measured as theirs (the automatic
     * strategy's fall-back would read them as costing more than exact ones).
     */
    void write(unsigned int step, double time, std::vector<BodySnapshot> bodies);

    /** Whether write() writes in the background: where this process may run on two cores or more. */
    static bool writes_in_background();

    /** Wait until every file is written; throws the error of the last one, if any. */
    void finish();

    std::size_t        n_files() const;
    const std::string &pvd_file() const;

    /** Write the files of the series to a checkpoint; after finish(). */
    void save(BinaryWriter &writer) const;
    /** Go on from the series save() wrote: its files are on disk, the next ones follow. */
    void load(BinaryReader &reader);

  private:
    /** Write one file and the PVD record (in the background). */
    void write_now(unsigned int step, double time, const std::vector<BodySnapshot> &bodies);

    /** One VTU file through deal.II's DataOut (Float32). */
    void write_deal_ii_vtu(const std::string &filename, const std::vector<BodySnapshot> &bodies,
                           bool with_error_estimate) const;

    std::future<void>                           pending;
    std::string                                 directory;
    std::string                                 scene;
    std::string                                 precision;
    std::string                                 pvd_name;
    std::vector<std::pair<double, std::string>> times_and_names;
    /** The obstacles' files, with their times (none without obstacles). */
    std::vector<std::pair<double, std::string>> obstacle_times_and_names;
  };

  /** One row of the per-step log. */
  struct StepLogRow
  {
    unsigned int              step = 0;
    double                    time = 0;
    fem::StepStatistics       statistics;
    double                    n_elements     = 0;
    double                    step_seconds   = 0;
    double                    kinetic_energy = 0;
    double                    elastic_energy = 0;
    /** ImplicitEuler's energy accounting: potential of the constant loads, tool springs. */
    double                    potential_energy = 0;
    double                    tool_energy      = 0;
    double                    total_energy     = 0;
    /** Work of the tool's moving targets so far. */
    double                    external_work    = 0;
    double                    tool_work_on_body = 0;
    /** Energy the changes of the body put in or took out so far (ImplicitEuler::change_energy()). */
    double                    change_energy     = 0;
    /** fem::EnergyBalance::ratio(): held over put in. */
    double                    energy_ratio     = 0;
    /** Trajectory error against the corotational run (app::PositionError, worst vertex and
        RMS); negative when none runs. */
    double                    error_vs_corotational     = -1;
    double                    rms_error_vs_corotational = -1;
    /** The contact step's report, and the totals so far of the contact impulses' work and friction's dissipation. */
    fem::ContactStepReport    contact;
    double                    contact_work         = 0;
    double                    friction_dissipation = 0;
  };

  /**
   * The CSV log: a header row, then a row per step. The file is rewritten whole (under a
   * temporary name, then renamed) after the first row and then at most every half second,
   * and by flush(), which the run calls at its end and before it reports an error, and the
   * destructor.
   */
  class StepLog
  {
  public:
    /**
     * @p with_error: add the columns error_vs_corotational and rms_error_vs_corotational;
     * @p with_contact: the contact columns (contacts, contacts_per_obstacle as "12;3",
     * largest_penetration, gs_iterations,
     * gs_residual, normal_force, friction_force, t_contact, contact_work,
     * friction_dissipation).
     */
    StepLog(const std::string &filename, bool with_error, bool with_contact = false);
    /** Flushes (errors are swallowed: a destructor must not throw). */
    ~StepLog();

    void add(const StepLogRow &row);
    /** Write every row added so far; throws InputError if the file cannot be written. */
    void flush();

    const std::string &filename() const;

    /** The header row (the column names). */
    std::string header() const;

    /** Write the rows so far to a checkpoint. */
    void save(BinaryWriter &writer) const;
    /** Go on from the rows save() wrote (the file is rewritten with them at the next flush). */
    void load(BinaryReader &reader);

  private:
    std::string              file;
    bool                     with_error;
    bool                     with_contact;
    std::vector<std::string> rows;
    std::size_t              written_rows = 0;
    Stopwatch                since_written;
  };
} // namespace warpchol::app
