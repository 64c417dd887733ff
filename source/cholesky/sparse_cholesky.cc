#include <warpchol/base/format.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/low_rank_change.h>
#include <warpchol/cholesky/numeric_simplicial.h>
#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/solve.h>
#include <warpchol/cholesky/sparse_cholesky.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>

namespace warpchol::cholesky
{
  std::string to_string(const FactorizationMethod method)
  {
    return name_of(factorization_method_names, method);
  }

  FactorizationMethod parse_factorization_method(const std::string &name)
  {
    return parse_name(factorization_method_names, name, "factorization method");
  }

  double SparseCholesky::Statistics::fill() const
  {
    return nnz_a > 0 ? static_cast<double>(nnz_l) / static_cast<double>(nnz_a) : 0.;
  }

  namespace
  {
    /**
     * permuted.load(matrix) (of @p values, if not null), dropping the factor (@p factor_valid)
     * if it fails: a load that
     * stops part way (a value that is not finite, an asymmetric pair) leaves C with some of
     * the new values and L with the old factor, and the next load, which finds the changed
     * columns by comparing with C, would miss those already written. The next
     * refactorize() then factors in full.
     */
    std::vector<Index> load_or_drop_factor(PermutedMatrix &permuted, const sparse::CSCMatrix &matrix,
                                           const double *values, bool &factor_valid,
                                           const std::vector<Index> *listed_columns = nullptr)
    {
      try
        {
          if (listed_columns != nullptr)
            return values != nullptr ? permuted.load_columns(matrix, values, *listed_columns) :
                                       permuted.load_columns(matrix, *listed_columns);
          return values != nullptr ? permuted.load(matrix, values) : permuted.load(matrix);
        }
      catch (...)
        {
          factor_valid = false;
          throw;
        }
    }
  } // namespace

  SparseCholesky::SparseCholesky()
    : SparseCholesky(Settings())
  {}

  SparseCholesky::SparseCholesky(const Settings &settings)
    : solver_settings(settings)
    , refactorization_costs(settings.change_method == ChangeMethod::by_flops)
  {
    blas::use_single_threaded_blas();
  }

  SparseCholesky::State SparseCholesky::state() const
  {
    return !analyzed ? State::empty : factor_valid ? State::factorized : State::analyzed;
  }

  void SparseCholesky::require(const State required, const std::string &call) const
  {
    if (state() >= required)
      return;
    if (!analyzed)
      throw Error(call + " called before analyze()");
    throw Error(call + " called without a valid factorization");
  }

  void SparseCholesky::analyze(const sparse::CSCMatrix &matrix)
  {
    const Stopwatch stopwatch;
    mark_factor_changed();
    analyzed              = false;
    factor_valid          = false;
    matrix_holds_factored = true;
    pending_columns.clear();
    stale_columns.clear();
    if (!(solver_settings.top_flops_fraction >= 0. && solver_settings.top_flops_fraction <= 1.))
      throw InputError("top_flops_fraction " + std::to_string(solver_settings.top_flops_fraction) +
                       " is not in [0, 1]");
    if (matrix.n_rows != matrix.n_cols)
      throw MatrixError("matrix is not square: " + std::to_string(matrix.n_rows) + "x" +
                        std::to_string(matrix.n_cols));
    matrix.check_consistency();

    // Fill-reducing ordering, then a postorder of its elimination tree: the same fill, but
    // every subtree becomes a contiguous range of columns (supernodes, locality).
    const Ordering ordering = compute_ordering(matrix, solver_settings.ordering);
    permuted_matrix.setup(matrix, ordering.permutation);
    const std::vector<Index> postorder = postorder_tree(cholesky::elimination_tree(permuted_matrix.lower()));
    fill_reducing_permutation = compose_permutations(ordering.permutation, postorder);
    inverse_permutation       = invert_permutation(fill_reducing_permutation);
    permuted_matrix.setup(matrix, fill_reducing_permutation);

    stats                   = Statistics();
    stats.n                 = matrix.n_cols;
    stats.nnz_a             = permuted_matrix.n_nonzeros();
    stats.vertex_block_size = ordering.vertex_block_size;
    if (solver_settings.method == FactorizationMethod::supernodal)
      {
        symbolic_factorization = SymbolicFactorization();
        std::vector<double>().swap(l_values);
        supernodal_structure = analyze_supernodal(permuted_matrix.lower(),
                                                  cholesky::elimination_tree(permuted_matrix.lower()),
                                                  solver_settings.relaxation);
        // The values come with the first factorization: a solver that only analyzes (beside
        // a peer's) holds none.
        supernodal_factor.clear(solver_settings.preconditioner_precision);
        stats.nnz_l        = supernodal_structure.nnz_l();
        stats.flops        = supernodal_structure.flops;
        stats.exact_flops  = supernodal_structure.exact_flops;
        stats.n_supernodes = supernodal_structure.n_supernodes();
        top_supernode      = cholesky::top_supernodes(supernodal_structure, solver_settings.top_flops_fraction);
        for (Index s = 0; s < stats.n_supernodes; ++s)
          if (top_supernode[s])
            {
              ++stats.n_top_supernodes;
              stats.top_flops += supernodal_structure.supernode_flops[s];
            }
        stats.factor_bytes = supernodal_structure.n_stored_values() * sizeof(double) +
                             (supernodal_structure.row_index.size() + supernodal_structure.row_start.size() +
                              supernodal_structure.value_start.size() + supernodal_structure.first_column.size()) *
                               sizeof(Index);
        // The preconditioner's copy of the values, where it is kept, with its column scales.
        if (solver_settings.preconditioner_precision != PreconditionerPrecision::full)
          stats.factor_bytes +=
            supernodal_structure.n_stored_values() *
              (solver_settings.preconditioner_precision == PreconditionerPrecision::single ? 4 : 2) +
            2 * sizeof(float) * supernodal_structure.n;
      }
    else
      {
        supernodal_structure   = SupernodalSymbolic();
        top_supernode.clear();
        symbolic_factorization = analyze_left_looking(permuted_matrix.lower());
        std::vector<double>().swap(l_values);
        stats.nnz_l        = symbolic_factorization.nnz_l();
        stats.flops        = symbolic_factorization.flops;
        stats.exact_flops  = symbolic_factorization.flops;
        stats.factor_bytes = symbolic_factorization.nnz_l() * sizeof(double) +
                             symbolic_factorization.row_index.size() * sizeof(Index) +
                             symbolic_factorization.column_start.size() * sizeof(Index);
      }
    stats.analyze_seconds = stopwatch.seconds();
    analyzed              = true;
  }

