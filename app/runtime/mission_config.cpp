#include "app/runtime/mission_config.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <variant>
#include <vector>

#include "app/calibration/calibration_file.h"
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

/// One number of the tree: its section ("" top level, "servo.ik_tolerance_4dof"), key and field.
struct Field {
  std::string section;
  std::string key;
  std::variant<double*, int*> value;
};

void AddTolerance(std::vector<Field>* f, const std::string& section, PoseTolerance* t) {
  f->push_back({section, "position_m", &t->position_m});
  f->push_back({section, "approach_rad", &t->approach_rad});
  f->push_back({section, "roll_rad", &t->roll_rad});
}

/// Every number of the tree in file order (the vectors, paths and calibrations apart).
std::vector<Field> Fields(MissionConfig* c) {
  std::vector<Field> f = {
      {"", "takeoff_altitude_m", &c->takeoff_altitude_m},
      {"", "yaw_rad", &c->yaw_rad},
      {"", "arrive_tolerance_m", &c->arrive_tolerance_m},
      {"", "tracking_radius_m", &c->tracking_radius_m},
      {"", "lift_m", &c->lift_m},
      {"", "servo_rate_hz", &c->servo_rate_hz},
      {"", "setpoint_rate_hz", &c->setpoint_rate_hz},
      {"", "reevaluate_rate_hz", &c->reevaluate_rate_hz},
      {"", "object_filter_s", &c->object_filter_s},
      {"", "vehicle_lag_s", &c->vehicle_lag_s},
      {"", "predict_max_s", &c->predict_max_s},
      {"", "length_fit_s", &c->length_fit_s},
      {"", "length_break_m", &c->length_break_m},
      {"", "length_break_frames", &c->length_break_frames},
      {"", "length_refit_frames", &c->length_refit_frames},
      {"", "empty_close_shift_max_m", &c->empty_close_shift_max_m},
      {"", "search_timeout_s", &c->search_timeout_s},
      {"", "timeout_s", &c->timeout_s},
      {"", "servo_margin_m", &c->servo_margin_m},
  };
  PlacementConfig& pl = c->placement;
  f.insert(f.end(), {{"placement", "search_x_m", &pl.search_x_m},
                     {"placement", "search_y_m", &pl.search_y_m},
                     {"placement", "search_z_m", &pl.search_z_m},
                     {"placement", "step_m", &pl.step_m},
                     {"placement", "end_margin_m", &pl.end_margin_m},
                     {"placement", "object_yaw_rad", &pl.object_yaw_rad}});
  GraspPolicyConfig& p = c->policy;
  f.insert(f.end(), {{"policy", "near_tolerance_m", &p.near_tolerance_m},
                     {"policy", "settle_s", &p.settle_s},
                     {"policy", "max_attempts", &p.max_attempts},
                     {"policy", "lost_timeout_s", &p.lost_timeout_s},
                     {"policy", "held_velocity_trust_s", &p.held_velocity_trust_s},
                     {"policy", "held_min_speed_mps", &p.held_min_speed_mps},
                     {"policy", "held_max_carry_m", &p.held_max_carry_m},
                     {"policy", "planning_timeout_s", &p.planning_timeout_s},
                     {"policy", "switch_margin", &p.switch_margin},
                     {"policy", "unreachable_to_switch", &p.unreachable_to_switch},
                     {"policy", "branch_jump_rad", &p.branch_jump_rad},
                     {"policy", "branch_drift_rad_per_s", &p.branch_drift_rad_per_s},
                     {"policy", "max_reaims", &p.max_reaims},
                     {"policy", "reaim_wait_s", &p.reaim_wait_s},
                     {"policy", "carried_unreachable_s", &p.carried_unreachable_s},
                     {"policy", "home_tolerance_m", &p.home_tolerance_m},
                     {"policy", "target_on_object_m", &p.target_on_object_m},
                     {"policy", "close_together_m", &p.close_together_m},
                     {"policy", "close_wait_s", &p.close_wait_s}});
  GraspPlannerConfig& g = c->planner;
  f.insert(f.end(), {{"planner", "depth_min_m", &g.depth_min_m},
                     {"planner", "depth_max_m", &g.depth_max_m},
                     {"planner", "precatch_distance_m", &g.precatch_distance_m},
                     {"planner", "safe_volume_margin_m", &g.safe_volume_margin_m},
                     {"planner", "arms_margin_m", &g.arms_margin_m},
                     {"planner", "object_margin_m", &g.object_margin_m},
                     {"planner", "support_directions", &g.support_directions},
                     {"planner", "exact_top_k", &g.exact_top_k},
                     {"planner", "quality_weight", &g.quality_weight},
                     {"planner", "task_weight", &g.task_weight},
                     {"planner", "cost_weight_per_rad", &g.cost_weight_per_rad},
                     {"planner", "reach_margin_m", &g.reach_margin_m},
                     {"planner", "robust_branch_rad", &g.robust_branch_rad},
                     {"planner", "wrist_margin_rad", &g.wrist_margin_rad},
                     {"planner", "edge_margin_m", &g.edge_margin_m},
                     {"planner", "grasp_axis_approaches", &g.grasp_axis_approaches},
                     {"planner", "grasp_axis_depths", &g.grasp_axis_depths},
                     {"planner.contacts", "resolution_m", &g.contacts.resolution_m},
                     {"planner.friction", "mu", &g.friction.mu},
                     {"planner.friction", "cone_edges", &g.friction.cone_edges},
                     {"planner.friction", "torsional_m", &g.friction.torsional_m}});
  ServoConfig& s = c->servo;
  f.insert(f.end(), {{"servo", "gain_per_s", &s.gain_per_s},
                     {"servo", "switch_blend_per_s", &s.switch_blend_per_s},
                     {"servo", "speed_fraction", &s.speed_fraction},
                     {"servo", "max_accel_rad_s2", &s.max_accel_rad_s2},
                     {"servo", "limit_zone_rad", &s.limit_zone_rad},
                     {"servo", "stale_target_s", &s.stale_target_s},
                     {"servo", "guide_near_rad", &s.guide_near_rad},
                     {"servo", "guide_far_rad", &s.guide_far_rad},
                     {"servo", "guide_min", &s.guide_min},
                     {"servo", "retarget_m", &s.retarget_m},
                     {"servo", "retarget_rad", &s.retarget_rad},
                     {"servo", "unreachable_retry_s", &s.unreachable_retry_s},
                     {"servo", "random_vias", &s.random_vias},
                     {"servo", "path_check_step_rad", &s.path_check_step_rad},
                     {"servo", "search_budget", &s.search_budget},
                     {"servo", "command_lead_rad", &s.command_lead_rad}});
  AddTolerance(&f, "servo.ik_tolerance_4dof", &c->servo_ik_tolerance_4dof);
  GraspSequenceConfig& q = c->grasp_sequence;
  AddTolerance(&f, "grasp_sequence.precatch_tolerance", &q.precatch_tolerance);
  AddTolerance(&f, "grasp_sequence.grasp_tolerance", &q.grasp_tolerance);
  f.push_back({"grasp_sequence", "precatch_timeout_s", &q.precatch_timeout_s});
  f.push_back({"grasp_sequence", "grasp_timeout_s", &q.grasp_timeout_s});
  return f;
}

