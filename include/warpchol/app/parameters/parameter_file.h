#pragma once

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <exception>
#include <string>
#include <utility>
#include <vector>

/**
 * @file
 * A parameter file as deal.II reads it: its includes written out, where each line and entry
 * comes from, and deal.II's messages about it made one line that names the file and line.
 */
namespace warpchol::app
{
  /** An entry of a subsection that was renamed: its old name is still read as the new one. */
  struct RenamedEntry
  {
    const char *subsection;
    const char *old_name;
    const char *new_name;
  };

  /**
   * Every renamed entry, the one list that AllParameters declares as deal.II aliases and the
   * locator reads set statements by: a file that uses an old name runs as before, with a
   * warning naming the new one.
   */
  inline constexpr std::array<RenamedEntry, 2> renamed_entries{
    {{"Model", "Update threshold", "Rerotation threshold"}, {"Bodies", "Update thresholds", "Rerotation thresholds"}}};

  /**
   * A parameter file as deal.II's ParameterHandler reads it, with its includes written out
   * in place, and where each of its lines and entries comes from: so that a value rejected
   * after parsing (a bound ParameterHandler's patterns cannot express, a missing file) is
   * reported at its file and line, and a relative path is taken relative to the folder of
   * the file that holds it.
   *
   * "include FILE" takes a relative FILE relative to the folder of the file the statement is
   * in (deal.II would take the working directory), like every other path of a parameter
   * file. An include that cannot be followed is an InputError naming the file and line of
   * the statement: a file that is missing, not a regular file (a device reads forever),
   * binary, already being read (a cycle), or that leaves other subsections open than it
   * found.
   */
  class ParameterFileLocator
  {
  public:
    ParameterFileLocator() = default;
    /** Read @p filename and what it includes (an empty name stands for the defaults). */
    explicit ParameterFileLocator(const std::string &filename);

    /** The file's text with every include statement replaced by the lines of its file. */
    const std::string &text() const;

    /** "FILE:LINE" of line @p line (from 1) of text(): the file and the line it comes from. */
    std::string origin(int line) const;

    /**
     * "FILE:LINE: Subsection/Entry" at the statement that sets the entry last (the value
     * ParameterHandler keeps), or "FILE: Subsection/Entry (default)" if none does.
     */
    std::string where(const std::string &subsection, const std::string &entry) const;

    /** Whether a set statement of the file (or of a file it includes) sets Subsection/Entry. */
    bool sets(const std::string &subsection, const std::string &entry) const;

    /**
     * Every set statement that names an entry by its old name (renamed_entries): its
     * "FILE:LINE" and the entry. where() and sets() know such a statement by the new name.
     */
    std::vector<std::pair<std::string, RenamedEntry>> old_names() const;

    /** "Subsection/Entry" of the set statement at line @p line (from 1) of text(), "" if none is there. */
    std::string entry_at(int line) const;

    /** Throw InputError "where(...) = VALUE: message". */
    [[noreturn]] void fail(const dealii::ParameterHandler &prm, const std::string &subsection,
                           const std::string &entry, const std::string &message) const;

    /**
     * The folder of the file that sets Subsection/Entry (the top file's if none does), to
     * which a relative path in the entry's value refers ("" for the working directory).
     */
    std::string directory_of(const std::string &subsection, const std::string &entry) const;
    const std::string &filename() const;

  private:
    /**
     * Append file @p file_index of @p files to text(), its includes written out; @p
     * subsections: the subsections open at its start, @p chain: the files being read (their
     * canonical paths).
     */
    void read(unsigned int file_index, std::vector<std::string> &subsections, std::vector<std::string> &chain);

    std::string file;
    std::string expanded_text;
    /** The top file and every file it includes, each path relative to the working directory. */
    std::vector<std::string> files;
    /** Per line of expanded_text: the index of its file in files, and its line there. */
    std::vector<std::pair<unsigned int, int>> line_origins;
    /** "Subsection/Entry" -> line of expanded_text, for every "set" statement (new names). */
    std::vector<std::pair<std::string, int>> set_lines;
    /** The entry and the line of expanded_text of every set statement of an old name. */
    std::vector<std::pair<RenamedEntry, int>> old_name_lines;
  };

  namespace parameters
  {
    // The subsections' code names deal.II's ParameterHandler and Patterns as its own.
    using dealii::ParameterHandler;
    namespace Patterns = dealii::Patterns;

    /** @p text without the blanks (spaces, tabs, carriage returns) at its ends. */
    std::string trim(const std::string &text);

    /**
     * A parameter file is text: one that looks binary is refused (InputError "@p where: not
     * a parameter file: ...") before deal.II echoes its bytes.
     */
    void refuse_binary(const std::string &filename, const std::string &where);

    /**
     * ParameterHandler's exceptions carry a several-line message after deal.II's header;
     * keep the "Additional information" as one line, with "Line <N> of file <F>:" written
     * as "F:N:" (the file and line of @p file's text(), an included file's included), and the
     * file's text in it shortened (shorten_quoted_input()).
     */
    std::string parameter_handler_message(const std::exception &error, const ParameterFileLocator &file);

    /**
     * The numbered events a parameter file's @p text holds ("subsection Cut 2", "Grasp 3",
     * "Material change 2", ...), in the order of their numbers: they are declared as the
     * first ones are, so that any number of them can be set. A number below 2 is left
     * undeclared (the first event is the subsection without a number): ParameterHandler
     * names it as an unknown subsection.
     */
    std::vector<std::string> numbered_events(const std::string &text, const std::string &kind);
  } // namespace parameters
} // namespace warpchol::app
