#pragma once

#include <warpchol/base/named_values.h>
#include <warpchol/base/types.h>
#include <warpchol/cholesky/compliance.h>
#include <warpchol/cholesky/modify.h>
#include <warpchol/cholesky/numeric_supernodal.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/permuted_matrix.h>
#include <warpchol/cholesky/refactorization_choice.h>
#include <warpchol/cholesky/supernodal_symbolic.h>
#include <warpchol/cholesky/symbolic.h>
#include <warpchol/sparse/csc_matrix.h>

#include <string>
#include <cstdint>
#include <vector>

/**
 * @file
 * The solver facade, in the spirit of Eigen's SimplicialLLT and CHOLMOD:
 * analyze (pattern) / factorize (values) / refactorize (values, changed columns) / solve.
 */
namespace warpchol::cholesky
{
  /** How the numeric factor is computed. */
  enum class FactorizationMethod
  {
    /** Column by column, left-looking: the one that refactorizes partially. */
    left_looking,
    /** Row by row (CSparse's cs_chol), the report's baseline: refactorization is full. */
    up_looking,
    /** Left-looking by supernodes with BLAS-3 kernels: the fast one, also refactorizes partially. */
    supernodal
  };

  /** The names of the methods (base/named_values.h): "left", "up", "supernodal". */
  inline constexpr NameTable<FactorizationMethod, 3> factorization_method_names{
    {{FactorizationMethod::left_looking, "left"},
     {FactorizationMethod::up_looking, "up"},
     {FactorizationMethod::supernodal, "supernodal"}}};

  /** "left", "up" or "supernodal". */
  std::string to_string(FactorizationMethod method);

  /** Parse "left", "up" or "supernodal"; throws InputError otherwise. */
  FactorizationMethod parse_factorization_method(const std::string &name);

  /**
   * What SparseCholesky::refactorize() may assume of the columns it is told changed.
   */
  enum class ChangeListing
  {
    /**
     * Some changed columns may be missing: every value of A is compared with the last
     * loaded one, O(nnz(A)) reads, and what differs is recomputed too.
     */
    searched,
    /**
     * No stored entry of A outside the listed columns changed since the last load (a caller
     * that re-assembled exactly those columns): only theirs are read. An entry changed
     * elsewhere is then not seen, and the factor is not that of A.
     */
    complete
  };

  /**
   * How much of the factor SparseCholesky::refactorize() brings up to date. With nested
   * dissection every changed column's elimination-tree path runs through the top
   * separators, which hold most of the flops: a caller that uses the factor as a
   * preconditioner may refresh them only every few steps.
   */
  enum class Refresh
  {
    /** Every column that depends on a change since the factor was last exact: L is the exact factor of A. */
    all,
    /**
     * Only the supernodes below the top (see Settings::top_flops_fraction); the dirty top
     * supernodes stay stale (remembered) until a later Refresh::all. Supernodal method only
     * (InputError otherwise).
     */
    below_top,
    /** Nothing: the values are loaded and the changes remembered as pending. */
    none
  };

