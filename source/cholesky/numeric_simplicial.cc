#include <warpchol/base/exceptions.h>
#include <warpchol/cholesky/numeric_simplicial.h>
#include <warpchol/sparse/conversions.h>

#include <cmath>

namespace warpchol::cholesky
{
  namespace
  {
    /** The pivot must be positive and finite (a NaN pivot fails the test as well). */
    void check_pivot(const Index column, const double pivot)
    {
      if (!(pivot > 0.) || !std::isfinite(pivot))
        throw NotPositiveDefinite(column, pivot);
    }
  } // namespace

  double left_looking_column_flops(const SymbolicFactorization &symbolic, const Index j)
  {
    // cdiv(j): the square root and the divisions.
    double flops = static_cast<double>(symbolic.column_start[j + 1] - symbolic.column_start[j]);
    for (Index p = symbolic.row_start[j]; p < symbolic.row_start[j + 1]; ++p)
      {
        // cmod(j,k): a multiply-add for each entry of column k at or below row j.
        const Index k = symbolic.row_column[p];
        flops += 2. * static_cast<double>(symbolic.column_start[k + 1] - symbolic.row_entry[p]);
      }
    return flops;
  }

  double factorize_left_looking(const SymbolicFactorization &symbolic,
                                const sparse::CSCMatrix     &lower,
                                const std::vector<Index>    &columns,
                                std::vector<double>         &l_values)
  {
    const Index n = symbolic.n;
    l_values.resize(symbolic.nnz_l());
    const Index n_columns = columns.empty() ? n : static_cast<Index>(columns.size());

    // Dense accumulator for the current column, zero outside the column being built.
    std::vector<double> work(n, 0.);
    double              flops = 0;
    for (Index c = 0; c < n_columns; ++c)
      {
        const Index j = columns.empty() ? c : columns[c];
        // c = C(j:n, j)
        for (Index p = lower.column_start[j]; p < lower.column_start[j + 1]; ++p)
          work[lower.row_index[p]] = lower.values[p];
        // c -= L(j:n,k) L(j,k) for every k with L(j,k) != 0: the row structure of row j.
        for (Index p = symbolic.row_start[j]; p < symbolic.row_start[j + 1]; ++p)
          {
            const Index  k      = symbolic.row_column[p];
            const Index  first  = symbolic.row_entry[p]; // position of L(j,k)
            const Index  last   = symbolic.column_start[k + 1];
            const double l_jk   = l_values[first];
            const Index *rows   = symbolic.row_index.data();
            const double *l_k   = l_values.data();
            for (Index q = first; q < last; ++q)
              work[rows[q]] -= l_k[q] * l_jk;
            flops += 2. * static_cast<double>(last - first);
          }
        // cdiv(j): the pivot, then the column below it; the accumulator is cleared.
        const Index  begin = symbolic.column_start[j], end = symbolic.column_start[j + 1];
        const double pivot = work[j];
        work[j]            = 0.;
        check_pivot(j, pivot);
        const double l_jj = std::sqrt(pivot);
        l_values[begin]   = l_jj;
        for (Index q = begin + 1; q < end; ++q)
          {
            const Index i = symbolic.row_index[q];
            l_values[q]   = work[i] / l_jj;
            work[i]       = 0.;
          }
        flops += static_cast<double>(end - begin);
      }
    return flops;
  }

  void factorize_up_looking(const SymbolicFactorization &symbolic,
                            const sparse::CSCMatrix     &lower,
                            std::vector<double>         &l_values)
  {
    const Index n = symbolic.n;
    l_values.assign(symbolic.nnz_l(), 0.);
    const sparse::CSCMatrix upper = sparse::upper_triangle(lower);

    std::vector<double> work(n, 0.);
    std::vector<Index>  next_free(symbolic.column_start.begin(), symbolic.column_start.end() - 1);
    std::vector<Index>  mark(n, -1), stack(n), path(n);
    for (Index k = 0; k < n; ++k)
      {
        // Pattern of row k of L (cs_ereach): the union of the tree paths from each i with
        // C(i,k) != 0 up to k, in topological order (descendants before ancestors).
        Index top = n;
        mark[k]   = k;
        double diagonal = 0.;
        for (Index p = upper.column_start[k]; p < upper.column_start[k + 1]; ++p)
          {
            Index i = upper.row_index[p];
            if (i == k)
              {
                diagonal = upper.values[p];
                continue;
              }
            work[i]           = upper.values[p];
            Index path_length = 0;
            for (; mark[i] != k; i = symbolic.parent[i])
              {
                path[path_length++] = i;
                mark[i]             = k;
              }
            while (path_length > 0)
              stack[--top] = path[--path_length];
          }
        // Sparse triangular solve L(0:k-1,0:k-1) x = C(0:k-1,k), one column of L at a time.
        for (; top < n; ++top)
          {
            const Index  i    = stack[top];
            const Index  diag = symbolic.column_start[i];
            const double l_ki = work[i] / l_values[diag];
            work[i]           = 0.;
            for (Index q = diag + 1; q < next_free[i]; ++q)
              work[symbolic.row_index[q]] -= l_values[q] * l_ki;
            diagonal -= l_ki * l_ki;
            const Index position = next_free[i]++;
            if (symbolic.row_index[position] != k)
              throw Error("up-looking factorization: structure mismatch in column " +
                          std::to_string(i));
            l_values[position] = l_ki;
          }
        check_pivot(k, diagonal);
        l_values[next_free[k]++] = std::sqrt(diagonal);
      }
  }
} // namespace warpchol::cholesky
