// WCC's A with a reference rotation per vertex (ContributionFrames) is the same
// preconditioner as with the nodal frames themselves: an exact step's A, assembled in the
// elements' frames of reference P = the step's nodal rotations, is P A' P^T for the A'
// assembled with frames R_v^T Q_e (what a refresh beside the steps makes, reference I), to
// 1e-14 relative; so is it after the solve rotations move on and a few elements are
// re-rotated in both, whose columns re-assembled give the bits of a full assembly whatever
// the elements that share their SIMD groups. With no element re-rotated its assembly gives
// the exact path's very bits, also once the step's rotations, referenced until then, are
// kept before the next step overwrites them; a reference computed later from the element
// rotations is the one the step had.

#include "bar_tests.h"
#include "tests.h"

#include <warpchol/fem/elastic_body.h>
#include <warpchol/fem/system_matrix.h>
#include <warpchol/mesh/mesh_generators.h>
#include <warpchol/models/contribution_frames.h>

#include <deal.II/grid/tria.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include <array>

namespace
{
  using namespace warpchol;

  fem::Matrix3 random_rotation(tests::Random &random, const double largest_angle)
  {
    const fem::Vector3 axis(2 * random.uniform() - 1, 2 * random.uniform() - 1, 2 * random.uniform() - 1);
    return Eigen::AngleAxisd(largest_angle * random.uniform(), axis.normalized()).toRotationMatrix();
  }

  /** The symmetric dense matrix of the lower triangle @p lower. */
  Eigen::MatrixXd dense(const sparse::CSCMatrix &lower)
  {
    Eigen::MatrixXd result = Eigen::MatrixXd::Zero(lower.n_cols, lower.n_cols);
    for (Index j = 0; j < lower.n_cols; ++j)
      for (Index k = lower.column_start[j]; k < lower.column_start[j + 1]; ++k)
        {
          result(lower.row_index[k], j) = lower.values[k];
          result(j, lower.row_index[k]) = lower.values[k];
        }
    return result;
  }

  /** P A P^T with P block diagonal, the rotation @p rotations[v] on the unknowns of vertex v. */
  Eigen::MatrixXd conjugated(const fem::ElasticBody &body, const std::vector<fem::Matrix3> &rotations,
                             const Eigen::MatrixXd &a)
  {
    Eigen::MatrixXd p = Eigen::MatrixXd::Zero(a.rows(), a.cols());
    for (unsigned int v = 0; v < body.n_vertices(); ++v)
      if (!body.is_fixed(v))
        p.block<3, 3>(body.first_unknown(v), body.first_unknown(v)) = rotations[v];
    return p * a * p.transpose();
  }

  double relative_difference(const Eigen::MatrixXd &a, const Eigen::MatrixXd &b)
  {
    return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
  }
} // namespace

