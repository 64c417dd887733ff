#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

/**
 * @file
 * Short number formatting for one-line messages, and quoting what an input file holds in
 * them: a message must stay one short line that a terminal shows as it is, whatever bytes
 * the file holds.
 */
namespace warpchol
{
  /** @p value with @p digits significant digits ("%.*g"): 1.5e-08, 42, nan, inf. */
  std::string format_number(double value, int digits = 6);

  /**
   * @p text with every byte outside printable ASCII written as \\xNN (a tab, a newline or
   * an escape sequence as well), so that it prints as one line and changes no terminal
   * setting.
   */
  std::string printable(std::string_view text);

  /**
   * The start of @p text, printable(), at most @p max_characters long: cut with "..." when
   * longer.
   */
  std::string excerpt(std::string_view text, std::size_t max_characters = 40);

  /**
   * True if @p text looks like binary data rather than text: it holds a NUL byte, or more
   * than a tenth of its bytes are control characters (other than white space) or not
   * valid UTF-8.
   */
  bool looks_binary(std::string_view text);

  /**
   * How a message quotes what an input file holds: "'EXCERPT'" (excerpt()), followed by
   * " (binary data)" if @p text looks_binary(). Every reader quotes through this.
   */
  std::string quote(std::string_view text, std::size_t max_characters = 40);

  /** The choices @p names as a message lists them: "a", "a or b", "a, b or c". */
  std::string alternatives(const std::vector<std::string> &names);
} // namespace warpchol