const std::vector<std::string> kTopKeys = {"world",       "perception",       "approach_w_m",
                                           "grasp_dto_m", "calibration_left", "calibration_right"};

/// The node of a dotted section below root (root itself for "").
std::optional<ConfigNode> Section(const ConfigNode& root, const std::string& section) {
  ConfigNode node = root;
  std::size_t start = 0;
  while (start < section.size()) {
    const std::size_t dot = section.find('.', start);
    const std::string key = section.substr(start, dot == std::string::npos ? dot : dot - start);
    if (!node.Has(key)) return std::nullopt;
    node = node.Child(key);
    start = dot == std::string::npos ? section.size() : dot + 1;
  }
  return node;
}

std::string Number(double v) { return fmt::format("{}", v); }

}  // namespace

GraspPlannerConfig MissionPlannerDefaults() {
  GraspPlannerConfig c;
  // Contacts at least 2.5 cm behind the tool point: the closing line then
  // crosses the object even with the few millimetres of pose and tracking
  // error left in flight (a pair at the tool point itself closes on air) ...
  c.depth_min_m = 0.025;
  // ... and up to the pads' roots (0.02 m inside the tips, 0.12 m long): a
  // followed pair is then exactly solvable in more of the close's servo cycles
  // (the contacts may sit deeper as the object sways).
  c.depth_max_m = 0.10;
  c.edge_margin_m = 0.015;
  // Pairs that stay feasible with the object 2 cm off along each axis rank
  // first: the followed pair is solved again every cycle while the vehicle
  // sways (3 cm, 2 cm vertically) and the placement puts the object where
  // both arms have such pairs.
  c.reach_margin_m = 0.02;
  // ... on the branch the mission follows them on (policy.branch_jump_rad
  // plus a second's drift): grasps that reach through the sway only on
  // another branch are refused as soon as the object moves.
  c.robust_branch_rad = 0.5;
  // The 6-DoF arm's grasp-axis IK tries 16 approaches about the closing axis
  // at 3 depths: at 8 and the middle depth it reached a few of the U-shape's
  // pairs, none of them through the sway with the other arm clear.
  c.grasp_axis_approaches = 16;
  c.grasp_axis_depths = 3;
  return c;
}

