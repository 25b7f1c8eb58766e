#include "app/calibration/calibrate_command.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "app/calibration/calibrate_intrinsics.h"
#include "app/calibration/calibration_file.h"
#include "app/calibration/calibration_hardware.h"
#include "app/calibration/calibration_samples.h"
#include "app/calibration/calibration_visp.h"
#include "app/calibration/interrupt_guard.h"
#include "app/calibration/tag_board_mesh.h"
#include "app/report/progress.h"
#include "app/report/summary_file.h"
#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/collision.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "core/transforms.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kMaxReprojectionPx = 1.0;  // a sample above this is rejected
constexpr double kMinBoardFraction = 0.5;   // of the board's tags seen
constexpr int kPlanningCandidates = 40000;  // random joint vectors tried
constexpr double kImageMarginPx = 15.0;

struct Sample {
  std::string image;  // relative to the output folder
  Eigen::VectorXd q_rad;
  bool accepted = false;
  std::string reject_reason;
  HandEyeSample data;  // bMe, cMt, corners
};

Side ParseSide(const std::string& arm) {
  if (arm == "left") return Side::kLeft;
  if (arm == "right") return Side::kRight;
  throw ConfigError("--arm: '" + arm + "' is not left or right");
}

/// Board corners of every tag, in t.
std::vector<Eigen::Vector3d> AllCorners(const TagBoardConfig& board) {
  std::vector<Eigen::Vector3d> corners;
  for (const BoardTag& tag : BoardTags(board))
    corners.insert(corners.end(), tag.corners_t.begin(), tag.corners_t.end());
  return corners;
}

/// Joint vectors whose board is in full view, faces the camera and is near,
/// with the arm clear of the safe volume and of the other arm where it is; then
/// a diverse subset (greedy: each next pose the farthest in rotation from
/// those already chosen).
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

void WriteSamplesYaml(const std::string& path, const std::string& platform_path, Side side,
                      const TagBoardConfig& board, const std::vector<Sample>& samples) {
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "platform" << YAML::Value << platform_path;
  y << YAML::Key << "arm" << YAML::Value << SideName(side);
  y << YAML::Key << "board" << YAML::Value;
  EmitTagBoard(board, &y);
  y << YAML::Key << "samples" << YAML::Value << YAML::BeginSeq;
  for (const Sample& s : samples) {
    y << YAML::BeginMap;
    y << YAML::Key << "image" << YAML::Value << s.image;
    y << YAML::Key << "accepted" << YAML::Value << s.accepted;
    y << YAML::Key << "reject_reason" << YAML::Value << s.reject_reason;
    y << YAML::Key << "q_rad" << YAML::Value << YAML::Flow
      << std::vector<double>(s.q_rad.data(), s.q_rad.data() + s.q_rad.size());
    y << YAML::Key << "cMt" << YAML::Value << YAML::Flow << FlattenRowMajor(s.data.cMt);
    y << YAML::Key << "corners" << YAML::Value;
    EmitCorners(s.data.corners, &y);
    y << YAML::EndMap;
  }
  y << YAML::EndSeq << YAML::EndMap;
  std::ofstream out(path);
  out << "# aerograsp calibration samples: re-solve with `aerograsp calibrate --resolve DIR`.\n"
      << y.c_str() << "\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

std::vector<Sample> ReadSamplesYaml(const std::string& path, std::string* platform_path, Side* side,
                                    TagBoardConfig* board) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"platform", "arm", "board", "samples"});
  *platform_path = root.GetString("platform");
  CheckFileExists(path, "platform", *platform_path);
  *side = ParseSide(root.GetString("arm"));
  *board = TagBoardConfig::FromNode(root.Child("board"));
  const Platform platform = Platform::Load(*platform_path);
  const YAML::Node all = YAML::LoadFile(path)["samples"];
  if (!all || !all.IsSequence()) root.Fail("samples", "expected a list of samples");
  std::vector<Sample> samples;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string where = "samples[" + std::to_string(i) + "]";
    try {
      Sample s;
      s.image = all[i]["image"].as<std::string>();
      s.accepted = all[i]["accepted"].as<bool>();
      s.reject_reason = all[i]["reject_reason"].as<std::string>("");
      const auto q = all[i]["q_rad"].as<std::vector<double>>();
      CheckFinite(path, where + ".q_rad", q);
      s.q_rad = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<long>(q.size()));
      if (s.q_rad.size() != platform.arm(*side).dof())
        root.Fail(where + ".q_rad", "wrong number of joints");
      s.data.bMe = platform.arm(*side).ForwardKinematics(s.q_rad);
      const auto m = all[i]["cMt"].as<std::vector<double>>();
      if (m.size() != 16) root.Fail(where + ".cMt", "expected 16 numbers");
      CheckFinite(path, where + ".cMt", m);
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) s.data.cMt.matrix()(r, c) = m[4 * r + c];
      }
      s.data.corners = ReadCorners(all[i]["corners"], root, where + ".corners");
      samples.push_back(std::move(s));
    } catch (const YAML::Exception& e) {
      root.Fail(where, std::string("malformed: ") + e.what());
    }
  }
  return samples;
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

