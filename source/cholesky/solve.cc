#include <warpchol/cholesky/solve.h>

namespace warpchol::cholesky
{
  void solve_simplicial(const SymbolicFactorization &symbolic,
                        const std::vector<double>   &l_values,
                        double                      *y,
                        const Index                  n_rhs)
  {
    const Index   n    = symbolic.n;
    const Index  *rows = symbolic.row_index.data();
    const double *l    = l_values.data();
    for (Index r = 0; r < n_rhs; ++r)
      {
        double *x = y + r * n;
        // L z = y, column by column.
        for (Index j = 0; j < n; ++j)
          {
            const Index begin = symbolic.column_start[j], end = symbolic.column_start[j + 1];
            const double x_j  = x[j] / l[begin];
            x[j]              = x_j;
            for (Index q = begin + 1; q < end; ++q)
              x[rows[q]] -= l[q] * x_j;
          }
        // L^T x = z, columns in reverse.
        for (Index j = n - 1; j >= 0; --j)
          {
            const Index begin = symbolic.column_start[j], end = symbolic.column_start[j + 1];
            double      sum   = x[j];
            for (Index q = begin + 1; q < end; ++q)
              sum -= l[q] * x[rows[q]];
            x[j] = sum / l[begin];
          }
      }
  }
} // namespace warpchol::cholesky
