#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/base/types.h>
#include <warpchol/sparse/csc_matrix.h>

#include <deal.II/lac/sparse_matrix.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

/**
 * @file
 * The peers a user would pick instead of warpchol's updatable factor, as selectable
 * backends of the step's linear system (Solver/Backend): CHOLMOD, UMFPACK, Eigen, Trilinos
 * AMG-CG, and SOFA's warp-preconditioned CG. Every scene runs with any of them, so that
 * one benchmark compares them on the same steps.
 */
namespace warpchol::backends
{
  /** The backends Solver/Backend names. */
  enum class Backend
  {
    /** This project's supernodal factor, refactorized partially (the default). */
    warpchol,
    /** CHOLMOD supernodal LL^T with its own ordering, refactorized in full every step. */
    cholmod,
    /** deal.II's SparseDirectUMFPACK (LU), refactorized in full every step. */
    umfpack,
    /** Eigen's SimplicialLLT (AMD ordering), refactorized in full every step. */
    eigen,
    /** Eigen's CholmodSupernodalLLT wrapper of CHOLMOD, refactorized in full every step. */
    eigen_cholmod,
    /**
     * deal.II's TrilinosWrappers::SolverCG with an ML algebraic multigrid preconditioner
     * (PreconditionAMG, the rigid-body modes as near null space), set up once and reused
     * while the matrix changes.
     */
    trilinos_amg_cg,
    /**
     * SOFA's approach: CG on the exact corotational matrix preconditioned by the rest
     * factor rotated by the nodal rotations (WCC with no update, Strategy = preconditioned).
     */
    warp_preconditioned_cg
  };

  /** The names of the backends (base/named_values.h), in the order of the enum. */
  inline constexpr NameTable<Backend, 7> backend_names{{{Backend::warpchol, "warpchol"},
                                                        {Backend::cholmod, "cholmod"},
                                                        {Backend::umfpack, "umfpack"},
                                                        {Backend::eigen, "eigen"},
                                                        {Backend::eigen_cholmod, "eigen_cholmod"},
                                                        {Backend::trilinos_amg_cg, "trilinos_amg_cg"},
                                                        {Backend::warp_preconditioned_cg, "warp_preconditioned_cg"}}};

  /** Every backend, in the order of the enum. */
  std::vector<Backend> all_backends();
  /** "warpchol", "cholmod", "umfpack", "eigen", "eigen_cholmod", "trilinos_amg_cg", "warp_preconditioned_cg". */
  std::string to_string(Backend backend);
  /** The inverse of to_string(); throws InputError "unknown backend 'x' (expected ...)". */
  Backend parse_backend(const std::string &name);

  /**
   * Whether @p backend replaces warpchol's factor by a LinearSolver of its own (every
   * backend but warpchol and warp_preconditioned_cg, which use warpchol's factor).
   */
  bool replaces_factor(Backend backend);
  /** Whether @p backend solves by iterations to a tolerance (Settings::tolerance). */
  bool iterates(Backend backend);

  /** The choice of a backend and, for the iterative ones, when they stop. */
  struct Settings
  {
    Backend      backend = Backend::warpchol;
    /** Iterative backends stop at |b - A x| <= tolerance |b|. */
    double       tolerance = 1e-6;
    unsigned int max_iterations = 1000;
  };

  /**
   * A solver of the step's symmetric positive definite system A x = b over the free dofs,
   * the interface of the peers that replace warpchol's factor. factorize() is called
   * whenever the values of A changed (its pattern never does): a direct solver factors
   * again in full, an iterative one updates its copy of the matrix (and, the first time,
   * sets its preconditioner up).
   */
  class LinearSolver
  {
  public:
    virtual ~LinearSolver() = default;

    /** The backend's name, as Solver/Backend writes it. */
    virtual std::string name() const = 0;

    /**
     * A's values changed. @p matrix and @p csc hold the same values (CSC with both
     * triangles): each solver takes the form its library reads. Throws
     * NotPositiveDefinite (column of A) or MatrixError if the matrix cannot be factored.
     */
    virtual void factorize(const dealii::SparseMatrix<double> &matrix, const sparse::CSCMatrix &csc) = 0;

    /**
     * x = A^-1 b for the A of the last factorize(). An iterative solver starts from @p x
     * when it has the right size (a good guess: the last step's) and throws MatrixError
     * if it does not reach its tolerance.
     */
    virtual void solve(const std::vector<double> &b, std::vector<double> &x) = 0;

    /**
     * The mesh's topology changed (elements were cut): a solver that keeps an analysis of
     * the pattern makes it anew at the next factorize(), as SOFA's solvers do on a
     * topological change. Nothing by default.
     */
    virtual void topology_changed();

    /** Whether solve() iterates from the guess it is given (false: a direct solver). */
    virtual bool is_iterative() const;

    /** Iterations of the last solve() (0 for a direct solver). */
    virtual unsigned int last_iterations() const;

    /**
     * Bytes of the factor or preconditioner (the matrix copy an iterative solver keeps
     * included), as the library allocated them.
     */
    virtual std::size_t memory_bytes() const = 0;
  };

  /**
   * The linear solver of @p settings (a backend that replaces_factor()), for matrices whose
   * near null space is @p rigid_body_modes (6 vectors over the unknowns: 3 translations
   * and 3 rotations; used by AMG).
   */
  std::unique_ptr<LinearSolver> create_linear_solver(const Settings &settings,
                                                     const std::vector<std::vector<double>> &rigid_body_modes);

  /**
   * Start MPI (one process) unless it runs already, for the Trilinos objects that need it,
   * and finalize it at exit. Only the runs that use Trilinos pay its start-up (a second
   * with Open MPI's singleton daemon): the programs do not start it in main().
   */
  void require_mpi();

  /**
   * Bytes in use on the heap now (glibc's mallinfo2): the difference around a library's
   * set-up measures what it allocated, for libraries that do not report it themselves.
   */
  std::size_t heap_bytes_in_use();

  /** The heap's growth while @p action runs (0 if it shrank). */
  std::size_t heap_growth_of(const std::function<void()> &action);
} // namespace warpchol::backends
