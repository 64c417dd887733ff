#include <warpchol/app/command_line.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <cmath>
#include <iostream>

namespace warpchol::app
{
  int run_program(const std::string &program_name, const std::function<void()> &body)
  {
    try
      {
        body();
      }
    catch (const InputError &error)
      {
        std::cerr << program_name << ": " << error.what() << std::endl;
        return 2;
      }
    catch (const std::exception &error)
      {
        std::cerr << program_name << ": " << error.what() << std::endl;
        return 1;
      }
    return 0;
  }

  CommandLine::CommandLine(const int argc, char **argv)
    : arguments(argv + 1, argv + argc)
  {}

  bool CommandLine::has_next() const
  {
    return position < arguments.size();
  }

  std::string CommandLine::next()
  {
    return arguments.at(position++);
  }

  std::string CommandLine::value_of(const std::string &option)
  {
    if (!has_next())
      throw InputError(option + " needs a value");
    return next();
  }

  double CommandLine::number_of(const std::string &option)
  {
    const std::string text  = value_of(option);
    std::size_t       used  = 0;
    double            value = 0;
    try
      {
        value = std::stod(text, &used);
      }
    catch (const std::exception &)
      {
        used = 0;
      }
    if (used == 0 || used != text.size() || !std::isfinite(value))
      throw InputError(option + ": '" + text + "' is not a number");
    return value;
  }

  long CommandLine::integer_of(const std::string &option, const long min, const long max)
  {
    const double value = number_of(option);
    if (value != std::floor(value) || value < static_cast<double>(min) || value > static_cast<double>(max))
      throw InputError(option + " must be an integer in [" + std::to_string(min) + ", " +
                       std::to_string(max) + "], got " + format_number(value));
    return static_cast<long>(value);
  }
} // namespace warpchol::app
