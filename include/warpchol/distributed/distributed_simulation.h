#pragma once

#include <warpchol/app/parameters.h>
#include <warpchol/base/stage_times.h>
#include <warpchol/distributed/distributed_body.h>
#include <warpchol/distributed/distributed_solver.h>
#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <ostream>
#include <string>
#include <vector>

/**
 * @file
 * A scene run over the ranks of an MPI communicator: `mpirun -np N warpchol FILE.prm`.
 */
namespace warpchol::distributed
{
  /** What one step of a distributed run did, summed or maximized over the ranks. */
  struct DistributedStep
  {
    /** Elements whose contribution to A was recomputed, over all ranks. */
    unsigned long elements_rerotated = 0;
    /** CG iterations (0 for MUMPS). */
    unsigned int cg_iterations = 0;
    /** This rank's seconds per stage (the names of fem::stage). */
    StageTimes stages;
    /** This rank's wall-clock seconds of the whole step. */
    double seconds = 0;
  };

  /**
   * The implicit Euler steps of a scene (the serial ImplicitEuler's, DESIGN.md eq. 1) with
   * the body distributed (DistributedBody), the matrix assembled on every rank from its own
   * elements, and the step solved by Distributed/Linear solver. The models:
   * - linear: the rest matrix, assembled once;
   * - corotational: every element's R_e K_e R_e^T, assembled every step;
   * - stiffness_warping: the rest matrix in the nodal frames, (S A S^T) v = rhs;
   * - warp_canceling: each rank estimates its own elements (fem::estimate_element_error,
   *   against the impulse scale of the whole body) and re-assembles those over the
   *   threshold; the step solves the WCC system in the nodal frames. Threshold 0 is
   *   corotation, inf stiffness warping.
   *
   * Loads as in serial runs: gravity, a region force, the pulling tool, fixed vertices, a
   * rigid initial velocity. What a distributed run does not do is refused at its entry:
   * several bodies, checkpoints, the comparison with corotation, a WCC target error or a
   * step strategy other than partial or auto (the factor is not warpchol's; auto, the
   * default scene's, runs as partial with a warning), waiting for rest.
   *
   * Results: DIRECTORY/SCENE/ holds a VTU piece per rank and step written
   * (SCENE-NNNNN.RANK.vtu), the PVTU record of each step and SCENE.pvd, and log.csv (rank 0;
   * the stage times are the slowest rank's).
   */
  class DistributedSimulation
  {
  public:
    /**
     * Build the scene on @p communicator from @p mesh (built alike on every rank, from the
     * same @p parameters, which check_supported() accepted; partitioned here). Collective.
     */
    DistributedSimulation(const app::AllParameters &parameters, app::SceneMesh &mesh, MPI_Comm communicator);

    /**
     * Throw InputError at the entries a distributed run does not support; take what it has
     * for Model/Strategy = auto (partial: the step's system is the WCC one, solved by
     * Distributed/Linear solver), said in @p parameters' warnings; create the output
     * directory. The same on every rank: before anything collective.
     */
    static void check_supported(app::AllParameters &parameters);

    /** Run the steps; rank 0 prints the summary to @p out and the progress line. */
    void run(std::ostream &out);

    const DistributedBody &body() const;

    /** @name The energies of the current state, summed over the ranks (as ImplicitEuler's). */
    /** @{ */
    double kinetic_energy() const;
    /** With the element rotations of the current positions (none for the linear model). */
    double elastic_energy() const;
    double potential_energy() const;
    double tool_energy() const;
    /** @} */

  private:
    void set_up_loads(const app::SceneMesh &mesh);
    /** The six rigid-body modes over the owned rows (0 on fixed dofs), mode after mode. */
    std::vector<double> rigid_body_modes() const;
    /** The global dofs of element @p e and which of them are free. */
    void element_dofs(unsigned int e, std::array<dealii::types::global_dof_index, 12> &dofs,
                      std::array<bool, 12> &free) const;
    /** solver = 0, then 1 on the fixed rows and the tool's springs on the diagonal. */
    void reset_matrix();
    /** Add @p factor times the warped contribution of element @p e (S_a, Q) to A. */
    void add_element(unsigned int e, const std::array<fem::Matrix3, 4> &nodal_rotations,
                     const fem::Matrix3 &element_rotation, double factor);
    /** Add @p factor times the element matrix @p matrix of element @p e to A. */
    void add_element(unsigned int e, const fem::ElementMatrix &matrix, double factor);
    /** WCC: the owned elements whose error exceeds the threshold. */
    std::vector<unsigned int> elements_to_rerotate(StageTimes &stages);