  /**
   * A sparse Cholesky solver for symmetric positive definite matrices, A = P L L^T P^T,
   * whose factor can be *updated* when some columns of A change: refactorize() recomputes
   * the changed columns of C = P^T A P and their elimination-tree ancestors, and reuses
   * every other column of L as it is.
   *
   * @code
   *   SparseCholesky solver;          // METIS ordering, left-looking
   *   solver.analyze(A);              // ordering + symbolic analysis (pattern only)
   *   solver.factorize(A);            // numeric factorization
   *   solver.solve(b, x);
   *   ... change the entries of some columns of A (same pattern) ...
   *   solver.refactorize(A, changed_columns);
   *   solver.solve(b, x);
   * @endcode
   *
   * A change of A that is a sum of few outer products (a spring on a few vertices, a few
   * elements cut or changed) is cheaper to take as an update of the factor than by
   * recomputing the columns on its paths: refactorize() weighs both for each change (and
   * update() / downdate() apply a C C^T the caller knows, as CHOLMOD's cholmod_updown).
   *
   * A caller that uses the factor as a preconditioner may bring it up to date only in part
   * (supernodal method): refactorize(A, changed_columns, Refresh::below_top) every step and
   * refactorize(A, {}, Refresh::all) every few steps recompute the top supernodes, which
   * hold most of the flops, only then.
   *
   * The matrix is given in CSC form, either with both triangles stored (then its pattern
   * and values must be symmetric) or with the lower triangle only.
   */
  class SparseCholesky
  {
  public:
    /** Choices made before analyze(). */
    struct Settings
    {
      OrderingSettings    ordering;
      /**
       * Supernodal, as the simulation, SparseDirectCholesky and Python use: the one that
       * updates, downdates and leaves the top of the tree stale (below_top) too.
       */
      FactorizationMethod method = FactorizationMethod::supernodal;
      /** Supernode amalgamation (supernodal method). */
      SupernodeRelaxation relaxation;
      /** Threads of the supernodal factorization (1: serial, no TBB). */
      unsigned int        n_threads = 1;
      /**
       * The top of the supernodal elimination tree, which Refresh::below_top leaves stale,
       * is the smallest upward-closed set of supernodes holding at least this fraction of
       * the factorization flops: 0 makes it empty (Refresh::below_top is then
       * Refresh::all), 1 makes it every supernode. Supernodal method.
       */
      double              top_flops_fraction = 0.5;
      /**
       * Keep a copy of the factor in this precision for apply_preconditioner() (supernodal
       * method; PreconditionerPrecision): single halves the memory traffic of the
       * memory-bound triangular solves, half quarters it; the copy adds a half or a quarter
       * to the factor's memory. solve() always uses the double factor.
       */
      PreconditionerPrecision preconditioner_precision = PreconditionerPrecision::full;
      /**
       * How refactorize() takes a change of A when the factor was exact (supernodal
       * method): by the cheapest of an update of the factor and the recomputation of its
       * columns (ChangeMethod).
       */
      ChangeMethod        change_method = ChangeMethod::automatic;
      /** ModificationSettings::pivot_tolerance of downdates. */
      double              downdate_pivot_tolerance = 1e-12;
      /**
       * A change touching more rows and columns than this is never taken as an update
       * (its low-rank form is found by a dense factorization on them, and the update's
       * cost grows with its rank: recomputing wins long before).
       */
      Index               max_update_rows = 600;
    };

    /** What the last calls did and cost. Times are wall-clock seconds. */
    struct Statistics
    {
      Index  n                 = 0;
      /** Stored entries of the lower triangle of A. */
      Index  nnz_a             = 0;
      /** Entries of L, diagonal included. */
      Index  nnz_l             = 0;
      /**
       * Flops a full factorization by the chosen method spends (supernodes: their padding
       * included), as SupernodalSymbolic::flops, Python's flops and every flops_* here count.
       */
      double flops             = 0;
      /** Flops of a factorization without padding (sum of squared column counts, CHOLMOD's fl), as SupernodalSymbolic::exact_flops. */
      double exact_flops       = 0;
      /** Supernodes (supernodal method; 0 otherwise). */
      Index  n_supernodes      = 0;
      int    vertex_block_size = 1;
      double analyze_seconds   = 0;
      /** The last factorize(), or a refactorize() that had to factor everything. */
      double factorize_seconds = 0;
      /** The last refactorize(). (No solve time: solve() is const and may run on several threads at once, so it writes nothing; its caller times it.) */
      double refactorize_seconds = 0;
      /** Columns of L the last refactorize() recomputed. */
      Index  columns_recomputed  = 0;
      /** Supernodes the last refactorize() recomputed (wholly or from a column on). */
      Index  supernodes_recomputed = 0;
      /** Flops the last refactorize() spent. */
      double flops_recomputed    = 0;
      Index  n_factorizations    = 0;
      Index  n_refactorizations  = 0;
      /** Bytes the numeric factor takes once factorized (values, the structure that indexes them, a single-precision copy). */
      std::size_t factor_bytes   = 0;
      /** Supernodes in the top (Settings::top_flops_fraction) and their flops (share: top_flops / flops). */
      Index  n_top_supernodes    = 0;
      double top_flops           = 0;
      /** Columns of C changed (loaded) but not yet refactored, after the last call. */
      Index  pending_columns     = 0;
      /** Top supernodes that are stale after the last call, and the flops a Refresh::all would spend on them alone. */
      Index  stale_supernodes    = 0;
      double stale_flops         = 0;

