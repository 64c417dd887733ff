/**
 * libFuzzer target: the Matrix Market reader (sparse/matrix_market.h), from a stream as
 * warpchol-factor and the tests read it.
 *
 * A malformed file must end in warpchol::Error (InputError naming the line); a file that
 * is read must give a consistent matrix. Anything else (a crash, a sanitizer report, an
 * exception of another kind, a hang) is a finding.
 */

#include <warpchol/base/exceptions.h>
#include <warpchol/sparse/matrix_market.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace
{
  /**
   * True if the size line (the first line after the banner that is neither blank nor a
   * comment) claims more than 2^22 columns. A matrix of n columns rightly takes n + 1
   * column pointers whatever its entries (the reader checks the claim against the
   * machine's memory, not against the fuzzer's 2 GB limit), so such an input is no
   * finding. A claimed number of entries, which the file must hold, goes to the reader:
   * it checks it against the file's size before allocating.
   */
  bool claims_huge_matrix(const std::string &text)
  {
    std::istringstream input(text);
    std::string        line;
    std::getline(input, line); // the banner
    while (std::getline(input, line))
      {
        if (line.find_first_not_of(" \t\r\n\v\f") == std::string::npos || line[0] == '%')
          continue;
        std::istringstream size_line(line);
        long long          n_rows = 0, n_cols = 0;
        size_line >> n_rows >> n_cols;
        constexpr long long limit = 1 << 22;
        return n_cols > limit;
      }
    return false;
  }
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, const std::size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  if (claims_huge_matrix(text))
    return 0;
  std::istringstream stream(text);
  try
    {
      const auto matrix = warpchol::sparse::read_matrix_market(stream, "fuzz.mtx");
      // What the reader returns, the solver trusts: it must be a valid CSC matrix.
      try
        {
          matrix.check_consistency();
        }
      catch (const warpchol::Error &error)
        {
          std::fprintf(stderr, "read_matrix_market returned an inconsistent matrix: %s\n",
                       error.what());
          std::abort();
        }
    }
  catch (const warpchol::Error &)
    {
      // Refused with a message: what a malformed file should get.
    }
  return 0;
}
