#pragma once

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
   * ("NAME: message") and an exit status: 2 for bad input (InputError), 1 for any other
   * error, 0 on success.
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

  private:
    std::vector<std::string> arguments;
    std::size_t              position = 0;
  };
} // namespace warpchol::app
