#pragma once

#include <warpchol/cholesky/sparse_cholesky.h>

#include <string>
#include <variant>
#include <vector>

/**
 * @file
 * The fields of SparseCholesky::Statistics that the solver reports, listed once: Python's
 * statistics dict, the simulation's log columns and its summary read this table, so that
 * a new statistic is one line here (and its member in Statistics).
 */
namespace warpchol::cholesky
{
  /** A statistic's value as its type: a count, a measure, a flag or a name. */
  using StatisticValue = std::variant<long long, double, bool, std::string>;

  /** One reported field of SparseCholesky::Statistics. */
  struct StatisticsField
  {
    /** Its name: the key of Python's statistics dict. */
    const char *name;
    /** The column of the simulation's log that shows it per step, or nullptr if none does. */
    const char *log_column;
    /** What it means, in a line. */
    const char *description;
    /** Its value in @p statistics. */
    StatisticValue (*value)(const SparseCholesky::Statistics &statistics);
    /**
     * Whether @p statistics hold a value of it (the log leaves the cell empty otherwise):
     * what the last refactorize() weighed is there only when it weighed an update.
     */
    bool (*is_set)(const SparseCholesky::Statistics &statistics);
  };

  /** The reported fields of SparseCholesky::Statistics, in the order Python's dict lists them. */
  const std::vector<StatisticsField> &statistics_fields();
} // namespace warpchol::cholesky
