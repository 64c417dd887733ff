// The matrix a solver benchmark (warpchol-factor, warpchol-sweep) reads to factor: an empty
// one, a non-square one and a "general" one whose pattern or values are not symmetric are
// bad input, refused in one line naming the file and the entry as the file numbers it
// (from 1); the programs exit with status 2 (tests/CMakeLists.txt). A general file that is
// symmetric, and a symmetric one, are read.

#include "tests.h"

#include <warpchol/sparse/matrix_market.h>

using namespace warpchol;

namespace
{
  void read(const std::string &label, const std::string &filename, const std::string &text)
  {
    std::ofstream(filename) << text;
    tests::print_result_or_error(label, [&] {
      const sparse::CSCMatrix matrix = sparse::read_symmetric_matrix_market(filename);
      return "read, " + std::to_string(matrix.n_rows) + "x" + std::to_string(matrix.n_cols) + ", " +
             std::to_string(matrix.n_nonzeros()) + " entries stored";
    });
  }

  const std::string general = "%%MatrixMarket matrix coordinate real general\n";
} // namespace

int main()
{
  read("0 x 0, symmetric", "empty.mtx", "%%MatrixMarket matrix coordinate real symmetric\n0 0 0\n");
  read("0 x 0, general", "empty_general.mtx", general + "0 0 0\n");
  read("3 x 0", "no_columns.mtx", general + "3 0 0\n");
  read("3 x 2", "not_square.mtx", general + "3 2 1\n1 1 1\n");
  read("(2,1) without (1,2)", "lower_only.mtx", general + "2 2 3\n1 1 2\n2 1 1\n2 2 2\n");
  read("(1,3) without (3,1)", "upper_only.mtx", general + "3 3 4\n1 1 2\n2 2 2\n3 3 2\n1 3 1\n");
  read("A(2,1) != A(1,2)", "values.mtx", general + "2 2 4\n1 1 2\n2 1 1\n1 2 1.5\n2 2 2\n");
  read("general and symmetric", "symmetric_general.mtx",
       general + "3 3 7\n1 1 4\n2 1 -1\n1 2 -1\n2 2 4\n3 2 -1\n2 3 -1\n3 3 4\n");
  read("symmetric", "symmetric.mtx", "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n2 2 1\n");
}