      /** How the last refactorize() (or update()) brought the factor up to date. */
      RefactorizationMethod method = RefactorizationMethod::none;
      /**
       * What the last refactorize() weighed, when it weighed an update (ChangeMethod): the
       * rank of the change in low-rank form and the flops and predicted seconds of an
       * update, a partial and a full refactorization; negative when not weighed.
       */
      Index  update_rank               = 0;
      double update_flops              = -1;
      double partial_flops             = -1;
      double predicted_update_seconds  = -1;
      double predicted_partial_seconds = -1;
      double predicted_full_seconds    = -1;
      /** Whether the last refactorize() tried an update that a downdate's pivot stopped (it recomputed instead). */
      bool   update_fell_back          = false;
      /** Updates and downdates done (by refactorize() or update()). */
      Index  n_updates                 = 0;

      /** nnz(L) / nnz(tril(A)). */
      double fill() const;
    };

    /**
     * What the solver holds, in the order a solver goes through (Eigen's analysis and
     * factorization flags as one value): nothing, an analyzed pattern, or a valid factor
     * (exact, or partly refreshed: factor_is_exact()). A refused matrix takes a solver
     * from factorized back to analyzed, a refused pattern to empty.
     */
    enum class State
    {
      empty,
      analyzed,
      factorized
    };

    /** The names of the states (base/named_values.h): "empty", "analyzed", "factorized". */
    static constexpr NameTable<State, 3> state_names{
      {{State::empty, "empty"}, {State::analyzed, "analyzed"}, {State::factorized, "factorized"}}};

    SparseCholesky();
    explicit SparseCholesky(const Settings &settings);

    /** What the solver holds now. */
    State state() const;

    /**
     * Throw Error unless the solver holds at least @p required: "<call> called before
     * analyze()" or "<call> called without a valid factorization". The precondition check
     * of every entry point, here and in the wrappers (deal.II's SparseDirectCholesky, the
     * Python module), so that each states it once and in the same words.
     */
    void require(State required, const std::string &call) const;

    /**
     * Fill-reducing ordering (postordered) and symbolic analysis of the pattern of the
     * square matrix @p matrix. Throws MatrixError on a non-square or (full storage)
     * non-symmetric pattern.
     */
    void analyze(const sparse::CSCMatrix &matrix);

    /**
     * Numeric factorization of @p matrix (analyzed first if nothing is: State::empty),
     * which has the analyzed pattern or a subset of it:
     * the entries it leaves out are zeros (arithmetic drops explicit zeros; CHOLMOD takes
     * such a matrix too). Throws NotPositiveDefinite naming the column (user numbering) and
     * value of the failed pivot, MatrixError naming the entry for one outside the analyzed
     * pattern, a NaN, an infinity or an asymmetric pair, and for another size or storage.
     */
    void factorize(const sparse::CSCMatrix &matrix);

    /**
     * factorize(), with the values of @p matrix read from @p values (matrix.n_nonzeros() of
     * them, in the order of its entries) instead of matrix.values, which are not used: for
     * a caller that holds them elsewhere (the Python module: in NumPy's array), without
     * copying them.
     */
    void factorize(const sparse::CSCMatrix &matrix, const double *values);

