#pragma once

#include <functional>
#include <ostream>
#include <string>

/**
 * @file
 * Writing a file so that no reader ever sees it half-written.
 */
namespace warpchol
{
  /**
   * Call @p write on a stream opened on a temporary file next to @p filename, then rename
   * the temporary over @p filename. If @p write throws or the stream fails, the temporary
   * is removed, @p filename is left as it was, and the error propagates (InputError naming
   * the file when the stream failed).
   */
  void write_file_atomically(const std::string                        &filename,
                             const std::function<void(std::ostream &)> &write);
} // namespace warpchol