int main()
{
  dealii::Triangulation<3> triangulation;
  const std::vector<bool>  fixed =
    tests::bar_held_at_one_end(triangulation, dealii::Point<3>(1, 0.1, 0.15), {{8, 2, 3}});
  for (const auto mass : {fem::MassMatrix::lumped, fem::MassMatrix::consistent})
    {
      std::cout << (mass == fem::MassMatrix::lumped ? "lumped" : "consistent") << " mass:" << std::endl;
      const fem::ElasticBody        body(triangulation, fem::Material{1e5, 0.45, 1000}, mass, fixed);
      const fem::SystemCoefficients coefficients = fem::SystemCoefficients::implicit_euler(0.01, 0.1, 0.05);
      tests::Random                 random(11);

      // The exact step: element rotations Q, nodal rotations R from them.
      std::vector<fem::Matrix3> element_rotations(body.n_elements());
      for (auto &rotation : element_rotations)
        rotation = random_rotation(random, 2);
      std::vector<fem::Matrix3> nodal;
      body.compute_nodal_rotations(element_rotations, nodal);

      // With reference R: A in the elements' frames. With reference I: frames R_v^T Q_e.
      fem::ContributionFrames referenced(body.n_elements()), plain(body.n_elements()), later(body.n_elements());
      referenced.reset(element_rotations, &nodal);
      later.reset(element_rotations, nullptr);
      std::vector<std::array<fem::Matrix3, 4>> frames(body.n_elements());
      for (unsigned int e = 0; e < body.n_elements(); ++e)
        for (unsigned int a = 0; a < 4; ++a)
          frames[e][a] = nodal[body.element_vertices(e)[a]].transpose() * element_rotations[e];
      plain.adopt(frames);

      fem::SystemMatrix exact_path(body, coefficients), with_reference(body, coefficients), without(body, coefficients);
      exact_path.assemble(fem::ElementFrames::rotated(element_rotations));
      with_reference.assemble(referenced.element_frames());
      without.assemble(plain.element_frames());
      tests::check("  no element re-rotated: the exact path's bits",
                   with_reference.lower().values == exact_path.lower().values);
      tests::check_below("  A = P A' P^T, relative difference",
                         relative_difference(dense(with_reference.lower()),
                                             conjugated(body, nodal, dense(without.lower()))),
                         1e-14);
      // The step's rotations, referenced, then kept before the next step overwrites them.
      {
        std::vector<fem::Matrix3> step_rotations = element_rotations;
        fem::ContributionFrames   kept(body.n_elements());
        kept.reset(step_rotations, &nodal);
        kept.keep_rotations(step_rotations);
        std::fill(step_rotations.begin(), step_rotations.end(), fem::Matrix3::Zero());
        fem::SystemMatrix after_overwrite(body, coefficients);
        after_overwrite.assemble(kept.element_frames());
        tests::check("  rotations kept before the next step's overwrite them: the same bits",
                     after_overwrite.lower().values == exact_path.lower().values &&
                       step_rotations.size() == element_rotations.size());
      }

      // Steps later: the nodal rotations moved; every 97th element re-rotated in both (few: re-assembled in part).
      std::vector<fem::Matrix3> moved(body.n_vertices());
      for (unsigned int v = 0; v < body.n_vertices(); ++v)
        moved[v] = random_rotation(random, 0.3) * nodal[v];
      referenced.update_solve_rotations(body, moved);
      plain.update_solve_rotations(body, moved);
      later.update_solve_rotations(body, moved);
      tests::check("  a reference computed later: the step's own bits",
                   later.solve_rotations() == referenced.solve_rotations());
      std::vector<unsigned int> rerotated;
      for (unsigned int e = 2; e < body.n_elements(); e += 97)
        {
          const fem::Matrix3 rotation = random_rotation(random, 0.3) * element_rotations[e];
          referenced.rerotate(e, body.element_vertices(e), rotation);
          plain.rerotate(e, body.element_vertices(e), rotation);
          rerotated.push_back(e);
        }
      with_reference.reassemble(rerotated, referenced.element_frames());
      without.reassemble(rerotated, plain.element_frames());
      tests::check_below("  after re-rotations, A = P A' P^T, relative difference",
                         relative_difference(dense(with_reference.lower()),
                                             conjugated(body, nodal, dense(without.lower()))),
                         1e-14);
      // Elements with frames and without share the SIMD groups differently in a partial and
      // a full assembly: each element's bits must not depend on its group.
      fem::SystemMatrix full(body, coefficients);
      full.assemble(referenced.element_frames());
      tests::check("  re-assembled in part: the very bits of a full assembly",
                   with_reference.lower().values == full.lower().values);
      // S = R P^T on either side of A: S A^-1 S^T = R A'^-1 R^T.
      bool same_solve_rotations = true;
      for (unsigned int v = 0; v < body.n_vertices(); ++v)
        same_solve_rotations = same_solve_rotations &&
                               (referenced.solve_rotations()[v] * nodal[v] - plain.solve_rotations()[v]).norm() < 1e-14;
      tests::check("  S P = R for every vertex (1e-14)", same_solve_rotations);
      // What the error estimate reads: the frames of one element not re-rotated, one re-rotated.
      const auto of_rotated = referenced.of(0);
      const auto of_rerotated = referenced.of(2);
      tests::check("  the frames of an element not re-rotated: its rotation",
                   of_rotated[3] == element_rotations[0] && !(of_rerotated[3] == element_rotations[2]));
    }
}
