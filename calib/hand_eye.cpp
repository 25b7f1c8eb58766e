#include "calib/hand_eye.h"

#include <visp3/vision/vpHandEyeCalibration.h>

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "core/conversions.h"
#include "core/stdout_capture.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

/// eMt from X = cMb: the chordal mean over samples of (cMb bMe_i)^-1 cMt_i.
Eigen::Isometry3d MeanBoardOnGripper(const std::vector<HandEyeSample>& samples,
                                     const Eigen::Isometry3d& cMb) {
  Eigen::Matrix3d sum_R = Eigen::Matrix3d::Zero();
  Eigen::Vector3d sum_t = Eigen::Vector3d::Zero();
  for (const HandEyeSample& s : samples) {
    const Eigen::Isometry3d eMt = (cMb * s.bMe).inverse() * s.cMt;
    sum_R += eMt.linear();
    sum_t += eMt.translation();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum_R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0.0) {
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = -1.0;
    R = svd.matrixU() * D * svd.matrixV().transpose();
  }
  Eigen::Isometry3d eMt = Eigen::Isometry3d::Identity();
  eMt.linear() = R;
  eMt.translation() = sum_t / static_cast<double>(samples.size());
  return eMt;
}

/// Fills the per-sample residuals and the reprojection error of a solution.
void Evaluate(const std::vector<HandEyeSample>& samples, const CameraIntrinsics& K,
              HandEyeResult* r) {
  r->residual_mm.clear();
  r->residual_deg.clear();
  double sq_mm = 0.0, sq_deg = 0.0, sq_px = 0.0;
  std::size_t corners = 0;
  for (const HandEyeSample& s : samples) {
    const Eigen::Isometry3d cMt = r->cMb * s.bMe * r->eMt;
    const PoseError e = ComparePoses(cMt, s.cMt);
    r->residual_mm.push_back(1e3 * e.translation_m);
    r->residual_deg.push_back(kRadToDeg * e.rotation_rad);
    sq_mm += r->residual_mm.back() * r->residual_mm.back();
    sq_deg += r->residual_deg.back() * r->residual_deg.back();
    for (const auto& [p_t, px] : s.corners) {
      const Eigen::Vector3d p_c = cMt * p_t;
      sq_px += (K.Project(p_c) - px).squaredNorm();
      ++corners;
    }
  }
  r->residual_mm_rms = std::sqrt(sq_mm / samples.size());
  r->residual_deg_rms = std::sqrt(sq_deg / samples.size());
  r->reprojection_rms_px = corners ? std::sqrt(sq_px / corners) : 0.0;
}

HandEyeResult Failed(const std::string& method, const std::string& message) {
  HandEyeResult r;
  r.method = method;
  r.message = message;
  return r;
}

/// A small rigid perturbation: rotation vector w (rad) and translation v (m).
Eigen::Isometry3d Exp(const Eigen::Vector3d& w, const Eigen::Vector3d& v) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double angle = w.norm();
  if (angle > 0.0) T.linear() = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  T.translation() = v;
  return T;
}

}  // namespace