ServoConfig MissionServoDefaults() {
  ServoConfig c;
  // A first-order tracker of gain k follows a sway of w = 2 pi 0.5 Hz with an
  // error of about A w / sqrt(w^2 + k^2): 2.2 cm of a 3 cm sway at k = 3/s,
  // 0.6 cm at 15/s.
  c.gain_per_s = 15.0;
  c.unreachable_retry_s = 0.1;  // the sway brings a target back within a cycle or two
  // The SCS servos take positions in counts of 0.21 deg and follow with a lag.
  c.command_lead_rad = 0.03;
  return c;
}

GraspSequenceConfig MissionSequenceDefaults() {
  GraspSequenceConfig c;
  // The object sways +-3 cm at 0.5 Hz and the arm follows a frame period and a
  // servo lag behind it: a few millimetres of tracking error remain, which the
  // gripper's clearance takes.
  c.precatch_tolerance.position_m = 0.01;
  c.grasp_tolerance.position_m = 0.006;
  c.precatch_timeout_s = 10.0;  // 0.35 m from home while the target sways
  c.grasp_timeout_s = 5.0;
  return c;
}

ServoConfig MissionConfig::ServoFor(int dof) const {
  ServoConfig c = servo;
  if (dof < 6) c.ik.tolerance = servo_ik_tolerance_4dof;
  return c;
}

MissionConfig MissionConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  MissionConfig c;
  c.source = path;
  std::map<std::string, std::vector<std::string>> keys;  // per section, its keys and subsections
  keys[""] = kTopKeys;
  for (const Field& f : Fields(&c)) {
    keys[f.section].push_back(f.key);
    const std::size_t dot = f.section.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : f.section.substr(0, dot);
    const std::string child = dot == std::string::npos ? f.section : f.section.substr(dot + 1);
    std::vector<std::string>& parent_keys = keys[parent];
    if (!f.section.empty() &&
        std::find(parent_keys.begin(), parent_keys.end(), child) == parent_keys.end())
      parent_keys.push_back(child);
  }
  for (const auto& [section, allowed] : keys) {
    if (const auto node = Section(root, section)) node->RequireOnlyKeys(allowed);
  }
  for (const Field& f : Fields(&c)) {
    const auto node = Section(root, f.section);
    if (!node) continue;
    if (auto* d = std::get_if<double*>(&f.value)) **d = node->GetDouble(f.key, **d);
    if (auto* i = std::get_if<int*>(&f.value)) **i = node->GetInt(f.key, **i);
  }
  if (root.Has("world")) c.world = root.GetPath("world");
  if (root.Has("perception") && !root.GetString("perception").empty())
    c.perception = root.GetPath("perception");
  if (root.Has("approach_w_m")) c.approach_w_m = root.GetVector3("approach_w_m");
  if (root.Has("grasp_dto_m")) c.grasp_dto_m = root.GetVector3("grasp_dto_m");
  for (const char* key : {"calibration_left", "calibration_right"}) {
    if (root.Has(key) && !root.GetString(key).empty()) {
      (std::string(key) == "calibration_left" ? c.calibration_left : c.calibration_right) =
          root.GetPath(key);
    }
  }
  c.Validate(c.source, "");
  c.calibrated_cMb[0] =
      LoadCalibration(c.source, "calibration_left", c.calibration_left, Side::kLeft);
  c.calibrated_cMb[1] =
      LoadCalibration(c.source, "calibration_right", c.calibration_right, Side::kRight);
  return c;
}