    /**
     * Partial refactorization after the entries of @p changed_columns (user numbering) of
     * @p matrix (the analyzed pattern or a subset of it, as factorize() takes) changed:
     * recompute exactly the columns of L on the elimination-tree paths from those columns
     * (permuted) to the root, reuse the others. A column of C whose
     * values changed without being listed is found while loading the values and recomputed
     * as well, so the factor always matches @p matrix; with ChangeListing::complete the
     * caller vouches that none did, and only the listed columns are read (what the solver
     * takes as changed stays the same: the listed columns, and those still pending).
     *
     * With @p refresh other than Refresh::all the factor is brought up to date only in part
     * (see Refresh) and is then the exact factor of no matrix, though still a valid
     * preconditioner (L L^T is SPD); what it leaves out is remembered and recomputed by a
     * later Refresh::all, so the changes need to be listed only once.
     *
     * Throws InputError for a column out of range or Refresh::below_top with a method other
     * than the supernodal one, and what factorize() throws. If nothing is analyzed yet
     * (State::empty), analyzes @p matrix first, as factorize() does; if no valid factor
     * exists yet, factors fully whatever @p refresh. A matrix that factorize() or refactorize() refuses
     * (another pattern, a value that is not finite, asymmetric values, a pivot that is not
     * positive) leaves no valid factor: solve() throws until the next factorization.
     */
    void refactorize(const sparse::CSCMatrix  &matrix,
                     const std::vector<Index> &changed_columns,
                     Refresh                   refresh = Refresh::all,
                     ChangeListing             listing = ChangeListing::searched);

    /** refactorize(), with the values of @p matrix read from @p values, as factorize() above reads them. */
    void refactorize(const sparse::CSCMatrix  &matrix,
                     const double             *values,
                     const std::vector<Index> &changed_columns,
                     Refresh                   refresh = Refresh::all,
                     ChangeListing             listing = ChangeListing::searched);

    /**
     * L L^T + C C^T: the factor of A + C C^T, in place (CHOLMOD's cholmod_updown). @p c is
     * n x k in the user's numbering (its storage flag is not read: every stored entry is an entry of
     * C), each column's rows coupled in A's factor (for instance the dofs of one element or
     * one vertex): C C^T must fit L's pattern, which is refused naming the column and rows
     * otherwise. The solver's copy of A is updated too, so that a later refactorize()
     * finds the change. Supernodal method; needs an exact factor (factor_is_exact()).
     */
    void update(const sparse::CSCMatrix &c);

    /**
     * L L^T - C C^T, as update(). Throws NotPositiveDefinite, the factor left that of A,
     * if A - C C^T is not positive definite (or loses all but a few digits of a pivot,
     * Settings::downdate_pivot_tolerance): the caller may then factor the matrix it
     * meant anew. The columns the downdate changed are then recomputed from the copy of A
     * (equal to a factorization's), or, after an update that reached outside A's pattern,
     * put back from a copy the downdate kept as it went, bit for bit.
     */
    void downdate(const sparse::CSCMatrix &c);

    /** Both in one pass: column t of @p c is added if signs[t] = +1, subtracted if -1. */
    void modify(const sparse::CSCMatrix &c, const std::vector<double> &signs);

    /**
     * The predicted seconds of refactorize(matrix, @p changed_columns, @p refresh) now, as
     * its choice between an update and a recomputation would have it (the change's rank
     * taken as the number of changed columns): what a caller that weighs refreshing
     * against other work compares; the method it would take in @p method if not null.
     * Throws as refactorize() does.
     */
    double predicted_seconds(const std::vector<Index> &changed_columns, Refresh refresh,
                             RefactorizationMethod *method = nullptr) const;

    /**
     * The flops refactorize(matrix, @p changed_columns, @p refresh) would spend now: on the
     * listed columns (user numbering) and on what is pending or stale. Changes the next load
     * finds without their being listed are not foreseen. Throws as refactorize() does.
     */
    double predicted_flops(const std::vector<Index> &changed_columns, Refresh refresh) const;

