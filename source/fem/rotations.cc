#include <warpchol/fem/rotations.h>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace warpchol::fem
{
  Matrix3 rotation_of(const Matrix3 &deformation_gradient)
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
} // namespace warpchol::fem
