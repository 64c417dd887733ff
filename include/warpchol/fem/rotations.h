#pragma once

#include <warpchol/fem/small_dense.h>

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
   */
  Matrix3 rotation_of(const Matrix3 &deformation_gradient);
} // namespace warpchol::fem