    /** Whether L is the exact factor of the last loaded matrix: nothing pending, nothing stale. */
    bool factor_is_exact() const;

    /**
     * Solve A x = b for one right-hand side; with a factor that is not exact
     * (factor_is_exact()), solve L L^T x = b, a preconditioner for A: every pivot is
     * positive, so L L^T is SPD. Throws Error only when no factor exists.
     */
    void solve(const std::vector<double> &b, std::vector<double> &x) const;

    /**
     * Solve A X = B for @p n_rhs right-hand sides stored column by column (leading
     * dimension n) in @p b; the solutions go to @p x (which may alias @p b).
     */
    void solve(const double *b, double *x, Index n_rhs) const;

    /**
     * x = (L L^T)^-1 b with the factor as it is (exact or partly refreshed): the
     * preconditioner of an iterative solve, with the copy of the factor in
     * Settings::preconditioner_precision (the same as solve() at full precision).
     */
    void apply_preconditioner(const double *b, double *x) const;

    /**
     * Bring the preconditioner's copy of the factor up to date now, which
     * apply_preconditioner() otherwise does on first use: a thread that factors for another
     * to iterate with does it beside the steps.
     */
    void prepare_preconditioner();

    /**
     * The compliance W = H (L L^T)^-1 H^T (m x m, column-major) of the m columns of @p ht
     * (n x m, the rows of H in the user's numbering), from the factor as it is: A^-1 when
     * the factor is exact (factor_is_exact()), the preconditioner's inverse otherwise
     * (compliance.h). Supernodal method (InputError otherwise). What it cost goes to
     * @p statistics if not null.
     */
    std::vector<double> compliance(const sparse::CSCMatrix &ht, ComplianceMethod method = ComplianceMethod::paths,
                                   ComplianceStatistics *statistics = nullptr) const;

    /**
     * The block of A^-1 among the unknowns @p unknowns (user numbering, distinct) into
     * @p columns (KeptInverseColumns::gram, |S| x |S|, in the order of @p unknowns), from
     * the factor as it is, as compliance() takes it: what persists from the last call with
     * the same @p columns is kept while factor_revision() is the same. Supernodal method
     * (InputError otherwise, and for an unknown out of range).
     */
    void inverse_block(const std::vector<Index> &unknowns, KeptInverseColumns &columns) const;

    /**
     * A number that changes whenever the factor's values may have (analyze(), factorize(),
     * a refactorize() that recomputed or updated columns, update(), downdate(),
     * load_numeric()), unique among the solvers of the process: two that share it hold the
     * same factor (a copy's, before either changes). 0 before the first factorization.
     */
    std::uint64_t factor_revision() const;

    /** L, the factor of P^T A P (permuted numbering; a triangular matrix, full storage). */
    sparse::CSCMatrix factor() const;

    /**
     * Bytes of numeric values held now (L's, and the preconditioner's copy): 0 until the
     * first factorization, since analyze() allocates none (a solver that only analyzes, as
     * beside a peer's, holds none). Statistics::factor_bytes is what a factorization takes.
     */
    std::size_t numeric_bytes() const;

    /** perm[k] = column of A that is column k of P^T A P. */
    const std::vector<Index> &permutation() const;

    /** The column-by-column structure (left- and up-looking methods; empty for supernodal). */
    const SymbolicFactorization &symbolic() const;

    /** The supernodal structure (supernodal method; empty otherwise). */
    const SupernodalSymbolic &supernodal_symbolic() const;

    /** Parent of each column of P^T A P in the elimination tree. */
    const std::vector<Index> &elimination_tree() const;

    /**
     * The columns of L (permuted numbering, sorted) that the last refactorize() recomputed:
     * the elimination-tree closure of the changes, without the top's for Refresh::below_top,
     * with the stale ones for Refresh::all.
     */
    const std::vector<Index> &recomputed_columns() const;

