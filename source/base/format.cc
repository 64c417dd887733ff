#include <warpchol/base/format.h>

#include <cstdio>

namespace warpchol
{
  std::string format_number(const double value, const int digits)
  {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.*g", digits, value);
    return buffer;
  }
} // namespace warpchol
