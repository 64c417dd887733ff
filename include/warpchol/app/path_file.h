#pragma once

#include <warpchol/surgery/instrument_path.h>

#include <string>

/**
 * @file
 * Instrument paths from files (issue 27): a CSV of time and position, one sample a line,
 * as a haptic device records it (100-1000 Hz).
 */
namespace warpchol::app
{
  /**
   * An instrument path read from a CSV file, with where its samples are, so that a path
   * that does not cover its use is reported at its first or last line.
   *
   * The file: one sample a line, "time, x, y, z" (a tool's or jaws' path) or "time, start
   * x, y, z, end x, y, z" (a blade's two ends), separated by commas; an optional first line
   * of column names (it starts with a letter), empty lines and lines starting with # are
   * skipped. Times in seconds, strictly increasing; positions in metres.
   */
  struct PathFile
  {
    /** The file's name as given (relative to the working directory); empty: no path. */
    std::string         file_name;
    fem::InstrumentPath path;
    /** The lines of the first and the last sample. */
    int                 first_line = 0;
    int                 last_line  = 0;

    /**
     * Read @p file_name, a path of @p n_values values per sample (3 or 6; @p columns
     * names them for the messages: "time, x, y, z"), or of @p n_values + @p optional_values
     * if its first sample has them (then every sample). Throws InputError "FILE:LINE: ..."
     * for a line with another number of columns, a value that is not a finite number, a
     * time not after the one before; "FILE: ..." for a file that cannot be read or holds no
     * sample.
     */
    static PathFile read(const std::string &file_name, unsigned int n_values, const std::string &columns,
                         unsigned int optional_values = 0);

    /**
     * Throw InputError "FILE:LINE: ..." unless the path has samples from @p from to @p to
     * (s): @p use says what uses it then ("Cut 2 (Start time to Start time + Duration)").
     */
    void check_covers(double from, double to, const std::string &use) const;
  };
} // namespace warpchol::app
