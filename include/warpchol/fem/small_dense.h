#pragma once

#include <Eigen/Core>

/**
 * @file
 * The small dense matrices of the element computations, with Eigen's fixed-size types:
 * 3x3 rotations and deformation gradients, the 12x12 matrices of a tetrahedron (4
 * vertices x 3 components, numbered 3 a + c for local vertex a and component c).
 */
namespace warpchol::fem
{
  using Vector3 = Eigen::Vector3d;
  using Matrix3 = Eigen::Matrix3d;

  /** A 12x12 matrix of one tetrahedron, rows and columns 3 a + c (vertex a, component c). */
  using ElementMatrix = Eigen::Matrix<double, 12, 12>;
  /** A vector on the 4 vertices of one tetrahedron, entries 3 a + c. */
  using ElementVector = Eigen::Matrix<double, 12, 1>;
} // namespace warpchol::fem
