// The extension module warpchol._warpchol, which the package warpchol (src/warpchol)
// re-exports: cholesky::SparseCholesky on SciPy sparse matrices (CSC or CSR; both
// triangles of a symmetric matrix stored, or one) and NumPy arrays.
//
//   solver = warpchol.SparseCholesky()          # supernodal, METIS
//   solver.analyze(A); solver.factorize(A)      # or solver.factorize(A) alone
//   x = solver.solve(b)                         # or solver(b)
//   solver.refactorize(A, changed_columns)      # A: the analyzed pattern (or part of it), new values
//   solver.update(C); solver.downdate(C)        # the factor of A + C C^T, of A - C C^T
//   solver.inverse_operator()                   # A^-1 as a SciPy LinearOperator
//
// The matrix's arrays are read where SciPy keeps them: at analyze() its pattern becomes
// the solver's CSC form; afterwards each call compares the pattern with the analyzed one
// (memcmp) and the solver reads the values from SciPy's array, without a copy, where their
// order is the solver's (SciPy's indices sorted and no triangle to swap, the common case;
// else they are copied once, into the CSC form). A pattern that is a subset of the
// analyzed one (arithmetic drops explicit zeros) has its values placed in the analyzed
// order first, zeros where it has no entry. Solves write into a new array, without a copy
// of the right-hand side when it is float64 and contiguous (column-major for several).

#include <warpchol/base/exceptions.h>
#include <warpchol/base/stopwatch.h>
#include <warpchol/cholesky/blas.h>
#include <warpchol/cholesky/ordering.h>
#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/cholesky/statistics_fields.h>
#include <warpchol/sparse/csc_matrix.h>
#include <warpchol/sparse/pattern_subset.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace py = pybind11;

namespace warpchol::python
{
  namespace
  {
    /**
     * The arrays of a SciPy matrix in CSC or CSR format. Read as CSC, a CSR matrix's arrays
     * are those of its transpose: for a symmetric matrix the matrix itself, for one stored
     * triangle the other triangle.
     */
    struct SciPyArrays
    {
      std::string format;
      Index       n_rows = 0;
      Index       n_cols = 0;
      py::array   indptr;
      py::array   indices;
      py::array   data;
    };

    SciPyArrays arrays_of(const py::object &matrix)
    {
      const auto not_csc_or_csr = [&](const std::string &what) {
        return py::type_error("warpchol: expected a SciPy sparse matrix in CSC or CSR format, got " + what);
      };
      if (!py::hasattr(matrix, "format"))
        throw not_csc_or_csr(py::str(py::type::of(matrix).attr("__name__")));
      SciPyArrays arrays;
      arrays.format = py::str(matrix.attr("format"));
      if (arrays.format != "csc" && arrays.format != "csr")
        throw not_csc_or_csr("one in " + arrays.format + " format (convert it with .tocsc())");
      for (const char *attribute : {"shape", "indptr", "indices", "data"})
        if (!py::hasattr(matrix, attribute))
          throw not_csc_or_csr("an object without " + std::string(attribute));
      const auto shape = matrix.attr("shape").cast<std::pair<Index, Index>>();
      arrays.n_rows    = shape.first;
      arrays.n_cols    = shape.second;
      arrays.indptr    = py::array::ensure(matrix.attr("indptr"), py::array::c_style);
      arrays.indices   = py::array::ensure(matrix.attr("indices"), py::array::c_style);
      arrays.data      = matrix.attr("data");
      return arrays;
    }

    /** Call @p visit with the data of the integer array @p array (int32 or int64, as SciPy uses). */
    template <typename Visit>
    decltype(auto) visit_indices(const py::array &array, const Visit &visit)
    {
      if (array.ndim() == 1 && py::isinstance<py::array_t<std::int32_t>>(array))
        return visit(static_cast<const std::int32_t *>(array.data()));
      if (array.ndim() == 1 && py::isinstance<py::array_t<std::int64_t>>(array))
        return visit(static_cast<const std::int64_t *>(array.data()));
      throw py::type_error("warpchol: the matrix's index arrays are " +
                           std::string(py::str(array.dtype())) + ", expected int32 or int64");
    }

