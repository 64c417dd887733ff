// A Matrix Market header is checked against the file and the memory before anything is
// allocated for it: a header that announces more entries than the rest of the file can
// hold (an entry line takes at least 6 bytes), or a matrix larger than the machine's
// memory, is refused with one line naming the file and the line of the header, not with
// std::bad_alloc. (tools/warpchol-factor.huge_header checks the program's exit status.)

#include <warpchol/sparse/matrix_market.h>

#include "simulation_tests.h"

#include <regex>
#include <sstream>

using namespace warpchol;

namespace
{
  void read_text(const std::string &label, const std::string &text)
  {
    tests::expect_error(label, [&] {
      std::istringstream stream(text);
      sparse::read_matrix_market(stream, "inline.mtx");
    });
  }
} // namespace

int main()
{
  const std::string banner = "%%MatrixMarket matrix coordinate real symmetric\n";

  // SOFA-sized headers over tiny files: the bytes left decide.
  // A copy in the working directory: the message names the file as it was given.
  tests::write_file("huge_header.mtx", tests::read_file(tests::data_file("huge_header.mtx")));
  tests::expect_error("1e9 x 1e9 with 1e12 entries (tests/data/huge_header.mtx)",
                      [] { sparse::read_matrix_market("huge_header.mtx"); });
  read_text("3 entries announced, 2 given in 12 bytes", banner + "3 3 3\n1 1 4\n2 2 4\n");
  // The bound is tight: six bytes hold one entry ("1 1 4\n"), five bytes without the last
  // newline too; ten bytes cannot hold two.
  {
    std::istringstream stream(banner + "2 2 2\n1 1 4\n2 2 4");
    tests::check("2 entries in 11 bytes (the last without its newline) read",
                 sparse::read_matrix_market(stream, "inline.mtx").n_nonzeros() == 2);
  }
  read_text("2 entries in 10 bytes", banner + "2 2 2\n1 1 4\n2 2\n");
  // The size line is the last line, without its newline: nothing is left (a fuzz finding:
  // the end-of-file state hid the size of the file and 5 GB were reserved).
  read_text("2e8 entries after a size line that ends the file", banner + "1 1 214748364");

  // Few entries but 1e15 columns: their starts alone need 8e15 bytes. The machine's memory
  // varies: the message is printed with it replaced by M.
  try
    {
      std::istringstream stream(banner + "1000000000000000 1000000000000000 1\n1 1 1\n");
      sparse::read_matrix_market(stream, "inline.mtx");
      std::cout << "1e15 columns: NO ERROR" << std::endl;
    }
  catch (const Error &error)
    {
      std::cout << "1e15 columns: "
                << std::regex_replace(error.what(), std::regex("the [0-9.e+]+ GB of memory"),
                                      "the M GB of memory")
                << std::endl;
    }

  // A valid file still reads, header check and all.
  std::istringstream valid(banner + "2 2 3\n1 1 4\n2 1 -1\n2 2 4\n");
  const auto         matrix = sparse::read_matrix_market(valid, "valid.mtx");
  tests::check("a valid 2x2 file reads (3 stored entries)", matrix.n_nonzeros() == 3);
}