  double SparseCholesky::run_numeric(const RefreshPlan &plan)
  {
    stats.columns_recomputed    = 0;
    stats.supernodes_recomputed = 0;
    // Nothing to do; the factorizations would take an empty list for "everything".
    if (!plan.full && plan.columns.empty())
      return 0.;
    mark_factor_changed();
    factor_valid = false;
    if (solver_settings.method != FactorizationMethod::supernodal &&
        static_cast<Index>(l_values.size()) != symbolic_factorization.nnz_l())
      l_values.assign(symbolic_factorization.nnz_l(), 0.);
    try
      {
        double flops = 0;
        switch (solver_settings.method)
          {
            case FactorizationMethod::up_looking:
              factorize_up_looking(symbolic_factorization, permuted_matrix.lower(), l_values);
              flops                    = symbolic_factorization.flops;
              stats.columns_recomputed = stats.n;
              break;
            case FactorizationMethod::left_looking:
              flops = factorize_left_looking(symbolic_factorization, permuted_matrix.lower(),
                                             plan.full ? std::vector<Index>() : plan.columns, l_values);
              stats.columns_recomputed = plan.full ? stats.n : static_cast<Index>(plan.columns.size());
              break;
            case FactorizationMethod::supernodal:
              stats.columns_recomputed    = plan.full ? stats.n : plan.supernodes.n_columns;
              stats.supernodes_recomputed = plan.full ? stats.n_supernodes :
                                                        static_cast<Index>(plan.supernodes.supernodes.size());
              flops = supernodal_factor.factorize(supernodal_structure, permuted_matrix.lower(),
                                                  plan.supernodes.supernodes, plan.supernodes.start_offsets,
                                                  solver_settings.n_threads);
              break;
          }
        factor_valid = true;
        return flops;
      }
    catch (const NotPositiveDefinite &failure)
      {
        // Report the column as the user numbers it.
        throw NotPositiveDefinite(fill_reducing_permutation[failure.column], failure.pivot);
      }
  }

  void SparseCholesky::factorize(const sparse::CSCMatrix &matrix)
  {
    factorize_values(matrix, nullptr);
  }

  void SparseCholesky::factorize(const sparse::CSCMatrix &matrix, const double *const values)
  {
    factorize_values(matrix, values);
  }

  void SparseCholesky::factorize_values(const sparse::CSCMatrix &matrix, const double *const values)
  {
    if (!analyzed)
      analyze(matrix);
    // The factor's memory first, outside the factorization's time: the cost models take
    // that time for what a factorization costs, every later one in memory already touched.
    if (solver_settings.method == FactorizationMethod::supernodal)
      supernodal_factor.allocate(supernodal_structure);
    const Stopwatch stopwatch;
    load_or_drop_factor(permuted_matrix, matrix, values, factor_valid);
    pending_columns.clear();
    stale_columns.clear();
    RefreshPlan everything;
    everything.full        = true;
    const Stopwatch numeric_stopwatch;
    stats.flops_recomputed = run_numeric(everything);
    refactorization_costs.record(RefactorizationMethod::full, stats.flops_recomputed, numeric_stopwatch.seconds());
    permuted_matrix.mark_factored();
    matrix_holds_factored = true;
    stats.method          = RefactorizationMethod::full;
    last_recomputed_columns.clear();
    record_backlog();
    ++stats.n_factorizations;
    stats.factorize_seconds = stopwatch.seconds();
  }