    /** Whether the index arrays @p a and @p b hold the same values (each int32 or int64). */
    bool same_indices(const py::array &a, const py::array &b)
    {
      if (a.size() != b.size())
        return false;
      if (a.itemsize() == b.itemsize())
        return std::memcmp(a.data(), b.data(), a.nbytes()) == 0;
      return visit_indices(a, [&](const auto *a_values) {
        return visit_indices(b, [&](const auto *b_values) { return std::equal(a_values, a_values + a.size(), b_values); });
      });
    }

    /** The stored values as float64 (a copy only if they are another type). */
    py::array_t<double, py::array::c_style> float64_values(const py::array &data)
    {
      if (data.dtype().kind() == 'c')
        throw py::type_error("warpchol: the matrix is complex; SparseCholesky factors real matrices");
      return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(data);
    }

    /** The values of an index array (int32 or int64) as Index. */
    std::vector<Index> index_vector(const py::array &array)
    {
      return visit_indices(array, [&](const auto *values) { return std::vector<Index>(values, values + array.size()); });
    }
  } // namespace

  /**
   * cholesky::SparseCholesky on SciPy matrices: the pattern given to analyze() (in the
   * user's storage), the solver's CSC form of it, and where each stored value goes there.
   */
  class SciPyCholesky
  {
    using State = cholesky::SparseCholesky::State;

  public:
    SciPyCholesky(const std::string &method, const std::string &ordering, const unsigned int n_threads,
                  const std::string &change_method)
      : solver(settings(method, ordering, n_threads, change_method))
    {}

    /** Ordering and symbolic analysis of the pattern of @p matrix. */
    void analyze(const py::object &matrix)
    {
      read_pattern(arrays_of(matrix));
      const py::gil_scoped_release unlocked;
      solver.analyze(csc);
    }

    /** Numeric factorization of @p matrix (analyzed first if nothing is, as the solver does). */
    void factorize(const py::object &matrix)
    {
      if (solver.state() == State::empty)
        analyze(matrix);
      const Values                 values = values_of(matrix);
      const py::gil_scoped_release unlocked;
      name_non_finite(values, [&] { solver.factorize(csc, values.data); });
    }

    /**
     * Partial refactorization after the entries of @p changed_columns changed (analyzed first
     * if nothing is); @p complete: nothing else changed (cholesky::ChangeListing::complete).
     */
    void refactorize(const py::object &matrix, const py::object &changed_columns, const bool complete)
    {
      if (solver.state() == State::empty)
        analyze(matrix);
      const auto columns = py::array_t<Index, py::array::c_style | py::array::forcecast>::ensure(changed_columns);
      if (!columns || columns.ndim() != 1)
        throw py::type_error("warpchol: changed_columns must be a sequence of column indices");
      const std::vector<Index>     changed(columns.data(), columns.data() + columns.size());
      const Values                 values = values_of(matrix);
      const py::gil_scoped_release unlocked;
      const auto listing = complete ? cholesky::ChangeListing::complete : cholesky::ChangeListing::searched;
      name_non_finite(values,
                      [&] { solver.refactorize(csc, values.data, changed, cholesky::Refresh::all, listing); });
    }

