#include "app/commands/replay_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands/convert_command.h"
#include "app/commands/replay_accuracy.h"
#include "app/commands/visp_peer.h"
#include "app/exit_codes.h"
#include "app/report/pose_plot.h"
#include "app/report/progress.h"
#include "app/report/replay_report.h"
#include "app/report/report_folder.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "app/runtime/telemetry_frames.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "core/platform.h"
#include "core/transforms.h"
#include "detection/object_tracker.h"
#include "detection/perception_config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// With the filter in the world: position noise along ICP's weak direction (m).
constexpr double kWorldWeakDirectionStdM = 0.02;

nlohmann::json TimesJson(const std::vector<double>& v) {
  nlohmann::json j;
  j["median"] = Percentile(v, 0.5, kNaN);
  j["p95"] = Percentile(v, 0.95, kNaN);
  j["frames"] = v.size();
  if (v.empty()) j["median"] = nullptr, j["p95"] = nullptr;
  return j;
}

}  // namespace

Eigen::Isometry3d ParsePose(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  std::string token;
  while (in >> token) {
    std::size_t used = 0;
    double x;
    try {
      x = std::stod(token, &used);
    } catch (const std::exception&) {
      throw std::invalid_argument("--init-pose: '" + token + "' is not a number");
    }
    if (used != token.size() || !std::isfinite(x))
      throw std::invalid_argument("--init-pose: '" + token + "' is not a number");
    v.push_back(x);
  }
  return PoseFromValues(v);
}

Eigen::Isometry3d PoseFromValues(const std::vector<double>& v, const std::string& option) {
  for (double x : v) {
    if (!std::isfinite(x)) throw std::invalid_argument(option + ": values must be finite");
  }
  if (v.size() != 7)
    throw std::invalid_argument(
        fmt::format("{}: expected 7 numbers (x y z qw qx qy qz), got {}", option, v.size()));
  const Eigen::Vector4d q(v[3], v[4], v[5], v[6]);
  if (q.norm() < 1e-9) throw std::invalid_argument(option + ": the quaternion is zero");
  return MakeTransformWxyz(Eigen::Vector3d(v[0], v[1], v[2]), q);
}

