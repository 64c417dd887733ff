#include <warpchol/fem/rotations.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

#include <warpchol/base/simd.h>

// What every target shares, compiled once (this file is included again per SIMD target).
#ifndef warpchol_fem_rotations_shared
#define warpchol_fem_rotations_shared
namespace warpchol::fem
{
  Matrix3 rotation_by_svd(const Matrix3 &deformation_gradient)
  {
    // Jacobi SVD is accurate to rounding for 3x3 matrices, also near the identity where
    // the singular values coincide: U and V are then arbitrary but U V^T is not.
    const Eigen::JacobiSVD<Matrix3> svd(deformation_gradient,
                                        Eigen::ComputeFullU | Eigen::ComputeFullV);
    Matrix3 u = svd.matrixU();
    const Matrix3 &v = svd.matrixV();
    // Eigen sorts the singular values in decreasing order: column 2 is the smallest.
    if ((u * v.transpose()).determinant() < 0)
      u.col(2) = -u.col(2);
    return u * v.transpose();
  }

  namespace
  {
    /** Whether rotation_of() takes the SVD for a matrix of determinant @p determinant and squared norm @p size. */
    inline bool inverted_or_flat(const double determinant, const double size)
    {
      return !(determinant > 1e-6 * size * std::sqrt(size));
    }

    /** The cofactor matrix of @p x (det(x) x^-T) and the determinant. */
    inline Matrix3 cofactor(const Matrix3 &x, double &determinant)
    {
      Matrix3 result;
      result.col(0) = x.col(1).cross(x.col(2));
      result.col(1) = x.col(2).cross(x.col(0));
      result.col(2) = x.col(0).cross(x.col(1));
      determinant   = x.col(0).dot(result.col(0));
      return result;
    }
  } // namespace

  Matrix3 rotation_of(const Matrix3 &deformation_gradient)
  {
    const double size = deformation_gradient.squaredNorm();
    double       determinant;
    Matrix3      cof = cofactor(deformation_gradient, determinant);
    // Inverted, flat or zero (or NaN): the SVD and Irving's projection decide.
    if (inverted_or_flat(determinant, size))
      return rotation_by_svd(deformation_gradient);

    Matrix3 x = deformation_gradient;
    for (unsigned int iteration = 0; iteration < 40; ++iteration)
      {
        // X^-T = cof(X) / det X. Scaling equalizes |gamma X| and |X^-T / gamma|, which
        // pulls far-from-orthogonal iterates in fast; near convergence gamma -> 1 and the
        // plain step converges quadratically.
        const double  inverse_determinant = 1 / determinant;
        const double  gamma               = std::sqrt(std::sqrt(cof.squaredNorm() / x.squaredNorm()) *
                                                      std::abs(inverse_determinant));
        const Matrix3 next   = (0.5 * gamma) * x + (0.5 * inverse_determinant / gamma) * cof;
        const double  change = (next - x).squaredNorm();
        x                    = next;
        // Quadratic convergence: a change of 1e-9 leaves an error of about 1e-18.
        if (change < 1e-18)
          return x;
        cof = cofactor(x, determinant);
        if (!(determinant > 0))
          break;
      }
    return rotation_by_svd(deformation_gradient);
  }

  std::size_t RotationPaths::total() const
  {
    return lanes + newton + svd;
  }

  RotationPaths &RotationPaths::operator+=(const RotationPaths &other)
  {
    lanes += other.lanes;
    newton += other.newton;
    svd += other.svd;
    return *this;
  }

} // namespace warpchol::fem
#endif