PoseSetDiversity MeasureDiversity(const std::vector<HandEyeSample>& samples) {
  PoseSetDiversity d;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    for (std::size_t j = i + 1; j < samples.size(); ++j) {
      const Eigen::AngleAxisd relative(samples[i].bMe.linear().transpose() *
                                       samples[j].bMe.linear());
      d.max_rotation_deg = std::max(d.max_rotation_deg, kRadToDeg * relative.angle());
      if (relative.angle() > 2.0 * M_PI / 180.0)
        scatter += relative.axis() * relative.axis().transpose();
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const double top = eig.eigenvalues().maxCoeff();
  for (int k = 0; k < 3; ++k) d.axis_rank += top > 0.0 && eig.eigenvalues()[k] > 0.02 * top;
  d.least_axis_e = eig.eigenvectors().col(0);  // eigenvalues in increasing order
  return d;
}

std::string DiversityAdvice(const PoseSetDiversity& diversity, std::size_t samples) {
  if (samples < 2) return "take samples with the gripper turned differently";
  if (diversity.max_rotation_deg < 20.0) {
    return "turn the gripper further between samples (at most " +
           std::to_string(static_cast<int>(diversity.max_rotation_deg)) +
           " deg apart so far; 20 or more wanted)";
  }
  if (diversity.axis_rank >= 3) return "";
  int axis = 0;
  diversity.least_axis_e.cwiseAbs().maxCoeff(&axis);
  const char* names[3] = {"its x axis", "its y axis", "its approach axis (z)"};
  return std::string("rotate the gripper more about ") + names[axis];
}

HandEyeResult SolveEyeToHandVisp(const std::vector<HandEyeSample>& samples,
                                 const CameraIntrinsics& K) {
  if (samples.size() < 3) return Failed("visp", "needs at least 3 samples");
  std::vector<vpHomogeneousMatrix> cMo, rMe;
  for (const HandEyeSample& s : samples) {
    cMo.push_back(ToVisp(s.cMt));
    rMe.push_back(ToVisp(s.bMe.inverse()));  // the "robot" pose is eMb
  }
  vpHomogeneousMatrix bMc;
  int status = -1;
  try {
    const StdoutCapture quiet;  // ViSP prints its iterations
    status = vpHandEyeCalibration::calibrate(cMo, rMe, bMc);
  } catch (const vpException& e) {
    return Failed("visp", std::string("vpHandEyeCalibration: ") + e.what());
  }
  if (status != 0)
    return Failed("visp", "vpHandEyeCalibration did not converge (singular pose set?)");
  HandEyeResult r;
  r.method = "visp";
  r.cMb = FromVisp(bMc).inverse();
  if (!IsValidTransform(r.cMb))
    return Failed("visp", "vpHandEyeCalibration returned an invalid transform");
  r.eMt = MeanBoardOnGripper(samples, r.cMb);
  r.ok = true;
  Evaluate(samples, K, &r);
  return r;
}

std::vector<HandEyeResult> SolveEyeToHandOpenCv(const std::vector<HandEyeSample>& samples,
                                                const CameraIntrinsics& K) {
  const std::pair<cv::HandEyeCalibrationMethod, const char*> methods[] = {
      {cv::CALIB_HAND_EYE_TSAI, "opencv-tsai"},
      {cv::CALIB_HAND_EYE_PARK, "opencv-park"},
      {cv::CALIB_HAND_EYE_HORAUD, "opencv-horaud"},
      {cv::CALIB_HAND_EYE_ANDREFF, "opencv-andreff"},
      {cv::CALIB_HAND_EYE_DANIILIDIS, "opencv-daniilidis"}};
  std::vector<cv::Mat> R_gripper2base, t_gripper2base, R_target2cam, t_target2cam;
  auto to_cv = [](const Eigen::Isometry3d& aMb, std::vector<cv::Mat>* R, std::vector<cv::Mat>* t) {
    cv::Mat r(3, 3, CV_64F), v(3, 1, CV_64F);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r.at<double>(i, j) = aMb.linear()(i, j);
      v.at<double>(i) = aMb.translation()[i];
    }
    R->push_back(r);
    t->push_back(v);
  };
  for (const HandEyeSample& s : samples) {
    to_cv(s.bMe.inverse(), &R_gripper2base, &t_gripper2base);  // eye-to-hand: pass eMb
    to_cv(s.cMt, &R_target2cam, &t_target2cam);
  }
  std::vector<HandEyeResult> results;
  for (const auto& [method, name] : methods) {
    if (samples.size() < 3) {
      results.push_back(Failed(name, "needs at least 3 samples"));
      continue;
    }
    cv::Mat R, t;
    try {
      cv::calibrateHandEye(R_gripper2base, t_gripper2base, R_target2cam, t_target2cam, R, t,
                           method);
    } catch (const cv::Exception& e) {
      results.push_back(Failed(name, e.what()));
      continue;
    }
    HandEyeResult r;
    r.method = name;
    Eigen::Isometry3d bMc = Eigen::Isometry3d::Identity();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) bMc.linear()(i, j) = R.at<double>(i, j);
      bMc.translation()[i] = t.at<double>(i);
    }
    if (!bMc.matrix().allFinite() || !IsValidTransform(bMc)) {
      results.push_back(Failed(name, "returned an invalid transform (singular pose set?)"));
      continue;
    }
    r.cMb = bMc.inverse();
    r.eMt = MeanBoardOnGripper(samples, r.cMb);
    r.ok = true;
    Evaluate(samples, K, &r);
    results.push_back(r);
  }
  return results;
}

