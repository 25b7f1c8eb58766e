#include "app/calibration/hand_eye_plan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/collision.h"
#include "core/random.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr int kPlanningCandidates = 40000;  // random joint vectors tried
constexpr double kImageMarginPx = 15.0;

/// Board corners of every tag, in t.
std::vector<Eigen::Vector3d> AllCorners(const TagBoardConfig& board) {
  std::vector<Eigen::Vector3d> corners;
  for (const BoardTag& tag : BoardTags(board))
    corners.insert(corners.end(), tag.corners_t.begin(), tag.corners_t.end());
  return corners;
}

/// The board's outline seen at cMt.
void DrawBoardOutline(cv::Mat* canvas, const CameraIntrinsics& K, const Eigen::Isometry3d& cMt,
                      const TagBoardConfig& board, const cv::Scalar& colour, int thickness) {
  const Eigen::Vector2d half = 0.5 * board.Size();
  const Eigen::Vector3d outline_t[4] = {{-half.x(), -half.y(), 0},
                                        {half.x(), -half.y(), 0},
                                        {half.x(), half.y(), 0},
                                        {-half.x(), half.y(), 0}};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = K.Project(cMt * outline_t[k]),
                          b = K.Project(cMt * outline_t[(k + 1) % 4]);
    cv::line(*canvas, cv::Point2d(a.x(), a.y()), cv::Point2d(b.x(), b.y()), colour, thickness,
             cv::LINE_AA);
  }
}

}  // namespace

std::vector<Eigen::VectorXd> PlanPoses(const Platform& platform, Side side,
                                       const TagBoardConfig& board, const Eigen::Isometry3d& eMt,
                                       const Eigen::VectorXd& other_q, int count,
                                       std::uint64_t seed) {
  const ArmModel& arm = platform.arm(side);
  const PlatformCollision collision(platform);
  const Eigen::Isometry3d cMb = platform.dMc().inverse() * platform.dMb(side);
  const CameraIntrinsics& K = platform.camera();
  const std::vector<Eigen::Vector3d> corners = AllCorners(board);
  FastRandom rng(seed);
  std::vector<Eigen::VectorXd> candidates;
  std::vector<Eigen::Matrix3d> rotations;
  for (int i = 0; i < kPlanningCandidates; ++i) {
    Eigen::VectorXd q(arm.dof());
    for (int j = 0; j < arm.dof(); ++j)
      q[j] = rng.Uniform(arm.lower_limits()[j], arm.upper_limits()[j]);
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    const Eigen::Isometry3d cMt = cMb * bMe * eMt;
    const Eigen::Vector3d to_camera = -cMt.translation().normalized();
    const Eigen::Vector3d front = -cMt.linear().col(2);  // the printed face looks along -z_t
    if (cMt.translation().z() < 0.2 || cMt.translation().z() > 0.6) continue;
    if (front.dot(to_camera) < std::cos(60.0 / kRadToDeg)) continue;
    bool in_view = true;
    for (const Eigen::Vector3d& p_t : corners) {
      const Eigen::Vector3d p_c = cMt * p_t;
      const Eigen::Vector2d px = K.Project(p_c);
      in_view = in_view && p_c.z() > 0.1 && px.x() > kImageMarginPx && px.y() > kImageMarginPx &&
                px.x() < K.width - kImageMarginPx && px.y() < K.height - kImageMarginPx;
    }
    if (!in_view) continue;
    if (collision.ArmInSafeVolume(side, q)) continue;  // the upper arm passes 5 mm under it
    if (side == Side::kLeft ? collision.ArmsCollide(q, other_q, 0.01)
                            : collision.ArmsCollide(other_q, q, 0.01))
      continue;
    candidates.push_back(q);
    rotations.push_back(bMe.linear());
  }
  std::vector<Eigen::VectorXd> chosen;
  if (candidates.empty()) return chosen;
  std::vector<double> nearest(candidates.size(), 1e9);
  std::size_t next = 0;
  for (int k = 0; k < count && k < static_cast<int>(candidates.size()); ++k) {
    chosen.push_back(candidates[next]);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const double angle = Eigen::AngleAxisd(rotations[next].transpose() * rotations[i]).angle();
      nearest[i] = std::min(nearest[i], angle);
    }
    next = static_cast<std::size_t>(std::max_element(nearest.begin(), nearest.end()) -
                                    nearest.begin());
  }
  return chosen;
}

