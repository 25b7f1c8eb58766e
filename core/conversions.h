// The one place where poses cross between Eigen, ViSP and PCL. This header only
// forward-declares ViSP's type; a caller that uses the ViSP overloads includes
// <visp3/core/vpHomogeneousMatrix.h> itself. PCL's registration works on
// Eigen::Matrix4f, so PCL needs no header here.
#pragma once

#include <Eigen/Geometry>

class vpHomogeneousMatrix;

namespace aerograsp {

vpHomogeneousMatrix ToVisp(const Eigen::Isometry3d& aMb);
Eigen::Isometry3d FromVisp(const vpHomogeneousMatrix& aMb);

/// PCL registration's single-precision 4x4 transform.
Eigen::Matrix4f ToPclMatrix(const Eigen::Isometry3d& aMb);
/// From PCL's 4x4; the rotation is re-orthonormalised (float round-off).
Eigen::Isometry3d FromPclMatrix(const Eigen::Matrix4f& aMb);

}  // namespace aerograsp
