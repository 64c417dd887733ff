#pragma once

#include <warpchol/app/path_file.h>
#include <warpchol/backends/linear_solver.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/small_dense.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/step_strategy.h>

#include <deal.II/base/parameter_handler.h>

#include <limits>
#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * The parameters of a scene, read from a .prm file with deal.II's ParameterHandler. As in
 * step-44, one small struct per subsection with a static declare_parameters() and a
 * parse_parameters(), and AllParameters that gathers them and is built from a file.
 *
 * Every error names the file, the line and the entry, on one line:
 *   torus.prm:12: Material/Poisson's ratio = 0.5: must be < 0.5 (incompressible)
 */
namespace warpchol::app
{
  /**
   * A parameter file as deal.II's ParameterHandler reads it, with its includes written out
   * in place, and where each of its lines and entries comes from: so that a value rejected
   * after parsing (a bound ParameterHandler's patterns cannot express, a missing file) is
   * reported at its file and line, and a relative path is taken relative to the folder of
   * the file that holds it.
   *
   * "include FILE" takes a relative FILE relative to the folder of the file the statement is
   * in (deal.II would take the working directory), like every other path of a parameter
   * file. An include that cannot be followed is an InputError naming the file and line of
   * the statement: a file that is missing, not a regular file (a device reads forever),
   * binary, already being read (a cycle), or that leaves other subsections open than it
   * found.
   */
  class ParameterFileLocator
  {
  public:
    ParameterFileLocator() = default;
    /** Read @p filename and what it includes (an empty name stands for the defaults). */
    explicit ParameterFileLocator(const std::string &filename);

    /** The file's text with every include statement replaced by the lines of its file. */
    const std::string &text() const;

    /** "FILE:LINE" of line @p line (from 1) of text(): the file and the line it comes from. */
    std::string origin(int line) const;

    /**
     * "FILE:LINE: Subsection/Entry" at the statement that sets the entry last (the value
     * ParameterHandler keeps), or "FILE: Subsection/Entry (default)" if none does.
     */
    std::string where(const std::string &subsection, const std::string &entry) const;

    /** Throw InputError "where(...) = VALUE: message". */
    [[noreturn]] void fail(const dealii::ParameterHandler &prm, const std::string &subsection,
                           const std::string &entry, const std::string &message) const;

    /**
     * The folder of the file that sets Subsection/Entry (the top file's if none does), to
     * which a relative path in the entry's value refers ("" for the working directory).
     */
    std::string directory_of(const std::string &subsection, const std::string &entry) const;
    const std::string &filename() const;

  private:
    /**
     * Append file @p file_index of @p files to text(), its includes written out; @p
     * subsections: the subsections open at its start, @p chain: the files being read (their
     * canonical paths).
     */
    void read(unsigned int file_index, std::vector<std::string> &subsections, std::vector<std::string> &chain);

    std::string file;
    std::string expanded_text;
    /** The top file and every file it includes, each path relative to the working directory. */
    std::vector<std::string> files;
    /** Per line of expanded_text: the index of its file in files, and its line there. */
    std::vector<std::pair<unsigned int, int>> line_origins;
    /** "Subsection/Entry" -> line of expanded_text, for every "set" statement. */
    std::vector<std::pair<std::string, int>> set_lines;
  };

  /**
   * A WCC update threshold as a parameter file or a command line writes it: a number >= 0
   * or inf (infinity). Returns false (and leaves @p threshold unspecified) for anything else.
   */
  bool parse_threshold(const std::string &text, double &threshold);

  /** A set of vertices given by a region: a box, a sphere, a list of ids, all or none. */
  struct RegionParameters
  {
    std::string         kind = "none";
    fem::Vector3        box_lower_corner{0, 0, 0};
    fem::Vector3        box_upper_corner{0, 0, 0};
    fem::Vector3        sphere_center{0, 0, 0};
    double              sphere_radius = 0;
    std::vector<long>   vertex_ids;

