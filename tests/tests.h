#pragma once

/**
 * @file
 * Helpers shared by the deal.II-style tests: each test prints what it checks to stdout,
 * which the test driver compares with tests/NAME.output through numdiff.
 *
 * A check prints its verdict ("yes"/"NO"), not a raw rounding-level number, so that the
 * expected output does not depend on the last bits of floating-point arithmetic while a
 * failed check still changes the output and fails the test.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/sparse/csc_matrix.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace tests
{
  /**
   * Whether the test runs under AddressSanitizer (.ci/sanitize). Its instrumentation slows
   * the project's code several times and not BLAS: a decision taken on measured seconds
   * there is not the one a user's build takes.
   */
#if defined(__SANITIZE_ADDRESS__)
  constexpr bool sanitized = true;
#elif defined(__has_feature)
#  if __has_feature(address_sanitizer)
  constexpr bool sanitized = true;
#  else
  constexpr bool sanitized = false;
#  endif
#else
  constexpr bool sanitized = false;
#endif

  /** Path of a file in tests/data (SOURCE_DIR is defined by deal.II's test macros). */
  inline std::string data_file(const std::string &name)
  {
    return std::string(SOURCE_DIR) + "/data/" + name;
  }

  /** The whole text of file @p filename ("" if it cannot be read). */
  inline std::string read_file(const std::string &filename)
  {
    std::ifstream      file(filename);
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
  }

  /** max |a - b| / max |b| over the entries (1 if the sizes differ; max |a - b| where b is 0). */
  inline double max_relative_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    if (a.size() != b.size())
      return 1;
    double largest = 0, difference = 0;
    for (std::size_t k = 0; k < b.size(); ++k)
      {
        largest    = std::max(largest, std::abs(b[k]));
        difference = std::max(difference, std::abs(a[k] - b[k]));
      }
    return largest > 0 ? difference / largest : difference;
  }

  /** Print "label: value <= bound: yes" (or NO); returns whether the check held. */
  inline bool check_below(const std::string &label, const double value, const double bound)
  {
    const bool holds = value <= bound; // false for NaN as well
    std::cout << label << " <= " << warpchol::format_number(bound, 2) << ": "
              << (holds ? "yes" : "NO") << (holds ? "" : " (" + warpchol::format_number(value) + ")")
              << std::endl;
    return holds;
  }

  /** Print "label: yes" (or NO). */
  inline bool check(const std::string &label, const bool condition)
  {
    std::cout << label << ": " << (condition ? "yes" : "NO") << std::endl;
    return condition;
  }

  /**
   * Run @p action, which must throw a warpchol::Error; print "label: <message>" or
   * "label: NO ERROR". The message is part of the compared output.
   */
  inline void expect_error(const std::string &label, const std::function<void()> &action)
  {
    try
      {
        action();
        std::cout << label << ": NO ERROR" << std::endl;
      }
    catch (const warpchol::Error &error)
      {
        std::cout << label << ": " << error.what() << std::endl;
      }
  }

  /**
   * Run @p action and print "label: <what it returns>", or "label: <message>" of the
   * warpchol::Error it throws: what is read, or why it is refused.
   */
  inline void print_result_or_error(const std::string &label, const std::function<std::string()> &action)
  {
    std::string result;
    try
      {
        result = action();
      }
    catch (const warpchol::Error &error)
      {
        result = error.what();
      }
    std::cout << label << ": " << result << std::endl;
  }

  /**
   * Run @p action, which must throw the deal.II exception @p Exception; print "label:
   * <message>" (its print_info(), flagged if it is not one line), "label: NO ERROR", or
   * the name of another deal.II exception.
   */
  template <typename Exception>
  void expect_dealii_error(const std::string &label, const std::function<void()> &action)
  {
    try
      {
        action();
        std::cout << label << ": NO ERROR" << std::endl;
      }
    catch (const Exception &error)
      {
        std::ostringstream info;
        error.print_info(info);
        std::string message = info.str();
        message.erase(0, message.find_first_not_of(' '));
        while (!message.empty() && message.back() == '\n')
          message.pop_back();
        std::cout << label << ": " << message
                  << (message.find('\n') == std::string::npos ? "" : " [NOT ONE LINE]") << std::endl;
      }
    catch (const dealii::ExceptionBase &error)
      {
        std::cout << label << ": WRONG EXCEPTION " << error.get_exc_name() << std::endl;
      }
  }

  /** A small deterministic generator (splitmix64), the same on every platform. */
  class Random
  {
  public:
    explicit Random(const std::uint64_t seed)
      : state(seed)
    {}

    std::uint64_t next()
    {
      std::uint64_t x = (state += 0x9e3779b97f4a7c15ULL);
      x               = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
      x               = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
      return x ^ (x >> 31);
    }

    /** Uniform in [0, 1). */
    double uniform()
    {
      return static_cast<double>(next() >> 11) * 0x1.0p-53;
    }

    /** Uniform in [0, n). */
    warpchol::Index below(const warpchol::Index n)
    {
      return static_cast<warpchol::Index>(uniform() * static_cast<double>(n));
    }

  private:
    std::uint64_t state;
  };

  /**
   * A random sparse SPD matrix with lower storage: about @p per_column off-diagonal entries
   * per column in [-1, 1], and a diagonal that makes it strictly diagonally dominant.
   */
  inline warpchol::sparse::CSCMatrix random_spd(const warpchol::Index n, const int per_column,
                                                const std::uint64_t seed)
  {
    using warpchol::Index;
    Random                           random(seed);
    std::vector<std::vector<Index>>  rows(n);
    for (Index j = 0; j < n; ++j)
      for (int e = 0; e < per_column && j + 1 < n; ++e)
        rows[j].push_back(j + 1 + random.below(n - j - 1));
    warpchol::sparse::CSCMatrix matrix =
      warpchol::sparse::CSCMatrix::zero(n, n, warpchol::sparse::Storage::lower);
    std::vector<double> row_sums(n, 0.);
    std::vector<std::vector<double>> values(n);
    for (Index j = 0; j < n; ++j)
      {
        std::sort(rows[j].begin(), rows[j].end());
        rows[j].erase(std::unique(rows[j].begin(), rows[j].end()), rows[j].end());
        for (const Index i : rows[j])
          {
            const double v = 2. * random.uniform() - 1.;
            values[j].push_back(v);
            row_sums[i] += std::abs(v);
            row_sums[j] += std::abs(v);
          }
      }
    for (Index j = 0; j < n; ++j)
      {
        matrix.row_index.push_back(j);
        matrix.values.push_back(row_sums[j] + 0.5 + random.uniform());
        for (std::size_t e = 0; e < rows[j].size(); ++e)
          {
            matrix.row_index.push_back(rows[j][e]);
            matrix.values.push_back(values[j][e]);
          }
        matrix.column_start[j + 1] = static_cast<Index>(matrix.row_index.size());
      }
    return matrix;
  }

  /** b = A x for a solution x with entries uniform in [-0.5, 0.5), drawn with @p seed. */
  inline std::vector<double> right_hand_side_of_random_solution(const warpchol::sparse::CSCMatrix &matrix,
                                                                const std::uint64_t               seed)
  {
    Random              random(seed);
    std::vector<double> x(matrix.n_cols), b(matrix.n_rows);
    for (double &value : x)
      value = random.uniform() - 0.5;
    matrix.vmult(x.data(), b.data());
    return b;
  }

  /** Dense column-major copy of the (full) matrix represented by @p matrix. */
  inline std::vector<double> to_dense(const warpchol::sparse::CSCMatrix &matrix)
  {
    using warpchol::Index;
    std::vector<double> dense(matrix.n_rows * matrix.n_cols, 0.);
    for (Index j = 0; j < matrix.n_cols; ++j)
      for (Index k = matrix.column_start[j]; k < matrix.column_start[j + 1]; ++k)
        {
          const Index i = matrix.row_index[k];
          dense[i + j * matrix.n_rows] = matrix.values[k];
          if (matrix.storage == warpchol::sparse::Storage::lower)
            dense[j + i * matrix.n_rows] = matrix.values[k];
        }
    return dense;
  }

  /** The textbook dense Cholesky factor (column-major, lower), as an independent reference. */
  inline std::vector<double> dense_cholesky(std::vector<double> a, const warpchol::Index n)
  {
    using warpchol::Index;
    for (Index j = 0; j < n; ++j)
      {
        for (Index k = 0; k < j; ++k)
          for (Index i = j; i < n; ++i)
            a[i + j * n] -= a[i + k * n] * a[j + k * n];
        const double d = std::sqrt(a[j + j * n]);
        for (Index i = j; i < n; ++i)
          a[i + j * n] /= d;
        for (Index i = 0; i < j; ++i)
          a[i + j * n] = 0.;
      }
    return a;
  }
} // namespace tests
