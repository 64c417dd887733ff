#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/numeric_simplicial.h>
#include <warpchol/cholesky/partial.h>
#include <warpchol/cholesky/solve.h>
#include <warpchol/cholesky/sparse_cholesky.h>

#include <algorithm>

namespace warpchol::cholesky
{
  std::string to_string(const FactorizationMethod method)
  {
    return method == FactorizationMethod::left_looking ? "left" : "up";
  }

  FactorizationMethod parse_factorization_method(const std::string &name)
  {
    if (name == "left" || name == "left_looking")
      return FactorizationMethod::left_looking;
    if (name == "up" || name == "up_looking")
      return FactorizationMethod::up_looking;
    throw InputError("unknown factorization method '" + name + "' (expected left or up)");
  }

  double SparseCholesky::Statistics::fill() const
  {
    return nnz_a > 0 ? static_cast<double>(nnz_l) / static_cast<double>(nnz_a) : 0.;
  }

  SparseCholesky::SparseCholesky()
    : SparseCholesky(Settings())
  {}

  SparseCholesky::SparseCholesky(const Settings &settings)
    : solver_settings(settings)
  {}

  void SparseCholesky::analyze(const sparse::CSCMatrix &matrix)
  {
    const Stopwatch stopwatch;
    analyzed     = false;
    factor_valid = false;
    if (matrix.n_rows != matrix.n_cols)
      throw MatrixError("matrix is not square: " + std::to_string(matrix.n_rows) + "x" +
                        std::to_string(matrix.n_cols));
    matrix.check_consistency();

    // Fill-reducing ordering, then a postorder of its elimination tree: the same fill, but
    // every subtree becomes a contiguous range of columns (supernodes, locality).
    const Ordering ordering = compute_ordering(matrix, solver_settings.ordering);
    permuted_matrix.setup(matrix, ordering.permutation);
    const std::vector<Index> postorder = postorder_tree(elimination_tree(permuted_matrix.lower()));
    fill_reducing_permutation = compose_permutations(ordering.permutation, postorder);
    inverse_permutation       = invert_permutation(fill_reducing_permutation);
    permuted_matrix.setup(matrix, fill_reducing_permutation);

    symbolic_factorization = analyze_left_looking(permuted_matrix.lower());
    l_values.assign(symbolic_factorization.nnz_l(), 0.);

    stats                   = Statistics();
    stats.n                 = matrix.n_cols;
    stats.nnz_a             = permuted_matrix.n_nonzeros();
    stats.nnz_l             = symbolic_factorization.nnz_l();
    stats.flops             = symbolic_factorization.flops;
    stats.vertex_block_size = ordering.vertex_block_size;
    stats.factor_bytes      = l_values.size() * sizeof(double) +
                         symbolic_factorization.row_index.size() * sizeof(Index) +
                         symbolic_factorization.column_start.size() * sizeof(Index);
    stats.analyze_seconds = stopwatch.seconds();
    analyzed              = true;
  }

  double SparseCholesky::run_numeric(const std::vector<Index> &columns)
  {
    factor_valid = false;
    try
      {
        double flops = 0;
        if (solver_settings.method == FactorizationMethod::up_looking)
          {
            factorize_up_looking(symbolic_factorization, permuted_matrix.lower(), l_values);
            flops = symbolic_factorization.flops;
          }
        else
          flops = factorize_left_looking(symbolic_factorization, permuted_matrix.lower(), columns,
                                         l_values);
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
    if (!analyzed)
      analyze(matrix);
    const Stopwatch stopwatch;
    permuted_matrix.load(matrix);
    run_numeric({});
    last_recomputed_columns.clear();
    ++stats.n_factorizations;
    stats.factorize_seconds = stopwatch.seconds();
  }

  void SparseCholesky::refactorize(const sparse::CSCMatrix  &matrix,
                                   const std::vector<Index> &changed_columns)
  {
    if (!analyzed)
      throw Error("refactorize() called before analyze()");
    for (const Index column : changed_columns)
      if (column < 0 || column >= stats.n)
        throw InputError("changed column " + std::to_string(column) + " out of range [0, " +
                         std::to_string(stats.n) + ")");
    const Stopwatch    stopwatch;
    std::vector<Index> seeds = permuted_matrix.load(matrix);
    if (!factor_valid || solver_settings.method == FactorizationMethod::up_looking)
      {
        // No factor to update (or a method that cannot update): factor everything.
        run_numeric({});
        last_recomputed_columns.resize(stats.n);
        for (Index j = 0; j < stats.n; ++j)
          last_recomputed_columns[j] = j;
        stats.flops_recomputed  = stats.flops;
        stats.factorize_seconds = stopwatch.seconds();
      }
    else
      {
        for (const Index column : changed_columns)
          seeds.push_back(inverse_permutation[column]);
        last_recomputed_columns = etree_closure(symbolic_factorization.parent, seeds);
        stats.flops_recomputed  = last_recomputed_columns.empty() ? 0. : run_numeric(last_recomputed_columns);
      }
    stats.columns_recomputed  = static_cast<Index>(last_recomputed_columns.size());
    stats.refactorize_seconds = stopwatch.seconds();
    ++stats.n_refactorizations;
  }

  void SparseCholesky::solve(const std::vector<double> &b, std::vector<double> &x) const
  {
    if (!factor_valid)
      throw Error("solve() called without a valid factorization");
    if (static_cast<Index>(b.size()) != stats.n)
      throw InputError("right-hand side has " + std::to_string(b.size()) + " entries, expected " +
                       std::to_string(stats.n));
    x.resize(b.size());
    solve(b.data(), x.data(), 1);
  }

  void SparseCholesky::solve(const double *b, double *x, const Index n_rhs) const
  {
    if (!factor_valid)
      throw Error("solve() called without a valid factorization");
    const Stopwatch     stopwatch;
    const Index         n = stats.n;
    std::vector<double> y(n * n_rhs);
    for (Index r = 0; r < n_rhs; ++r)
      for (Index k = 0; k < n; ++k)
        y[r * n + k] = b[r * n + fill_reducing_permutation[k]];
    solve_simplicial(symbolic_factorization, l_values, y.data(), n_rhs);
    for (Index r = 0; r < n_rhs; ++r)
      for (Index k = 0; k < n; ++k)
        x[r * n + fill_reducing_permutation[k]] = y[r * n + k];
    stats.solve_seconds = stopwatch.seconds();
  }

  sparse::CSCMatrix SparseCholesky::factor() const
  {
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

  const std::vector<Index> &SparseCholesky::recomputed_columns() const
  {
    return last_recomputed_columns;
  }

  const SparseCholesky::Statistics &SparseCholesky::statistics() const
  {
    return stats;
  }

  const SparseCholesky::Settings &SparseCholesky::settings() const
  {
    return solver_settings;
  }
} // namespace warpchol::cholesky