  void SparseCholesky::check_request(const std::vector<Index> &changed_columns, const Refresh refresh) const
  {
    for (const Index column : changed_columns)
      if (column < 0 || column >= stats.n)
        throw InputError("changed column " + std::to_string(column) + " out of range [0, " +
                         std::to_string(stats.n) + ")");
    if (refresh == Refresh::below_top && solver_settings.method != FactorizationMethod::supernodal)
      throw InputError("Refresh::below_top needs the supernodal method, not " + to_string(solver_settings.method));
  }

  std::vector<Index> SparseCholesky::pending_with(const std::vector<Index> &changed_columns) const
  {
    std::vector<Index> changes = pending_columns;
    for (const Index column : changed_columns)
      changes.push_back(inverse_permutation[column]);
    std::sort(changes.begin(), changes.end());
    changes.erase(std::unique(changes.begin(), changes.end()), changes.end());
    return changes;
  }

  SparseCholesky::RefreshPlan SparseCholesky::plan_refresh(const std::vector<Index> &changes,
                                                           const Refresh             refresh) const
  {
    RefreshPlan plan;
    if (!factor_valid || (solver_settings.method == FactorizationMethod::up_looking && refresh != Refresh::none))
      {
        // No factor to update (or a method that cannot update): factor everything.
        plan.full = true;
        switch (solver_settings.method)
          {
            case FactorizationMethod::up_looking:
              plan.flops = symbolic_factorization.flops;
              break;
            case FactorizationMethod::left_looking:
              for (Index j = 0; j < stats.n; ++j)
                plan.flops += left_looking_column_flops(symbolic_factorization, j);
              break;
            case FactorizationMethod::supernodal:
              plan.flops = supernodal_structure.flops;
              break;
          }
        return plan;
      }

    plan.stale_columns = stale_columns;
    if (refresh == Refresh::none)
      return plan;
    const std::vector<Index> dirty = etree_closure(elimination_tree(), changes);
    if (refresh == Refresh::below_top)
      {
        // The dirty top columns wait for a Refresh::all. The top is upward-closed, so no
        // column below it depends on one in it, and between a recomputed column and a
        // recomputed ancestor every column is recomputed too.
        std::vector<Index> dirty_top;
        for (const Index j : dirty)
          (top_supernode[supernodal_structure.supernode_of[j]] ? dirty_top : plan.columns).push_back(j);
        std::vector<Index> stale;
        std::set_union(stale_columns.begin(), stale_columns.end(), dirty_top.begin(), dirty_top.end(),
                       std::back_inserter(stale));
        plan.stale_columns = std::move(stale);
      }
    else
      {
        // Both sets are upward-closed (unions of elimination-tree paths to the root), and so
        // is their union.
        std::set_union(dirty.begin(), dirty.end(), stale_columns.begin(), stale_columns.end(),
                       std::back_inserter(plan.columns));
        plan.stale_columns.clear();
      }

    if (solver_settings.method == FactorizationMethod::supernodal)
      {
        plan.supernodes = dirty_supernodes(supernodal_structure, plan.columns);
        plan.flops      = plan.supernodes.flops;
      }
    else
      for (const Index j : plan.columns)
        plan.flops += left_looking_column_flops(symbolic_factorization, j);
    return plan;
  }

  void SparseCholesky::refactorize(const sparse::CSCMatrix  &matrix,
                                   const std::vector<Index> &changed_columns,
                                   const Refresh             refresh,
                                   const ChangeListing       listing)
  {
    refactorize_values(matrix, nullptr, changed_columns, refresh, listing);
  }

  void SparseCholesky::refactorize(const sparse::CSCMatrix  &matrix,
                                   const double *const       values,
                                   const std::vector<Index> &changed_columns,
                                   const Refresh             refresh,
                                   const ChangeListing       listing)
  {
    refactorize_values(matrix, values, changed_columns, refresh, listing);
  }