    /** top_supernodes()[s]: whether supernode s is in the top (supernodal method; empty otherwise). */
    const std::vector<bool> &top_supernodes() const;

    const Statistics &statistics() const;

    const Settings &settings() const;

    /**
     * Factor and solve on @p n_threads threads from now on (Settings::n_threads): a copy
     * that factors beside the steps on a thread of its own takes one.
     */
    void set_thread_count(unsigned int n_threads);

    /** Take changes by @p method from now on (Settings::change_method); rates measured so far are forgotten. */
    void set_change_method(ChangeMethod method);

    /**
     * The flop rates learned from this solver's own factorizations, refactorizations and
     * updates (checkpointed with save_numeric()): what a caller foreseeing the cost of a
     * factorization reads, instead of timing the same calls again.
     */
    const RefactorizationCostModel &cost_model() const;

    /**
     * Write the numeric state to a checkpoint: the loaded values of A, the factor as it is
     * (exact or partly refreshed), what is pending and stale. The analysis is not written:
     * analyze() of the same matrix redoes it exactly.
     */
    void save_numeric(BinaryWriter &writer) const;
    /**
     * Read what save_numeric() wrote, after analyze() of the matrix it was written for:
     * the solver then goes on as the one that wrote it would have, to the bit. Throws
     * InputError if the sizes differ from this analysis.
     */
    void load_numeric(BinaryReader &reader);

  private:
    /** factorize() and refactorize() of @p values, or of matrix.values if null. */
    void factorize_values(const sparse::CSCMatrix &matrix, const double *values);
    void refactorize_values(const sparse::CSCMatrix  &matrix,
                            const double             *values,
                            const std::vector<Index> &changed_columns,
                            Refresh                   refresh,
                            ChangeListing             listing);

    /** solve(), with the preconditioner's copy of the factor if @p preconditioner. */
    void solve_in(const double *b, double *x, Index n_rhs, bool preconditioner) const;

    /** What one refactorize() computes, and the stale columns it leaves. */
    struct RefreshPlan
    {
      /** Factor everything (no valid factor, or the up-looking method). */
      bool               full = false;
      /**
       * Columns of L (permuted, sorted) to recompute: with each column, every ancestor up
       * to the first that is not recomputed (above it, nothing recomputed depends on it).
       */
      std::vector<Index> columns;
      /** The supernodes that hold them (supernodal method). */
      DirtySupernodes    supernodes;
      /** The stale columns after it. */
      std::vector<Index> stale_columns;
      double             flops = 0;
    };

    /** Throw InputError for a column out of range or a @p refresh the method cannot do. */
    void check_request(const std::vector<Index> &changed_columns, Refresh refresh) const;

    /**
     * The plan of a refactorize() with @p refresh when the columns @p changes of C (permuted,
     * sorted) have changed since the last one: pending ones included, stale ones not.
     */
    RefreshPlan plan_refresh(const std::vector<Index> &changes, Refresh refresh) const;

    /** @p changed_columns (user numbering) mapped to C's and merged with the pending ones. */
    std::vector<Index> pending_with(const std::vector<Index> &changed_columns) const;

    /** Factor the columns of @p plan; maps a failed pivot to the user's column. */
    double run_numeric(const RefreshPlan &plan);

    /** Record in the statistics what is pending and stale (the backlog a refresh has to take). */
    void record_backlog();

    /** Throw unless update() and its kind may run now (@p caller names it). */
    void check_modification(const std::string &caller) const;

    /**
     * Whether a change whose recomputation is @p plan (for @p refresh) may be taken as an
     * update of the factor at all: an exact factor of the copy of A (nothing stale, no
     * update outside A's pattern), a refresh of everything, something to recompute, the
     * supernodal method, and a Settings::change_method that updates.
     */
    bool may_update(Refresh refresh, const RefreshPlan &plan) const;

