// SparseCholesky::compliance(): W = H A^-1 H^T built by forward solves restricted to the
// elimination-tree paths of H's columns (BLAS-3 per supernode) equals SOFA's way (a
// full-length forward solve per row, then the dense product over all n) to 1e-12
// relative, and both equal H x_i with x_i = A^-1 h_i from full solves to 1e-10. On the
// tests' elasticity torus (METIS, supernodal) with contact-like rows (a normal and two
// tangents on one vertex's 3 dofs, vertices repeated so that paths coincide, one row on
// the root's column, one empty row), for m = 1, 3, 48, 150; and on a random SPD matrix.
// A method other than the supernodal one is refused.

#include <warpchol/cholesky/sparse_cholesky.h>

#include "tests.h"
#include "torus_elasticity.h"

#include <cmath>

using namespace warpchol;

namespace
{
  /** m contact-like rows: per vertex chosen at random, 3 rows on its 3 dofs (block_size 3), or single entries (1). */
  sparse::CSCMatrix contact_rows(const Index n, const Index m, const int block_size, const cholesky::SparseCholesky &solver,
                                 const std::uint64_t seed)
  {
    tests::Random     random(seed);
    sparse::CSCMatrix ht = sparse::CSCMatrix::zero(n, m);
    const Index       n_blocks = n / block_size;
    Index             block    = random.below(n_blocks);
    for (Index i = 0; i < m; ++i)
      {
        // A new vertex every 3 rows, sometimes one seen before.
        if (i % 3 == 0)
          block = (i % 9 == 6) ? block : random.below(n_blocks);
        if (i == 1 && m > 3)
          {
            // One row on the column that is eliminated last (the root's).
            ht.row_index.push_back(solver.permutation()[n - 1]);
            ht.values.push_back(1.);
          }
        else if (i == 2 && m > 3)
          {
            // An empty row (a contact direction that touches a fixed vertex only).
          }
        else
          for (int c = 0; c < block_size; ++c)
            {
              ht.row_index.push_back(block * block_size + c);
              ht.values.push_back(2. * random.uniform() - 1.);
            }
        ht.column_start[i + 1] = static_cast<Index>(ht.row_index.size());
      }
    return ht;
  }

  double max_abs(const std::vector<double> &values)
  {
    double largest = 0;
    for (const double v : values)
      largest = std::max(largest, std::abs(v));
    return largest;
  }

  double max_difference(const std::vector<double> &a, const std::vector<double> &b)
  {
    double largest = 0;
    for (std::size_t k = 0; k < a.size(); ++k)
      largest = std::max(largest, std::abs(a[k] - b[k]));
    return largest;
  }

  /** H A^-1 H^T from full solves with the factor: the exact compliance. */
  std::vector<double> compliance_by_solves(const cholesky::SparseCholesky &solver, const sparse::CSCMatrix &ht)
  {
    const Index         n = ht.n_rows, m = ht.n_cols;
    std::vector<double> x(static_cast<std::size_t>(n) * m, 0.);
    for (Index i = 0; i < m; ++i)
      for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
        x[ht.row_index[p] + static_cast<std::size_t>(i) * n] = ht.values[p];
    solver.solve(x.data(), x.data(), m);
    std::vector<double> w(static_cast<std::size_t>(m) * m, 0.);
    for (Index j = 0; j < m; ++j)
      for (Index i = 0; i < m; ++i)
        for (Index p = ht.column_start[i]; p < ht.column_start[i + 1]; ++p)
          w[i + static_cast<std::size_t>(j) * m] += ht.values[p] * x[ht.row_index[p] + static_cast<std::size_t>(j) * n];
    return w;
  }

  void check_matrix(const std::string &name, const sparse::CSCMatrix &matrix, const int block_size)
  {
    cholesky::SparseCholesky::Settings settings;
    settings.ordering.method = cholesky::OrderingMethod::metis;
    settings.method          = cholesky::FactorizationMethod::supernodal;
    cholesky::SparseCholesky solver(settings);
    solver.factorize(matrix);
    std::cout << name << ": n = " << matrix.n_cols << ", " << solver.supernodal_symbolic().n_supernodes()
              << " supernodes" << std::endl;
    for (const Index m : {1, 3, 48, 150})
      {
        const sparse::CSCMatrix   ht    = contact_rows(matrix.n_cols, m, block_size, solver, 17 + m);
        const std::vector<double> paths = solver.compliance(ht);
        const std::vector<double> full  = solver.compliance(ht, cholesky::ComplianceMethod::full_solves);
        const std::vector<double> exact = compliance_by_solves(solver, ht);
        const double              scale = max_abs(full);
        const std::string         prefix = "  m = " + std::to_string(m) + ": ";
        tests::check(prefix + "W is not zero", scale > 0);
        tests::check_below(prefix + "max |W_paths - W_full| / max |W_full|", max_difference(paths, full) / scale, 1e-12);
        tests::check_below(prefix + "max |W_full - H A^-1 H^T| / max |W|", max_difference(full, exact) / scale, 1e-10);
        if (m > 3)
          tests::check(prefix + "the empty row's row of W is zero", [&] {
            for (Index j = 0; j < m; ++j)
              if (paths[2 + static_cast<std::size_t>(j) * m] != 0. || paths[j + 2 * static_cast<std::size_t>(m)] != 0.)
                return false;
            return true;
          }());
      }
  }
} // namespace

int main()
{
  tests::TorusElasticity torus;
  check_matrix("torus elasticity", torus.system->lower(), 3);
  check_matrix("random SPD", tests::random_spd(900, 4, 3), 1);

  cholesky::SparseCholesky::Settings left;
  left.method = cholesky::FactorizationMethod::left_looking;
  cholesky::SparseCholesky simplicial(left);
  const sparse::CSCMatrix  matrix = tests::random_spd(50, 3, 1);
  simplicial.factorize(matrix);
  tests::expect_error("left-looking factor", [&] { simplicial.compliance(sparse::CSCMatrix::zero(50, 2)); });
}