  void SparseCholesky::refactorize_values(const sparse::CSCMatrix  &matrix,
                                          const double *const       values,
                                          const std::vector<Index> &changed_columns,
                                          const Refresh             refresh,
                                          const ChangeListing       listing)
  {
    if (!analyzed)
      analyze(matrix);
    check_request(changed_columns, refresh);
    const Stopwatch stopwatch;
    // Without a valid factor of the loaded values everything is read anew: what the listing
    // vouches for is a change since the last load.
    const bool               listed_only = listing == ChangeListing::complete && factor_valid && matrix_holds_factored;
    const std::vector<Index> unlisted =
      load_or_drop_factor(permuted_matrix, matrix, values, factor_valid, listed_only ? &changed_columns : nullptr);
    const std::vector<Index> listed   = pending_with(changed_columns);
    std::vector<Index>       changes;
    std::set_union(listed.begin(), listed.end(), unlisted.begin(), unlisted.end(), std::back_inserter(changes));

    // After an update() that reached outside A's pattern, the copy of A is not the factor's
    // matrix: only a full factorization makes them agree again.
    if (!matrix_holds_factored)
      factor_valid = false;
    // The factor is that of the values last marked factored: a change since can be an update.
    const bool        exact_before    = factor_valid && stale_columns.empty();
    const RefreshPlan plan            = plan_refresh(changes, refresh);
    const bool        update_possible = may_update(refresh, plan);
    if (refresh == Refresh::none && !plan.full)
      pending_columns = changes;
    else
      pending_columns.clear();
    stale_columns = plan.stale_columns;

    stats.update_rank               = 0;
    stats.update_flops              = -1;
    stats.partial_flops             = -1;
    stats.predicted_update_seconds  = -1;
    stats.predicted_partial_seconds = -1;
    stats.predicted_full_seconds    = -1;
    stats.update_fell_back          = false;
    const Stopwatch numeric_stopwatch;
    if (!(update_possible && updated_instead(changes, plan)))
      {
        stats.flops_recomputed = run_numeric(plan);
        stats.method           = plan.full ? RefactorizationMethod::full :
                                 plan.columns.empty() ? RefactorizationMethod::none :
                                                        RefactorizationMethod::partial;
        last_recomputed_columns = plan.columns;
      }
    // An update's rate in the flops its weighing predicts from (the plan's), so that what is
    // learned predicts the next weighing.
    refactorization_costs.record(stats.method,
                                 stats.method == RefactorizationMethod::update ? stats.update_flops : stats.flops_recomputed,
                                 numeric_stopwatch.seconds(), static_cast<unsigned int>(stats.update_rank));
    if (factor_is_exact())
      {
        if (exact_before && !plan.full)
          permuted_matrix.mark_factored(changes);
        else
          permuted_matrix.mark_factored();
        matrix_holds_factored = true;
      }
    if (plan.full)
      {
        last_recomputed_columns.resize(stats.n);
        for (Index j = 0; j < stats.n; ++j)
          last_recomputed_columns[j] = j;
        stats.factorize_seconds = stopwatch.seconds();
      }
    record_backlog();
    stats.refactorize_seconds = stopwatch.seconds();
    ++stats.n_refactorizations;
  }

  ModificationSettings SparseCholesky::modification_settings() const
  {
    ModificationSettings settings;
    settings.pivot_tolerance = solver_settings.downdate_pivot_tolerance;
    settings.n_threads       = solver_settings.n_threads;
    return settings;
  }

  namespace
  {
    /** Flops of the dense LDL^T that finds the low-rank form of a change on @p m rows. */
    double low_rank_form_flops(const Index m)
    {
      return static_cast<double>(m) * static_cast<double>(m) * static_cast<double>(m) / 3.;
    }

    /** The columns of L (permuted, sorted) a modification by @p plan changes. */
    std::vector<Index> modified_columns(const SupernodalSymbolic &symbolic, const ModificationPlan &plan)
    {
      std::vector<Index> columns;
      for (std::size_t k = 0; k < plan.supernodes.size(); ++k)
        for (Index j = symbolic.first_column[plan.supernodes[k]] + plan.start_columns[k];
             j < symbolic.first_column[plan.supernodes[k] + 1]; ++j)
          columns.push_back(j);
      return columns;
    }
  } // namespace

  bool SparseCholesky::may_update(const Refresh refresh, const RefreshPlan &plan) const
  {
    return factor_valid && matrix_holds_factored && stale_columns.empty() && refresh == Refresh::all &&
           !plan.full && !plan.columns.empty() && solver_settings.method == FactorizationMethod::supernodal &&
           solver_settings.change_method != ChangeMethod::recompute;
  }

  RefactorizationMethod SparseCholesky::recompute_method(const RefreshPlan &plan)
  {
    return plan.full      ? RefactorizationMethod::full :
           plan.flops > 0 ? RefactorizationMethod::partial :
                            RefactorizationMethod::none;
  }

  double SparseCholesky::predicted_recompute_seconds(const RefreshPlan &plan) const
  {
    const RefactorizationMethod method = recompute_method(plan);
    // A partial refactorization recomputes the top of the tree, whose large supernodes
    // run faster than the factorization's average rate: their own timings tell (not with
    // fixed rates, which choose alike on every machine).
    if (method == RefactorizationMethod::partial && solver_settings.method == FactorizationMethod::supernodal &&
        solver_settings.change_method != ChangeMethod::by_flops)
      {
        const double timed = supernodal_factor.timed_seconds(supernodal_structure, plan.supernodes.supernodes,
                                                             plan.supernodes.start_offsets);
        if (timed >= 0)
          return timed;
      }
    return refactorization_costs.predicted_seconds(method, plan.flops);
  }

  bool SparseCholesky::may_weigh_update(const Index touched_rows) const
  {
    return touched_rows <= solver_settings.max_update_rows;
  }