    /**
     * The factor of A + @p sign C C^T in place: @p c any SciPy sparse matrix (n x k),
     * converted to CSC with its duplicates summed and its stored zeros left out.
     */
    void modify(const py::object &c, const double sign)
    {
      const py::module_ scipy_sparse = py::module_::import("scipy.sparse");
      if (!scipy_sparse.attr("issparse")(c).cast<bool>())
        throw py::type_error("warpchol: expected C as a SciPy sparse matrix (n x k), got " +
                             std::string(py::str(py::type::of(c).attr("__name__"))));
      // A copy: tocsc() of a CSC matrix is the matrix itself, which sum_duplicates() would sort.
      const py::object csc = c.attr("tocsc")(py::arg("copy") = true);
      csc.attr("sum_duplicates")();
      csc.attr("eliminate_zeros")();
      const SciPyArrays arrays = arrays_of(csc);
      sparse::CSCMatrix columns = sparse::CSCMatrix::zero(arrays.n_rows, arrays.n_cols);
      const Index       nnz     = arrays.indices.size();
      columns.row_index.resize(nnz);
      visit_indices(arrays.indptr, [&](const auto *values) {
        std::copy(values, values + arrays.n_cols + 1, columns.column_start.begin());
      });
      visit_indices(arrays.indices, [&](const auto *values) { std::copy(values, values + nnz, columns.row_index.begin()); });
      const auto values = float64_values(arrays.data);
      columns.values.assign(values.data(), values.data() + values.size());
      const py::gil_scoped_release unlocked;
      if (sign > 0)
        solver.update(columns);
      else
        solver.downdate(columns);
    }

    /** x with A x = b, for b of shape (n,) or (n, k). */
    py::array solve(const py::array &b)
    {
      solver.require(State::factorized, "solve()");
      const Index n = solver.statistics().n;
      if (b.ndim() == 1 || b.ndim() == 2)
        if (b.shape(0) == n)
          {
            const Index n_rhs = b.ndim() == 2 ? b.shape(1) : 1;
            // Several right-hand sides column by column, as the solver takes them.
            const auto rhs = py::array_t<double, py::array::f_style | py::array::forcecast>::ensure(b);
            py::array_t<double, py::array::f_style> x(b.ndim() == 2 ? std::vector<py::ssize_t>{n, n_rhs} :
                                                                       std::vector<py::ssize_t>{n});
            const double *rhs_values = rhs.data();
            double       *x_values   = x.mutable_data();
            double                       seconds = 0;
            {
              const py::gil_scoped_release unlocked;
              const Stopwatch              stopwatch;
              solver.solve(rhs_values, x_values, n_rhs);
              seconds = stopwatch.seconds();
            }
            // Timed here: the solver's solve() is const and writes nothing. With the GIL
            // held again, Python's threads write this one at a time.
            last_solve_seconds = seconds;
            return std::move(x);
          }
      std::string shape;
      for (py::ssize_t d = 0; d < b.ndim(); ++d)
        shape += (d > 0 ? ", " : "") + std::to_string(b.shape(d));
      throw py::value_error("warpchol: the right-hand side has shape (" + shape + "), expected (" +
                            std::to_string(n) + ",) or (" + std::to_string(n) + ", k)");
    }

    const cholesky::SparseCholesky::Statistics &statistics() const
    {
      return solver.statistics();
    }

    /** Seconds of the last solve(), timed by this wrapper. */
    double solve_seconds() const
    {
      return last_solve_seconds;
    }

    /** "empty", "analyzed" or "factorized": the solver's state (SparseCholesky::State). */
    std::string state() const
    {
      return name_of(cholesky::SparseCholesky::state_names, solver.state());
    }

    std::string storage() const
    {
      return csc.storage == sparse::Storage::full ? "full" : "lower";
    }

  private:
    static cholesky::SparseCholesky::Settings settings(const std::string &method, const std::string &ordering,
                                                       const unsigned int n_threads, const std::string &change_method)
    {
      cholesky::SparseCholesky::Settings settings;
      settings.method          = cholesky::parse_factorization_method(method);
      settings.ordering.method = cholesky::parse_ordering_method(ordering);
      settings.n_threads       = std::max(1u, n_threads);
      settings.change_method   = cholesky::parse_change_method(change_method);
      return settings;
    }

