#include <warpchol/app/command_line.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
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
    catch (const OutputError &error)
      {
        std::cerr << program_name << ": " << error.what() << std::endl;
        return 3;
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

  bool CommandLine::read_solver_option(const std::string &argument, cholesky::SparseCholesky::Settings &settings)
  {
    if (argument == "--ordering")
      settings.ordering.method = cholesky::parse_ordering_method(value_of(argument));
    else if (argument == "--method")
      settings.method = cholesky::parse_factorization_method(value_of(argument));
    else if (argument == "--supernodal")
      {
        const std::string on_off = value_of(argument);
        if (on_off != "on" && on_off != "off")
          throw InputError("--supernodal: expected on or off, got '" + on_off + "'");
        settings.method = on_off == "on" ? cholesky::FactorizationMethod::supernodal :
                                           cholesky::FactorizationMethod::left_looking;
      }
    else if (argument == "--threads")
      settings.n_threads = static_cast<unsigned int>(integer_of(argument, 1, 256));
    else if (argument == "--change-method")
      settings.change_method = cholesky::parse_change_method(value_of(argument));
    else if (argument == "--relaxation")
      {
        const std::string text       = value_of(argument);
        auto             &relaxation = settings.relaxation;
        char              tail       = 0;
        long              n[3]       = {0, 0, 0};
        if (text == "off")
          relaxation.enabled = false;
        else if (std::sscanf(text.c_str(), "%ld,%ld,%ld,%lf,%lf,%lf%c", &n[0], &n[1], &n[2], &relaxation.zrelax[0],
                             &relaxation.zrelax[1], &relaxation.zrelax[2], &tail) == 6 &&
                 n[0] >= 0 && n[1] >= 0 && n[2] >= 0)
          for (int i = 0; i < 3; ++i)
            relaxation.nrelax[i] = n[i];
        else
          throw InputError("--relaxation: expected off or N0,N1,N2,Z0,Z1,Z2 (CHOLMOD's 4,16,48,0.8,0.1,0.05), got '" +
                           text + "'");
      }
    else
      return false;
    return true;
  }

  void CommandLine::read_help_or_input_file(const std::string &argument, const std::string &usage,
                                            std::string &input_file)
  {
    if (argument == "--help" || argument == "-h")
      {
        std::cout << usage << std::endl;
        std::exit(0);
      }
    if (!argument.empty() && argument[0] == '-')
      throw InputError("unknown option '" + argument + "'");
    if (!input_file.empty())
      throw InputError("more than one input file given ('" + input_file + "', '" + argument + "')");
    input_file = argument;
  }
} // namespace warpchol::app