  SparseCholesky::UpdateWeighing SparseCholesky::weigh_update(const Index             touched_rows,
                                                              const ModificationPlan &update_plan,
                                                              const RefreshPlan      &plan) const
  {
    UpdateWeighing weighing;
    weighing.rank         = update_plan.rank;
    weighing.update_flops = update_plan.flops + low_rank_form_flops(touched_rows);
    weighing.update_seconds  = refactorization_costs.predicted_seconds(RefactorizationMethod::update, weighing.update_flops,
                                                                       static_cast<unsigned int>(weighing.rank));
    weighing.partial_seconds = predicted_recompute_seconds(plan);
    weighing.full_seconds =
      refactorization_costs.predicted_seconds(RefactorizationMethod::full, supernodal_structure.flops);
    // Against the recomputation that runs if the update does not: the plan's, never a full
    // factorization in its place.
    weighing.update = solver_settings.change_method == ChangeMethod::update ||
                      weighing.update_seconds < weighing.partial_seconds;
    return weighing;
  }

  bool SparseCholesky::updated_instead(const std::vector<Index> &changes, const RefreshPlan &plan)
  {
    const std::vector<PermutedMatrix::Change> entries = permuted_matrix.changes_since_factored(changes);
    const std::vector<Index>                  rows    = touched_rows(entries);
    if (rows.empty())
      {
        // The values are those the factor was made from: nothing to do.
        stats.flops_recomputed      = 0;
        stats.columns_recomputed    = 0;
        stats.supernodes_recomputed = 0;
        stats.method                = RefactorizationMethod::none;
        last_recomputed_columns.clear();
        return true;
      }
    if (!may_weigh_update(static_cast<Index>(rows.size())))
      return false;
    // The low-rank form first: its columns, not the rows, are what an update works on (a
    // pivot raised adds a column, a row left empty drops one), and it costs little beside.
    const LowRankChange    form        = low_rank_form(stats.n, entries);
    const ModificationPlan update_plan = plan_modification(supernodal_structure, form.c);
    const UpdateWeighing   weighing    = weigh_update(static_cast<Index>(rows.size()), update_plan, plan);
    stats.update_rank               = weighing.rank;
    stats.update_flops              = weighing.update_flops;
    stats.partial_flops             = plan.flops;
    stats.predicted_update_seconds  = weighing.update_seconds;
    stats.predicted_partial_seconds = weighing.partial_seconds;
    stats.predicted_full_seconds    = weighing.full_seconds;
    if (!weighing.update)
      return false;

    // If a downdate fails, the columns it changed are recomputed below (they lie on the
    // changes' paths, which the partial refactorization recomputes): no copy to restore.
    ModificationSettings settings = modification_settings();
    settings.restore_on_failure   = false;
    mark_factor_changed();
    try
      {
        // The plan weighed is the one the modification works by: made once.
        const ModificationResult result =
          supernodal_factor.modify(supernodal_structure, form.c, update_plan, form.signs, settings);
        stats.flops_recomputed      = result.flops + low_rank_form_flops(static_cast<Index>(rows.size()));
        stats.columns_recomputed    = result.columns;
        stats.supernodes_recomputed = result.supernodes;
        stats.method                = RefactorizationMethod::update;
        last_recomputed_columns     = modified_columns(supernodal_structure, update_plan);
        ++stats.n_updates;
        return true;
      }
    catch (const NotPositiveDefinite &)
      {
        // A downdate that would lose a pivot (its columns, all on the changes' paths, hold
        // no factor now): recompute them, which reports the pivot in the user's numbering
        // if the matrix itself is not positive definite.
        stats.update_fell_back = true;
        return false;
      }
  }

  void SparseCholesky::check_modification(const std::string &caller) const
  {
    require(State::factorized, caller);
    if (solver_settings.method != FactorizationMethod::supernodal)
      throw InputError(caller + " needs the supernodal method, not " + to_string(solver_settings.method));
    if (!factor_is_exact())
      throw Error(caller + " needs the exact factor of A, and changes are pending or stale: refactorize() first");
  }

  void SparseCholesky::update(const sparse::CSCMatrix &c)
  {
    modify(c, std::vector<double>(c.n_cols, 1.));
  }

  void SparseCholesky::downdate(const sparse::CSCMatrix &c)
  {
    modify(c, std::vector<double>(c.n_cols, -1.));
  }

