#include <warpchol/app/parameters/step.h>
#include <warpchol/app/parameters/entries.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <cmath>

namespace warpchol::app
{
  namespace parameters
  {
    void TimeStepping::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      prm.declare_entry("Time step", "0.01", Patterns::Double(0), "dt (s), > 0: implicit Euler");
      prm.declare_entry("Number of steps", "100", Patterns::Integer(1), "Steps to run");
      prm.declare_entry("Rayleigh mass", "0", Patterns::Double(0),
                        "alpha (1/s) in the damping matrix B = alpha M + beta K");
      prm.declare_entry("Rayleigh stiffness", "0", Patterns::Double(0),
                        "beta (s) in the damping matrix B = alpha M + beta K");
      prm.declare_entry("Rest kinetic energy", "0", Patterns::Double(0),
                        "If > 0, stop once the kinetic energy (J) falls below it after the "
                        "first step: the body is at rest. Needs a fixed vertex when gravity or "
                        "a region force acts (otherwise the body never comes to rest)");
      prm.declare_entry("Energy growth limit", "10", Patterns::Double(0),
                        "Stop with an error (status 1) once the energy the body holds "
                        "(kinetic, elastic, tool springs) exceeds this many times the energy "
                        "put into it (initial energy, work of the tool and of gravity and the "
                        "region force): a diverging simulation. Implicit Euler dissipates, so a "
                        "stable run stays at or below 1; 0: never stop");
      prm.leave_subsection();
    }

