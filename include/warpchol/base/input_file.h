#pragma once

#include <fstream>
#include <string>

/**
 * @file
 * Opening an input file (a mesh, a parameter file, a matrix) with one line that says why
 * it cannot be read: missing, unreadable, or a directory, which a stream opens without
 * complaint and then reads as an empty file.
 */
namespace warpchol
{
  /**
   * Throw InputError unless @p filename names something that can be read as a file:
   * "FILE: cannot open the WHAT" if it does not exist or cannot be read, "FILE: is a
   * directory, not a WHAT" for a directory. @p what names the file's role ("mesh file").
   */
  void check_input_file(const std::string &filename, const std::string &what);

  /** check_input_file(), then the file opened for reading (binary: no conversion). */
  std::ifstream open_input_file(const std::string &filename, const std::string &what);
} // namespace warpchol