HandEyeResult RefineEyeToHand(const std::vector<HandEyeSample>& samples, const CameraIntrinsics& K,
                              const HandEyeResult& initial) {
  std::size_t corners = 0;
  for (const HandEyeSample& s : samples) corners += s.corners.size();
  if (!initial.ok) return Failed("refined", "no initial solution");
  if (corners < 6) return Failed("refined", "the samples carry too few board corners");

  // Parameters: left perturbations of cMb and right perturbations of eMt.
  auto residuals = [&](const Eigen::Isometry3d& cMb, const Eigen::Isometry3d& eMt) {
    Eigen::VectorXd r(2 * corners);
    std::size_t k = 0;
    for (const HandEyeSample& s : samples) {
      const Eigen::Isometry3d cMt = cMb * s.bMe * eMt;
      for (const auto& [p_t, px] : s.corners) {
        const Eigen::Vector3d p_c = cMt * p_t;
        const Eigen::Vector2d e =
            p_c.z() > 1e-6 ? Eigen::Vector2d(K.Project(p_c) - px) : Eigen::Vector2d(1e3, 1e3);
        r.segment<2>(2 * k++) = e;
      }
    }
    return r;
  };
  auto apply = [](const Eigen::Matrix<double, 12, 1>& delta, Eigen::Isometry3d* cMb,
                  Eigen::Isometry3d* eMt) {
    *cMb = Exp(delta.segment<3>(0), delta.segment<3>(3)) * *cMb;
    *eMt = *eMt * Exp(delta.segment<3>(6), delta.segment<3>(9));
  };
  Eigen::Isometry3d cMb = initial.cMb, eMt = initial.eMt;
  Eigen::VectorXd r = residuals(cMb, eMt);
  double cost = r.squaredNorm(), lambda = 1e-3;
  for (int iteration = 0; iteration < 50; ++iteration) {
    Eigen::MatrixXd J(r.size(), 12);
    for (int p = 0; p < 12; ++p) {
      const double h = 1e-6;
      Eigen::Matrix<double, 12, 1> delta = Eigen::Matrix<double, 12, 1>::Zero();
      delta[p] = h;
      Eigen::Isometry3d a = cMb, b = eMt;
      apply(delta, &a, &b);
      J.col(p) = (residuals(a, b) - r) / h;
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int attempt = 0; attempt < 10 && !improved; ++attempt) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() *= 1.0 + lambda;
      const Eigen::Matrix<double, 12, 1> step = -A.ldlt().solve(g);
      Eigen::Isometry3d a = cMb, b = eMt;
      apply(step, &a, &b);
      const Eigen::VectorXd r_new = residuals(a, b);
      if (r_new.squaredNorm() < cost) {
        cMb = a;
        eMt = b;
        r = r_new;
        const double old_cost = cost;
        cost = r.squaredNorm();
        lambda = std::max(1e-9, lambda / 10.0);
        improved = true;
        if (old_cost - cost < 1e-12 * old_cost) iteration = 50;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved) break;
  }
  HandEyeResult result;
  result.method = "refined";
  result.ok = true;
  result.cMb = cMb;
  result.eMt = eMt;
  Evaluate(samples, K, &result);
  return result;
}

}  // namespace aerograsp
