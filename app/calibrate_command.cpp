#include "app/calibrate_command.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "app/calibrate_intrinsics.h"
#include "app/calibration_file.h"
#include "app/calibration_hardware.h"
#include "app/calibration_samples.h"
#include "app/progress.h"
#include "app/summary_file.h"
#include "app/tag_board_mesh.h"
#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/collision.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/random.h"
#include "core/transforms.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kMaxReprojectionPx = 1.0;  // a sample above this is rejected
constexpr double kMinBoardFraction = 0.5;   // of the board's tags seen
constexpr int kPlanningCandidates = 40000;  // random joint vectors tried
constexpr double kImageMarginPx = 15.0;

/// Where the board sits on the gripper: a plate 25 mm past the tool point
/// (just beyond the fingertips, between the fingers, which are 0.132 m apart
/// and so do not hide the 0.074 m board), facing back along -z_e towards the
/// camera that looks over the arms; t is parallel to e.
Eigen::Isometry3d NominalBoardOnGripper() {
  return MakeTransform(Eigen::Vector3d(0.0, 0.0, 0.025), Eigen::Vector3d::Zero());
}

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
/// with the arm clear of the safe volume and of the other arm at home; then
/// a diverse subset (greedy: each next pose the farthest in rotation from
/// those already chosen).
std::vector<Eigen::VectorXd> PlanPoses(const Platform& platform, Side side,
                                       const TagBoardConfig& board, int count, std::uint64_t seed) {
  const ArmModel& arm = platform.arm(side);
  const PlatformCollision collision(platform);
  const Eigen::Isometry3d cMb = platform.dMc().inverse() * platform.dMb(side);
  const Eigen::Isometry3d eMt = NominalBoardOnGripper();
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
    const Eigen::VectorXd& other = platform.home(side == Side::kLeft ? Side::kRight : Side::kLeft);
    if (side == Side::kLeft ? collision.ArmsCollide(q, other, 0.01)
                            : collision.ArmsCollide(other, q, 0.01))
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
      s.q_rad = Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<long>(q.size()));
      if (s.q_rad.size() != platform.arm(*side).dof())
        root.Fail(where + ".q_rad", "wrong number of joints");
      s.data.bMe = platform.arm(*side).ForwardKinematics(s.q_rad);
      const auto m = all[i]["cMt"].as<std::vector<double>>();
      if (m.size() != 16) root.Fail(where + ".cMt", "expected 16 numbers");
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
  const Eigen::Vector2d half = 0.5 * board.Size();
  const Eigen::Vector3d outline_t[4] = {{-half.x(), -half.y(), 0},
                                        {half.x(), -half.y(), 0},
                                        {half.x(), half.y(), 0},
                                        {-half.x(), half.y(), 0}};
  auto draw = [&](const Eigen::Isometry3d& cMt, const cv::Scalar& colour, int thickness) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d a = K.Project(cMt * outline_t[k]),
                            b = K.Project(cMt * outline_t[(k + 1) % 4]);
      cv::line(canvas, cv::Point2d(a.x(), a.y()), cv::Point2d(b.x(), b.y()), colour, thickness,
               cv::LINE_AA);
    }
  };
  for (const Sample& s : samples) {
    if (!s.accepted) continue;
    draw(s.data.cMt, cv::Scalar(0, 220, 0), 2);
    if (solution.ok) draw(solution.cMb * s.data.bMe * solution.eMt, cv::Scalar(0, 0, 255), 1);
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
  const PoseSetDiversity diversity = MeasureDiversity(used);
  if (!diversity.Sufficient()) {
    out << fmt::format(
        "warning: the poses are not diverse enough (largest rotation {:.1f} deg, rotation axes "
        "span "
        "{} dimension(s)); the solution may be poor\n",
        diversity.max_rotation_deg, diversity.axis_rank);
  }
  if (diversity.axis_rank < 2) {
    throw std::runtime_error(
        folder +
        ": singular pose set: every rotation is about one axis; add poses that turn "
        "the gripper about other axes");
  }
  const HandEyeResult visp = SolveEyeToHandVisp(used, K);
  const std::vector<HandEyeResult> opencv = SolveEyeToHandOpenCv(used, K);
  const HandEyeResult refined = RefineEyeToHand(used, K, visp.ok ? visp : opencv.front());
  const HandEyeResult& best = refined.ok ? refined : visp;
  if (!best.ok) throw std::runtime_error(folder + ": the hand-eye solve failed: " + visp.message);

  out << fmt::format("{:<20} {:>12} {:>12} {:>10}", "method", "residual mm", "residual deg",
                     "reproj px");
  if (truth_cMb) out << fmt::format(" {:>12} {:>12}", "truth err mm", "truth err deg");
  out << "\n";
  std::vector<const HandEyeResult*> all = {&refined, &visp};
  for (const HandEyeResult& r : opencv) all.push_back(&r);
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
  out << fmt::format("wrote {}, {}/summary.json, {}/poses.png\n", yaml_path, folder, folder);
}

}  // namespace

