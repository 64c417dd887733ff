#pragma once

/**
 * @file
 * Helpers shared by the deal.II-style tests: each test prints what it checks to stdout,
 * which the test driver compares with tests/NAME.output through numdiff.
 *
 * A check prints its verdict ("yes"/"NO"), not a raw rounding-level number, so that the
 * expected output does not depend on the last bits of floating-point arithmetic while a
 * failed check still changes the output and fails the test.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/base/format.h>

#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>

namespace tests
{
  /** Path of a file in tests/data (SOURCE_DIR is defined by deal.II's test macros). */
  inline std::string data_file(const std::string &name)
  {
    return std::string(SOURCE_DIR) + "/data/" + name;
  }

  /** Print "label: value <= bound: yes" (or NO); returns whether the check held. */
  inline bool check_below(const std::string &label, const double value, const double bound)
  {
    const bool holds = value <= bound; // false for NaN as well
    std::cout << label << " <= " << warpchol::format_number(bound, 2) << ": "
              << (holds ? "yes" : "NO") << (holds ? "" : " (" + warpchol::format_number(value) + ")")
              << std::endl;
    return holds;
  }

  /** Print "label: yes" (or NO). */
  inline bool check(const std::string &label, const bool condition)
  {
    std::cout << label << ": " << (condition ? "yes" : "NO") << std::endl;
    return condition;
  }

  /**
   * Run @p action, which must throw a warpchol::Error; print "label: <message>" or
   * "label: NO ERROR". The message is part of the compared output.
   */
  inline void expect_error(const std::string &label, const std::function<void()> &action)
  {
    try
      {
        action();
        std::cout << label << ": NO ERROR" << std::endl;
      }
    catch (const warpchol::Error &error)
      {
        std::cout << label << ": " << error.what() << std::endl;
      }
  }
} // namespace tests