    /**
     * Keep the pattern of @p arrays and build the solver's CSC form of it: the arrays as
     * they are where their indices are sorted and unique and the stored triangle (if one)
     * is the lower one; otherwise sorted, or transposed from the upper triangle, with
     * the place of each value recorded.
     */
    void read_pattern(const SciPyArrays &arrays)
    {
      if (arrays.n_rows != arrays.n_cols)
        throw MatrixError("matrix is not square: " + std::to_string(arrays.n_rows) + "x" +
                          std::to_string(arrays.n_cols));
      const Index n = arrays.n_cols, nnz = arrays.indices.size();
      if (arrays.indptr.size() != n + 1)
        throw MatrixError("the matrix's indptr has " + std::to_string(arrays.indptr.size()) + " entries, expected " +
                          std::to_string(n + 1));
      // The pattern as the solver takes it, unless it has to be sorted or transposed below.
      std::vector<Index> &column_start = csc.column_start, &row_index = csc.row_index;
      column_start.resize(n + 1);
      row_index.resize(nnz);
      visit_indices(arrays.indptr, [&](const auto *values) { std::copy(values, values + n + 1, column_start.begin()); });
      visit_indices(arrays.indices, [&](const auto *values) { std::copy(values, values + nnz, row_index.begin()); });
      if (column_start[0] != 0 || column_start[n] != nnz)
        throw MatrixError("the matrix's indptr runs from " + std::to_string(column_start[0]) + " to " +
                          std::to_string(column_start[n]) + ", expected 0 to " + std::to_string(nnz));

      bool  sorted = true;
      Index n_above = 0, n_below = 0;
      for (Index j = 0; j < n; ++j)
        {
          if (column_start[j + 1] < column_start[j])
            throw MatrixError("the matrix's indptr decreases at " + std::to_string(j + 1));
          for (Index k = column_start[j]; k < column_start[j + 1]; ++k)
            {
              const Index i = row_index[k];
              if (i < 0 || i >= n)
                throw MatrixError("the matrix has an index " + std::to_string(i) + " out of range [0, " +
                                  std::to_string(n) + ")");
              if (k > column_start[j] && i <= row_index[k - 1])
                sorted = false;
              n_above += i < j;
              n_below += i > j;
            }
        }
      // One triangle stored, upper as read (a lower triangle in CSR, an upper one in CSC):
      // its transpose is the lower triangle.
      const bool transpose = n_below == 0 && n_above > 0;
      csc.n_rows = csc.n_cols = n;
      csc.storage             = n_above > 0 && n_below > 0 ? sparse::Storage::full : sparse::Storage::lower;
      csc.values.assign(nnz, 0.);
      // Copies of the user's index arrays as they are, which later matrices' are compared with
      // (and a subset's entries placed among).
      analyzed_indptr  = arrays.indptr.attr("copy")();
      analyzed_indices = arrays.indices.attr("copy")();
      analyzed_start   = column_start;
      analyzed_rows    = row_index;
      source.clear();
      if (sorted && !transpose)
        return;

      // Bucket the entries by their column in the solver's form (a counting sort), then sort
      // each column's rows, carrying the entries' places in the user's arrays along.
      const std::vector<Index> input_start = std::move(column_start), input_row = std::move(row_index);
      column_start.assign(n + 1, 0);
      for (Index j = 0; j < n; ++j)
        for (Index k = input_start[j]; k < input_start[j + 1]; ++k)
          ++column_start[(transpose ? input_row[k] : j) + 1];
      std::partial_sum(column_start.begin(), column_start.end(), column_start.begin());
      std::vector<std::pair<Index, Index>> entries(nnz); // (row, place in the user's arrays)
      std::vector<Index>                   next(column_start.begin(), column_start.end() - 1);
      for (Index j = 0; j < n; ++j)
        for (Index k = input_start[j]; k < input_start[j + 1]; ++k)
          entries[next[transpose ? input_row[k] : j]++] = {transpose ? j : input_row[k], k};
      row_index.resize(nnz);
      source.resize(nnz);
      for (Index j = 0; j < n; ++j)
        {
          std::sort(entries.begin() + column_start[j], entries.begin() + column_start[j + 1]);
          for (Index p = column_start[j]; p < column_start[j + 1]; ++p)
            {
              const auto [i, k] = entries[p];
              if (p > column_start[j] && entries[p - 1].first == i)
                throw MatrixError("the matrix stores entry (" + std::to_string(i) + "," + std::to_string(j) +
                                  ") twice; add the duplicates first (A.sum_duplicates())");
              row_index[p] = i;
              source[p]    = k;
            }
        }
    }