    void TimeStepping::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Time stepping");
      time_step           = prm.get_double("Time step");
      n_steps             = prm.get_integer("Number of steps");
      rayleigh_mass       = prm.get_double("Rayleigh mass");
      rayleigh_stiffness  = prm.get_double("Rayleigh stiffness");
      rest_kinetic_energy = prm.get_double("Rest kinetic energy");
      energy_growth_limit = prm.get_double("Energy growth limit");
      require_positive(prm, file, "Time stepping", "Time step");
      if (energy_growth_limit > 0 && energy_growth_limit < 1)
        file.fail(prm, "Time stepping", "Energy growth limit",
                  "must be 0 (off) or >= 1: a stable run may hold all the energy put in");
      prm.leave_subsection();
    }

    void Model::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Model");
      prm.declare_entry("Type", "warp_canceling", Patterns::Selection(selection_of(fem::model_type_names)),
                        "linear: no rotation, factor once; corotational: exact per-element "
                        "rotations, refactor every step; stiffness_warping: nodal rotations, "
                        "factor once; warp_canceling: WCC, partial refactorization of the "
                        "columns of the elements whose error estimate exceeds the threshold");
      prm.declare_entry("Rerotation threshold", "0.05", Patterns::Anything(),
                        "warp_canceling: a number >= 0 or inf. An element is re-rotated when its "
                        "error estimate (an impulse) exceeds this fraction of the step's impulse "
                        "scale: the mean over elements of |A_e v_e| + dt |f_e| (dimensionless). "
                        "0 re-rotates all (exact corotation), inf none (stiffness warping). Read "
                        "under its old name Update threshold too, with a warning");
      prm.declare_entry("Target error", "0", Patterns::Double(0, 1),
                        "warp_canceling: > 0 adapts the re-rotation threshold every step, from "
                        "Rerotation threshold, so that the trajectory error (max vertex error "
                        "against exact corotation over the largest displacement) stays near "
                        "this: each step measures its velocity error against exact corotation "
                        "(a matrix-free product and a solve) and the threshold follows to keep "
                        "it at half the target. 0: the threshold stays fixed. Needs Strategy = "
                        "partial or Iterate on = warp_canceling");
      prm.declare_entry("Strategy", "partial", Patterns::Selection(selection_of(fem::step_strategy_names)),
                        "warp_canceling: how a step keeps the factor up to date and solves. "
                        "partial: partial refactorization of every column that depends on an "
                        "update, direct solve (the WCC system exactly); preconditioned: the same "
                        "factor as the preconditioner of CG on the 'Iterate on' matrix; "
                        "delayed_top: every step only the supernodes below the top of the "
                        "elimination tree (Solver/Top flops fraction), the top every 'Refresh "
                        "interval' steps or after a solve of more than 'Refresh iterations' "
                        "iterations, CG; auto: per step the cheapest of refreshing all, below "
                        "the top or nothing, by a cost model of measured rates, CG; background: "
                        "the matrix with every element re-rotated is assembled and factored on a "
                        "thread of its own beside the steps, which solve by CG preconditioned "
                        "with the last factor that finished (Background lag; the threshold is "
                        "not used)");
      prm.declare_entry("Iterate on", "corotational", Patterns::Selection(selection_of(fem::iteration_target_names)),
                        "The matrix CG solves with (all strategies but partial): corotational "
                        "(the exact corotational matrix, matrix-free: the WCC error becomes "
                        "iterations) or warp_canceling (the assembled WCC matrix)");
      prm.declare_entry("CG tolerance", "1e-3", Patterns::Double(1e-15, 1),
                        "CG stops when |b - B x| <= this times |b|");
      prm.declare_entry("Max CG iterations", "100", Patterns::Integer(1, 100000),
                        "A solve that needs more refreshes the whole factor and starts again "
                        "(auto on the corotational matrix: at most the iterations an exact "
                        "step costs, fewer if CG's rate forecasts more, then an exact step)");
      prm.declare_entry("Refresh interval", "10", Patterns::Integer(1, 1000000),
                        "delayed_top: the top is refreshed at least every this many steps");
      prm.declare_entry("Refresh iterations", "8", Patterns::Integer(1, 100000),
                        "delayed_top: and in the step after a solve that needed more "
                        "iterations than this");
      prm.declare_entry("Background lag", "0", Patterns::Integer(0, 1000000),
                        "background: 0, a refresh is taken at the first step after it finished "
                        "(as fast as the machine allows; the trajectory depends on the timing "
                        "to the CG tolerance); N > 0, the refresh started at step k is taken at "
                        "step k + N, the step waiting for it if need be (deterministic: the same "
                        "bits on any machine and thread count, checkpoints resume exactly)");
      prm.leave_subsection();
    }

    void Model::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Model");
      // Choices: ParameterHandler has checked them against their one list.
      type = fem::parse_model_type(prm.get("Type"));
      if (!parse_threshold(prm.get("Rerotation threshold"), rerotation_threshold))
        file.fail(prm, "Model", "Rerotation threshold", "must be a number >= 0 or inf");
      // Choices: ParameterHandler has checked them against their one list.
      strategy.kind       = fem::parse_step_strategy(prm.get("Strategy"));
      strategy.iterate_on = fem::parse_iteration_target(prm.get("Iterate on"));
      target_error                = prm.get_double("Target error");
      strategy.cg_tolerance       = prm.get_double("CG tolerance");
      strategy.max_cg_iterations  = prm.get_integer("Max CG iterations");
      strategy.refresh_interval   = prm.get_integer("Refresh interval");
      strategy.refresh_iterations = prm.get_integer("Refresh iterations");
      strategy.background_lag     = prm.get_integer("Background lag");
      prm.leave_subsection();
    }

    void Solver::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      prm.declare_entry("Ordering", "metis", Patterns::Selection(selection_of(cholesky::ordering_names)),
                        "Fill-reducing ordering of the sparse Cholesky solver: natural, amd or "
                        "metis (nested dissection: the best for partial refactorizations)");
      prm.declare_entry("Method", "supernodal", Patterns::Selection(selection_of(cholesky::factorization_method_names)),
                        "Numeric factorization of the sparse Cholesky solver: supernodal "
                        "(left-looking by supernodes with BLAS-3 kernels, refactorizes "
                        "partially), left (left-looking, column by column, refactorizes partially) or "
                        "up (up-looking, CSparse's, always in full)");
      prm.declare_entry("Threads", "1", Patterns::Integer(1, 1024),
                        "Threads of the supernodal factorization and of the element loops "
                        "(rotations, error estimates); 1: serial");
      prm.declare_entry("Top flops fraction", "0.5", Patterns::Double(0, 1),
                        "The top of the elimination tree that Model/Strategy = delayed_top or "
                        "auto may leave stale: the smallest upward-closed set of supernodes "
                        "holding this fraction of the factorization flops");
      prm.declare_entry("Backend", "warpchol", Patterns::Selection(selection_of(backends::backend_names)),
                        "Who factors and solves each step's system: warpchol (this project's "
                        "factor, refactorized partially), or a peer: cholmod (CHOLMOD "
                        "supernodal, its own ordering), umfpack (deal.II's SparseDirectUMFPACK), "
                        "eigen (Eigen's SimplicialLLT), eigen_cholmod (Eigen's CHOLMOD "
                        "wrapper), each refactorizing in full every step; trilinos_amg_cg "
                        "(Trilinos CG with an ML AMG preconditioner set up once, rigid-body "
                        "modes as near null space); warp_preconditioned_cg (SOFA's: CG on the "
                        "corotational matrix, the rest factor rotated by the nodal rotations "
                        "as preconditioner; Model/Type = corotational)");
      prm.declare_entry("Tolerance", "1e-6", Patterns::Double(0),
                        "The iterative backends (trilinos_amg_cg, warp_preconditioned_cg) stop "
                        "at |b - A x| <= Tolerance |b|");
      prm.declare_entry("Max iterations", "1000", Patterns::Integer(1),
                        "The iterative backends fail past this many iterations");
      prm.declare_entry("Change method", "auto", Patterns::Selection(selection_of(cholesky::change_method_names)),
                        "How a change of A (a grasp, a cut, a material change, WCC's re-rotated "
                        "elements) reaches an exact factor (supernodal method): auto takes the "
                        "cheaper of an update of the factor by the change in low-rank form and "
                        "the recomputation of the columns on its paths, by their predicted "
                        "seconds at rates measured during the run; flops the same at fixed "
                        "rates (the same choices on any machine: reproducible bits); recompute "
                        "never updates; update always does where it can");
      prm.declare_entry("Preconditioner precision", "double", Patterns::Selection(selection_of(cholesky::preconditioner_precision_names)),
                        "The factor as CG's preconditioner (Model/Strategy other than partial, "
                        "supernodal method): single keeps a copy of L in 32 bits per entry, half "
                        "in 16 (IEEE half, each column scaled by a power of two), and solves "
                        "with it in single precision: a half or a quarter of the memory traffic "
                        "of the memory-bound triangular solves. CG's tolerance then should stay "
                        "above about 1e-6 (single) or 1e-3 (half: the preconditioner is a 5e-4 "
                        "relative rounding of L, CG corrects it in its iterations)");
      prm.leave_subsection();
    }

    void Solver::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Solver");
      // Choices: ParameterHandler has checked them against their one list.
      settings.ordering.method = cholesky::parse_ordering_method(prm.get("Ordering"));
      settings.method          = cholesky::parse_factorization_method(prm.get("Method"));
      backend.backend          = backends::parse_backend(prm.get("Backend"));
      backend.tolerance      = prm.get_double("Tolerance");
      backend.max_iterations = prm.get_integer("Max iterations");
      if (!(backend.tolerance > 0 && backend.tolerance < 1))
        file.fail(prm, "Solver", "Tolerance", "must be in (0, 1)");
      settings.n_threads          = prm.get_integer("Threads");
      settings.top_flops_fraction = prm.get_double("Top flops fraction");
      settings.preconditioner_precision =
        parse_name(cholesky::preconditioner_precision_names, prm.get("Preconditioner precision"), "precision");
      settings.change_method            = cholesky::parse_change_method(prm.get("Change method"));
      prm.leave_subsection();
    }

    void Distributed::declare_parameters(ParameterHandler &prm)
    {
      prm.enter_subsection("Distributed");
      prm.declare_entry("Linear solver", "amg_cg", Patterns::Selection("amg_cg|mumps"),
                        "How a distributed run (mpirun -np N warpchol FILE.prm, or "
                        "--distributed) solves each step: amg_cg, Trilinos CG preconditioned by "
                        "ML's algebraic multigrid with the rigid-body modes, set up once on the "
                        "rest matrix and reused; mumps, the distributed direct solver MUMPS "
                        "through PETSc, factoring again whenever the matrix changed. Serial runs "
                        "ignore this subsection");
      prm.declare_entry("Tolerance", "1e-8", Patterns::Double(0),
                        "amg_cg stops at |b - A x| <= tolerance |b|");
      prm.declare_entry("Max iterations", "1000", Patterns::Integer(1),
                        "amg_cg fails the step after this many iterations");
      prm.leave_subsection();
    }

    void Distributed::parse_parameters(ParameterHandler &prm, const ParameterFileLocator &file)
    {
      prm.enter_subsection("Distributed");
      linear_solver  = prm.get("Linear solver");
      tolerance      = prm.get_double("Tolerance");
      max_iterations = prm.get_integer("Max iterations");
      if (!(tolerance > 0 && tolerance < 1))
        file.fail(prm, "Distributed", "Tolerance", "must lie in (0, 1), got " + format_number(tolerance));
      prm.leave_subsection();
    }
  } // namespace parameters
} // namespace warpchol::app