void ShowPlan(const std::vector<Eigen::VectorXd>& poses, const Platform& platform, Side side,
              const CalibrationRig& rig, const RgbdFrame& frame, const std::string& picture,
              std::ostream& out) {
  const Eigen::Isometry3d cMb = platform.dMc().inverse() * platform.dMb(side);
  const CameraIntrinsics& K = platform.camera();
  out << fmt::format("{:>4}  {:<36} {:>22} {:>9} {:>12}\n", "pose", "joints (deg)",
                     "board in camera (m)", "tilt deg", "centre px");
  cv::Mat canvas(K.height, K.width, CV_8UC3, cv::Scalar(40, 40, 40));
  if (frame.color.width == K.width && frame.color.height == K.height) {
    const cv::Mat rgb(frame.color.height, frame.color.width, CV_8UC3,
                      const_cast<std::uint8_t*>(frame.color.data.data()));
    cv::cvtColor(rgb, canvas, cv::COLOR_RGB2BGR);
    canvas /= 2;
  }
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Isometry3d cMt = cMb * platform.arm(side).ForwardKinematics(poses[k]) * rig.eMt;
    std::string joints;
    for (int j = 0; j < poses[k].size(); ++j)
      joints += fmt::format("{:8.1f}", poses[k][j] * kRadToDeg);
    const Eigen::Vector3d p = cMt.translation();
    const double tilt =
        kRadToDeg * std::acos(std::clamp(-cMt.linear().col(2).dot(-p.normalized()), -1.0, 1.0));
    const Eigen::Vector2d centre = K.Project(p);
    out << fmt::format("{:>4}  {:<36} {:>6.3f} {:>7.3f} {:>7.3f} {:>9.1f} {:>5.0f} {:>5.0f}\n", k,
                       joints, p.x(), p.y(), p.z(), tilt, centre.x(), centre.y());
    DrawBoardOutline(&canvas, K, cMt, rig.board, cv::Scalar(0, 200, 255), 1);
    cv::putText(canvas, std::to_string(k), cv::Point2d(centre.x(), centre.y()),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }
  if (picture.empty()) return;
  cv::putText(canvas, "planned board poses (numbered) over the pre-flight frame", cv::Point(10, 20),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  cv::imwrite(picture, canvas);
  out << "picture of the plan: " << picture << "\n";
}

void DrawPoses(const std::string& folder, const std::vector<WizardSample>& samples,
               const TagBoardConfig& board, const CameraIntrinsics& K,
               const HandEyeResult& solution) {
  cv::Mat canvas(K.height, K.width, CV_8UC3, cv::Scalar(40, 40, 40));
  for (const WizardSample& s : samples) {
    if (!s.accepted) continue;
    const cv::Mat image = cv::imread((fs::path(folder) / s.image).string(), cv::IMREAD_GRAYSCALE);
    if (!image.empty()) {
      cv::Mat dim;
      cv::cvtColor(image / 2, dim, cv::COLOR_GRAY2BGR);
      canvas = dim;
    }
    break;
  }
  for (const WizardSample& s : samples) {
    if (!s.accepted) continue;
    DrawBoardOutline(&canvas, K, s.data.cMt, board, cv::Scalar(0, 220, 0), 2);
    if (solution.ok)
      DrawBoardOutline(&canvas, K, solution.cMb * s.data.bMe * solution.eMt, board,
                       cv::Scalar(0, 0, 255), 1);
  }
  cv::putText(canvas, "board measured (green) / predicted by the calibration (red)",
              cv::Point(10, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  cv::imwrite((fs::path(folder) / "poses.png").string(), canvas);
}

}  // namespace aerograsp
