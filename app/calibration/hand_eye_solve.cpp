#include "app/calibration/hand_eye_solve.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/calibration/calibration_file.h"
#include "app/calibration/calibration_visp.h"
#include "app/calibration/hand_eye_plan.h"
#include "app/report/summary_file.h"
#include "core/transforms.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

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

}  // namespace

void SolveHandEyeAndReport(const std::string& folder, const std::string& platform_path, Side side,
                           const TagBoardConfig& board, const std::vector<WizardSample>& samples,
                           const std::optional<Eigen::Isometry3d>& truth_cMb, std::ostream& out) {
  const Platform platform = Platform::Load(platform_path);
  const CameraIntrinsics& K = platform.camera();
  std::vector<HandEyeSample> used;
  int rejected = 0;
  for (const WizardSample& s : samples) {
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

}  // namespace aerograsp