void MissionConfig::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& s = source;
  CheckFileExists(s, prefix + "world", world);
  if (!perception.empty()) CheckFileExists(s, prefix + "perception", perception);
  CheckRange(s, prefix + "takeoff_altitude_m", takeoff_altitude_m, 0.5, 20.0, "m");
  CheckRange(s, prefix + "approach_w_m", approach_w_m, -100.0, 100.0, "m");
  CheckRange(s, prefix + "yaw_rad", yaw_rad, -M_PI, M_PI, "rad");
  CheckRange(s, prefix + "grasp_dto_m", grasp_dto_m, -1.0, 1.0, "m");
  CheckRange(s, prefix + "arrive_tolerance_m", arrive_tolerance_m, 1e-6, 5.0, "m");
  CheckRange(s, prefix + "tracking_radius_m", tracking_radius_m, 1e-6, 10.0, "m");
  CheckRange(s, prefix + "lift_m", lift_m, 0.0, 10.0, "m");
  CheckRange(s, prefix + "servo_rate_hz", servo_rate_hz, 10.0, 1000.0, "Hz");
  CheckRange(s, prefix + "setpoint_rate_hz", setpoint_rate_hz, 2.0, 100.0, "Hz");
  CheckRange(s, prefix + "reevaluate_rate_hz", reevaluate_rate_hz, 1e-6, 100.0, "Hz");
  CheckRange(s, prefix + "object_filter_s", object_filter_s, 1e-6, 10.0, "s");
  CheckRange(s, prefix + "vehicle_lag_s", vehicle_lag_s, 0.0, 5.0, "s");
  CheckRange(s, prefix + "predict_max_s", predict_max_s, 0.0, 1.0, "s");
  CheckRange(s, prefix + "length_fit_s", length_fit_s, 0.0, 30.0, "s");
  CheckRange(s, prefix + "length_break_m", length_break_m, 1e-6, 1.0, "m");
  CheckRange(s, prefix + "length_break_frames", length_break_frames, 1, 30, "");
  CheckRange(s, prefix + "length_refit_frames", length_refit_frames, 2, 300, "");
  CheckRange(s, prefix + "empty_close_shift_max_m", empty_close_shift_max_m, 0.0, 0.2, "m");
  CheckRange(s, prefix + "search_timeout_s", search_timeout_s, 1e-6, 600.0, "s");
  CheckRange(s, prefix + "timeout_s", timeout_s, 1e-6, 3600.0, "s");
  CheckRange(s, prefix + "servo_margin_m", servo_margin_m, 0.0, 0.05, "m");
  placement.Validate(s, prefix + "placement.");
  policy.Validate(s, prefix + "policy.");
  // The depth range is checked against the gripper's fingers when the
  // platform is known (GraspPlannerConfig::CheckFingers).
  planner.Validate(s, prefix + "planner.");
  servo.Validate(s, prefix + "servo.");
  servo_ik_tolerance_4dof.Validate(s, prefix + "servo.ik_tolerance_4dof.");
  grasp_sequence.Validate(s, prefix + "grasp_sequence.");
  LoadCalibration(s, prefix + "calibration_left", calibration_left, Side::kLeft);
  LoadCalibration(s, prefix + "calibration_right", calibration_right, Side::kRight);
}

std::string MissionConfig::ToYaml() const {
  MissionConfig copy = *this;
  std::string out;
  out += fmt::format("world: \"{}\"\nperception: \"{}\"\n", world, perception);
  const auto vector = [](const Eigen::Vector3d& v) {
    return fmt::format("[{}, {}, {}]", Number(v.x()), Number(v.y()), Number(v.z()));
  };
  out +=
      fmt::format("approach_w_m: {}\ngrasp_dto_m: {}\n", vector(approach_w_m), vector(grasp_dto_m));
  out += fmt::format("calibration_left: \"{}\"\ncalibration_right: \"{}\"\n", calibration_left,
                     calibration_right);
  std::string open;  // the section whose header was written last
  for (const Field& f : Fields(&copy)) {
    if (f.section != open) {
      // Headers of the sections not open yet ("planner" before "planner.contacts").
      std::size_t common = 0;
      while (common < f.section.size()) {
        const std::size_t dot = f.section.find('.', common);
        const std::size_t end = dot == std::string::npos ? f.section.size() : dot;
        const std::string prefix = f.section.substr(0, end);
        const bool is_open = open == prefix || open.rfind(prefix + ".", 0) == 0;
        if (!is_open) {
          const int depth = static_cast<int>(std::count(prefix.begin(), prefix.end(), '.'));
          out += fmt::format("{}{}:\n", std::string(2 * depth, ' '),
                             f.section.substr(common, end - common));
        }
        common = end + 1;
      }
      open = f.section;
    }
    const int depth =
        f.section.empty()
            ? 0
            : 1 + static_cast<int>(std::count(f.section.begin(), f.section.end(), '.'));
    const std::string value = std::holds_alternative<double*>(f.value)
                                  ? Number(*std::get<double*>(f.value))
                                  : std::to_string(*std::get<int*>(f.value));
    out += fmt::format("{}{}: {}\n", std::string(2 * depth, ' '), f.key, value);
  }
  return out;
}

}  // namespace aerograsp
