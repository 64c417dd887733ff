#include <warpchol/base/exceptions.h>

#include <warpchol/base/format.h>

namespace warpchol
{
  Error::Error(const std::string &one_line_message)
    : std::runtime_error(one_line_message)
  {}

  InputError::InputError(const std::string &one_line_message)
    : Error(one_line_message)
  {}

  OutputError::OutputError(const std::string &one_line_message)
    : Error(one_line_message)
  {}

  MatrixError::MatrixError(const std::string &one_line_message)
    : Error(one_line_message)
  {}

  SimulationError::SimulationError(const std::string &one_line_message)
    : Error(one_line_message)
  {}

  namespace
  {
    std::string describe_pivot(const long long column, const double pivot)
    {
      return "matrix is not positive definite: pivot of column " + std::to_string(column) +
             " is " + format_number(pivot);
    }
  } // namespace

  NotPositiveDefinite::NotPositiveDefinite(const long long column, const double pivot)
    : MatrixError(describe_pivot(column, pivot))
    , column(column)
    , pivot(pivot)
  {}

  NotPositiveDefinite::NotPositiveDefinite(const long long column, const double pivot,
                                           const std::string &one_line_message)
    : MatrixError(one_line_message)
    , column(column)
    , pivot(pivot)
  {}
} // namespace warpchol