  void SparseCholesky::modify(const sparse::CSCMatrix &c, const std::vector<double> &signs)
  {
    const bool all_up   = std::all_of(signs.begin(), signs.end(), [](double sign) { return sign > 0; });
    const bool all_down = std::all_of(signs.begin(), signs.end(), [](double sign) { return sign < 0; });
    check_modification(all_up ? "update()" : all_down ? "downdate()" : "modify()");
    if (c.n_rows != stats.n)
      throw InputError("C has " + std::to_string(c.n_rows) + " rows, the matrix " + std::to_string(stats.n));
    // C is a general n x k matrix: every stored entry is one of it, whatever its flag says.
    sparse::CSCMatrix general = c;
    general.storage           = sparse::Storage::full;
    general.check_consistency();
    const Stopwatch stopwatch;
    // C in the permuted numbering, each column's rows sorted.
    sparse::CSCMatrix permuted = sparse::CSCMatrix::zero(stats.n, c.n_cols);
    std::vector<std::pair<Index, double>> column;
    for (Index t = 0; t < c.n_cols; ++t)
      {
        column.clear();
        for (Index k = c.column_start[t]; k < c.column_start[t + 1]; ++k)
          {
            if (!std::isfinite(c.values[k]))
              throw MatrixError("C(" + std::to_string(c.row_index[k]) + "," + std::to_string(t) + ") = " +
                                format_number(c.values[k]) + " is not finite");
            column.emplace_back(inverse_permutation[c.row_index[k]], c.values[k]);
          }
        std::sort(column.begin(), column.end());
        for (const auto &[row, value] : column)
          {
            permuted.row_index.push_back(row);
            permuted.values.push_back(value);
          }
        permuted.column_start[t + 1] = static_cast<Index>(permuted.row_index.size());
      }
    check_modification_pattern(supernodal_structure, permuted, fill_reducing_permutation);
    // A failed downdate leaves its paths' columns holding no factor. Where the copy of A
    // holds the factored matrix, they are recomputed from it, which costs nothing unless it
    // fails; otherwise the downdate keeps a copy of what it changes, which doubles the
    // memory traffic of a downdate of low rank.
    ModificationSettings settings = modification_settings();
    settings.restore_on_failure   = !matrix_holds_factored;
    const ModificationPlan plan   = plan_modification(supernodal_structure, permuted);
    mark_factor_changed();
    try
      {
        const ModificationResult result =
          supernodal_factor.modify(supernodal_structure, permuted, plan, signs, settings);
        stats.flops_recomputed      = result.flops;
        stats.columns_recomputed    = result.columns;
        stats.supernodes_recomputed = result.supernodes;
      }
    catch (const NotPositiveDefinite &failure)
      {
        if (!settings.restore_on_failure)
          run_numeric(plan_refresh(modified_columns(supernodal_structure, plan), Refresh::all));
        const Index column = fill_reducing_permutation[failure.column];
        throw NotPositiveDefinite(column, failure.pivot,
                                  "the downdate would leave the matrix not positive definite: the pivot of column " +
                                    std::to_string(column) + " would be " + format_number(failure.pivot) +
                                    " (the factor stays that of the matrix before)");
      }
    if (!permuted_matrix.add_low_rank(permuted, signs))
      matrix_holds_factored = false;
    stats.method = RefactorizationMethod::update;
    ++stats.n_updates;
    stats.refactorize_seconds = stopwatch.seconds();
    refactorization_costs.record(RefactorizationMethod::update, stats.flops_recomputed, stats.refactorize_seconds,
                                 static_cast<unsigned int>(c.n_cols));
  }

  double SparseCholesky::predicted_seconds(const std::vector<Index> &changed_columns, const Refresh refresh,
                                           RefactorizationMethod *method) const
  {
    RefactorizationMethod ignored = RefactorizationMethod::none;
    if (method == nullptr)
      method = &ignored;
    require(State::analyzed, "predicted_seconds()");
    check_request(changed_columns, refresh);
    const std::vector<Index> changes = pending_with(changed_columns);
    const RefreshPlan        plan    = plan_refresh(changes, refresh);
    *method                = recompute_method(plan);
    const double recompute = predicted_recompute_seconds(plan);
    if (!may_update(refresh, plan))
      return recompute;
    // The values are not loaded yet: the changed columns stand for the rows they touch,
    // each the first row of a column of C.
    const Index touched = static_cast<Index>(changes.size());
    if (!may_weigh_update(touched))
      return recompute;
    const UpdateWeighing weighing = weigh_update(touched, plan_modification(supernodal_structure, changes), plan);
    if (!weighing.update)
      return recompute;
    *method = RefactorizationMethod::update;
    return weighing.update_seconds;
  }

  double SparseCholesky::predicted_flops(const std::vector<Index> &changed_columns, const Refresh refresh) const
  {
    require(State::analyzed, "predicted_flops()");
    check_request(changed_columns, refresh);
    return plan_refresh(pending_with(changed_columns), refresh).flops;
  }

  bool SparseCholesky::factor_is_exact() const
  {
    return factor_valid && pending_columns.empty() && stale_columns.empty();
  }

  void SparseCholesky::save_numeric(BinaryWriter &writer) const
  {
    writer.write(stats.n);
    writer.write(stats.nnz_l);
    writer.write(factor_valid);
    permuted_matrix.save(writer);
    writer.write(l_values);
    if (solver_settings.method == FactorizationMethod::supernodal)
      supernodal_factor.save(writer);
    writer.write(pending_columns);
    writer.write(stale_columns);
    writer.write(last_recomputed_columns);
    writer.write(stats.n_factorizations);
    writer.write(stats.n_refactorizations);
    writer.write(matrix_holds_factored);
    refactorization_costs.save(writer);
  }