    /**
     * Where a matrix's values are, for the solver: in SciPy's array (kept alive here) or in
     * csc; and in the order of the analyzed user arrays (SciPy's, or subset_values).
     */
    struct Values
    {
      py::array_t<double, py::array::c_style> array;
      const double                           *data       = nullptr;
      const double                           *user_order = nullptr;
      /** Whether the matrix's arrays are a CSR matrix's (entries named (column, row) as read). */
      bool transposed = false;
    };

    /**
     * The values of @p matrix in the order of the solver's CSC form: SciPy's own array where
     * the pattern is the analyzed one in the solver's order (no copy), else copied into the
     * CSC form's. A pattern that is a subset of the analyzed one has its values placed in
     * the analyzed order first, zeros where it has no entry; an entry outside it, NaN or
     * infinity raise MatrixError naming the entry.
     */
    Values values_of(const py::object &matrix)
    {
      const SciPyArrays arrays = arrays_of(matrix);
      const Index       n = csc.n_cols, nnz = csc.n_nonzeros();
      if (arrays.n_rows != n || arrays.n_cols != n)
        throw MatrixError("matrix is " + std::to_string(arrays.n_rows) + "x" + std::to_string(arrays.n_cols) +
                          ", the analyzed one " + std::to_string(n) + "x" + std::to_string(n) +
                          " (analyze the new matrix first)");
      Values values{float64_values(arrays.data)};
      values.transposed = arrays.format == "csr";
      if (values.array.ndim() != 1 || values.array.size() != arrays.indices.size())
        throw MatrixError("the matrix has " + std::to_string(values.array.size()) + " values for " +
                          std::to_string(arrays.indices.size()) + " entries");
      values.data = values.array.data();
      if (!same_indices(arrays.indptr, analyzed_indptr) || !same_indices(arrays.indices, analyzed_indices))
        {
          // Another pattern: a subset of the analyzed one, or refused naming an entry outside.
          if (arrays.indptr.ndim() != 1 || arrays.indptr.size() != n + 1)
            throw MatrixError("the matrix's indptr has " + std::to_string(arrays.indptr.size()) +
                              " entries, expected " + std::to_string(n + 1));
          const std::vector<Index> indptr = index_vector(arrays.indptr), indices = index_vector(arrays.indices);
          const std::vector<Index> places =
            sparse::places_in_pattern(n, analyzed_start.data(), analyzed_rows.data(), indptr.data(), indices.data(),
                                      static_cast<Index>(indices.size()), values.transposed);
          subset_values.assign(nnz, 0.);
          for (std::size_t k = 0; k < places.size(); ++k)
            subset_values[places[k]] = values.data[k];
          values.data = subset_values.data();
        }
      values.user_order = values.data;
      if (!source.empty())
        {
          for (Index p = 0; p < nnz; ++p)
            csc.values[p] = values.data[source[p]];
          values.data = csc.values.data();
        }
      return values;
    }

    /**
     * @p factor(), which loads @p values into the solver; a MatrixError it raises while the
     * values hold a NaN or an infinity is told as that, naming the entry as the user stores
     * it (the solver names it in its own CSC form, which may be the user's transpose).
     */
    template <typename Factor>
    void name_non_finite(const Values &values, const Factor &factor)
    {
      try
        {
          factor();
        }
      catch (const NotPositiveDefinite &)
        {
          throw;
        }
      catch (const MatrixError &)
        {
          const Index nnz = static_cast<Index>(analyzed_rows.size());
          for (Index p = 0; p < nnz; ++p)
            if (!std::isfinite(values.user_order[p]))
              {
                const Index column =
                  std::upper_bound(analyzed_start.begin(), analyzed_start.end(), p) - analyzed_start.begin() - 1;
                const Index row = analyzed_rows[p];
                throw MatrixError(values.transposed ? sparse::non_finite_entry_message(column, row, values.user_order[p]) :
                                                      sparse::non_finite_entry_message(row, column, values.user_order[p]));
              }
          throw;
        }
    }