/// Outlines of the board as measured (green) and as the calibration predicts
/// (red) for every accepted sample, over the first accepted image.
void DrawPoses(const std::string& folder, const std::vector<Sample>& samples,
               const TagBoardConfig& board, const CameraIntrinsics& K,
               const HandEyeResult& solution) {
  cv::Mat canvas(K.height, K.width, CV_8UC3, cv::Scalar(40, 40, 40));
  for (const Sample& s : samples) {
    if (!s.accepted) continue;
    const cv::Mat image = cv::imread((fs::path(folder) / s.image).string(), cv::IMREAD_GRAYSCALE);
    if (!image.empty()) {
      cv::Mat dim;
      cv::cvtColor(image / 2, dim, cv::COLOR_GRAY2BGR);
      canvas = dim;
    }
    break;
  }
  for (const Sample& s : samples) {
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

nlohmann::json ErrorToTruth(const HandEyeResult& r, const std::optional<Eigen::Isometry3d>& truth) {
  nlohmann::json j = {{"ok", r.ok}};
  if (!r.ok) {
    j["message"] = r.message;
    return j;
  }
  j["residual_mm"] = r.residual_mm_rms;
  j["residual_deg"] = r.residual_deg_rms;
  j["reprojection_px"] = r.reprojection_rms_px;
  if (truth) {
    const PoseError e = ComparePoses(r.cMb, *truth);
    j["error_to_truth_mm"] = 1e3 * e.translation_m;
    j["error_to_truth_deg"] = kRadToDeg * e.rotation_rad;
  }
  return j;
}

/// The solvers' residuals (and errors to the truth, when known), one line each.
void PrintMethods(const std::vector<const HandEyeResult*>& all,
                  const std::optional<Eigen::Isometry3d>& truth_cMb, std::ostream& out) {
  out << fmt::format("{:<20} {:>12} {:>12} {:>10}", "method", "residual mm", "residual deg",
                     "reproj px");
  if (truth_cMb) out << fmt::format(" {:>12} {:>12}", "truth err mm", "truth err deg");
  out << "\n";
  for (const HandEyeResult* r : all) {
    if (!r->ok) {
      out << fmt::format("{:<20} failed: {}\n", r->method, r->message);
      continue;
    }
    out << fmt::format("{:<20} {:>12.3f} {:>12.3f} {:>10.3f}", r->method, r->residual_mm_rms,
                       r->residual_deg_rms, r->reprojection_rms_px);
    if (truth_cMb) {
      const PoseError e = ComparePoses(r->cMb, *truth_cMb);
      out << fmt::format(" {:>12.3f} {:>12.4f}", 1e3 * e.translation_m, kRadToDeg * e.rotation_rad);
    }
    out << "\n";
  }
}

/// Refuses a pose set whose rotations span one axis (the solve is singular)
/// and warns when it is poorly spread.
PoseSetDiversity CheckDiversity(const std::string& folder, const std::vector<HandEyeSample>& used,
                                std::ostream& out) {
  const PoseSetDiversity diversity = MeasureDiversity(used);
  if (!diversity.Sufficient()) {
    out << fmt::format(
        "warning: the poses are not diverse enough (largest rotation {:.1f} deg, rotation axes "
        "span {} dimension(s)); the solution may be poor\n",
        diversity.max_rotation_deg, diversity.axis_rank);
  }
  if (diversity.axis_rank < 2) {
    throw std::runtime_error(
        folder +
        ": singular pose set: every rotation is about one axis; add poses that turn "
        "the gripper about other axes");
  }
  return diversity;
}

/// Solves from the accepted samples, prints the comparison, writes the
/// calibration YAML, summary.json and poses.png.
void SolveAndReport(const std::string& folder, const std::string& platform_path, Side side,
                    const TagBoardConfig& board, const std::vector<Sample>& samples,
                    const std::optional<Eigen::Isometry3d>& truth_cMb, std::ostream& out) {
  const Platform platform = Platform::Load(platform_path);
  const CameraIntrinsics& K = platform.camera();
  std::vector<HandEyeSample> used;
  int rejected = 0;
  for (const Sample& s : samples) {
    if (s.accepted) {
      used.push_back(s.data);
    } else {
      ++rejected;
    }
  }
  out << fmt::format("samples: {} used, {} rejected (kept in {}/samples.yaml)\n", used.size(),
                     rejected, folder);
  if (used.size() < 3) {
    throw std::runtime_error(
        fmt::format("{}: only {} usable samples (at least 3 needed): no board visible or all "
                    "samples rejected; see samples.yaml for the reasons",
                    folder, used.size()));
  }
  const PoseSetDiversity diversity = CheckDiversity(folder, used, out);
  const HandEyeResult visp = SolveEyeToHandVisp(used, K);
  const std::vector<HandEyeResult> opencv = SolveEyeToHandOpenCv(used, K);
  const HandEyeResult refined = RefineEyeToHand(used, K, visp.ok ? visp : opencv.front());
  const HandEyeResult& best = refined.ok ? refined : visp;
  if (!best.ok) throw std::runtime_error(folder + ": the hand-eye solve failed: " + visp.message);

  std::vector<const HandEyeResult*> all = {&refined, &visp};
  for (const HandEyeResult& r : opencv) all.push_back(&r);
  PrintMethods(all, truth_cMb, out);

  // The calibration the mission loads: cMb, and dMb through the nominal dMc.
  const Eigen::Isometry3d dMb = platform.dMc() * best.cMb;
  const std::string yaml_path =
      (fs::path(folder) / fmt::format("calibration_{}.yaml", SideName(side))).string();
  ArmCalibration calibration;
  calibration.side = side;
  calibration.method = best.method;
  calibration.cMb = best.cMb;
  calibration.dMb = dMb;
  calibration.eMt = best.eMt;
  calibration.residual_mm = best.residual_mm_rms;
  calibration.residual_deg = best.residual_deg_rms;
  calibration.Write(yaml_path);
  const std::string stem = fmt::format("calibration_{}", SideName(side));
  WriteRosFrames(folder, stem, kCameraOpticalFrame, ArmBaseFrame(side), best.cMb,
                 fmt::format("aerograsp calibration of the {} arm: its base ({}) in the camera's "
                             "optical frame ({}: z forward, x right, y down)",
                             SideName(side), ArmBaseFrame(side), kCameraOpticalFrame));
  nlohmann::json summary = {{"arm", SideName(side)},
                            {"samples_used", used.size()},
                            {"samples_rejected", rejected},
                            {"method", best.method},
                            {"residual_mm", best.residual_mm_rms},
                            {"residual_deg", best.residual_deg_rms},
                            {"reprojection_px", best.reprojection_rms_px},
                            {"max_rotation_between_poses_deg", diversity.max_rotation_deg},
                            {"visp", ErrorToTruth(visp, truth_cMb)}};
  nlohmann::json per_method;
  for (const HandEyeResult& r : opencv)
    per_method[r.method.substr(std::string("opencv-").size())] = ErrorToTruth(r, truth_cMb);
  summary["opencv"] = per_method;
  if (truth_cMb) {
    const PoseError e = ComparePoses(best.cMb, *truth_cMb);
    summary["error_to_truth_mm"] = 1e3 * e.translation_m;
    summary["error_to_truth_deg"] = kRadToDeg * e.rotation_rad;
  }
  WriteSummaryFile(folder, summary.dump(2));
  DrawPoses(folder, samples, board, K, best);
  out << fmt::format("wrote {}, {}/{}.urdf, {}/{}_tf.sh, {}/summary.json, {}/poses.png\n",
                     yaml_path, folder, stem, folder, stem, folder, folder);
}

/// `--resolve DIR` on a data set in ViSP's convention (app/calibration/calibration_visp.h):
/// ViSP's solver (what visp-compute-eye-to-hand-calibration /
/// visp-compute-eye-in-hand-calibration give) and OpenCV's five for
/// comparison; writes the result as ViSP pose files (rPc.yaml and ePo.yaml
/// eye-to-hand, eMc.yaml and rPo.yaml eye-in-hand), a URDF joint, the
/// static_transform_publisher command and summary.json in `out_folder`.
void ResolveVispDataset(const std::string& folder, HandEyeSetup setup, double tag_size_m,
                        const std::string& out_folder, std::ostream& out) {
  const VispDataset data = ReadVispDataset(folder, tag_size_m);
  const std::vector<HandEyeSample> samples = ToHandEyeSamples(data, setup);
  out << fmt::format("{}: {} samples in ViSP's convention ({}){}\n", folder, samples.size(),
                     HandEyeSetupName(setup),
                     data.has_camera
                         ? fmt::format("; camera {} ({} distortion)", data.camera.source,
                                       data.camera.distortion ? "with" : "without")
                         : "");
  if (samples.size() < 3)
    throw std::runtime_error(
        fmt::format("{}: only {} samples (at least 3 needed)", folder, samples.size()));
  const PoseSetDiversity diversity = CheckDiversity(folder, samples, out);
  const CameraIntrinsics K = data.has_camera ? data.camera.K : CameraIntrinsics{};
  const HandEyeResult visp = SolveEyeToHandVisp(samples, K);
  const std::vector<HandEyeResult> opencv = SolveEyeToHandOpenCv(samples, K);
  std::vector<const HandEyeResult*> all = {&visp};
  for (const HandEyeResult& r : opencv) all.push_back(&r);
  PrintMethods(all, std::nullopt, out);
  if (!visp.ok) throw std::runtime_error(folder + ": the hand-eye solve failed: " + visp.message);

  fs::create_directories(out_folder);
  // The solvers' cMb is cMr (eye-to-hand) or cMe (eye-in-hand); their eMt is eMo or rMo.
  const bool to_hand = setup == HandEyeSetup::kEyeToHand;
  const Eigen::Isometry3d camera_in_robot = visp.cMb.inverse();  // rMc or eMc
  const std::string camera_file = to_hand ? "rPc.yaml" : "eMc.yaml";
  const std::string object_file = to_hand ? "ePo.yaml" : "rPo.yaml";
  WriteVispPose((fs::path(out_folder) / camera_file).string(), camera_in_robot);
  WriteVispPose((fs::path(out_folder) / object_file).string(), visp.eMt);
  const std::string parent = to_hand ? "robot_base" : "end_effector";
  WriteRosFrames(out_folder, "hand_eye", parent, kCameraOpticalFrame, camera_in_robot,
                 fmt::format("hand-eye calibration ({}) of {}: the camera's optical frame ({}: z "
                             "forward, x right, y down) in the robot's {} frame",
                             HandEyeSetupName(setup), folder, kCameraOpticalFrame,
                             to_hand ? "base" : "end-effector"));
  nlohmann::json summary = {{"setup", HandEyeSetupName(setup)},
                            {"samples_used", samples.size()},
                            {"method", visp.method},
                            {"residual_mm", visp.residual_mm_rms},
                            {"residual_deg", visp.residual_deg_rms},
                            {"max_rotation_between_poses_deg", diversity.max_rotation_deg},
                            {to_hand ? "rMc" : "eMc", FlattenRowMajor(camera_in_robot)},
                            {to_hand ? "eMo" : "rMo", FlattenRowMajor(visp.eMt)}};
  nlohmann::json per_method;
  for (const HandEyeResult& r : opencv) {
    nlohmann::json j = {{"ok", r.ok}};
    if (r.ok) {
      const PoseError e = ComparePoses(r.cMb, visp.cMb);
      j["residual_mm"] = r.residual_mm_rms;
      j["residual_deg"] = r.residual_deg_rms;
      j["difference_to_visp_mm"] = 1e3 * e.translation_m;
      j["difference_to_visp_deg"] = kRadToDeg * e.rotation_rad;
    } else {
      j["message"] = r.message;
    }
    per_method[r.method.substr(std::string("opencv-").size())] = j;
  }
  summary["opencv"] = per_method;
  WriteSummaryFile(out_folder, summary.dump(2));
  const Eigen::Vector3d t = camera_in_robot.translation(), tu = ThetaU(camera_in_robot.linear());
  out << fmt::format(
      "{} (camera in the robot's {}): t = {:.6f} {:.6f} {:.6f} m, theta-u = {:.6f} {:.6f} {:.6f} "
      "rad\nwrote {}/{}, {}/{}, {}/hand_eye.urdf, {}/hand_eye_tf.sh, {}/summary.json\n",
      to_hand ? "rMc" : "eMc", to_hand ? "base" : "end-effector", t.x(), t.y(), t.z(), tu.x(),
      tu.y(), tu.z(), out_folder, camera_file, out_folder, object_file, out_folder, out_folder,
      out_folder);
}

// ---- the wizard on devices ----

/// A reason to stop the run at once: the arms are stopped where they are and
/// the samples kept.
struct StopRun {
  std::string reason;
};

constexpr double kStep_s = 0.05;        // control period of the wizard's moves
constexpr double kPathCheckRad = 0.02;  // spacing of the configurations checked along a move

/// Throws StopRun on Ctrl-C or when a servo stopped answering or left its
/// voltage or temperature range.
void CheckFaults(HandEyeHardware& hw) {
  if (InterruptGuard::Interrupted()) throw StopRun{"interrupted (Ctrl-C)"};
  ScsArmsDriver* scs = hw.scs();
  if (!scs) return;
  const CalibrationRig& rig = hw.rig();
  for (const ScsServoStatus& s : scs->servo_statuses()) {
    if (s.failed_reads >= rig.max_failed_reads) {
      throw StopRun{
          fmt::format("servo {} (id {}) stopped answering on {} ({} reads failed in a row)", s.name,
                      s.id, hw.ArmsWhere(), s.failed_reads)};
    }
    if (s.voltage_v > 0.0 && (s.voltage_v < rig.min_voltage_v || s.voltage_v > rig.max_voltage_v)) {
      throw StopRun{fmt::format("servo {} (id {}): supply {:.1f} V outside {:.1f}-{:.1f} V", s.name,
                                s.id, s.voltage_v, rig.min_voltage_v, rig.max_voltage_v)};
    }
    if (s.temperature_c > rig.max_temperature_c) {
      throw StopRun{fmt::format("servo {} (id {}): {} C, above {:.0f} C", s.name, s.id,
                                s.temperature_c, rig.max_temperature_c)};
    }
  }
}

/// Why the straight joint-space move from `from` to `to` is refused ("" when
/// every configuration along it keeps clear of the safe volume and of the
/// other arm where it stands).
std::string CheckMove(const PlatformCollision& collision, Side side, const Eigen::VectorXd& from,
                      const Eigen::VectorXd& to, const Eigen::VectorXd& other_q) {
  const int steps =
      std::max(1, static_cast<int>(std::ceil((to - from).cwiseAbs().maxCoeff() / kPathCheckRad)));
  for (int k = 1; k <= steps; ++k) {
    const Eigen::VectorXd q = from + (to - from) * (static_cast<double>(k) / steps);
    if (collision.ArmInSafeVolume(side, q)) return "the move would enter the safe volume";
    if (side == Side::kLeft ? collision.ArmsCollide(q, other_q, 0.01)
                            : collision.ArmsCollide(other_q, q, 0.01))
      return "the move would come within 1 cm of the other arm";
  }
  return "";
}

/// Moves `side` to `target` at the rig's joint speed (targets sent every
/// control period along the straight joint-space line), then waits until it
/// settles. Returns "" when settled, else why not.
std::string MoveAndSettle(HandEyeHardware& hw, Side side, const Eigen::VectorXd& target) {
  const CalibrationRig& rig = hw.rig();
  ArmsDriver& arms = hw.arms();
  const Eigen::VectorXd start = arms.JointPositions(side);
  const double duration =
      (target - start).cwiseAbs().maxCoeff() / (rig.joint_speed_deg_s * M_PI / 180.0);
  const double t0 = hw.now_s();
  for (double f = 0.0; f < 1.0;) {
    f = duration > 0.0 ? std::min(1.0, (hw.now_s() - t0 + kStep_s) / duration) : 1.0;
    arms.SetJointTargets(side, start + f * (target - start));
    hw.Wait(kStep_s);
    CheckFaults(hw);
  }
  // Settled: every joint within the tolerance of its target, readings unchanged
  // (by less than half the tolerance) for the settle window. The target is sent
  // every period, as a control loop does (the bus driver's watchdog holds stale ones).
  const double tolerance = rig.settle_tolerance_deg * M_PI / 180.0;
  const double t_settle = hw.now_s();
  Eigen::VectorXd last = arms.JointPositions(side);
  double still_since = hw.now_s();
  while (hw.now_s() - t_settle < rig.settle_timeout_s) {
    arms.SetJointTargets(side, target);
    hw.Wait(kStep_s);
    CheckFaults(hw);
    const Eigen::VectorXd q = arms.JointPositions(side);
    if ((q - last).cwiseAbs().maxCoeff() > 0.5 * tolerance) still_since = hw.now_s();
    last = q;
    if ((q - target).cwiseAbs().maxCoeff() <= tolerance &&
        hw.now_s() - still_since >= rig.settle_window_s - 1e-9)
      return "";
  }
  return fmt::format("arm not settled after {:.1f} s", rig.settle_timeout_s);
}

/// The planned poses: joints, where the board would be and how it would face
/// the camera, as a table; and the boards' outlines over the pre-flight frame.
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

/// The board seen from where the arm stands now: its pose, or why not.
std::string BoardSeen(const RgbdFrame& frame, const CalibrationRig& rig, const CameraIntrinsics& K,
                      TagDetector* detector) {
  if (frame.color.width == 0) return "no frame";
  const BoardPose pose = EstimateBoardPose(detector->Detect(frame.color), rig.board, K);
  if (!pose.valid)
    return fmt::format(
        "not seen (no tag of the {}x{} board, ids {}-{}): is it on the gripper, "
        "facing the camera?",
        rig.board.rows, rig.board.cols, rig.board.first_id,
        rig.board.first_id + rig.board.rows * rig.board.cols - 1);
  return "";
}

std::string Degrees(const Eigen::VectorXd& q) {
  std::string s;
  for (int j = 0; j < q.size(); ++j) s += fmt::format("{}{:.1f}", j ? ", " : "", q[j] * kRadToDeg);
  return s;
}

/// Hand-guided: waits until a person has let go of the limp arm (readings
/// unchanged for the settle window) while the driver's command follows the
/// readings, so that the arm does not jump when its torque comes back.
/// Returns "" when still, else why the sample is rejected.
std::string WaitStill(HandEyeHardware& hw, Side side) {
  const CalibrationRig& rig = hw.rig();
  ArmsDriver& arms = hw.arms();
  const double tolerance = rig.settle_tolerance_deg * M_PI / 180.0;
  const double t0 = hw.now_s();
  Eigen::VectorXd last = arms.JointPositions(side);
  double still_since = t0;
  while (hw.now_s() - t0 < rig.settle_timeout_s) {
    arms.SetJointTargets(side, arms.JointPositions(side));
    hw.Wait(kStep_s);
    CheckFaults(hw);
    const Eigen::VectorXd q = arms.JointPositions(side);
    if ((q - last).cwiseAbs().maxCoeff() > 0.5 * tolerance) still_since = hw.now_s();
    last = q;
    if (hw.now_s() - still_since >= rig.settle_window_s - 1e-9) return "";
  }
  return fmt::format("arm still moving after {:.1f} s", rig.settle_timeout_s);
}

/// One sample where the arm stands: the joints read, a frame grabbed, the
/// board detected and the rejection rules applied (`unsettled`, when not
/// empty, rejects it); the image and, accepted, its ViSP files written.
Sample TakeSample(HandEyeHardware& hw, Side side, TagDetector* detector, const std::string& out_dir,
                  std::size_t index, const std::string& unsettled, RgbdFrame* frame) {
  const TagBoardConfig& board = hw.rig().board;
  RgbdCamera& camera = hw.camera();
  if (!camera.Grab(frame)) throw StopRun{"camera: no frame: the stream stopped"};
  Sample s;
  s.image = fmt::format("samples/{:03d}.png", index);
  s.q_rad = hw.arms().JointPositions(side);
  s.data.bMe = hw.platform().arm(side).ForwardKinematics(s.q_rad);
  WriteColorPng(frame->color, (fs::path(out_dir) / s.image).string());
  const std::vector<TagDetection> detections = detector->Detect(frame->color);
  const BoardPose pose = EstimateBoardPose(detections, board, camera.intrinsics());
  s.data.cMt = pose.cMt;
  s.data.corners = MatchBoardCorners(detections, board);
  const int board_tags = board.rows * board.cols;
  if (!unsettled.empty()) {
    s.reject_reason = unsettled;
  } else if (!pose.valid || pose.tags_used < kMinBoardFraction * board_tags) {
    s.reject_reason = fmt::format("board partly seen ({} of {} tags)", pose.tags_used, board_tags);
  } else if (pose.reprojection_rms_px > kMaxReprojectionPx) {
    s.reject_reason = fmt::format("reprojection error {:.2f} px", pose.reprojection_rms_px);
  }
  s.accepted = s.reject_reason.empty();
  if (s.accepted) {  // the same sample in ViSP's convention (eye-to-hand: rPe = bMe, cPo = cMt)
    WriteVispSample((fs::path(out_dir) / "visp").string(), static_cast<int>(index) + 1, s.data.bMe,
                    s.data.cMt, (fs::path(out_dir) / s.image).string());
  }
  return s;
}

/// The accepted samples' spread and, when it is short, what to add.
std::string DiversityLine(const std::vector<Sample>& samples) {
  std::vector<HandEyeSample> used;
  for (const Sample& s : samples) {
    if (s.accepted) used.push_back(s.data);
  }
  const PoseSetDiversity d = MeasureDiversity(used);
  const std::string advice = DiversityAdvice(d, used.size());
  return fmt::format("{} accepted, {:.0f} deg apart at most, rotation axes span {} dimension(s){}",
                     used.size(), d.max_rotation_deg, d.axis_rank,
                     advice.empty() ? "" : ": " + advice);
}

}  // namespace

void RunHandEyeWizard(const CalibrateCommandOptions& options, HandEyeHardware& hw, std::istream& in,
                      std::ostream& out, std::ostream& progress) {
  const Side side = ParseSide(options.arm);
  const CalibrationRig& rig = hw.rig();
  const TagBoardConfig& board = rig.board;
  RgbdCamera& camera = hw.camera();
  ArmsDriver& arms = hw.arms();
  const Platform& platform = hw.platform();
  const Side other = side == Side::kLeft ? Side::kRight : Side::kLeft;
  if (options.hand_guided && !hw.scs()) {
    throw ConfigError(fmt::format(
        "{}: arms.backend: '{}': hand-guided samples turn the arm's torque off, which needs the "
        "servo bus ('scs', or 'sim-bus' simulated)",
        hw.config().source, hw.config().arms.backend));
  }

  // Pre-flight: nothing has moved and the torque is as the servos had it.
  RgbdFrame frame;
  std::vector<std::string> failures = PreflightDevices(hw, &frame, out);
  TagDetector detector(board.family);
  // The arm may rest where the board faces away: then the board is looked for
  // again at the first pose, before the others.
  const std::string seen = BoardSeen(frame, rig, camera.intrinsics(), &detector);
  bool board_confirmed = seen.empty();
  out << fmt::format("  {:<8} board: {}\n", seen.empty() ? "ok" : "WARNING",
                     seen.empty() ? fmt::format("seen from the start pose ({} tag36h11 tags, "
                                                "{:.0f} mm)",
                                                board.rows * board.cols, 1e3 * board.tag_size_m)
                                  : seen +
                                        " from the start pose; looked for again at the "
                                        "first pose");
  if (!failures.empty()) {
    std::string all;
    for (const std::string& f : failures) all += "\n  " + f;
    throw HardwareError(
        fmt::format("{}: the pre-flight check failed; nothing moved:{}", hw.config().source, all));
  }

  // The plan: the poses visited, or suggested to the person guiding the arm.
  const std::vector<Eigen::VectorXd> poses = PlanPoses(
      platform, side, board, rig.eMt, arms.JointPositions(other), options.poses, options.seed);
  if (poses.empty()) {
    throw std::runtime_error(
        fmt::format("no arm pose of the {} arm shows the whole board to the camera while "
                    "clear of the safe volume",
                    SideName(side)));
  }
  out << fmt::format("planned {} poses of the {} arm (of {} requested){}; devices: {}\n",
                     poses.size(), SideName(side), options.poses,
                     options.hand_guided ? ", suggested to the hand"
                                         : fmt::format(" at {:.0f} deg/s", rig.joint_speed_deg_s),
                     hw.config().source);
  ShowPlan(poses, platform, side, rig, frame,
           options.out_dir.empty() ? "" : (fs::path(options.out_dir) / "plan.png").string(), out);
  if (options.dry_run) {
    out << "dry run: nothing moved\n";
    return;
  }
  // Devices named by a hardware file may be real arms; the in-process simulator moves nothing.
  if (!options.yes && !options.hardware_path.empty()) {
    out << (options.hand_guided
                ? fmt::format("turn the {} arm's torque off (hold it) to place it by hand? [y/N] ",
                              SideName(side))
                : fmt::format("move the {} arm through these {} poses? [y/N] ", SideName(side),
                              poses.size()))
        << std::flush;
    std::string answer;
    std::getline(in, answer);
    if (answer != "y" && answer != "yes") throw std::runtime_error("not confirmed: nothing moved");
  }

  fs::create_directories(fs::path(options.out_dir) / "samples");
  const std::string visp_folder = (fs::path(options.out_dir) / "visp").string();
  fs::create_directories(visp_folder);
  SaveCameraXml(camera.intrinsics(), "Camera", (fs::path(visp_folder) / "camera.xml").string());
  const PlatformCollision collision(platform);
  std::vector<Sample> samples;
  const std::string samples_yaml = (fs::path(options.out_dir) / "samples.yaml").string();
  const InterruptGuard interrupt;
  auto keep = [&](const Sample& s) {
    samples.push_back(s);
    WriteSamplesYaml(samples_yaml, hw.config().platform, side, board,
                     samples);  // nothing is lost on an error
  };
  try {
    if (options.hand_guided) {
      hw.Arm(side);
      out << fmt::format(
          "the {} arm is limp: place it, let go, press Enter to take a sample; q "
          "and Enter to solve\n",
          SideName(side));
      for (std::size_t next = 0;;) {
        out << fmt::format("sample {}: suggested pose {}: joints [{}] deg\n", samples.size(), next,
                           Degrees(poses[next]))
            << std::flush;
        std::string line;
        if (!std::getline(in, line) || line == "q") break;
        CheckFaults(hw);
        const std::string moving = WaitStill(hw, side);
        const Sample s =
            TakeSample(hw, side, &detector, options.out_dir, samples.size(), moving, &frame);
        keep(s);
        next = (next + 1) % poses.size();
        if (s.accepted) {
          out << "  taken: " << DiversityLine(samples) << "\n";
        } else {
          out << "  rejected: " << s.reject_reason << "\n";
        }
      }
      hw.Stiffen(side);
    } else {
      hw.Arm();
      Progress bar(progress, "calibrate", static_cast<std::int64_t>(poses.size()), "poses");
      for (std::size_t k = 0; k < poses.size(); ++k) {
        const std::string refused = CheckMove(collision, side, arms.JointPositions(side), poses[k],
                                              arms.JointPositions(other));
        if (!refused.empty()) {
          out << fmt::format("  pose {:3d} skipped: {}\n", k, refused);
          continue;
        }
        const std::string unsettled = MoveAndSettle(hw, side, poses[k]);
        const Sample s =
            TakeSample(hw, side, &detector, options.out_dir, samples.size(), unsettled, &frame);
        if (!board_confirmed) {
          const std::string again = BoardSeen(frame, rig, camera.intrinsics(), &detector);
          if (!again.empty()) {
            throw StopRun{
                fmt::format("board: {} at pose {}, where the plan puts all of it in view: check "
                            "calibration.board and calibration.board_in_tool_* in {}",
                            again, k, rig.source)};
          }
          board_confirmed = true;
        }
        keep(s);
        bar.Update(static_cast<std::int64_t>(k + 1));
      }
      bar.Finish();
    }
  } catch (const StopRun& stop) {
    arms.Stop();
    out << fmt::format("stopped: {}; both arms hold where they are (the {} arm at [{}] deg)\n",
                       stop.reason, SideName(side), Degrees(arms.JointPositions(side)));
    throw HardwareError(fmt::format(
        "{}; the arms were stopped; the {} samples taken so far are kept in {} (solve them with "
        "`calibrate --resolve {}`)",
        stop.reason, samples.size(), samples_yaml, options.out_dir));
  }
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].accepted)
      out << fmt::format("  sample {:3d} rejected: {}\n", i, samples[i].reject_reason);
  }
  // In the simulator the truth is the world's platform's nominal geometry.
  std::optional<Eigen::Isometry3d> truth_cMb;
  if (World* world = hw.world())
    truth_cMb = world->platform().dMc().inverse() * world->platform().dMb(side);
  SolveAndReport(options.out_dir, hw.config().platform, side, board, samples, truth_cMb, out);
}

