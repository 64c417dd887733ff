#include <warpchol/app/path_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace warpchol::app
{
  namespace
  {
    std::string trim(const std::string &text)
    {
      const auto first = text.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return "";
      return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
    }

    std::vector<std::string> fields(const std::string &line)
    {
      std::vector<std::string> result;
      std::istringstream       stream(line);
      for (std::string field; std::getline(stream, field, ',');)
        result.push_back(trim(field));
      if (!line.empty() && line.back() == ',')
        result.emplace_back(); // a trailing comma: an empty last column
      return result;
    }
  } // namespace

  PathFile PathFile::read(const std::string &file_name, const unsigned int least_values, const std::string &columns,
                          const unsigned int optional_values)
  {
    // The first sample decides between the values without and with the optional ones.
    unsigned int n_values = least_values;
    std::ifstream input = open_input_file(file_name, "path file");
    std::string   text((std::istreambuf_iterator<char>(input)), std::istreambuf_iterator<char>());
    if (looks_binary(text.substr(0, 4096)))
      throw InputError(file_name + ": not a path file (CSV of " + columns + "): it starts with " + quote(text));

    PathFile result;
    result.file_name = file_name;
    std::vector<double> times, values;
    std::istringstream  lines(text);
    int                 number = 0, previous_line = 0;
    bool                header_allowed = true;
    for (std::string line; std::getline(lines, line);)
      {
        ++number;
        line = trim(line);
        if (line.empty() || line[0] == '#')
          continue;
        const std::string where = file_name + ":" + std::to_string(number) + ": ";
        // Column names, once, before the first sample.
        if (header_allowed && std::isalpha(static_cast<unsigned char>(line[0])))
          {
            header_allowed = false;
            continue;
          }
        header_allowed                       = false;
        const std::vector<std::string> items = fields(line);
        if (times.empty() && optional_values > 0 && items.size() == least_values + optional_values + 1)
          n_values = least_values + optional_values;
        if (items.size() != n_values + 1)
          throw InputError(where + std::to_string(items.size()) + (items.size() == 1 ? " column" : " columns") +
                           ", a sample needs " + std::to_string(n_values + 1) +
                           (times.empty() && optional_values > 0 ?
                              " or " + std::to_string(least_values + optional_values + 1) :
                              "") +
                           " (" + columns + (!times.empty() && optional_values > 0 ? ", as the first sample has" : "") +
                           ")");
        for (unsigned int c = 0; c < items.size(); ++c)
          {
            char        *end   = nullptr;
            const double value = std::strtod(items[c].c_str(), &end);
            if (items[c].empty() || *end != '\0')
              throw InputError(where + "column " + std::to_string(c + 1) + " is " + quote(items[c]) +
                               ": not a number (" + columns + ")");
            if (!std::isfinite(value))
              throw InputError(where + "column " + std::to_string(c + 1) + " is " + items[c] +
                               ": a path needs finite numbers");
            (c == 0 ? times : values).push_back(value);
          }
        if (times.size() > 1 && !(times.back() > times[times.size() - 2]))
          throw InputError(where + "time " + format_number(times.back(), 12) + " s is not after the previous sample's " +
                           format_number(times[times.size() - 2], 12) + " s (line " + std::to_string(previous_line) +
                           "): times must increase");
        if (times.size() == 1)
          result.first_line = number;
        previous_line    = number;
        result.last_line = number;
      }
    if (times.empty())
      throw InputError(file_name + ": holds no sample (lines of " + columns + ")");
    result.path = fem::InstrumentPath(std::move(times), std::move(values), n_values);
    return result;
  }

  void PathFile::check_covers(const double from, const double to, const std::string &use) const
  {
    if (path.start_time() > from)
      throw InputError(file_name + ":" + std::to_string(first_line) + ": the path starts at " +
                       format_number(path.start_time()) + " s, after " + use + " starts at " + format_number(from) +
                       " s");
    if (path.end_time() < to)
      throw InputError(file_name + ":" + std::to_string(last_line) + ": the path ends at " +
                       format_number(path.end_time()) + " s, before " + use + " ends at " + format_number(to) + " s");
  }
} // namespace warpchol::app