    cholesky::SparseCholesky solver;
    /** The seconds of the last solve(). */
    double                   last_solve_seconds = 0;
    /**
     * The analyzed pattern as the user's arrays hold it (indptr, indices), read as CSC: CSR
     * arrays too, which for a symmetric matrix describe the same matrix.
     */
    py::array analyzed_indptr;
    py::array analyzed_indices;
    /** The same arrays as Index, as read (CSC; a CSR matrix's read as its transpose). */
    std::vector<Index> analyzed_start;
    std::vector<Index> analyzed_rows;
    /** The values of a matrix whose pattern is a subset of the analyzed one, in the analyzed user order. */
    std::vector<double> subset_values;
    /** The solver's form of the matrix: full storage, or the lower triangle. */
    sparse::CSCMatrix csc;
    /** source[p]: the place in the user's values of csc.values[p]; empty where it is p. */
    std::vector<Index> source;
  };

  /** The statistics property's documentation: each key with its meaning (cholesky::statistics_fields()). */
  const std::string &statistics_documentation()
  {
    static const std::string documentation = [] {
      std::string text = "Sizes, fill, flops and counts of the factorization (see SparseCholesky::Statistics); "
                         "update_rank, update_flops, partial_flops and the predicted seconds: what the last "
                         "refactorize() weighed (0 and -1 where it weighed no update). The keys:";
      for (const auto &field : cholesky::statistics_fields())
        text += std::string("\n- ") + field.name + ": " + field.description;
      return text;
    }();
    return documentation;
  }
} // namespace warpchol::python

