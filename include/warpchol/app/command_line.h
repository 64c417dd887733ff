#pragma once

#include <warpchol/cholesky/sparse_cholesky.h>

#include <functional>
#include <string>
#include <vector>

/**
 * @file
 * Small helpers for the command-line tools: reading option values with a one-line error
 * that names the option.
 */
namespace warpchol::app
{
  /**
   * Run the body of program @p program_name and turn its errors into one line on stderr
   * ("NAME: message") and an exit status: 2 for bad input (InputError), 3 for a result that
   * cannot be written (OutputError: a full disk), 1 for any other error, 0 on success.
   */
  int run_program(const std::string &program_name, const std::function<void()> &body);

  /** The arguments of a program after its name, read one by one. */
  class CommandLine
  {
  public:
    CommandLine(int argc, char **argv);

    /** True while arguments remain. */
    bool has_next() const;

    /** The next argument. */
    std::string next();

    /** The value of option @p option (the next argument); InputError if there is none. */
    std::string value_of(const std::string &option);

    /** The value of @p option as a finite number; InputError naming the option otherwise. */
    double number_of(const std::string &option);

    /** The value of @p option as an integer in [min, max]; InputError naming the option otherwise. */
    long integer_of(const std::string &option, long min, long max);

    /**
     * If @p argument is one of the solver options, read its value into @p settings and
     * return true: --ordering natural|amd|metis, --method left|up|supernodal,
     * --supernodal on|off, --threads N, --relaxation off|N0,N1,N2,Z0,Z1,Z2 (supernode
     * amalgamation, CHOLMOD's nrelax and zrelax).
     */
    bool read_solver_option(const std::string &argument, cholesky::SparseCholesky::Settings &settings);

    /**
     * The arguments every tool treats alike: --help prints @p usage and exits, another
     * option is unknown (InputError), anything else is the one input file, stored in
     * @p input_file (a second one is an InputError).
     */
    void read_help_or_input_file(const std::string &argument, const std::string &usage, std::string &input_file);

  private:
    std::vector<std::string> arguments;
    std::size_t              position = 0;
  };
} // namespace warpchol::app
