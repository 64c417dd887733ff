#include <warpchol/app/parameters/parameter_file.h>
#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>
#include <warpchol/base/input_file.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace warpchol::app
{
  namespace
  {
    /** Collapse runs of white space into one blank. */
    std::string one_line(const std::string &text)
    {
      std::istringstream words(text);
      std::string        word, result;
      while (words >> word)
        result += (result.empty() ? "" : " ") + word;
      return result;
    }

    /**
     * deal.II quotes the file's text in its messages: the line that cannot be parsed or
     * the unknown entry between < and >, a value after "The entry value ", a subsection's
     * name at the end. Keep an excerpt() of each, so that the message stays a short line
     * whatever the file holds.
     */
    std::string shorten_quoted_input(const std::string &message)
    {
      std::string result;
      std::size_t position = 0;
      while (position < message.size())
        {
          const auto open = message.find('<', position);
          if (open == std::string::npos)
            break;
          const auto close = message.find('>', open + 1);
          if (close == std::string::npos)
            break;
          result += message.substr(position, open + 1 - position) +
                    excerpt(message.substr(open + 1, close - open - 1), 60) + ">";
          position = close + 1;
        }
      result += message.substr(position);
      for (const auto &[before, after] :
           {std::pair<std::string, std::string>{"The entry value ", " for the entry named "},
            std::pair<std::string, std::string>{"There is no such subsection to be entered: ", ""}})
        {
          const auto begin = result.find(before);
          if (begin == std::string::npos)
            continue;
          const auto start = begin + before.size();
          const auto end   = after.empty() ? result.size() : result.find(after, start);
          if (end != std::string::npos)
            result = result.substr(0, start) + excerpt(result.substr(start, end - start), 60) +
                     result.substr(end);
        }
      // Whatever else deal.II says, on one printable line of a bounded length.
      return excerpt(result, 600);
    }
  } // namespace

  namespace parameters
  {
    std::string trim(const std::string &text)
    {
      const auto first = text.find_first_not_of(" \t\r");
      if (first == std::string::npos)
        return "";
      return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
    }

    void refuse_binary(const std::string &filename, const std::string &where)
    {
      std::ifstream input(filename, std::ios::binary);
      std::string   start(4096, '\0');
      input.read(start.data(), start.size());
      start.resize(input.gcount());
      if (looks_binary(start))
        throw InputError(where + ": not a parameter file: it starts with " + quote(start));
    }

    /**
     * deal.II's "The entry value V for the entry named E does not match the given pattern:
     * [Selection a|b|c ]" as "PATH = V: not one of a, b or c", PATH the entry's
     * "Subsection/Entry" (@p path; E if empty); any other message as it is.
     */
    std::string choice_message(const std::string &message, const std::string &path)
    {
      const std::string value_prefix = "The entry value ", entry_prefix = " for the entry named ",
                        pattern_prefix = " does not match the given pattern: [Selection ";
      const auto entry   = message.find(entry_prefix);
      const auto pattern = message.find(pattern_prefix);
      const auto end     = message.rfind(']');
      if (message.rfind(value_prefix, 0) != 0 || entry == std::string::npos || pattern == std::string::npos ||
          end == std::string::npos || end < pattern)
        return message;
      const std::string value = message.substr(value_prefix.size(), entry - value_prefix.size());
      const std::string name  = message.substr(entry + entry_prefix.size(), pattern - entry - entry_prefix.size());
      std::vector<std::string> choices;
      std::istringstream       names(trim(message.substr(pattern + pattern_prefix.size(), end - pattern - pattern_prefix.size())));
      for (std::string choice; std::getline(names, choice, '|');)
        choices.push_back(choice);
      return (path.empty() ? name : path) + " = " + value + ": not one of " + alternatives(choices);
    }

    std::string parameter_handler_message(const std::exception &error, const ParameterFileLocator &file)
    {
      std::string       message = error.what();
      const std::string marker  = "Additional information:";
      const auto        begin   = message.find(marker);
      if (begin != std::string::npos)
        message = message.substr(begin + marker.size());
      const auto stack = message.find("Stacktrace:");
      if (stack != std::string::npos)
        message.resize(stack);
      message = one_line(message);
      // "Line <N> of file <F>: ...", read by hand: what follows may be long.
      const std::string line_prefix = "Line <", file_prefix = "> of file <";
      // deal.II leaves out the '>' after the file's name in some messages.
      const auto line_end = message.find(file_prefix);
      const auto file_end = line_end == std::string::npos ?
                              std::string::npos :
                              message.find_first_of(">:", line_end + file_prefix.size());
      if (message.rfind(line_prefix, 0) == 0 && file_end != std::string::npos)
        {
          const std::string line = message.substr(line_prefix.size(), line_end - line_prefix.size());
          const std::string file_name = message.substr(line_end + file_prefix.size(),
                                                       file_end - line_end - file_prefix.size());
          std::string rest = message.substr(file_end);
          if (!rest.empty() && rest[0] == '>')
            rest.erase(0, 1);
          if (!rest.empty() && rest[0] == ':')
            rest.erase(0, 1);
          if (!rest.empty() && rest[0] == ' ')
            rest.erase(0, 1);
          // A line of the text with its includes written out: the file and line it is.
          const bool        ours = file_name == file.filename() && !line.empty() && line.size() < 10 &&
                                line.find_first_not_of("0123456789") == std::string::npos;
          const std::string where = ours ? file.origin(std::stoi(line)) : file_name + ":" + line;
          const std::string path  = ours ? file.entry_at(std::stoi(line)) : "";
          return where + ": " + shorten_quoted_input(choice_message(rest, path));
        }
      return shorten_quoted_input(choice_message(message, ""));
    }

    std::vector<std::string> numbered_events(const std::string &text, const std::string &kind)
    {
      std::vector<unsigned long> numbers;
      std::istringstream         lines(text);
      for (std::string line; std::getline(lines, line);)
        {
          std::istringstream words(line);
          std::string        word, name;
          if (!(words >> word) || word != "subsection")
            continue;
          std::getline(words, name);
          name = trim(name);
          if (name.size() <= kind.size() + 1 || name.compare(0, kind.size() + 1, kind + " ") != 0)
            continue;
          const std::string number = trim(name.substr(kind.size() + 1));
          if (number.empty() || number.size() > 6 ||
              !std::all_of(number.begin(), number.end(), [](const unsigned char c) { return std::isdigit(c); }) ||
              number[0] == '0' || std::stoul(number) < 2)
            continue;
          numbers.push_back(std::stoul(number));
        }
      std::sort(numbers.begin(), numbers.end());
      numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
      std::vector<std::string> names;
      for (const unsigned long n : numbers)
        names.push_back(kind + " " + std::to_string(n));
      return names;
    }
  } // namespace parameters

  using parameters::refuse_binary;
  using parameters::trim;

  // ---------------------------------------------------------------------------------------
  ParameterFileLocator::ParameterFileLocator(const std::string &filename)
    : file(filename)
    , files{filename}
  {
    std::vector<std::string> subsections;
    std::error_code          error;
    std::vector<std::string> chain{std::filesystem::weakly_canonical(filename, error).string()};
    read(0, subsections, chain);
  }

  namespace
  {
    /** The folder of @p filename with its '/', "" for the working directory. */
    std::string folder_of(const std::string &filename)
    {
      const auto slash = filename.find_last_of('/');
      return slash == std::string::npos ? std::string() : filename.substr(0, slash + 1);
    }
  } // namespace

  void ParameterFileLocator::read(const unsigned int file_index, std::vector<std::string> &subsections,
                                  std::vector<std::string> &chain)
  {
    // Copied: files grows while the includes are read.
    const std::string name = files[file_index];
    std::ifstream     input(name);
    int               line_number = 0;
    bool              continued   = false;
    for (std::string line; std::getline(input, line);)
      {
        ++line_number;
        const std::string statement = trim(line.substr(0, line.find('#')));
        const std::string first     = statement.substr(0, statement.find_first_of(" \t"));
        const std::string rest      = trim(statement.substr(first.size()));
        // A line that ends in a backslash goes on in the next: that one starts no statement.
        const bool continuation = continued;
        continued               = !trim(line).empty() && trim(line).back() == '\\';
        if (continuation || (first != "include" && first != "INCLUDE"))
          {
            expanded_text += line + "\n";
            line_origins.emplace_back(file_index, line_number);
            if (continuation)
              continue;
            if (first == "subsection")
              subsections.push_back(one_line(rest));
            else if (first == "end" && !subsections.empty())
              subsections.pop_back();
            else if (first == "set")
              {
                std::string path;
                for (const auto &subsection : subsections)
                  path += subsection + "/";
                path += one_line(rest.substr(0, rest.find('=')));
                const int line_index = static_cast<int>(line_origins.size());
                for (const RenamedEntry &renamed : renamed_entries)
                  if (path == std::string(renamed.subsection) + "/" + renamed.old_name)
                    {
                      old_name_lines.emplace_back(renamed, line_index);
                      path = std::string(renamed.subsection) + "/" + renamed.new_name;
                    }
                set_lines.emplace_back(path, line_index);
              }
            continue;
          }

        // Relative to the folder of this file, as every path a parameter file holds.
        const std::string included = rest.empty() || rest[0] == '/' ? rest : folder_of(name) + rest;
        const std::string where = name + ":" + std::to_string(line_number) + ": include " + quote(rest);
        struct stat       status;
        if (::stat(included.c_str(), &status) != 0)
          throw InputError(where + ": cannot open it");
        if (!S_ISREG(status.st_mode))
          throw InputError(where + ": not a regular file");
        refuse_binary(included, where);
        std::error_code   error;
        const std::string path = std::filesystem::weakly_canonical(included, error).string();
        if (std::find(chain.begin(), chain.end(), path) != chain.end())
          throw InputError(where + ": it is already being read (a cycle of includes)");
        // deal.II requires an included file to close the subsections it opens.
        const std::vector<std::string> open_before = subsections;
        chain.push_back(path);
        files.push_back(included);
        read(files.size() - 1, subsections, chain);
        chain.pop_back();
        if (subsections != open_before)
          throw InputError(where + ": its 'subsection' and 'end' statements do not pair up");
      }
  }

  const std::string &ParameterFileLocator::text() const
  {
    return expanded_text;
  }

  std::string ParameterFileLocator::origin(const int line) const
  {
    if (line < 1 || line > static_cast<int>(line_origins.size()))
      return file + ":" + std::to_string(line);
    const auto &[file_index, file_line] = line_origins[line - 1];
    return files[file_index] + ":" + std::to_string(file_line);
  }

  std::string ParameterFileLocator::where(const std::string &subsection,
                                          const std::string &entry) const
  {
    const std::string path = subsection + "/" + entry;
    if (file.empty())
      return "defaults: " + path;
    for (auto set = set_lines.rbegin(); set != set_lines.rend(); ++set)
      if (set->first == path)
        return origin(set->second) + ": " + path;
    return file + ": " + path + " (default)";
  }

  bool ParameterFileLocator::sets(const std::string &subsection, const std::string &entry) const
  {
    const std::string path = subsection + "/" + entry;
    return std::any_of(set_lines.begin(), set_lines.end(), [&](const auto &set) { return set.first == path; });
  }

  std::vector<std::pair<std::string, RenamedEntry>> ParameterFileLocator::old_names() const
  {
    std::vector<std::pair<std::string, RenamedEntry>> result;
    for (const auto &[renamed, line] : old_name_lines)
      result.emplace_back(origin(line), renamed);
    return result;
  }

  std::string ParameterFileLocator::entry_at(const int line) const
  {
    for (const auto &[path, set_line] : set_lines)
      if (set_line == line)
        return path;
    return "";
  }

  void ParameterFileLocator::fail(const dealii::ParameterHandler &prm,
                                  const std::string &subsection, const std::string &entry,
                                  const std::string &message) const
  {
    // The value comes from the file: an excerpt of it, printable.
    throw InputError(where(subsection, entry) + " = " + excerpt(prm.get(entry), 60) + ": " + message);
  }

  std::string ParameterFileLocator::directory_of(const std::string &subsection, const std::string &entry) const
  {
    const std::string path = subsection + "/" + entry;
    for (auto set = set_lines.rbegin(); set != set_lines.rend(); ++set)
      if (set->first == path)
        return folder_of(files[line_origins[set->second - 1].first]);
    return folder_of(file);
  }

  const std::string &ParameterFileLocator::filename() const
  {
    return file;
  }
} // namespace warpchol::app