// The module's bindings, one .def per function in the order help() lists them: a table that
// reads as the Python interface does (hence its length).
PYBIND11_MODULE(_warpchol, module)
{
  using warpchol::python::SciPyCholesky;
  module.doc() = "The extension module of the package warpchol (import warpchol; help(warpchol)).";
  module.attr("__version__") = WARPCHOL_VERSION;
  // OpenBLAS chose its kernels when it was loaded, before this module: only the
  // environment of the next Python can choose them.
  if (const char *kernels = warpchol::cholesky::blas::kernels_for_this_cpu())
    {
      const std::string warning = "OpenBLAS runs its " + warpchol::cholesky::blas::kernel_name() +
                                  " kernels, without the AVX2 this CPU has (an OpenBLAS older than the "
                                  "CPU); start Python with OPENBLAS_CORETYPE=" +
                                  kernels + " for factorizations several times faster";
      if (PyErr_WarnEx(PyExc_RuntimeWarning, warning.c_str(), 1) != 0)
        throw py::error_already_set();
    }

  // The solver's errors, one line each, as Python exceptions of the same names.
  auto &error = py::register_exception<warpchol::Error>(module, "Error", PyExc_RuntimeError);
  auto &input_error = py::register_exception<warpchol::InputError>(module, "InputError", error.ptr());
  auto &matrix_error = py::register_exception<warpchol::MatrixError>(module, "MatrixError", error.ptr());
  auto &not_positive_definite =
    py::register_exception<warpchol::NotPositiveDefinite>(module, "NotPositiveDefinite", matrix_error.ptr());
  error.doc() = "Base class of warpchol's errors: a one-line message that says what is wrong and where.";
  input_error.doc() = "An argument the solver cannot use: a column out of range, a C whose rows the factor does "
                      "not couple, a call the method does not offer.";
  matrix_error.doc() = "A matrix the solver cannot factor, naming the entry: not square, not symmetric, a NaN or an "
                       "infinity, an entry outside the analyzed pattern.";
  not_positive_definite.doc() = "A matrix that is not positive definite: names the column and its pivot.";

  py::class_<SciPyCholesky> solver_class(module, "SparseCholesky", R"(A sparse Cholesky solver, A = P L L^T P^T, that refactorizes in part.

A is a symmetric positive definite SciPy sparse matrix or array in CSC or CSR format, with
both triangles stored or one. After analyze(A) and factorize(A), refactorize(A,
changed_columns) takes A with new values in the listed columns (and, by symmetry, rows),
and recomputes only the columns of L that depend on them, or updates the factor by the
change where that is cheaper. update(C) and downdate(C) give the factor of A + C C^T and
A - C C^T for a C of few columns, in place.

factorize() and refactorize() take the analyzed pattern or a subset of it: the entries a
matrix leaves out are zeros (SciPy's arithmetic drops explicit zeros, A + D with a
diagonal D for one). An entry outside the analyzed pattern, a NaN or an infinity raise
MatrixError naming the entry.

solve(b), or solver(b), gives x with A x = b; inverse_operator() is A^-1 as a SciPy
LinearOperator (for scipy.sparse.linalg's iterative solvers and eigensolvers).

method: "supernodal" (default), "left" or "up"; ordering: "metis" (default), "amd" or
"natural"; threads: threads of the supernodal factorization and solves; change_method: how
refactorize() takes a change, "auto" (default: the cheaper of an update and a
recomputation, by times measured as it goes), "flops" (the same at fixed rates: the same
choice on any machine), "recompute" (never update) or "update" (whenever possible).)");
  solver_class
    .def(py::init<const std::string &, const std::string &, unsigned int, const std::string &>(),
         py::arg("method") = "supernodal", py::arg("ordering") = "metis", py::arg("threads") = 1,
         py::arg("change_method") = "auto",
         "A solver with the given settings (see the class's documentation); nothing analyzed yet.")
    .def("analyze", &SciPyCholesky::analyze, py::arg("A"),
         "Fill-reducing ordering and symbolic analysis of the pattern of A (its values are not read). Raises "
         "MatrixError for a matrix that is not square, a pattern that is not symmetric (both triangles stored) or "
         "an entry stored twice.")
    .def("factorize", &SciPyCholesky::factorize, py::arg("A"),
         "Numeric factorization of A (analyzing its pattern first if analyze() was not called). A has the analyzed "
         "pattern or a subset of it (the entries it leaves out are zeros). Raises NotPositiveDefinite naming the "
         "column and its pivot, MatrixError naming an entry outside the analyzed pattern, a NaN, an infinity or an "
         "asymmetric pair; the solver then holds no factor until the next factorization.")
    .def("refactorize", &SciPyCholesky::refactorize, py::arg("A"), py::arg("changed_columns"),
         py::arg("complete") = false,
         "Partial refactorization: A has the analyzed pattern (or a subset of it, as factorize() takes) and new "
         "values in changed_columns (and the same rows); a column that changed without being listed is found and "
         "recomputed as well, unless complete=True: the caller vouches that no stored entry outside those columns "
         "changed, and only they are read (for a caller that re-assembled only them). A change of low rank may be "
         "taken as an update of the factor instead, where that is cheaper (statistics[\"method\"]). Raises as "
         "factorize() does, and InputError for a column out of range.")
    .def(
      "update", [](SciPyCholesky &self, const py::object &c) { self.modify(c, 1.); }, py::arg("C"),
      "The factor of A + C C^T, in place, without refactorizing (CHOLMOD's cholmod_updown, scikit-sparse's "
      "update_inplace): C is a SciPy sparse matrix of n rows and k columns in any format (duplicates summed, "
      "stored zeros left out), each column's rows coupled in the factor as the dofs of one element or one vertex "
      "are (InputError names two that are not). Supernodal method, after a factorization; a later refactorize() "
      "starts from A + C C^T.")
    .def(
      "downdate", [](SciPyCholesky &self, const py::object &c) { self.modify(c, -1.); }, py::arg("C"),
      "The factor of A - C C^T, in place, as update() (scikit-sparse's update_inplace(C, subtract=True)). Raises "
      "NotPositiveDefinite if A - C C^T is not positive definite; the factor is then left that of A.")
    .def("solve", &SciPyCholesky::solve, py::arg("b"),
         "x with A x = b, for b of shape (n,) or (n, k) (a new float64 array of b's shape). Raises Error without a "
         "valid factorization, ValueError for b of another shape.")
    .def("__call__", &SciPyCholesky::solve, py::arg("b"), "solve(b), as scikit-sparse's factor(b).")
    .def(
      "inverse_operator",
      [](const py::object &self) {
        const auto  n      = self.attr("n").cast<warpchol::Index>();
        const auto  solve  = self.attr("solve");
        const auto  linalg = py::module_::import("scipy.sparse.linalg");
        // A^-1 is symmetric: its adjoint solves too.
        return linalg.attr("LinearOperator")(py::make_tuple(n, n), py::arg("matvec") = solve,
                                             py::arg("rmatvec") = solve, py::arg("matmat") = solve,
                                             py::arg("rmatmat") = solve, py::arg("dtype") = py::dtype::of<double>());
      },
      "A^-1 as a scipy.sparse.linalg.LinearOperator of shape (n, n), float64: its products are solve()s with the "
      "factor as it is at each product (a later refactorize() or update() is seen). For SciPy's iterative solvers "
      "(a preconditioner M) and eigensolvers (shift-invert).")
    .def_property_readonly(
      "n", [](const SciPyCholesky &self) { return self.statistics().n; },
      "Rows (and columns) of the analyzed matrix; 0 before analyze().")
    .def_property_readonly(
      "shape",
      [](const SciPyCholesky &self) { return py::make_tuple(self.statistics().n, self.statistics().n); },
      "(n, n), the shape of A.")
    .def_property_readonly("storage", &SciPyCholesky::storage,
                           "How the analyzed matrix stores its entries: \"full\" or \"lower\".")
    .def_property_readonly("state", &SciPyCholesky::state,
                           "What the solver holds: \"empty\" (nothing analyzed), \"analyzed\" (a pattern, no "
                           "valid factor: none yet, or the last matrix was refused) or \"factorized\".")
    .def_property_readonly(
      "flops", [](const SciPyCholesky &self) { return self.statistics().flops; },
      "Flops of a full factorization by the chosen method.")
    .def_property_readonly(
      "flops_recomputed", [](const SciPyCholesky &self) { return self.statistics().flops_recomputed; },
      "Flops of the last factorize() or refactorize().")
    .def_property_readonly(
      "columns_recomputed", [](const SciPyCholesky &self) { return self.statistics().columns_recomputed; },
      "Columns of L the last factorize() or refactorize() computed.")
    .def_property_readonly(
      "timings",
      [](const SciPyCholesky &self) {
        const auto &stats = self.statistics();
        py::dict    timings;
        timings["analyze"]     = stats.analyze_seconds;
        timings["factorize"]   = stats.factorize_seconds;
        timings["refactorize"] = stats.refactorize_seconds;
        timings["solve"]       = self.solve_seconds();
        return timings;
      },
      "Seconds of the last call of each kind, inside the solver (the C++ call; solve: around it, since the "
      "solver's solve() is const and records nothing).")
    .def_property_readonly(
      "statistics",
      [](const SciPyCholesky &self) {
        // Every reported field, as cholesky::statistics_fields() lists them.
        py::dict statistics;
        for (const auto &field : warpchol::cholesky::statistics_fields())
          std::visit([&](const auto &value) { statistics[field.name] = value; }, field.value(self.statistics()));
        return statistics;
      },
      warpchol::python::statistics_documentation().c_str());

  // What help() and repr() show: the package's names, not the extension module's.
  for (const char *name : {"Error", "InputError", "MatrixError", "NotPositiveDefinite", "SparseCholesky"})
    module.attr(name).attr("__module__") = "warpchol";
}