int RunReplayCommand(const ReplayCommandOptions& options, std::ostream& out,
                     std::ostream& progress) {
  // The filter in the world gets noise along ICP's weak direction, unless the file says otherwise.
  PerceptionOptions perception;
  if (options.filter_frame == "world") perception.weak_direction_std_m = kWorldWeakDirectionStdM;
  if (!options.perception_config.empty())
    perception = LoadPerceptionOptions(options.perception_config, perception);
  ReportFolder folder(options.out_dir, options.overwrite);

  const std::unique_ptr<RecordedCamera> recording =
      OpenRecording(options.sequence, options.recording);
  RecordedCamera& camera = *recording;
  const SequenceInfo& info = camera.info();
  const std::string object_name = options.object.empty() ? info.object : options.object;
  if (object_name.empty()) {
    throw std::invalid_argument(options.sequence +
                                ": the recording names no object; give --object");
  }
  // A relative path in sequence.yaml is relative to the sequence folder.
  const fs::path beside = fs::path(options.sequence) / object_name;
  const ObjectModel object =
      ObjectModel::Load(options.object.empty() && fs::path(object_name).is_relative() &&
                                !fs::exists(object_name) && fs::exists(beside)
                            ? beside.string()
                            : object_name);

  std::unique_ptr<BoxDetector> detector;
  std::string detector_path;
  if (options.use_detector) {
    detector_path = options.detector.empty() ? ObjectDetectorPath(object) : options.detector;
    if (!detector_path.empty()) detector = std::make_unique<BoxDetector>(detector_path);
  }
  std::optional<Eigen::Isometry3d> dMc;  // the camera mount, for a filter in the world
  if (options.filter_frame == "world") {
    if (info.frame_count > 0 && !camera.extras(0).vehicle) {
      throw std::invalid_argument(options.sequence +
                                  ": --filter-frame world needs the vehicle states (vehicle.csv)");
    }
    dMc = Platform::Load(options.platform.empty() ? DataPath("config/platform_4dof.yaml")
                                                  : options.platform)
              .dMc();
  } else if (options.filter_frame != "camera") {
    throw std::invalid_argument("--filter-frame: '" + options.filter_frame +
                                "' is not one of camera, world");
  }
  ObjectTracker tracker(object, perception, std::move(detector));
  const ModelCloud& model = tracker.model();

  std::optional<Eigen::Isometry3d> init = options.init_cMo;
  if (options.init_from_truth) {
    if (!camera.has_groundtruth())
      throw std::invalid_argument(options.sequence +
                                  ": --init-from-truth needs the ground truth (groundtruth.csv; "
                                  "for a TUM folder groundtruth.txt and --object-in-world)");
    init = camera.extras(0).cMo;
  }
  if (init) tracker.SetInitialPose(*init);
  std::unique_ptr<VispPeerTracker> peer;
  if (options.run_peer)
    peer = std::make_unique<VispPeerTracker>(object, info.intrinsics, folder.path());

  CommandTelemetry telemetry =
      OpenTelemetry(LoadTelemetryConfig(options.telemetry), folder.path(), "replay",
                    [&out](const std::string& line) { out << "telemetry: " << line << "\n"; });
  TelemetrySink* sink = telemetry.sink();
  if (sink && dMc) {
    sink->StaticTransforms(0.0, {{telemetry_frame::kMap, telemetry_frame::kWorld, MapMWorld()},
                                 {telemetry_frame::kBody, telemetry_frame::kCamera, *dMc}});
  }
  const std::string poses_path = (fs::path(folder.path()) / "poses.csv").string();
  std::ofstream poses(poses_path);
  if (!poses) throw std::runtime_error(poses_path + ": cannot be written");
  poses << "frame,stamp_s,tx_m,ty_m,tz_m,qw,qx,qy,qz,confidence,state,measured,global_init,gated,"
           "detection_score,"
           "cloud_points,icp_inliers,icp_rmse_mm,rejected_distance,rejected_normal,rejected_color,"
           "support_ratio,"
           "support_coverage,nis,frame_ms,peer_tx_m,peer_ty_m,peer_tz_m,peer_qw,peer_qx,peer_qy,"
           "peer_qz,peer_state\n";

  const std::int64_t total = options.max_frames > 0
                                 ? std::min<std::int64_t>(options.max_frames, info.frame_count)
                                 : info.frame_count;
  Progress bar(progress, "replay", total, "frames");
  AccuracyCounter ours(model), theirs(model);
  std::vector<double> frame_ms, detect_ms, cloud_ms, icp_ms, global_ms, filter_ms, peer_ms;
  std::vector<double> box_iou;
  int peer_failures = 0;
  std::string peer_first_error;
  int box_hits = 0, box_visible = 0, measured = 0, global_runs = 0, gated = 0, found_frames = 0;
  PoseTrace truth_trace, our_trace, peer_trace;
  truth_trace.name = "truth";
  our_trace.name = "aerograsp";
  peer_trace.name = "ViSP mbt (dense depth)";
  RgbdFrame frame;
  std::int64_t i = 0;
  std::string stop_reason;
  for (; i < total; ++i) {
    try {
      if (!camera.Grab(&frame)) break;
    } catch (const HardwareError& e) {
      stop_reason = e.what();  // a truncated sequence: report what was processed
      break;
    }
    std::optional<Eigen::Isometry3d> wMc;
    if (dMc) {
      const std::optional<VehicleState>& vehicle = camera.extras(i).vehicle;
      if (!vehicle) {
        stop_reason =
            fmt::format("{}: frame {} has no vehicle state (needed by --filter-frame world)",
                        options.sequence, i);
        break;
      }
      wMc = vehicle->wMd * *dMc;
    }
    const FrameReport r = tracker.Process(frame.color, frame.depth, frame.stamp_s, info.intrinsics,
                                          info.depth_scale_m, wMc);
    const ObjectEstimate& e = r.estimate;
    const bool found = e.valid && e.state == TrackState::kFound;
    frame_ms.push_back(r.times.total_ms);
    detect_ms.push_back(r.times.detect_ms);
    cloud_ms.push_back(r.times.cloud_ms);
    filter_ms.push_back(r.times.filter_ms);
    if (r.icp.iterations > 0 && !r.global_init) icp_ms.push_back(r.times.icp_ms);
    if (r.global_init) global_ms.push_back(r.times.global_ms), ++global_runs;
    measured += r.measured;
    gated += r.gated;
    found_frames += found;

    std::optional<PeerResult> peer_result;
    if (peer) {
      if (!peer->initialized()) {
        // Initialised the same way as ours: the given first pose, else our first found pose.
        if (init && i == 0)
          peer->Initialize(*init);
        else if (found)
          peer->Initialize(e.cMo);
      }
      if (peer->initialized()) {
        peer_result = peer->Track(frame.color, frame.depth, info.depth_scale_m);
        peer_ms.push_back(peer_result->ms);
        if (!peer_result->error.empty()) {
          ++peer_failures;
          if (peer_first_error.empty())
            peer_first_error = fmt::format("frame {}: {}", i, peer_result->error);
        }
      }
    }

    const std::optional<Eigen::Isometry3d>& truth = camera.extras(i).cMo;
    if (sink) {  // the recording's clock; the filter in the world when it has wMc
      PublishPerceivedFrame(sink, frame.stamp_s,
                            wMc ? telemetry_frame::kWorld : telemetry_frame::kCamera, e, found,
                            frame, info.intrinsics, info.depth_scale_m);
      std::vector<TelemetryTransform> tf;
      if (wMc)
        tf.push_back({telemetry_frame::kWorld, telemetry_frame::kBody, *wMc * dMc->inverse()});
      if (e.valid) tf.push_back({telemetry_frame::kCamera, telemetry_frame::kObject, e.cMo});
      if (truth) tf.push_back({telemetry_frame::kCamera, telemetry_frame::kObjectTruth, *truth});
      if (!tf.empty()) sink->Transforms(frame.stamp_s, tf);
    }
    bool visible = false;
    if (truth) {
      // Visibility of the truth: depth only (no colour image, no colour check).
      const PoseSupport s =
          ScorePoseSupport(model, *truth, {}, frame.depth, info.depth_scale_m, info.intrinsics);
      visible = s.projected >= 20 && s.coverage() >= 0.3;
      if (visible) {
        ++box_visible;
        const double iou = r.detection ? BoxIoU(r.detection->box, s.box) : 0.0;
        box_iou.push_back(iou);
        box_hits += iou >= 0.5;
      }
      ours.Add(visible, truth, found, e.cMo);
      if (peer)
        theirs.Add(visible, truth, peer_result && peer_result->ok,
                   peer_result ? peer_result->cMo : e.cMo);
      truth_trace.stamp_s.push_back(frame.stamp_s);
      truth_trace.x_m.push_back(truth->translation().x());
      truth_trace.y_m.push_back(truth->translation().y());
      truth_trace.z_m.push_back(truth->translation().z());
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto trace = [&](PoseTrace* t, bool ok, const Eigen::Isometry3d& cMo) {
      t->stamp_s.push_back(frame.stamp_s);
      t->x_m.push_back(ok ? cMo.translation().x() : nan);
      t->y_m.push_back(ok ? cMo.translation().y() : nan);
      t->z_m.push_back(ok ? cMo.translation().z() : nan);
      t->rotation_error_deg.push_back(
          ok && truth
              ? SymmetricRotationError(cMo.linear(), truth->linear(), model.symmetry) * 180.0 / M_PI
              : nan);
      t->found.push_back(ok ? 1 : 0);
    };
    trace(&our_trace, found, e.cMo);
    if (peer)
      trace(&peer_trace, peer_result && peer_result->ok, peer_result ? peer_result->cMo : e.cMo);

    const Eigen::Vector4d q = QuaternionWxyz(e.cMo);
    poses << fmt::format(
        "{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.3f},{},{},{},{},{:.3f}", i,
        frame.stamp_s, e.cMo.translation().x(), e.cMo.translation().y(), e.cMo.translation().z(),
        q[0], q[1], q[2], q[3], e.confidence, e.valid ? ToString(e.state) : "none", int(r.measured),
        int(r.global_init), int(r.gated), r.detection ? r.detection->score : 0.0f);
    poses << fmt::format(",{},{},{:.2f},{},{},{},{:.3f},{:.3f},{:.2f},{:.2f}", r.cloud_points,
                         r.icp.inliers, 1e3 * r.icp.rmse_m,
                         r.icp.rejected_distance + r.icp.rejected_no_model, r.icp.rejected_normal,
                         r.icp.rejected_color, r.support.ratio(), r.support.coverage(), r.nis,
                         r.times.total_ms);
    if (peer_result) {
      const Eigen::Vector4d pq = QuaternionWxyz(peer_result->cMo);
      poses << fmt::format(",{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{}",
                           peer_result->cMo.translation().x(), peer_result->cMo.translation().y(),
                           peer_result->cMo.translation().z(), pq[0], pq[1], pq[2], pq[3],
                           peer_result->ok ? "found" : "lost");
    } else {
      poses << ",,,,,,,,none";
    }
    poses << "\n";
    bar.Update(i + 1);
  }
  bar.Finish();
  const int frames = static_cast<int>(i);
  const std::string mcap = telemetry.Close();

  nlohmann::json summary;
  summary["sequence"] = options.sequence;
  summary["recording"] = info.description;
  summary["object"] = object.name;
  summary["frames"] = frames;
  summary["filter_frame"] = options.filter_frame;
  summary["perception"] =
      options.perception_config.empty() ? "code defaults" : options.perception_config;
  if (!stop_reason.empty()) summary["stopped_early"] = stop_reason;
  summary["detector"] =
      tracker.has_detector() ? detector_path : "none (global registration on the whole frame)";
  summary["symmetry"] = {{"discrete_rotations", model.symmetry.rotations.size()},
                         {"continuous_axis", model.symmetry.continuous_axis_o.has_value()}};
  summary["frames_found"] = found_frames;
  summary["frames_measured"] = measured;
  summary["global_inits"] = global_runs;
  summary["gated_measurements"] = gated;
  summary["frame_ms_median"] = Percentile(frame_ms, 0.5, kNaN);
  summary["frame_ms_p95"] = Percentile(frame_ms, 0.95, kNaN);
  summary["stage_ms"] = {{"detect", TimesJson(detect_ms)},
                         {"crop_cloud_normals", TimesJson(cloud_ms)},
                         {"icp_tracking", TimesJson(icp_ms)},
                         {"global_init", TimesJson(global_ms)},
                         {"filter", TimesJson(filter_ms)}};
  summary["timing"] = "thread CPU time, one core (global_init: all cores)";
  const GlobalSearchStats& g = tracker.global_stats();
  summary["global_search"] = {{"frames", g.frames},
                              {"searches", g.searches},
                              {"found", g.found},
                              {"exhausted", g.exhausted},
                              {"max_frames", g.max_frames},
                              {"work_per_frame_limit", perception.global.work_per_frame},
                              {"work_per_frame_mean", frames > 0 ? double(g.work) / frames : 0.0},
                              {"cpu_ms_per_frame_mean", frames > 0 ? g.cpu_ms / frames : 0.0}};
  if (camera.has_groundtruth()) {
    const nlohmann::json acc = AccuracyJson(ours.Finish(), model.diameter_m);
    for (auto& [key, value] : acc.items()) summary[key] = value;
    summary["rotation_error"] =
        "angle of R_true^-1 R_est minimised over the object's rotational symmetries; for an axis "
        "of continuous "
        "symmetry, the angle between the axes";
    summary["detection_recall_definition"] =
        "frames where the tracker reports the object found / frames where the object is visible in "
        "the truth";
    if (tracker.has_detector()) {
      summary["detector_box_recall"] = box_visible ? double(box_hits) / box_visible : 0.0;
      summary["detector_box_iou_mean"] =
          box_iou.empty() ? 0.0
                          : std::accumulate(box_iou.begin(), box_iou.end(), 0.0) / box_iou.size();
    }
  }
  if (peer) {
    nlohmann::json p;
    p["name"] = "ViSP vpMbGenericTracker, dense depth features";
    p["initialised"] = !peer_ms.empty();
    p["tracking_failures"] = peer_failures;
    if (!peer_first_error.empty()) p["first_error"] = peer_first_error;
    p["frame_ms_median"] = Percentile(peer_ms, 0.5, kNaN);
    p["frame_ms_p95"] = Percentile(peer_ms, 0.95, kNaN);
    if (camera.has_groundtruth()) {
      const nlohmann::json acc = AccuracyJson(theirs.Finish(), model.diameter_m);
      for (auto& [key, value] : acc.items()) p[key] = value;
    }
    summary["visp_peer"] = p;
  }
  NullNonFiniteFields(&summary);
  const std::string summary_path = WriteSummaryFile(folder.path(), summary.dump(2));
  auto num = [&](const char* key, double scale) {
    return summary.contains(key) && summary[key].is_number()
               ? fmt::format("{:.2f}", scale * summary[key].get<double>())
               : std::string("-");
  };
  std::vector<PoseTrace> traces{our_trace};
  if (peer) traces.push_back(peer_trace);
  std::vector<std::vector<std::string>> headline = {
      {"recording", options.sequence},
      {"frames (object found)", fmt::format("{} ({})", frames, found_frames)},
      {"frame time median / p95 (ms)", num("frame_ms_median", 1) + " / " + num("frame_ms_p95", 1)}};
  if (camera.has_groundtruth()) {
    headline.push_back({"translation RMSE (mm)", num("translation_rmse_m", 1e3)});
    headline.push_back({"rotation RMSE (deg)", num("rotation_rmse_deg", 1)});
    headline.push_back({"detection recall (%)", num("detection_recall", 100)});
    headline.push_back({"ADD-S recall (%)", num("add_s_recall", 100)});
  }
  if (!stop_reason.empty()) headline.push_back({"stopped early", stop_reason});
  WriteReplayReport("Replay report: " + object.name, headline,
                    camera.has_groundtruth() ? truth_trace : PoseTrace{}, traces, folder.path());
  out << fmt::format("replay: {} frames of {}, object {}, detector {}\n", frames, options.sequence,
                     object.name,
                     tracker.has_detector() ? "yes" : "no (whole-frame global registration)");
  if (!stop_reason.empty()) out << "  stopped early: " << stop_reason << "\n";
  out << fmt::format(
      "  found {} frames, {} global inits, {} gated; frame {} ms median, {} ms p95\n", found_frames,
      global_runs, gated, num("frame_ms_median", 1), num("frame_ms_p95", 1));
  out << fmt::format(
      "  global registration: {} searches ({} found the object, {} tried everything), {} frames; "
      "{:.1f} ms CPU and {:.0f} pairings a frame on average (limit {})\n",
      g.searches, g.found, g.exhausted, g.frames, frames > 0 ? g.cpu_ms / frames : 0.0,
      frames > 0 ? double(g.work) / frames : 0.0,
      perception.global.work_per_frame > 0 ? std::to_string(perception.global.work_per_frame)
                                           : std::string("none"));
  if (camera.has_groundtruth()) {
    out << fmt::format(
        "  translation RMSE {} mm, rotation RMSE {} deg, detection recall {} %, ADD-S recall {} "
        "%\n",
        num("translation_rmse_m", 1e3), num("rotation_rmse_deg", 1), num("detection_recall", 100),
        num("add_s_recall", 100));
    const nlohmann::json& acc = summary;
    if (acc.value("reacquisitions", 0) + acc.value("never_reacquired", 0) > 0) {
      out << fmt::format(
          "  fully hidden and seen again {} times: found again within {} frames at most, {} "
          "never\n",
          acc.value("reacquisitions", 0) + acc.value("never_reacquired", 0),
          acc.value("reacquire_max_frames", 0), acc.value("never_reacquired", 0));
    }
  }
  folder.Commit();  // also when stopped early: the report says so
  out << "  wrote " << folder.Final(summary_path) << " and "
      << folder.Final((fs::path(folder.path()) / "index.html").string()) << "\n";
  if (!mcap.empty()) out << "  wrote " << folder.Final(mcap) << "\n";
  return stop_reason.empty() ? kExitOk : kExitStoppedEarly;
}

void AddReplayOptions(CLI::App* cmd, ReplayCommandOptions* o) {
  const auto init = std::make_shared<std::vector<double>>();  // seven numbers, a pose once parsed
  cmd->add_option("sequence", o->sequence,
                  "Recording: sequence folder, RealSense .bag or TUM RGB-D folder")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--out", o->out_dir,
                  "Output folder (index.html, summary.json, poses.csv, pose_vs_truth.png)")
      ->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--object", o->object,
                  "Object (shipped name or model path) [from sequence.yaml]");
  cmd->add_option("--detector", o->detector, "Detector ONNX [data/objects/NAME/detector.onnx]");
  cmd->add_flag("!--no-detector", o->use_detector,
                "No CNN: global registration on the whole frame");
  cmd->add_option("--init-pose", *init, "Known first cMo: x y z (m) qw qx qy qz")
      ->expected(7)
      ->check(cli::Finite());
  cmd->add_flag("--init-from-truth", o->init_from_truth, "Known first cMo from groundtruth.csv");
  cmd->add_flag("!--no-peer", o->run_peer, "Do not run ViSP's vpMbGenericTracker beside ours");
  cmd->add_option(
         "--filter-frame", o->filter_frame,
         "Pose filter frame: camera, or world (camera poses from the recorded vehicle states)")
      ->capture_default_str();
  cmd->add_option("--platform", o->platform,
                  "Platform YAML for the camera mount [config/platform_4dof.yaml]");
  cmd->add_option("--frames", o->max_frames, "Process at most this many frames (0: all)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--perception", o->perception_config,
                  "Perception YAML (see data/config/perception_default.yaml) [the code's defaults]")
      ->check(CLI::ExistingFile);
  AddTelemetryOptions(cmd, &o->telemetry);
  const std::function<void()> recording = AddRecordingOptions(cmd, &o->recording);
  cmd->callback([o, init, recording] {
    if (!init->empty()) o->init_cMo = PoseFromValues(*init);
    recording();
  });
}

}  // namespace aerograsp
