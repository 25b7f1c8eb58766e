#include "core/conversions.h"

#include <visp3/core/vpHomogeneousMatrix.h>

namespace aerograsp {

vpHomogeneousMatrix ToVisp(const Eigen::Isometry3d& aMb) {
  vpHomogeneousMatrix M;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) M[r][c] = aMb.matrix()(r, c);
  return M;
}

Eigen::Isometry3d FromVisp(const vpHomogeneousMatrix& aMb) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  for (unsigned r = 0; r < 3; ++r)
    for (unsigned c = 0; c < 4; ++c) M.matrix()(r, c) = aMb[r][c];
  return M;
}

Eigen::Matrix4f ToPclMatrix(const Eigen::Isometry3d& aMb) { return aMb.matrix().cast<float>(); }

Eigen::Isometry3d FromPclMatrix(const Eigen::Matrix4f& aMb) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  const Eigen::Matrix3d R = aMb.topLeftCorner<3, 3>().cast<double>();
  M.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  M.translation() = aMb.topRightCorner<3, 1>().cast<double>();
  return M;
}

}  // namespace aerograsp
