#pragma once

#include <warpchol/fem/small_dense.h>

#include <cstddef>

/**
 * @file
 * Rotations of deformed elements: the rotation factor of the polar decomposition, made
 * robust to inverted elements.
 */
namespace warpchol::fem
{
  /**
   * The rotation R of the polar decomposition F = R S (S symmetric), computed through the
   * singular value decomposition F = U Sigma V^T as R = U V^T.
   *
   * When det F < 0 (an inverted element) U V^T would be a reflection; following Irving,
   * Teran and Fedkiw (2004, "Invertible finite elements"), the sign of the column of U that
   * belongs to the smallest singular value is flipped, so the result is always a proper
   * rotation (det R = +1) and the element is treated as inverted along its thinnest
   * direction. The same projection turns a volume-weighted sum of rotations into the
   * nearest rotation (the nodal rotations of stiffness warping).
   *
   * About 1 us per call (Jacobi SVD): the reference and the fallback of rotation_of().
   */
  Matrix3 rotation_by_svd(const Matrix3 &deformation_gradient);

  /**
   * The same rotation as rotation_by_svd(), fast: Higham's Newton iteration for the polar
   * factor, X <- (gamma X + X^-T / gamma) / 2 from X = F with Frobenius-norm scaling gamma,
   * which converges quadratically to R for any F with det F > 0 (4 to 6 iterations for
   * the strains of soft tissue; about 60 ns). X^-T is the cofactor matrix over det X: no
   * pivoting, no square root but the scaling's.
   *
   * Where the iteration does not apply or would lose accuracy it falls back to the SVD,
   * so Irving's handling is unchanged: an inverted element (det F <= 0), a nearly flat
   * one (det F below 1e-6 |F|^3), or no convergence in 40 iterations.
   */
  Matrix3 rotation_of(const Matrix3 &deformation_gradient);

  /**
   * Which path the rotations of rotations_of() took: the SIMD lanes, the scalar Newton
   * iteration of rotation_of() (a lane that had not converged after the lanes' most steps:
   * a very large strain), or the SVD (inverted or nearly flat: Irving's projection).
   * Counts add up over calls.
   */
  struct RotationPaths
  {
    std::size_t lanes  = 0;
    std::size_t newton = 0;
    std::size_t svd    = 0;

    std::size_t     total() const;
    RotationPaths &operator+=(const RotationPaths &other);
  };

  /**
   * rotations[k] = rotation_of(gradients[k]) for k < @p count, the same results, faster:
   * eight matrices at a time, one per SIMD lane (their entries laid out lane by lane so
   * that the compiler vectorizes every operation of the iteration across the eight; a
   * last group of fewer is padded with the identity). Five Newton steps without branches,
   * then, while a lane that can converge has not, up to seven more on the group (a large
   * strain: a thin body bent far, an overloaded one), a converged lane keeping its value,
   * so that each result depends on its own matrix alone (not on the threads' ranges);
   * then rotation_of() for any lane that still needs more, or its fallback (inverted,
   * flat). One Newton step is a chain of dependent operations (cofactors, determinant,
   * square roots, division): eight independent chains side by side keep the pipelines
   * full. Where each rotation went is added to @p paths, if given.
   *
   * No warm start from the last step's rotation: the iteration's speed depends on the
   * singular values of F alone (each Newton step maps sigma to (sigma + 1/sigma) / 2),
   * which a rotation of F changes not at all.
   */
  void rotations_of(const Matrix3 *gradients, Matrix3 *rotations, std::size_t count,
                    RotationPaths *paths = nullptr);
} // namespace warpchol::fem
