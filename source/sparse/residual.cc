#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/residual.h>

#include <algorithm>
#include <cmath>

namespace warpchol::sparse
{
  namespace
  {
    std::vector<double> residual_vector(const CSCMatrix &matrix, const std::vector<double> &x,
                                        const std::vector<double> &b)
    {
      std::vector<double> r(matrix.n_rows);
      matrix.vmult(x.data(), r.data());
      for (std::size_t i = 0; i < r.size(); ++i)
        r[i] -= b[i];
      return r;
    }

    double norm_2(const std::vector<double> &v)
    {
      double sum = 0;
      for (const double value : v)
        sum += value * value;
      return std::sqrt(sum);
    }

    double norm_inf(const std::vector<double> &v)
    {
      double largest = 0;
      for (const double value : v)
        largest = std::max(largest, std::abs(value));
      return largest;
    }
  } // namespace

  double relative_residual(const CSCMatrix &matrix, const std::vector<double> &x,
                           const std::vector<double> &b)
  {
    const double r = norm_2(residual_vector(matrix, x, b)), scale = norm_2(b);
    return scale > 0 ? r / scale : r;
  }

  double backward_error(const CSCMatrix &matrix, const std::vector<double> &x,
                        const std::vector<double> &b)
  {
    // ||A||_inf = largest absolute row sum = largest absolute column sum (A symmetric or
    // not, of the full matrix: use its transpose's column sums).
    const CSCMatrix full = to_full_storage(matrix);
    std::vector<double> row_sums(full.n_rows, 0.);
    for (Index j = 0; j < full.n_cols; ++j)
      for (Index k = full.column_start[j]; k < full.column_start[j + 1]; ++k)
        row_sums[full.row_index[k]] += std::abs(full.values[k]);
    const double denominator = norm_inf(row_sums) * norm_inf(x) + norm_inf(b);
    const double r           = norm_inf(residual_vector(matrix, x, b));
    return denominator > 0 ? r / denominator : r;
  }

  double relative_difference(const CSCMatrix &a, const CSCMatrix &b)
  {
    if (a.n_rows != b.n_rows || a.n_cols != b.n_cols)
      throw MatrixError("cannot compare a " + std::to_string(a.n_rows) + "x" +
                        std::to_string(a.n_cols) + " matrix with a " + std::to_string(b.n_rows) +
                        "x" + std::to_string(b.n_cols) + " one");
    double difference = 0, reference = 0;
    for (Index j = 0; j < a.n_cols; ++j)
      {
        // Merge the two sorted columns.
        Index p = a.column_start[j], q = b.column_start[j];
        while (p < a.column_start[j + 1] || q < b.column_start[j + 1])
          {
            const Index row_a = p < a.column_start[j + 1] ? a.row_index[p] : a.n_rows;
            const Index row_b = q < b.column_start[j + 1] ? b.row_index[q] : b.n_rows;
            const double value_a = row_a <= row_b ? a.values[p] : 0.;
            const double value_b = row_b <= row_a ? b.values[q] : 0.;
            if (row_a <= row_b)
              ++p;
            if (row_b <= row_a)
              ++q;
            difference += (value_a - value_b) * (value_a - value_b);
            reference += value_a * value_a;
          }
      }
    return reference > 0 ? std::sqrt(difference / reference) : std::sqrt(difference);
  }

  std::vector<Index> changed_columns(const CSCMatrix &a, const CSCMatrix &b)
  {
    if (a.n_cols != b.n_cols || a.column_start != b.column_start || a.row_index != b.row_index)
      throw MatrixError("changed_columns(): the two matrices have different patterns");
    std::vector<Index> columns;
    for (Index j = 0; j < b.n_cols; ++j)
      if (!std::equal(b.values.begin() + b.column_start[j], b.values.begin() + b.column_start[j + 1],
                      a.values.begin() + a.column_start[j]))
        columns.push_back(j);
    return columns;
  }
} // namespace warpchol::sparse
