// The fast polar decomposition (scaled Newton iteration, SVD fallback), one by one and in
// SIMD batches, gives the rotation of the SVD-based one, with Irving's handling of inverted
// elements, to 1e-12 on random, near-identity, near-singular and inverted deformation
// gradients; every result is a proper rotation. The batches say which path each matrix
// took (the lanes, the scalar Newton iteration, the SVD), and a matrix gets the same bits
// wherever it sits in a batch (the threads' ranges split the elements anywhere).

#include "tests.h"

#include <warpchol/fem/rotations.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

using namespace warpchol;

namespace
{
  fem::Matrix3 random_rotation(tests::Random &random)
  {
    const fem::Vector3 axis(2 * random.uniform() - 1, 2 * random.uniform() - 1, 2 * random.uniform() - 1);
    return Eigen::AngleAxisd(6.3 * random.uniform(), axis.normalized()).toRotationMatrix();
  }

  /** U diag(s) V^T with random rotations U, V. */
  fem::Matrix3 with_singular_values(tests::Random &random, const fem::Vector3 &singular_values)
  {
    return random_rotation(random) * singular_values.asDiagonal() * random_rotation(random).transpose();
  }

  /**
   * Print the largest |fast - svd| of rotation_of() and of the batched rotations_of(), and
   * whether every fast result is a rotation.
   */
  void compare(const std::string &label, const std::vector<fem::Matrix3> &gradients)
  {
    std::vector<fem::Matrix3> batched(gradients.size());
    fem::RotationPaths        paths;
    fem::rotations_of(gradients.data(), batched.data(), gradients.size(), &paths);
    std::cout << label << ": " << gradients.size() << " matrices, lanes " << paths.lanes << ", scalar Newton "
              << paths.newton << ", SVD " << paths.svd << std::endl;
    // The same matrices one position later (another group of eight each, the last group
    // padded): the same bits.
    std::vector<fem::Matrix3> shifted(gradients.size() + 1, fem::Matrix3::Identity()), shifted_rotations(shifted.size());
    std::copy(gradients.begin(), gradients.end(), shifted.begin() + 1);
    fem::rotations_of(shifted.data(), shifted_rotations.data(), shifted.size());
    tests::check(label + ": the same bits one position later in the batch",
                 std::equal(batched.begin(), batched.end(), shifted_rotations.begin() + 1));
    double difference = 0, batch_difference = 0, not_rotation = 0;
    for (std::size_t k = 0; k < gradients.size(); ++k)
      {
        const fem::Matrix3 fast = fem::rotation_of(gradients[k]);
        const fem::Matrix3 svd  = fem::rotation_by_svd(gradients[k]);
        difference              = std::max(difference, (fast - svd).norm());
        batch_difference        = std::max(batch_difference, (batched[k] - svd).norm());
        for (const auto &r : {fast, batched[k]})
          not_rotation = std::max({not_rotation, (r.transpose() * r - fem::Matrix3::Identity()).norm(),
                                   std::abs(r.determinant() - 1)});
      }
    tests::check_below(label + ": |R_fast - R_svd|", difference, 1e-12);
    tests::check_below(label + ": |R_batched - R_svd|", batch_difference, 1e-12);
    tests::check_below(label + ": |R^T R - I| and |det R - 1|", not_rotation, 1e-13);
  }
} // namespace

int main()
{
  tests::Random random(7);
  const unsigned int n = 20000;

  std::vector<fem::Matrix3> uniform, near_identity, stretched, near_singular, flat, inverted, mildly_inverted;
  for (unsigned int k = 0; k < n; ++k)
    {
      fem::Matrix3 f;
      for (unsigned int i = 0; i < 9; ++i)
        f.data()[i] = 2 * random.uniform() - 1;
      // Keep the well-posed ones: a polar factor exists and is unique where the two
      // smallest singular values do not both vanish.
      if (std::abs(f.determinant()) > 1e-3)
        (f.determinant() > 0 ? uniform : inverted).push_back(f);

      fem::Matrix3 small;
      for (unsigned int i = 0; i < 9; ++i)
        small.data()[i] = 1e-6 * (2 * random.uniform() - 1);
      near_identity.push_back(random_rotation(random) * (fem::Matrix3::Identity() + small));

      // Soft tissue: stretches and compressions up to a factor 3.
      stretched.push_back(with_singular_values(
        random, fem::Vector3(0.33 + 2.7 * random.uniform(), 0.33 + 2.7 * random.uniform(), 0.33 + 2.7 * random.uniform())));
      // Nearly flat: the Newton iteration (1e-4) and the SVD fallback (1e-9).
      near_singular.push_back(with_singular_values(random, fem::Vector3(1 + random.uniform(), 0.5, 1e-4)));
      flat.push_back(with_singular_values(random, fem::Vector3(1 + random.uniform(), 0.5, 1e-9)));
      // Pushed through a face: det < 0, by a little or a lot.
      mildly_inverted.push_back(with_singular_values(random, fem::Vector3(1, 0.9, -1e-3 - 0.5 * random.uniform())));
    }
  compare("random, det > 0", uniform);
  compare("random, det < 0", inverted);
  compare("near the identity", near_identity);
  compare("stretched", stretched);
  compare("near-singular (sigma_min 1e-4)", near_singular);
  compare("flat (sigma_min 1e-9)", flat);
  compare("inverted", mildly_inverted);
  // Large strains (an overloaded body, a thin one bent far): the lanes take more steps
  // before any leaves them for the scalar path.
  std::vector<fem::Matrix3> large_strain;
  for (unsigned int k = 0; k < n; ++k)
    large_strain.push_back(with_singular_values(
      random, fem::Vector3(std::pow(10., 2 * random.uniform() - 1), std::pow(10., 2 * random.uniform() - 1),
                           std::pow(10., 2 * random.uniform() - 1))));
  compare("large strain (stretches 0.1 to 10)", large_strain);
  // Batches that mix the easy lanes with those that need the scalar path.
  std::vector<fem::Matrix3> mixed;
  for (unsigned int k = 0; k < 1000; ++k)
    for (const auto *set : {&near_identity, &flat, &stretched, &mildly_inverted, &uniform})
      mixed.push_back((*set)[k]);
  compare("mixed batches", mixed);

  // Irving: an element inverted along z keeps the rotation and reflects only along z.
  const fem::Matrix3 rotation = random_rotation(random);
  fem::Matrix3       inverted_along_z = fem::Matrix3::Identity();
  inverted_along_z(2, 2)              = -0.2;
  tests::check_below("inverted along its thinnest direction: R = the rotation",
                     (fem::rotation_of(rotation * inverted_along_z) - rotation).norm(), 1e-12);
  tests::check_below("exact rotation: R = F", (fem::rotation_of(rotation) - rotation).norm(), 1e-14);
}
