#include "servo/pbvs.h"

#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/visual_features/vpFeatureThetaU.h>
#include <visp3/visual_features/vpFeatureTranslation.h>
#include <visp3/vs/vpServo.h>

#include "core/conversions.h"

namespace aerograsp {

struct PbvsTask::Impl {
  // ViSP's "camera" c is our end effector e and its "desired camera" cd is g:
  // the features are built from cdMc = gMe.
  vpFeatureTranslation t{vpFeatureTranslation::cdMc};
  vpFeatureThetaU tu{vpFeatureThetaU::cdRc};
  vpServo task;

  explicit Impl(double gain) {
    task.setServo(vpServo::EYEINHAND_CAMERA);
    task.setInteractionMatrixType(vpServo::CURRENT);
    task.setLambda(gain);
    task.addFeature(t);
    task.addFeature(tu);
  }
};

PbvsTask::PbvsTask(double gain_per_s) : impl_(std::make_unique<Impl>(gain_per_s)) {}
PbvsTask::~PbvsTask() = default;
PbvsTask::PbvsTask(PbvsTask&&) noexcept = default;
PbvsTask& PbvsTask::operator=(PbvsTask&&) noexcept = default;

Eigen::Matrix<double, 6, 1> PbvsTask::Twist(const Eigen::Isometry3d& bMe,
                                            const Eigen::Isometry3d& bMg) {
  const vpHomogeneousMatrix gMe = ToVisp(bMg.inverse() * bMe);
  impl_->t.buildFrom(gMe);
  impl_->tu.buildFrom(gMe);
  const vpColVector v_e = impl_->task.computeControlLaw();  // twist of e, in e
  const Eigen::Matrix3d bRe = bMe.linear();
  Eigen::Matrix<double, 6, 1> twist_b;
  twist_b.head<3>() = bRe * Eigen::Vector3d(v_e[0], v_e[1], v_e[2]);
  twist_b.tail<3>() = bRe * Eigen::Vector3d(v_e[3], v_e[4], v_e[5]);
  return twist_b;
}

}  // namespace aerograsp
