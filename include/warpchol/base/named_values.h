#pragma once

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

/**
 * @file
 * The one list of an enumeration's names: to_string(), the parsers, deal.II's
 * Patterns::Selection in the parameter files and the Python module all read it, so that
 * a choice's names are written once.
 */
namespace warpchol
{
  /** An enumerator and its name. */
  template <typename Enum>
  struct NamedValue
  {
    Enum        value;
    const char *name;
  };

  /** The names of an enumeration, in the order they are documented (aliases after the name they stand for). */
  template <typename Enum, std::size_t N>
  using NameTable = std::array<NamedValue<Enum>, N>;

  /** The first name of @p value ("unknown" if it has none). */
  template <typename Enum, std::size_t N>
  std::string name_of(const NameTable<Enum, N> &table, const Enum value)
  {
    for (const auto &entry : table)
      if (entry.value == value)
        return entry.name;
    return "unknown";
  }

  /** "a|b|c": the list of Patterns::Selection. */
  template <typename Enum, std::size_t N>
  std::string selection_of(const NameTable<Enum, N> &table)
  {
    std::string names;
    for (const auto &entry : table)
      names += (names.empty() ? "" : "|") + std::string(entry.name);
    return names;
  }

  /** The value named @p name; throws InputError "unknown <what> 'x' (expected a, b or c)". */
  template <typename Enum, std::size_t N>
  Enum parse_name(const NameTable<Enum, N> &table, const std::string &name, const std::string &what)
  {
    std::vector<std::string> names;
    for (const auto &entry : table)
      {
        if (name == entry.name)
          return entry.value;
        names.emplace_back(entry.name);
      }
    throw InputError("unknown " + what + " " + quote(name) + " (expected " + alternatives(names) + ")");
  }
} // namespace warpchol
