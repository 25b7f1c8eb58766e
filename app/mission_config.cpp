#include "app/mission_config.h"

#include <cmath>

#include "app/calibration_file.h"
#include "core/config.h"

namespace aerograsp {
namespace {

/// The cMb of a calibration file named by `key` (none for an empty path).
std::optional<Eigen::Isometry3d> LoadCalibration(const std::string& source, const std::string& key,
                                                 const std::string& path, Side side) {
  if (path.empty()) return std::nullopt;
  CheckFileExists(source, key, path);
  ArmCalibration calibration;
  try {
    calibration = ArmCalibration::Load(path);
  } catch (const ConfigError& e) {
    throw ConfigError(source + ": " + key + ": " + e.what());
  }
  if (calibration.side != side) {
    throw ConfigError(source + ": " + key + ": " + path + ": arm: the file calibrates the " +
                      SideName(calibration.side) + " arm, not the " + SideName(side) + " one");
  }
  return calibration.cMb;
}

}  // namespace

MissionConfig MissionConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"world",
                        "perception",
                        "takeoff_altitude_m",
                        "approach_w_m",
                        "yaw_rad",
                        "grasp_dto_m",
                        "arrive_tolerance_m",
                        "near_tolerance_m",
                        "tracking_radius_m",
                        "lift_m",
                        "servo_rate_hz",
                        "setpoint_rate_hz",
                        "reevaluate_rate_hz",
                        "object_filter_s",
                        "settle_s",
                        "max_attempts",
                        "lost_timeout_s",
                        "search_timeout_s",
                        "planning_timeout_s",
                        "timeout_s",
                        "servo_margin_m",
                        "grasp_edge_margin_m",
                        "calibration_left",
                        "calibration_right"});
  MissionConfig c;
  c.source = path;
  if (root.Has("world")) c.world = root.GetPath("world");
  if (root.Has("perception") && !root.GetString("perception").empty())
    c.perception = root.GetPath("perception");
  c.takeoff_altitude_m = root.GetDouble("takeoff_altitude_m", c.takeoff_altitude_m);
  if (root.Has("approach_w_m")) c.approach_w_m = root.GetVector3("approach_w_m");
  c.yaw_rad = root.GetDouble("yaw_rad", c.yaw_rad);
  if (root.Has("grasp_dto_m")) c.grasp_dto_m = root.GetVector3("grasp_dto_m");
  c.arrive_tolerance_m = root.GetDouble("arrive_tolerance_m", c.arrive_tolerance_m);
  c.near_tolerance_m = root.GetDouble("near_tolerance_m", c.near_tolerance_m);
  c.tracking_radius_m = root.GetDouble("tracking_radius_m", c.tracking_radius_m);
  c.lift_m = root.GetDouble("lift_m", c.lift_m);
  c.servo_rate_hz = root.GetDouble("servo_rate_hz", c.servo_rate_hz);
  c.setpoint_rate_hz = root.GetDouble("setpoint_rate_hz", c.setpoint_rate_hz);
  c.reevaluate_rate_hz = root.GetDouble("reevaluate_rate_hz", c.reevaluate_rate_hz);
  c.object_filter_s = root.GetDouble("object_filter_s", c.object_filter_s);
  c.settle_s = root.GetDouble("settle_s", c.settle_s);
  c.max_attempts = root.GetInt("max_attempts", c.max_attempts);
  c.lost_timeout_s = root.GetDouble("lost_timeout_s", c.lost_timeout_s);
  c.search_timeout_s = root.GetDouble("search_timeout_s", c.search_timeout_s);
  c.planning_timeout_s = root.GetDouble("planning_timeout_s", c.planning_timeout_s);
  c.timeout_s = root.GetDouble("timeout_s", c.timeout_s);
  c.servo_margin_m = root.GetDouble("servo_margin_m", c.servo_margin_m);
  c.grasp_edge_margin_m = root.GetDouble("grasp_edge_margin_m", c.grasp_edge_margin_m);
  for (const char* key : {"calibration_left", "calibration_right"}) {
    if (root.Has(key) && !root.GetString(key).empty()) {
      (std::string(key) == "calibration_left" ? c.calibration_left : c.calibration_right) =
          root.GetPath(key);
    }
  }
  c.Validate();
  c.calibrated_cMb[0] =
      LoadCalibration(c.source, "calibration_left", c.calibration_left, Side::kLeft);
  c.calibrated_cMb[1] =
      LoadCalibration(c.source, "calibration_right", c.calibration_right, Side::kRight);
  return c;
}

void MissionConfig::Validate() const {
  const std::string& s = source;
  CheckFileExists(s, "world", world);
  if (!perception.empty()) CheckFileExists(s, "perception", perception);
  CheckRange(s, "takeoff_altitude_m", takeoff_altitude_m, 0.5, 20.0, "m");
  CheckRange(s, "approach_w_m", approach_w_m, -100.0, 100.0, "m");
  CheckRange(s, "yaw_rad", yaw_rad, -M_PI, M_PI, "rad");
  CheckRange(s, "grasp_dto_m", grasp_dto_m, -1.0, 1.0, "m");
  CheckRange(s, "arrive_tolerance_m", arrive_tolerance_m, 1e-6, 5.0, "m");
  CheckRange(s, "near_tolerance_m", near_tolerance_m, 1e-6, 1.0, "m");
  CheckRange(s, "tracking_radius_m", tracking_radius_m, 1e-6, 10.0, "m");
  CheckRange(s, "lift_m", lift_m, 0.0, 10.0, "m");
  CheckRange(s, "servo_rate_hz", servo_rate_hz, 10.0, 1000.0, "Hz");
  CheckRange(s, "setpoint_rate_hz", setpoint_rate_hz, 2.0, 100.0, "Hz");
  CheckRange(s, "reevaluate_rate_hz", reevaluate_rate_hz, 1e-6, 100.0, "Hz");
  CheckRange(s, "object_filter_s", object_filter_s, 1e-6, 10.0, "s");
  CheckRange(s, "settle_s", settle_s, 0.0, 5.0, "s");
  CheckRange(s, "max_attempts", max_attempts, 1, 100, "");
  CheckRange(s, "lost_timeout_s", lost_timeout_s, 1e-6, 60.0, "s");
  CheckRange(s, "search_timeout_s", search_timeout_s, 1e-6, 600.0, "s");
  CheckRange(s, "planning_timeout_s", planning_timeout_s, 1e-6, 600.0, "s");
  CheckRange(s, "timeout_s", timeout_s, 1e-6, 3600.0, "s");
  CheckRange(s, "servo_margin_m", servo_margin_m, 0.0, 0.05, "m");
  CheckRange(s, "grasp_edge_margin_m", grasp_edge_margin_m, 0.0, 0.05, "m");
  LoadCalibration(s, "calibration_left", calibration_left, Side::kLeft);
  LoadCalibration(s, "calibration_right", calibration_right, Side::kRight);
}

}  // namespace aerograsp