namespace {

void RunWizard(const CalibrateCommandOptions& options, std::istream& in, std::ostream& out,
               std::ostream& progress) {
  const Side side = ParseSide(options.arm);
  if (options.out_dir.empty() && !options.dry_run)
    throw ConfigError("--out: an output folder is required");
  if (!options.out_dir.empty()) {  // the board to print, before any device is needed
    fs::create_directories(options.out_dir);
    WriteBoardSvg(CalibrationRig::Load(options.hardware_path).board,
                  (fs::path(options.out_dir) / "board.svg").string());
  }
  const std::unique_ptr<HandEyeHardware> hw =
      OpenHandEyeHardware(options.hardware_path, options.world_config, options.seed, side, out);
  RunHandEyeWizard(options, *hw, in, out, progress);
}

}  // namespace

void RunCalibrateCommand(const CalibrateCommandOptions& options, std::istream& in,
                         std::ostream& out, std::ostream& progress) {
  if (!options.resolve_dir.empty()) {
    if (IsIntrinsicsFolder(options.resolve_dir)) {
      ResolveIntrinsics(options.resolve_dir, out);
      return;
    }
    const std::string samples_yaml = (fs::path(options.resolve_dir) / "samples.yaml").string();
    if (!fs::exists(samples_yaml) && IsVispDataset(options.resolve_dir)) {
      ResolveVispDataset(options.resolve_dir, ParseHandEyeSetup(options.setup, "--setup"),
                         options.tag_size_m,
                         options.out_dir.empty() ? options.resolve_dir : options.out_dir, out);
      return;
    }
    if (!fs::exists(samples_yaml)) {
      throw ConfigError(options.resolve_dir +
                        ": holds neither samples.yaml (aerograsp's samples) nor pose_rPe_N.yaml / "
                        "pose_cPo_N.yaml files (ViSP's convention) nor intrinsics views");
    }
    std::string platform_path;
    Side side;
    TagBoardConfig board;
    const std::vector<Sample> samples =
        ReadSamplesYaml(samples_yaml, &platform_path, &side, &board);
    SolveAndReport(options.resolve_dir, platform_path, side, board, samples, std::nullopt, out);
    return;
  }
  if (options.intrinsics) {
    RunCalibrateIntrinsics(options, out, progress);
    return;
  }
  RunWizard(options, in, out, progress);
}

void RunCalibrateCommand(const CalibrateCommandOptions& options, std::ostream& out,
                         std::ostream& progress) {
  RunCalibrateCommand(options, std::cin, out, progress);
}

}  // namespace aerograsp