    /** The region entries, in the current subsection; @p what says what the region is for. */
    static void declare_parameters(dealii::ParameterHandler &prm, const std::string &what,
                                   const std::string &default_kind = "none");
    void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file,
                                 const std::string &subsection);
  };

  namespace parameters
  {
    /** Subsection "Mesh": a generated torus or box, or a mesh file. */
    struct Mesh
    {
      /** "torus", "box", "cylinder", "tube" or "file". */
      std::string           source = "torus";
      /** The mesh file as written in the parameter file. */
      std::string           file_name;
      double                scale = 1;
      /** Global refinements of a mesh read from a file (each tetrahedron into 8). */
      unsigned int          refinements = 0;
      fem::TorusGeometry    torus;
      fem::BoxGeometry      box;
      fem::CylinderGeometry cylinder;
      fem::TubeGeometry     tube;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Material". */
    struct Material
    {
      double          youngs_modulus = 50;
      double          poisson_ratio  = 0.45;
      double          density        = 20;
      /** > 0: the density is set so that the body has this mass (kg), density is unused. */
      double          total_mass  = 0;
      fem::MassMatrix mass_matrix = fem::MassMatrix::lumped;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Time stepping". */
    struct TimeStepping
    {
      double       time_step          = 0.01;
      unsigned int n_steps            = 100;
      double       rayleigh_mass      = 0;
      double       rayleigh_stiffness = 0;
      /** Stop before n_steps once the kinetic energy falls below this (J); 0: never. */
      double       rest_kinetic_energy = 0;
      /**
       * Stop with a SimulationError once the energy the body holds exceeds this many times
       * the energy put into it (fem::EnergyBalance); 0: never.
       */
      double       energy_growth_limit = 10;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Model". */
    struct Model
    {
      std::string       type             = "warp_canceling";
      double            update_threshold = 0.05;
      /** > 0: the threshold adapts each step to keep the trajectory error near this. */
      double            target_error = 0;
      /** How a WCC step refreshes its factor and solves. */
      fem::StepStrategy strategy;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

    /** Subsection "Solver": parsed by the solver's own parsers, so new choices need no change here. */
    struct Solver
    {
      cholesky::SparseCholesky::Settings settings;
      /** Who factors and solves the step's system: warpchol's factor or a peer's. */
      backends::Settings                 backend;

      /** The supernodal method by default: the fast one, which refactorizes partially. */
      Solver();

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

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

    /**
     * Subsection "Bodies": copies of the mesh side by side, each with its own model and
     * update threshold, each solved on its own (the report's side-by-side stability
     * figures: three tori with no update, a moderate threshold and exact corotation). Every
     * copy is the same scene (regions, loads, initial state) in its own frame; copy i is
     * shown shifted by i times the spacing in the one VTU series.
     */
    struct Bodies
    {
      unsigned int             count   = 1;
      fem::Vector3             spacing{0, 0, 0};
      /** One model type per body; empty: Model/Type for all. */
      std::vector<std::string> model_types;
      /** One threshold per body; empty: Model/Update threshold for all. */
      std::vector<double>      update_thresholds;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };

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

    /**
     * Subsection "Distributed": how a run under MPI (mpirun -np N, or --distributed) solves
     * the step's system, on the engines made for it (distributed/).
     */
    struct Distributed
    {
      /** "amg_cg" (Trilinos CG with ML AMG) or "mumps" (PETSc's MUMPS, direct). */
      std::string  linear_solver = "amg_cg";
      /** CG stops at |b - A x| <= tolerance |b|. */
      double       tolerance = 1e-8;
      unsigned int max_iterations = 1000;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void        parse_parameters(dealii::ParameterHandler &prm, const ParameterFileLocator &file);
    };
  } // namespace parameters

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
    parameters::Bodies        bodies;
    parameters::Output        output;
    parameters::Distributed   distributed;

    /** The defaults. */
    AllParameters();

    /**
     * Read @p filename. Throws InputError "FILE:LINE: ..." for a file that cannot be read,
     * an unknown subsection or entry, a value out of range.
     */
    explicit AllParameters(const std::string &filename);

    /** Declare every subsection and entry in @p prm. */
    static void declare_parameters(dealii::ParameterHandler &prm);

    /** Write the documented defaults as a .prm file. */
    static void print_defaults(std::ostream &out);

    /** The scene's name: Output/Scene, else the parameter file's name without .prm. */
    std::string scene_name() const;
    /**
     * The parameters of body @p index (from 0) of Bodies: Model/Type and Model/Update
     * threshold replaced by that body's, Bodies/Number of bodies set to 1.
     */
    AllParameters body(unsigned int index) const;

    /**
     * These parameters with the exact corotational model solved by warpchol's direct
     * factor: the reference a run's trajectory error is measured against.
     */
    AllParameters exact_corotational() const;

    /** The mesh file with a relative name taken relative to the parameter file that sets it. */
    std::string mesh_file_path() const;

    ParameterFileLocator file;

    /**
     * Every entry as "Subsection/Entry = value" (nested subsections joined by '/'), in the
     * ParameterHandler's order, defaults included: what a checkpoint was written with.
     */
    std::vector<std::string> entries;

  private:
    void parse_parameters(dealii::ParameterHandler &prm);
    /** Read the instruments' path files and check that each covers its use. */
    void read_paths();
    /** Throw InputError at Solver/Backend if the backend cannot run the model as set. */
    void check_backend(dealii::ParameterHandler &prm) const;
  };
} // namespace warpchol::app
