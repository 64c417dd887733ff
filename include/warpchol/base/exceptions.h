#pragma once

#include <stdexcept>
#include <string>

/**
 * @file
 * The project's exceptions. Each carries a single line that says what is wrong and where
 * (file and line, column, cell, entry), so that a program can print it as it is and exit
 * with a non-zero status.
 */
namespace warpchol
{
  /** Base class of every error the project reports to a user. */
  class Error : public std::runtime_error
  {
  public:
    explicit Error(const std::string &one_line_message);
  };

  /** An input file or a parameter that cannot be used: names the file, line and entry. */
  class InputError : public Error
  {
  public:
    explicit InputError(const std::string &one_line_message);
  };

  /**
   * A result that cannot be written: the output directory cannot be created or written,
   * the disk is full, a file cannot be renamed into place. Names the file or directory and
   * the system's reason ("no space left on device"); programs exit with status 3.
   */
  class OutputError : public Error
  {
  public:
    explicit OutputError(const std::string &one_line_message);
  };

  /** A matrix that the solver cannot factor (not square, not symmetric, NaN, ...). */
  class MatrixError : public Error
  {
  public:
    explicit MatrixError(const std::string &one_line_message);
  };

  /**
   * A simulation that diverges: its energy grew far past what the loads put in, or a value
   * stopped being finite. Names the step.
   */
  class SimulationError : public Error
  {
  public:
    explicit SimulationError(const std::string &one_line_message);
  };

  /**
   * A non-positive pivot met during a Cholesky factorization: the matrix is not positive
   * definite. Carries the column (in the user's numbering) and the pivot value.
   */
  class NotPositiveDefinite : public MatrixError
  {
  public:
    NotPositiveDefinite(long long column, double pivot);
    /** The same with a message of its own (a downdate that stops before the pivot fails). */
    NotPositiveDefinite(long long column, double pivot, const std::string &one_line_message);

    /** The column of the input matrix (user numbering) whose pivot failed. */
    long long column;
    /** The value of the pivot, A(j,j) minus the updates, before the square root. */
    double pivot;
  };
} // namespace warpchol