  void SparseCholesky::load_numeric(BinaryReader &reader)
  {
    require(State::analyzed, "load_numeric()");
    mark_factor_changed();
    const auto n     = reader.get<Index>();
    const auto nnz_l = reader.get<Index>();
    if (n != stats.n || nnz_l != stats.nnz_l)
      reader.fail("the factor was written for n = " + std::to_string(n) + ", nnz(L) = " +
                  std::to_string(nnz_l) + ", this analysis has n = " + std::to_string(stats.n) +
                  ", nnz(L) = " + std::to_string(stats.nnz_l));
    factor_valid = reader.get<bool>();
    permuted_matrix.load(reader);
    // L's values, if the writer had factorized (the supernodal method keeps its own).
    const std::size_t expected_l_values =
      solver_settings.method == FactorizationMethod::supernodal ? 0 : symbolic_factorization.nnz_l();
    reader.read(l_values);
    if (l_values.size() != expected_l_values && !(l_values.empty() && !factor_valid))
      reader.fail("the factor holds " + std::to_string(l_values.size()) + " values, this analysis " +
                  std::to_string(expected_l_values));
    if (solver_settings.method == FactorizationMethod::supernodal)
      supernodal_factor.load(reader, supernodal_structure);
    if (factor_valid && numeric_bytes() == 0)
      reader.fail("the factor is said to be valid but holds no values");
    reader.read(pending_columns);
    reader.read(stale_columns);
    reader.read(last_recomputed_columns);
    for (const auto *columns : {&pending_columns, &stale_columns, &last_recomputed_columns})
      for (const Index column : *columns)
        if (column < 0 || column >= stats.n)
          reader.fail("a column " + std::to_string(column) + " is out of range");
    reader.read(stats.n_factorizations);
    reader.read(stats.n_refactorizations);
    reader.read(matrix_holds_factored);
    refactorization_costs.load(reader);
    record_backlog();
  }

  void SparseCholesky::record_backlog()
  {
    stats.pending_columns = static_cast<Index>(pending_columns.size());
    stats.stale_supernodes = 0;
    stats.stale_flops      = 0;
    if (!stale_columns.empty())
      {
        const DirtySupernodes stale = dirty_supernodes(supernodal_structure, stale_columns);
        stats.stale_supernodes      = static_cast<Index>(stale.supernodes.size());
        stats.stale_flops           = stale.flops;
      }
  }

  void SparseCholesky::solve(const std::vector<double> &b, std::vector<double> &x) const
  {
    require(State::factorized, "solve()");
    if (static_cast<Index>(b.size()) != stats.n)
      throw InputError("right-hand side has " + std::to_string(b.size()) + " entries, expected " +
                       std::to_string(stats.n));
    x.resize(b.size());
    solve(b.data(), x.data(), 1);
  }

  void SparseCholesky::solve(const double *b, double *x, const Index n_rhs) const
  {
    solve_in(b, x, n_rhs, false);
  }

  void SparseCholesky::apply_preconditioner(const double *b, double *x) const
  {
    solve_in(b, x, 1, solver_settings.method == FactorizationMethod::supernodal);
  }

  void SparseCholesky::prepare_preconditioner()
  {
    if (factor_valid && solver_settings.method == FactorizationMethod::supernodal)
      supernodal_factor.round_copy(supernodal_structure);
  }

  void SparseCholesky::solve_in(const double *b, double *x, const Index n_rhs, const bool preconditioner) const
  {
    require(State::factorized, preconditioner ? "apply_preconditioner()" : "solve()");
    const Index         n = stats.n;
    std::vector<double> y(n * n_rhs);
    for (Index r = 0; r < n_rhs; ++r)
      for (Index k = 0; k < n; ++k)
        y[r * n + k] = b[r * n + fill_reducing_permutation[k]];
    if (preconditioner)
      supernodal_factor.solve_preconditioner(supernodal_structure, y.data(), solver_settings.n_threads);
    else if (solver_settings.method == FactorizationMethod::supernodal)
      supernodal_factor.solve(supernodal_structure, y.data(), n_rhs, solver_settings.n_threads);
    else
      solve_simplicial(symbolic_factorization, l_values, y.data(), n_rhs);
    for (Index r = 0; r < n_rhs; ++r)
      for (Index k = 0; k < n; ++k)
        x[r * n + fill_reducing_permutation[k]] = y[r * n + k];
  }

