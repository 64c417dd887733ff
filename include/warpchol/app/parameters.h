#pragma once

#include <warpchol/app/parameters/body.h>
#include <warpchol/app/parameters/contact.h>
#include <warpchol/app/parameters/entries.h>
#include <warpchol/app/parameters/events.h>
#include <warpchol/app/parameters/loads.h>
#include <warpchol/app/parameters/output.h>
#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/app/parameters/step.h>

#include <deal.II/base/parameter_handler.h>

#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The parameters of a scene, read from a .prm file with deal.II's ParameterHandler. As in
 * step-44, one small struct per subsection with a static declare_parameters() and a
 * parse_parameters() (app/parameters/: the file as read, the entries several subsections
 * share, and the subsections by group), and AllParameters that gathers them and is built
 * from a file.
 *
 * Every error names the file, the line and the entry, on one line:
 *   torus.prm:12: Material/Poisson's ratio = 0.5: must be < 0.5 (incompressible)
 */
namespace warpchol::app
{
  /**
   * Which run reads the parameters: a serial run ignores the Distributed subsection, a
   * distributed one (mpirun -np N with N > 1, or --distributed) the Solver subsection.
   */
  enum class RunKind
  {
    serial,
    distributed
  };

  /** Every subsection of a scene's parameter file. */
  struct AllParameters
  {
    parameters::Mesh          mesh;
    parameters::Material      material;
    parameters::TimeStepping  time_stepping;
    parameters::Model         model;
    parameters::Solver        solver;
    parameters::InitialState  initial_state;
    parameters::FixedVertices fixed_vertices;
    parameters::Gravity       gravity;
    parameters::RegionForce   region_force;
    parameters::Tool          tool;
    /**
     * The events: "Cut" (first, possibly inactive), then "Cut 2", "Cut 3", ... in the order
     * of their numbers; likewise the grasps and the material changes.
     */
    std::vector<parameters::Cut>            cuts;
    std::vector<parameters::Grasp>          grasps;
    std::vector<parameters::MaterialChange> material_changes;
    /** How contacts are solved, and the obstacles: "Obstacle" (possibly inactive), "Obstacle 2", ... */
    parameters::Contact                contact;
    std::vector<parameters::Obstacle>  obstacles;
    parameters::Bodies        bodies;
    parameters::Output        output;
    parameters::Distributed   distributed;

    /** The defaults. */
    AllParameters();

    /**
     * Read @p filename for a run of kind @p run_kind. Throws InputError "FILE:LINE: ..." for a
     * file that cannot be read, an unknown subsection or entry, a value out of range.
     */
    explicit AllParameters(const std::string &filename, RunKind run_kind = RunKind::serial);

    /** Declare every subsection and entry in @p prm. */
    static void declare_parameters(dealii::ParameterHandler &prm);

    /** Write the documented defaults as a .prm file. */
    static void print_defaults(std::ostream &out);

    /** The scene's name: Output/Scene, else the parameter file's name without .prm. */
    std::string scene_name() const;
    /**
     * The parameters of body @p index (from 0) of Bodies: Model/Type and Model/Rerotation
     * threshold replaced by that body's, Bodies/Number of bodies set to 1.
     */
    AllParameters body(unsigned int index) const;

    /**
     * These parameters with the exact corotational model solved by warpchol's direct
     * factor: the reference a run's trajectory error is measured against.
     */
    AllParameters exact_corotational() const;

    /** The model of each body: Bodies/Models, or Model/Type for the one body or all. */
    std::vector<fem::ModelType> model_types() const;

    /** The mesh file with a relative name taken relative to the parameter file that sets it. */
    std::string mesh_file_path() const;

    ParameterFileLocator file;
    /** The run the parameters were read for (which subsections it ignores). */
    RunKind run = RunKind::serial;

    /**
     * Every entry as "Subsection/Entry = value" (nested subsections joined by '/'), in the
     * ParameterHandler's order, defaults included: what a checkpoint was written with.
     */
    std::vector<std::string> entries;

    /**
     * One line per entry the file sets that the options chosen leave unused, naming the
     * entry and the choice that ignores it:
     *   torus.prm:14: Fixed vertices/Sphere radius = 0.1: ignored with Region = box
     * The run goes on (the programs print them first, as warnings); a distributed run adds
     * the settings it replaces (DistributedSimulation::check_supported()).
     */
    std::vector<std::string> warnings;

    /** Print warnings to @p err, one "warpchol: warning: ..." line each. */
    void print_warnings(std::ostream &err) const;

  private:
    void parse_parameters(dealii::ParameterHandler &prm);
    /** Read the instruments' path files and check that each covers its use. */
    void read_paths();
    /** Throw InputError at Solver/Backend if the backend cannot run the model as set. */
    void check_backend(dealii::ParameterHandler &prm) const;
    /** Fill warnings: the entries set in the file that the choices made ignore, for every subsection. */
    void warn_about_ignored_entries(dealii::ParameterHandler &prm);
    /** Add a warning for each of @p entries of @p subsection that the file sets: ignored with @p choice. */
    void warn_if_set(dealii::ParameterHandler &prm, const std::string &subsection,
                     const std::vector<std::string> &entries, const std::string &choice);
    /** The entries of a region's subsection that its kind leaves unused; @p what_it_moves with none. */
    void warn_about_region(dealii::ParameterHandler &prm, const RegionParameters &region,
                           const std::string &subsection, const std::vector<std::string> &what_it_moves);
    /** Mesh and Material: the other sources' entries, the density beside a total mass. */
    void warn_about_mesh_and_material(dealii::ParameterHandler &prm);
    /** Model, Bodies' models and (in a serial run) Solver: what the model, strategy and backend leave unused. */
    void warn_about_model_and_solver(dealii::ParameterHandler &prm);
    /** The fixed vertices, forces, tool, cuts, grasps and material changes. */
    void warn_about_instruments(dealii::ParameterHandler &prm);
    /** The obstacles' entries their shapes do not use, Contact without an obstacle, Output. */
    void warn_about_obstacles_and_output(dealii::ParameterHandler &prm);
    /** Distributed in a serial run; in a distributed run, what DistributedSimulation does not read. */
    void warn_about_run_kind(dealii::ParameterHandler &prm);
    /** Add to warnings each entry the file sets by its old name (renamed_entries). */
    void warn_about_old_names();
  };
} // namespace warpchol::app