// The batched polar decomposition, once per SIMD target (Highway's foreach_target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "fem/rotations.cc"
#include <hwy/foreach_target.h>
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace warpchol::fem::HWY_NAMESPACE
{
  namespace
  {
    /** Matrices side by side: entry i (column-major) of lane l is value[i][l]. */
    constexpr std::size_t lanes = 8;
    using LaneMatrix            = double[9][lanes];
    using LaneScalar            = double[lanes];

    /**
     * Newton steps of the batched iteration, the first ones scaled: enough for strains of
     * about 30 %. Up to the most steps while a lane that can converge has not (scaled:
     * such a lane is still far from orthogonal); a lane that needs more takes the scalar
     * path.
     */
    constexpr unsigned int batched_newton_steps = 5;
    constexpr unsigned int batched_scaled_steps = 2;
    constexpr unsigned int batched_most_steps   = 12;

    /**
     * One Newton step on every lane: x <- (gamma x + cof(x) / (gamma det x)) / 2, with
     * Frobenius scaling if @p scaled, else gamma = 1 (near convergence the scaling is 1 to
     * within the error, and its square roots are the slowest operations of the step).
     */
    inline void newton_step(LaneMatrix &x, LaneScalar &determinant, LaneScalar &change, const bool scaled)
    {
      alignas(64) LaneMatrix cof;
      for (std::size_t l = 0; l < lanes; ++l)
        {
          // Columns (0,1,2) at entries (0-2, 3-5, 6-8); cof column j = x_{j+1} x x_{j+2}.
          cof[0][l] = x[4][l] * x[8][l] - x[5][l] * x[7][l];
          cof[1][l] = x[5][l] * x[6][l] - x[3][l] * x[8][l];
          cof[2][l] = x[3][l] * x[7][l] - x[4][l] * x[6][l];
          cof[3][l] = x[7][l] * x[2][l] - x[8][l] * x[1][l];
          cof[4][l] = x[8][l] * x[0][l] - x[6][l] * x[2][l];
          cof[5][l] = x[6][l] * x[1][l] - x[7][l] * x[0][l];
          cof[6][l] = x[1][l] * x[5][l] - x[2][l] * x[4][l];
          cof[7][l] = x[2][l] * x[3][l] - x[0][l] * x[5][l];
          cof[8][l] = x[0][l] * x[4][l] - x[1][l] * x[3][l];
          determinant[l] = x[0][l] * cof[0][l] + x[1][l] * cof[1][l] + x[2][l] * cof[2][l];
        }
      alignas(64) LaneScalar x_weight, cof_weight;
      if (!scaled)
        for (std::size_t l = 0; l < lanes; ++l)
          {
            x_weight[l]   = 0.5;
            cof_weight[l] = 0.5 / determinant[l];
          }
      else
      for (std::size_t l = 0; l < lanes; ++l)
        {
          double x_norm = 0, cof_norm = 0;
          for (unsigned int i = 0; i < 9; ++i)
            {
              x_norm += x[i][l] * x[i][l];
              cof_norm += cof[i][l] * cof[i][l];
            }
          // An inverted or flat lane gets a NaN here and is redone by rotation_of().
          const double gamma = std::sqrt(std::sqrt(cof_norm / x_norm) / determinant[l]);
          x_weight[l]        = 0.5 * gamma;
          cof_weight[l]      = 0.5 / (gamma * determinant[l]);
        }
      for (std::size_t l = 0; l < lanes; ++l)
        change[l] = 0;
      for (unsigned int i = 0; i < 9; ++i)
        for (std::size_t l = 0; l < lanes; ++l)
          {
            const double next = x_weight[l] * x[i][l] + cof_weight[l] * cof[i][l];
            change[l] += (next - x[i][l]) * (next - x[i][l]);
            x[i][l] = next;
          }
    }
  } // namespace

  /**
   * The rotations of the @p used (<= 8) deformation gradients laid out lane by lane in
   * @p gradients (entry i of lane l at [i][l]) into @p rotations, laid out alike: the
   * batched iteration on the lanes (those past @p used are the identity, which converges
   * at once, so that every matrix takes the same path wherever the threads' ranges split
   * the elements), the scalar path for a lane it leaves unconverged. The fused pass calls
   * this on its own lanes, rotations_of() on matrices it lays out first.
   */
  void RotationLanes(const LaneMatrix &gradients, const std::size_t used, LaneMatrix &rotations, RotationPaths &taken)
  {
    LaneMatrix &x = rotations;
    alignas(64) LaneScalar determinant, change, size;
    for (std::size_t l = 0; l < lanes; ++l)
      for (unsigned int i = 0; i < 9; ++i)
        x[i][l] = l < used ? gradients[i][l] : i % 4 == 0 ? 1. : 0.;
    for (std::size_t l = 0; l < lanes; ++l)
      {
        size[l] = 0;
        for (unsigned int i = 0; i < 9; ++i)
          size[l] += x[i][l] * x[i][l];
      }
    newton_step(x, determinant, change, true);
    // The first determinant is det F: rotation_of()'s test for the SVD fallback.
    alignas(64) LaneScalar initial_determinant;
    for (std::size_t l = 0; l < lanes; ++l)
      initial_determinant[l] = determinant[l];
    for (unsigned int step = 1; step < batched_newton_steps; ++step)
      newton_step(x, determinant, change, step < batched_scaled_steps);
    // More steps while a lane that can converge has not (an inverted or flat one
    // cannot: its NaNs would keep the group iterating for nothing). A lane that has
    // converged keeps its value: each rotation is then that of its own matrix after as
    // many steps as it needed, whatever the other lanes of its group.
    bool converged[lanes];
    for (std::size_t l = 0; l < lanes; ++l)
      converged[l] = inverted_or_flat(initial_determinant[l], size[l]) || change[l] < 1e-18;
    for (unsigned int step = batched_newton_steps;
         step < batched_most_steps && std::find(converged, converged + lanes, false) != converged + lanes; ++step)
      {
        alignas(64) LaneMatrix before;
        std::copy(&x[0][0], &x[0][0] + 9 * lanes, &before[0][0]);
        newton_step(x, determinant, change, true);
        for (std::size_t l = 0; l < lanes; ++l)
          {
            if (converged[l])
              for (unsigned int i = 0; i < 9; ++i)
                x[i][l] = before[i][l];
            else
              converged[l] = change[l] < 1e-18;
          }
      }
    for (std::size_t l = 0; l < used; ++l)
      {
        // Converged where the last change was below 1e-9 (error about 1e-18), as
        // rotation_of() requires; any other lane takes the scalar path.
        const bool flat = inverted_or_flat(initial_determinant[l], size[l]);
        if (!flat && converged[l])
          ++taken.lanes;
        else
          {
            Matrix3 gradient;
            for (unsigned int i = 0; i < 9; ++i)
              gradient.data()[i] = gradients[i][l];
            const Matrix3 rotation = rotation_of(gradient);
            for (unsigned int i = 0; i < 9; ++i)
              x[i][l] = rotation.data()[i];
            ++(flat ? taken.svd : taken.newton);
          }
      }
  }

  /** rotations_of() on this target. */
  void RotationsOf(const Matrix3 *gradients, Matrix3 *rotations, const std::size_t count, RotationPaths *paths)
  {
    RotationPaths taken;
    for (std::size_t k = 0; k < count; k += lanes)
      {
        const std::size_t used = std::min(lanes, count - k);
        alignas(64) LaneMatrix f = {}, r;
        for (std::size_t l = 0; l < used; ++l)
          for (unsigned int i = 0; i < 9; ++i)
            f[i][l] = gradients[k + l].data()[i];
        RotationLanes(f, used, r, taken);
        for (std::size_t l = 0; l < used; ++l)
          for (unsigned int i = 0; i < 9; ++i)
            rotations[k + l].data()[i] = r[i][l];
      }
    if (paths != nullptr)
      *paths += taken;
  }
} // namespace warpchol::fem::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace warpchol::fem
{
  HWY_EXPORT(RotationsOf);

  void rotations_of(const Matrix3 *gradients, Matrix3 *rotations, const std::size_t count, RotationPaths *paths)
  {
    simd::use_target_from_environment();
    HWY_DYNAMIC_DISPATCH(RotationsOf)(gradients, rotations, count, paths);
  }
} // namespace warpchol::fem
#endif
