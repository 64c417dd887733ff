// Every bad input to the solver and the Matrix Market reader is rejected with a one-line
// message that says what and where: non-square or non-symmetric matrices, a matrix that is
// not positive definite (column and pivot value), NaN/Inf values (named as such, also as
// the twin of a stored pair), a changed-column list out of range, an entry outside the
// analyzed pattern, another size or storage, malformed Matrix Market files (with their
// line). A matrix whose pattern is a subset of the analyzed one is accepted: its factor is
// that of the analyzed pattern with explicit zeros, to the bit.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/sparse/conversions.h>
#include <warpchol/sparse/matrix_market.h>

#include "tests.h"

#include <limits>
#include <sstream>

using namespace warpchol;

namespace
{
  sparse::CSCMatrix from_market(const std::string &text)
  {
    std::istringstream stream(text);
    return sparse::read_matrix_market(stream, "inline.mtx");
  }

  const char *tridiagonal = "%%MatrixMarket matrix coordinate real symmetric\n"
                            "4 4 7\n1 1 4\n2 1 -1\n2 2 4\n3 2 -1\n3 3 4\n4 3 -1\n4 4 4\n";
} // namespace

// One bad input after another, in the order of the .output file: a list, not an algorithm.
int main()
{
  std::cout << "solver:" << std::endl;
  tests::expect_error("non-square", [] {
    cholesky::SparseCholesky solver;
    solver.analyze(from_market("%%MatrixMarket matrix coordinate real general\n3 2 1\n1 1 1\n"));
  });
  tests::expect_error("non-symmetric pattern", [] {
    cholesky::SparseCholesky solver;
    solver.analyze(from_market("%%MatrixMarket matrix coordinate real general\n"
                               "2 2 3\n1 1 2\n2 1 1\n2 2 2\n"));
  });
  tests::expect_error("non-symmetric values", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market("%%MatrixMarket matrix coordinate real general\n"
                                 "2 2 4\n1 1 2\n2 1 1\n1 2 1.5\n2 2 2\n"));
  });
  tests::expect_error("not positive definite", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market("%%MatrixMarket matrix coordinate real symmetric\n"
                                 "3 3 5\n1 1 1\n2 1 2\n2 2 1\n3 2 0.5\n3 3 1\n"));
  });
  tests::expect_error("negative diagonal, up-looking", [] {
    cholesky::SparseCholesky::Settings settings;
    settings.method = cholesky::FactorizationMethod::up_looking;
    cholesky::SparseCholesky solver(settings);
    solver.factorize(from_market("%%MatrixMarket matrix coordinate real symmetric\n"
                                 "2 2 2\n1 1 1\n2 2 -3\n"));
  });
  tests::expect_error("NaN value", [] {
    sparse::CSCMatrix a = from_market(tridiagonal);
    a.values[2]         = std::numeric_limits<double>::quiet_NaN();
    cholesky::SparseCholesky solver;
    solver.factorize(a);
  });
  tests::expect_error("infinite value", [] {
    sparse::CSCMatrix a = from_market(tridiagonal);
    a.values[3]         = std::numeric_limits<double>::infinity();
    cholesky::SparseCholesky solver;
    solver.factorize(a);
  });
  tests::expect_error("NaN above the diagonal, both triangles stored", [] {
    sparse::CSCMatrix a = sparse::to_full_storage(from_market(tridiagonal));
    a.values[a.column_start[1]] = std::numeric_limits<double>::quiet_NaN(); // A(0,1)
    cholesky::SparseCholesky solver;
    solver.factorize(a);
  });
  tests::expect_error("NaN below the diagonal, both triangles stored", [] {
    sparse::CSCMatrix a = sparse::to_full_storage(from_market(tridiagonal));
    a.values[1]         = std::numeric_limits<double>::quiet_NaN(); // A(1,0)
    cholesky::SparseCholesky solver;
    solver.factorize(a);
  });
  tests::expect_error("-inf at a later load", [] {
    sparse::CSCMatrix        a = from_market(tridiagonal);
    cholesky::SparseCholesky solver;
    solver.factorize(a);
    a.values[5] = -std::numeric_limits<double>::infinity(); // A(3,2)
    solver.refactorize(a, {2});
  });
  tests::expect_error("changed column out of range", [] {
    const sparse::CSCMatrix  a = from_market(tridiagonal);
    cholesky::SparseCholesky solver;
    solver.factorize(a);
    solver.refactorize(a, {1, 4});
  });
  tests::expect_error("negative changed column", [] {
    const sparse::CSCMatrix  a = from_market(tridiagonal);
    cholesky::SparseCholesky solver;
    solver.factorize(a);
    solver.refactorize(a, {-1});
  });
  tests::expect_error("entry outside the analyzed pattern", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market(tridiagonal));
    solver.refactorize(from_market("%%MatrixMarket matrix coordinate real symmetric\n"
                                   "4 4 7\n1 1 4\n2 1 -1\n4 1 -1\n2 2 4\n3 3 4\n4 3 -1\n4 4 4\n"),
                       {0});
  });
  tests::expect_error("another size than the analyzed one", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market(tridiagonal));
    solver.factorize(from_market("%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n1 1 4\n2 2 4\n3 3 4\n"));
  });
  tests::expect_error("another storage than the analyzed one", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market(tridiagonal));
    solver.factorize(sparse::to_full_storage(from_market(tridiagonal)));
  });
  tests::expect_error("unsorted CSC rows", [] {
    sparse::CSCMatrix a = from_market(tridiagonal);
    std::swap(a.row_index[0], a.row_index[1]);
    cholesky::SparseCholesky solver;
    solver.analyze(a);
  });
  tests::expect_error("solve before factorize", [] {
    cholesky::SparseCholesky solver;
    std::vector<double>      x;
    solver.solve(std::vector<double>(4, 1.), x);
  });
  tests::expect_error("right-hand side of the wrong size", [] {
    cholesky::SparseCholesky solver;
    solver.factorize(from_market(tridiagonal));
    std::vector<double> x;
    solver.solve(std::vector<double>(3, 1.), x);
  });
  tests::expect_error("unknown ordering", [] { cholesky::parse_ordering_method("rcm"); });

  std::cout << "Matrix Market:" << std::endl;
  tests::expect_error("missing file", [] { sparse::read_matrix_market("/nonexistent/a.mtx"); });
  tests::expect_error("empty file", [] { from_market(""); });
  tests::expect_error("bad banner", [] { from_market("%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 1\n"); });
  tests::expect_error("array format", [] { from_market("%%MatrixMarket matrix array real general\n1 1\n1\n"); });
  tests::expect_error("complex field", [] { from_market("%%MatrixMarket matrix coordinate complex general\n1 1 1\n1 1 1 0\n"); });
  tests::expect_error("skew-symmetric", [] { from_market("%%MatrixMarket matrix coordinate real skew-symmetric\n1 1 0\n"); });
  tests::expect_error("bad size line", [] { from_market("%%MatrixMarket matrix coordinate real general\n% comment\n2 two 1\n1 1 1\n"); });
  tests::expect_error("non-square symmetric", [] { from_market("%%MatrixMarket matrix coordinate real symmetric\n2 3 1\n1 1 1\n"); });
  tests::expect_error("entry out of range", [] { from_market("%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n3 1 1\n"); });
  tests::expect_error("value not a number", [] { from_market("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n2 2 1.5x\n"); });
  tests::expect_error("value not finite", [] { from_market("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n2 2 nan\n"); });
  // Values of several digits: bytes enough for the entries announced, which the header
  // check (matrix_market_header_too_large) asks for before these lines are read.
  tests::expect_error("missing value", [] { from_market("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1.000\n2 2\n"); });
  tests::expect_error("truncated file", [] { from_market("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1.000000\n2 2 1.000000\n"); });
  tests::expect_error("too many entries", [] { from_market("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1\n2 2 1\n"); });

  std::cout << "accepted:" << std::endl;
  const sparse::CSCMatrix a = from_market("%%MatrixMarket matrix coordinate integer symmetric\n"
                                          "% an upper entry is mirrored, a repeated one summed\n"
                                          "3 3 5\n1 1 2\n1 2 -1\n2 2 1\n2 2 1\n3 3 2\n");
  tests::check("upper entry mirrored into the lower triangle", a(1, 0) == -1. && a(0, 1) == -1.);
  tests::check("repeated entry summed", a(1, 1) == 2.);

  // The tridiagonal matrix with A(3,2) = A(2,3) = 0 stored, and without it (as arithmetic
  // leaves it): factorize() and refactorize() of the subset give the same bits.
  {
    sparse::CSCMatrix with_zero = from_market(tridiagonal);
    with_zero.values[5]         = 0.; // A(3,2)
    const sparse::CSCMatrix subset =
      from_market("%%MatrixMarket matrix coordinate real symmetric\n"
                  "4 4 6\n1 1 4\n2 1 -1\n2 2 4\n3 2 -1\n3 3 4\n4 4 4\n");
    const std::vector<double> b = {1., 2., 3., 4.};
    // Recomputed, not updated: the same arithmetic whichever is faster at the moment.
    cholesky::SparseCholesky::Settings settings;
    settings.change_method = cholesky::ChangeMethod::recompute;
    std::vector<double>      x_with_zero, x_subset, x_refactorized_with_zero, x_refactorized_subset;
    cholesky::SparseCholesky full_pattern(settings), subset_pattern(settings);
    full_pattern.analyze(from_market(tridiagonal));
    subset_pattern.analyze(from_market(tridiagonal));
    full_pattern.factorize(with_zero);
    full_pattern.solve(b, x_with_zero);
    subset_pattern.factorize(subset);
    subset_pattern.solve(b, x_subset);
    full_pattern.factorize(from_market(tridiagonal));
    full_pattern.refactorize(with_zero, {2, 3});
    full_pattern.solve(b, x_refactorized_with_zero);
    subset_pattern.factorize(from_market(tridiagonal));
    subset_pattern.refactorize(subset, {2, 3});
    subset_pattern.solve(b, x_refactorized_subset);
    tests::check("a subset of the analyzed pattern: the factor of the pattern with explicit zeros, to the bit",
                 x_subset == x_with_zero && x_refactorized_subset == x_refactorized_with_zero);
  }
}