  std::vector<double> SparseCholesky::compliance(const sparse::CSCMatrix &ht, const ComplianceMethod method,
                                                 ComplianceStatistics *statistics) const
  {
    require(State::factorized, "compliance()");
    if (solver_settings.method != FactorizationMethod::supernodal)
      throw InputError("compliance() needs the supernodal method, not " + to_string(solver_settings.method));
    if (ht.n_rows != stats.n)
      throw InputError("compliance(): the constraints have " + std::to_string(ht.n_rows) + " rows, A " +
                       std::to_string(stats.n));
    // H^T's rows in the factor's numbering, sorted within each column.
    sparse::CSCMatrix permuted = sparse::CSCMatrix::zero(ht.n_rows, ht.n_cols);
    std::vector<std::pair<Index, double>> column;
    for (Index i = 0; i < ht.n_cols; ++i)
      {
        column.clear();
        for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
          column.emplace_back(inverse_permutation[ht.row_index[p]], ht.values[p]);
        std::sort(column.begin(), column.end());
        for (const auto &[row, value] : column)
          {
            permuted.row_index.push_back(row);
            permuted.values.push_back(value);
          }
        permuted.column_start[i + 1] = static_cast<Index>(permuted.row_index.size());
      }
    const std::vector<double> &values = supernodal_factor.values();
    if (method == ComplianceMethod::full_solves)
      {
        if (statistics)
          {
            const double m       = static_cast<double>(ht.n_cols);
            statistics->supernodes_visited = supernodal_structure.n_supernodes();
            statistics->flops    = 2. * m * static_cast<double>(supernodal_structure.n_stored_values()) +
                                m * (m + 1) * static_cast<double>(stats.n);
          }
        return compliance_by_full_solves(supernodal_structure, values, permuted);
      }
    PathForwardSolve    paths = forward_solve_on_paths(supernodal_structure, values, permuted);
    std::vector<double> w     = compliance_from_paths(supernodal_structure, paths);
    if (statistics)
      {
        statistics->supernodes_visited = static_cast<Index>(paths.supernodes.size());
        statistics->flops              = paths.solve_flops + paths.product_flops;
      }
    return w;
  }

  void SparseCholesky::inverse_block(const std::vector<Index> &unknowns, KeptInverseColumns &columns) const
  {
    require(State::factorized, "inverse_block()");
    if (solver_settings.method != FactorizationMethod::supernodal)
      throw InputError("inverse_block() needs the supernodal method, not " + to_string(solver_settings.method));
    std::vector<Index> rows(unknowns.size());
    for (std::size_t i = 0; i < unknowns.size(); ++i)
      {
        if (unknowns[i] < 0 || unknowns[i] >= stats.n)
          throw InputError("inverse_block(): unknown " + std::to_string(unknowns[i]) + " is not in [0, " +
                           std::to_string(stats.n) + ")");
        rows[i] = inverse_permutation[unknowns[i]];
      }
    update_inverse_columns(supernodal_structure, supernodal_factor.values(), revision, rows, columns);
  }

  std::uint64_t SparseCholesky::factor_revision() const
  {
    return revision;
  }

  void SparseCholesky::mark_factor_changed()
  {
    // One counter for the process: a copy that factors on a thread of its own (the
    // background refresh) never takes a revision that another solver holds.
    static std::atomic<std::uint64_t> last_revision{0};
    revision = ++last_revision;
  }

  std::size_t SparseCholesky::numeric_bytes() const
  {
    return l_values.capacity() * sizeof(double) + supernodal_factor.memory_bytes();
  }

  sparse::CSCMatrix SparseCholesky::factor() const
  {
    if (numeric_bytes() == 0)
      throw Error("factor() called before factorize()");
    if (solver_settings.method == FactorizationMethod::supernodal)
      return supernodal_factor.to_csc(supernodal_structure);
    sparse::CSCMatrix l;
    l.n_rows       = stats.n;
    l.n_cols       = stats.n;
    l.storage      = sparse::Storage::full; // triangular, not symmetric: every entry stored
    l.column_start = symbolic_factorization.column_start;
    l.row_index    = symbolic_factorization.row_index;
    l.values       = l_values;
    return l;
  }

  const std::vector<Index> &SparseCholesky::permutation() const
  {
    return fill_reducing_permutation;
  }

  const SymbolicFactorization &SparseCholesky::symbolic() const
  {
    return symbolic_factorization;
  }

  const SupernodalSymbolic &SparseCholesky::supernodal_symbolic() const
  {
    return supernodal_structure;
  }

  const std::vector<Index> &SparseCholesky::elimination_tree() const
  {
    return solver_settings.method == FactorizationMethod::supernodal ? supernodal_structure.parent :
                                                                        symbolic_factorization.parent;
  }

  const std::vector<Index> &SparseCholesky::recomputed_columns() const
  {
    return last_recomputed_columns;
  }

  const std::vector<bool> &SparseCholesky::top_supernodes() const
  {
    return top_supernode;
  }

  const SparseCholesky::Statistics &SparseCholesky::statistics() const
  {
    return stats;
  }

  const SparseCholesky::Settings &SparseCholesky::settings() const
  {
    return solver_settings;
  }

  void SparseCholesky::set_change_method(const ChangeMethod method)
  {
    solver_settings.change_method = method;
    refactorization_costs         = RefactorizationCostModel(method == ChangeMethod::by_flops);
  }

  const RefactorizationCostModel &SparseCholesky::cost_model() const
  {
    return refactorization_costs;
  }

  void SparseCholesky::set_thread_count(const unsigned int n_threads)
  {
    solver_settings.n_threads = std::max(1u, n_threads);
  }
} // namespace warpchol::cholesky
