// ContactCompliance: a contact step's W factored as D^T G D (G the block of A^-1 among the
// contact vertices' unknowns, SparseCholesky::inverse_block(); D each contact's directions
// on its vertices, weighted) is the W of H A^-1 H^T from full solves, entry by entry
// (matrix()) and as a product (times()), to 1e-12 relative; projected Gauss-Seidel with the
// friction cone on it gives the impulses it gives on the whole W, to 1e-12, in the same
// sweeps. On the tests' elasticity torus: 30 contacts on single vertices, on edges and
// triangles (2 and 3 vertices by barycentric weights) and two on the same vertex, with
// random orthonormal directions. A whole W that is not m x m is refused.

#include <warpchol/cholesky/sparse_cholesky.h>
#include <warpchol/contact/contact_compliance.h>
#include <warpchol/contact/friction_cone_solver.h>

#include "tests.h"
#include "torus_elasticity.h"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <unordered_map>

using namespace warpchol;

int main()
{
  tests::TorusElasticity   torus;
  const sparse::CSCMatrix  matrix = torus.system->lower();
  const Index              n      = matrix.n_cols;
  cholesky::SparseCholesky solver = tests::supernodal_metis_solver();
  solver.factorize(matrix);

  // 30 contacts: 1, 2 or 3 vertices each (the last one on the first contact's vertex).
  tests::Random                           random(41);
  const Index                             n_contacts = 30;
  std::unordered_map<Index, Index>        slot_of_vertex;
  std::vector<Index>                      unknowns;
  std::vector<fem::ContactCompliance::ContactRows> contacts(n_contacts);
  // H^T: A's unknowns x 3 rows per contact.
  Eigen::MatrixXd ht = Eigen::MatrixXd::Zero(n, 3 * n_contacts);
  Index           first_vertex = -1;
  for (Index j = 0; j < n_contacts; ++j)
    {
      const Eigen::Matrix3d directions =
        Eigen::Matrix3d::NullaryExpr([&]() { return random.uniform() - 0.5; }).householderQr().householderQ();
      const unsigned int  n_parts = j == n_contacts - 1 ? 1 : 1 + static_cast<unsigned int>(j % 3);
      std::vector<double> weights(n_parts, 1.);
      if (n_parts > 1)
        {
          double sum = 0;
          for (double &w : weights)
            sum += (w = 0.1 + random.uniform());
          for (double &w : weights)
            w /= sum;
        }
      for (unsigned int k = 0; k < n_parts; ++k)
        {
          Index vertex = j == n_contacts - 1 ? first_vertex : random.below(n / 3);
          if (first_vertex < 0)
            first_vertex = vertex;
          const auto [place, added] = slot_of_vertex.emplace(vertex, static_cast<Index>(unknowns.size() / 3));
          if (added)
            for (Index c = 0; c < 3; ++c)
              unknowns.push_back(3 * vertex + c);
          fem::ContactCompliance::VertexRows &part = contacts[j].parts[contacts[j].n_parts++];
          part.slot                                = place->second;
          part.rows                                = weights[k] * directions;
          for (Index c = 0; c < 3; ++c)
            for (Index r = 0; r < 3; ++r)
              ht(3 * vertex + r, 3 * j + c) += part.rows(r, c);
        }
    }
  std::cout << "torus elasticity: n = " << n << "; " << n_contacts << " contacts on " << unknowns.size() / 3
            << " vertices" << std::endl;

  // W = H A^-1 H^T from full solves.
  const Index        m = 3 * n_contacts;
  Eigen::MatrixXd    x = ht;
  solver.solve(x.data(), x.data(), m);
  const Eigen::MatrixXd whole_matrix = ht.transpose() * x;
  const std::vector<double> whole(whole_matrix.data(), whole_matrix.data() + m * m);

  cholesky::KeptInverseColumns columns;
  solver.inverse_block(unknowns, columns);
  const fem::ContactCompliance factored = fem::ContactCompliance::factored(columns.gram, contacts);
  const fem::ContactCompliance given    = fem::ContactCompliance::whole(whole);
  tests::check_below("max |W factored - W from solves| / max |W|", tests::max_relative_difference(factored.matrix(), whole),
                     1e-12);
  bool blocks_equal = true;
  for (Index j = 0; j < n_contacts; ++j)
    blocks_equal = blocks_equal && (factored.diagonal_block(j) - given.diagonal_block(j)).norm() <=
                                     1e-12 * given.diagonal_block(j).norm();
  tests::check("the diagonal blocks agree to 1e-12", blocks_equal);

  std::vector<double> lambda(m);
  for (double &value : lambda)
    value = random.uniform() - 0.5;
  tests::check_below("max |W lambda factored - whole| / max |W lambda|",
                     tests::max_relative_difference(factored.times(lambda), given.times(lambda)), 1e-12);

  // Pressed in at 1 cm/s with a sideways slide, friction 0.5: some contacts stick, some slide.
  std::vector<double> free_velocity(m), friction(n_contacts, 0.5);
  for (Index j = 0; j < n_contacts; ++j)
    {
      free_velocity[3 * j]     = j % 4 == 3 ? 0.01 : -0.01; // every fourth separates
      free_velocity[3 * j + 1] = 0.002 * std::cos(j);
      free_velocity[3 * j + 2] = 0.002 * std::sin(j);
    }
  fem::GaussSeidelSettings gauss_seidel;
  gauss_seidel.tolerance      = 1e-12;
  gauss_seidel.max_iterations = 2000;
  std::vector<double>           lambda_factored, lambda_whole;
  const fem::GaussSeidelResult by_factored =
    fem::solve_friction_cone(factored, free_velocity, friction, gauss_seidel, lambda_factored);
  const fem::GaussSeidelResult by_whole =
    fem::solve_friction_cone(given, free_velocity, friction, gauss_seidel, lambda_whole);
  tests::check("Gauss-Seidel converges on both", by_factored.converged && by_whole.converged);
  tests::check("in the same sweeps", by_factored.iterations == by_whole.iterations);
  tests::check_below("max |lambda factored - whole| / max |lambda|", tests::max_relative_difference(lambda_factored, lambda_whole),
                     1e-12);
  Index active = 0;
  for (Index j = 0; j < n_contacts; ++j)
    active += lambda_whole[3 * j] > 0;
  tests::check("contacts both press and separate", active > 0 && active < n_contacts);

  tests::expect_error("a W of 10 entries", [] { fem::ContactCompliance::whole(std::vector<double>(10, 1.)); });
}