void RunCalibrateCommand(const CalibrateCommandOptions& options, std::ostream& out,
                         std::ostream& progress) {
  if (!options.resolve_dir.empty()) {
    if (IsIntrinsicsFolder(options.resolve_dir)) {
      ResolveIntrinsics(options.resolve_dir, out);
      return;
    }
    std::string platform_path;
    Side side;
    TagBoardConfig board;
    const std::vector<Sample> samples = ReadSamplesYaml(
        (fs::path(options.resolve_dir) / "samples.yaml").string(), &platform_path, &side, &board);
    SolveAndReport(options.resolve_dir, platform_path, side, board, samples, std::nullopt, out);
    return;
  }
  if (options.intrinsics) {
    RunCalibrateIntrinsics(options, out, progress);
    return;
  }
  const Side side = ParseSide(options.arm);
  if (options.out_dir.empty()) throw ConfigError("--out: an output folder is required");
  const CalibrationHardware hw =
      OpenCalibrationHardware(options.hardware_path, options.world_config, options.seed);
  World& world = *hw.devices->world();
  const TagBoardConfig board;
  world.AttachToTool(side, MakeBoardRenderMesh(board), NominalBoardOnGripper());
  RgbdCamera& camera = hw.devices->camera();
  ArmsDriver& arms = hw.devices->arms();
  const Platform& platform = hw.devices->platform();

  const std::vector<Eigen::VectorXd> poses =
      PlanPoses(platform, side, board, options.poses, options.seed);
  if (poses.empty()) {
    throw std::runtime_error(
        fmt::format("no arm pose of the {} arm shows the whole board to the camera while "
                    "clear of the safe volume",
                    SideName(side)));
  }
  out << fmt::format("planned {} poses of the {} arm (of {} requested); devices: {}\n",
                     poses.size(), SideName(side), options.poses, hw.config.source);
  fs::create_directories(fs::path(options.out_dir) / "samples");
  TagDetector detector(board.family);
  const int board_tags = board.rows * board.cols;
  std::vector<Sample> samples;
  Progress bar(progress, "calibrate", static_cast<std::int64_t>(poses.size()), "poses");
  const std::string samples_yaml = (fs::path(options.out_dir) / "samples.yaml").string();
  constexpr double kSettleStep_s = 0.05;
  for (const Eigen::VectorXd& target : poses) {
    // Settle: the measured joints stop changing and sit on the target the
    // servos were given. The target is sent every cycle, as a control loop
    // does (the bus driver's watchdog holds targets that grow stale).
    const double quantum = world.arm(side).quantum_rad();
    const double start = world.now_s();
    arms.SetJointTargets(side, target);
    Eigen::VectorXd last = arms.JointPositions(side);
    bool settled = false;
    while (world.now_s() - start < options.settle_timeout_s && !settled) {
      hw.devices->StepSimulation(kSettleStep_s);
      arms.SetJointTargets(side, target);
      const Eigen::VectorXd q = arms.JointPositions(side);
      settled = (q - last).cwiseAbs().maxCoeff() < 0.5 * quantum &&
                (q - world.arm(side).target_rad()).cwiseAbs().maxCoeff() < 1.5 * quantum;
      last = q;
    }
    RgbdFrame frame;
    camera.Grab(&frame);
    Sample s;
    s.image = fmt::format("samples/{:03d}.png", samples.size());
    s.q_rad = arms.JointPositions(side);
    s.data.bMe = platform.arm(side).ForwardKinematics(s.q_rad);
    WriteColorPng(frame.color, (fs::path(options.out_dir) / s.image).string());
    const std::vector<TagDetection> detections = detector.Detect(frame.color);
    const BoardPose pose = EstimateBoardPose(detections, board, camera.intrinsics());
    s.data.cMt = pose.cMt;
    s.data.corners = MatchBoardCorners(detections, board);
    if (!settled) {
      s.reject_reason = fmt::format("arm not settled after {:.1f} s", options.settle_timeout_s);
    } else if (!pose.valid || pose.tags_used < kMinBoardFraction * board_tags) {
      s.reject_reason =
          fmt::format("board partly seen ({} of {} tags)", pose.tags_used, board_tags);
    } else if (pose.reprojection_rms_px > kMaxReprojectionPx) {
      s.reject_reason = fmt::format("reprojection error {:.2f} px", pose.reprojection_rms_px);
    }
    s.accepted = s.reject_reason.empty();
    samples.push_back(s);
    WriteSamplesYaml(samples_yaml, hw.config.platform, side, board,
                     samples);  // nothing is lost on an error
    bar.Update(static_cast<std::int64_t>(samples.size()));
  }
  bar.Finish();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].accepted)
      out << fmt::format("  sample {:3d} rejected: {}\n", i, samples[i].reject_reason);
  }
  // In the simulator the truth is the world's platform's nominal geometry.
  const Platform& truth = world.platform();
  const Eigen::Isometry3d truth_cMb = truth.dMc().inverse() * truth.dMb(side);
  SolveAndReport(options.out_dir, hw.config.platform, side, board, samples, truth_cMb, out);
}

}  // namespace aerograsp