    /** What the rule "update or recompute" weighed for one change, and its verdict. */
    struct UpdateWeighing
    {
      /** Whether to update (else recompute @p plan). */
      bool   update  = false;
      /** The rank the update's plan foresees, and its flops (the low-rank form's included). */
      Index  rank         = 0;
      double update_flops = -1;
      /** Predicted seconds of the update, of recomputing the plan, of a full factorization. */
      double update_seconds  = -1;
      double partial_seconds = -1;
      double full_seconds    = -1;
    };

    /** What recomputing @p plan is: a full or a partial refactorization, or nothing. */
    static RefactorizationMethod recompute_method(const RefreshPlan &plan);

    /**
     * The predicted seconds of recomputing @p plan: a partial refactorization of the
     * supernodal factor from its supernodes' timings (SupernodalFactor::timed_seconds())
     * where they are measured, else at the rate the cost model learned.
     */
    double predicted_recompute_seconds(const RefreshPlan &plan) const;

    /** Whether a change touching @p touched_rows rows of A may be weighed as an update (Settings::max_update_rows). */
    bool may_weigh_update(Index touched_rows) const;

    /**
     * The one rule "update or recompute", for refactorize() and predicted_seconds() alike:
     * a change touching @p touched_rows rows of A, whose low-rank form C has the plan
     * @p update_plan, is taken as an update if it is predicted faster than recomputing
     * @p plan (always, with ChangeMethod::update). The callers ask may_weigh_update() first,
     * before they plan. refactorize() plans C's own columns; predicted_seconds(), which sees
     * no values yet, plans one column of C per changed column.
     */
    UpdateWeighing weigh_update(Index touched_rows, const ModificationPlan &update_plan, const RefreshPlan &plan) const;

    /**
     * Take the change of A since it was factored (columns @p changes of C) as an update
     * if weigh_update() chooses it; if so, run it and return true (false: recompute
     * @p plan). Sets the statistics of the choice.
     */
    bool updated_instead(const std::vector<Index> &changes, const RefreshPlan &plan);

    /** The settings of the update and downdate kernels. */
    ModificationSettings modification_settings() const;

    Settings              solver_settings;
    std::vector<Index>    fill_reducing_permutation;
    std::vector<Index>    inverse_permutation;
    SymbolicFactorization symbolic_factorization;
    SupernodalSymbolic    supernodal_structure;
    PermutedMatrix        permuted_matrix;
    std::vector<double>   l_values;
    SupernodalFactor      supernodal_factor;
    std::vector<Index>    last_recomputed_columns;
    /** Supernodes of the top (supernodal method). */
    std::vector<bool>     top_supernode;
    /** Columns of C (permuted, sorted) loaded with new values that no refactorization has used yet. */
    std::vector<Index>    pending_columns;
    /**
     * Columns of L in top supernodes (permuted, sorted) that depend on a change that
     * Refresh::below_top left out: the union of the elimination-tree closures left out.
     * A stale supernode is recomputed from its first stale column on, since the columns
     * before it depend on nothing that changed since it was last computed.
     */
    std::vector<Index>    stale_columns;
    bool                  analyzed     = false;
    bool                  factor_valid = false;
    /**
     * Whether the copy of A holds the matrix the factor is that of: not after an update()
     * whose C C^T reaches entries of L outside A's pattern (the next refactorize() factors
     * in full).
     */
    bool                  matrix_holds_factored = true;
    /** The rates of the choice between update and recomputation. */
    RefactorizationCostModel refactorization_costs;
    /** factor_revision(): set by mark_factor_changed(). */
    std::uint64_t         revision = 0;
    /** Give the factor a new revision: its values are about to change. */
    void                  mark_factor_changed();
    /** Written by the calls that change the solver only: the const ones may run concurrently. */
    Statistics            stats;
  };
} // namespace warpchol::cholesky