    /** One implicit Euler step: the element pass, then each of the steps below in turn. */
    void advance(DistributedStep &step);
    /** Re-assemble A as the model does (in full, WCC's elements over the threshold, or not); the elements re-assembled on this rank. */
    unsigned long reassemble(StageTimes &stages);
    /** rhs = M v + dt (f_ext + f_el(x) + tool springs) on the owned rows, in the solve frame. */
    void assemble_right_hand_side(StageTimes &stages);
    /** solution = the velocities extrapolated from the last two steps (CG's initial guess). */
    void set_initial_guess(StageTimes &stages);
    /** Solve A solution = rhs by Distributed/Linear solver. */
    void solve(DistributedStep &step);
    /** v from the solution (through the ghosts), x += dt v, the time and the step count. */
    void update_state(StageTimes &stages);
    /** Fill the ghosted @p field (dof vector) from per-vertex @p values of the owned vertices. */
    void to_dof_vector(const std::vector<fem::Vector3> &values, dealii::TrilinosWrappers::MPI::Vector &field) const;
    void write_vtu(unsigned int step);
    void print_summary(std::ostream &out, double run_seconds) const;

    const app::AllParameters                 &all;
    const std::string                        directory;
    std::unique_ptr<DistributedBody>         distributed_body;
    std::string                              mesh_text;
    fem::SystemCoefficients                  coefficients;
    std::unique_ptr<DistributedLinearSolver> solver;

    /** Per local vertex: positions, velocities, those of the step before. */
    std::vector<fem::Vector3> x;
    std::vector<fem::Vector3> v;
    std::vector<fem::Vector3> previous_v;
    std::vector<fem::Vector3> constant_forces;
    std::vector<unsigned char> is_tool_vertex;
    double                     time = 0;
    unsigned int               steps_done = 0;

    fem::ElasticBody::State state;
    /** WCC: per local element, the frames T_a = S_a^T Q_e its contribution was made with. */
    std::vector<std::array<fem::Matrix3, 4>> stored_frames;
    /** WCC: per local element, the relative estimate of the last step; 1 if it was re-rotated. */
    dealii::Vector<float> last_estimate;
    dealii::Vector<float> last_rerotated;

    /** Owned rows: the right-hand side and the solution in the solve frame. */
    std::vector<double> rhs;
    std::vector<double> solution;

    mutable dealii::TrilinosWrappers::MPI::Vector owned_field;
    mutable dealii::TrilinosWrappers::MPI::Vector ghosted_field;

    /** Totals of this rank, and the VTU steps written (for the PVD record). */
    StageTimes                                  stage_totals;
    double                                      step_seconds  = 0;
    double                                      setup_seconds = 0;
    unsigned long                               elements_rerotated = 0;
    unsigned long                               cg_iterations    = 0;
    std::vector<std::pair<double, std::string>> pvtu_records;
    std::vector<std::string>                    log_rows;
  };

  /**
   * Whether this process was started by an MPI launcher with more than one process
   * (OMPI_COMM_WORLD_SIZE, PMI_SIZE, MPI_LOCALNRANKS): then warpchol runs distributed.
   */
  bool launched_on_several_ranks();

  /**
   * Start MPI (and PETSc), run @p parameter_file distributed on MPI_COMM_WORLD, one thread
   * per rank, and return warpchol's exit status. Rank 0 prints to @p out and an error that
   * every rank meets alike (the parameters, the mesh) to @p err; an error one rank meets
   * alone is printed by that rank, which then aborts the others (MPI_Abort).
   */
  int run_distributed(int argc, const char *const *argv, const std::string &parameter_file, std::ostream &out,
                      std::ostream &err);
} // namespace warpchol::distributed
