#pragma once

#include <string>

/**
 * @file
 * Short number formatting for one-line messages.
 */
namespace warpchol
{
  /** @p value with @p digits significant digits ("%.*g"): 1.5e-08, 42, nan, inf. */
  std::string format_number(double value, int digits = 6);
} // namespace warpchol
