#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

/**
 * @file
 * Writing a file so that no reader ever sees it half-written, and so that a failed write
 * (a full disk) is reported on one line and leaves what was there.
 */
namespace warpchol
{
  /**
   * Call @p write on a stream opened on a temporary file next to @p filename, then rename
   * the temporary over @p filename. If @p write throws or a write fails, the temporary is
   * removed, @p filename is left as it was, and the error propagates.
   *
   * Every write to the file is checked, and so are the last flush and the close: a failed
   * one throws OutputError "FILE: no space left on device (wrote W of N bytes)" (the
   * system's reason, the bytes that reached the file and those @p write produced). After
   * a failure the stream stays good and counts what @p write still produces, so that a
   * writer that checks its stream (deal.II's do) does not throw an exception of its own.
   *
   * A @p filename that exists and is not a regular file (a device such as /dev/stdout or
   * /dev/full, a pipe) is written directly: there is nothing to replace, and a rename
   * would replace the device itself. A directory is an OutputError.
   */
  void write_file_atomically(const std::string                        &filename,
                             const std::function<void(std::ostream &)> &write);

  /**
   * Remove from @p directory the temporary files that write_file_atomically() left there
   * for processes that no longer run (NAME.tmp.PID: a run killed while it wrote NAME). Those
   * of a process that runs, this one's or another writer's, stay; so does what cannot be
   * removed. Returns how many were removed.
   */
  std::size_t remove_stale_temporaries(const std::string &directory);
} // namespace warpchol
