#include "hardware/hardware_config.h"

#include <cmath>
#include <filesystem>
#include <set>

#include "core/config.h"
#include "core/platform.h"

namespace aerograsp {
namespace {

constexpr double kDeg = M_PI / 180.0;

void LoadServos(const ConfigNode& n, Side side, ScsArmsConfig* scs) {
  const int s = static_cast<int>(side);
  const ConfigNode arm = n.Child(SideName(side));
  arm.RequireOnlyKeys({"j1", "j2", "j3", "j4", "j5", "j6", "gripper"});
  scs->joints[s].clear();
  for (int i = 1; arm.Has("j" + std::to_string(i)); ++i) {
    const ConfigNode j = arm.Child("j" + std::to_string(i));
    j.RequireOnlyKeys({"id", "deg_at_raw_0", "deg_at_raw_1023"});
    scs->joints[s].push_back({j.GetInt("id"), j.GetDouble("deg_at_raw_0") * kDeg,
                              j.GetDouble("deg_at_raw_1023") * kDeg});
  }
  const ConfigNode g = arm.Child("gripper");
  g.RequireOnlyKeys({"id", "raw_open", "raw_closed"});
  scs->grippers[s] = {g.GetInt("id"), g.GetInt("raw_open", 1023), g.GetInt("raw_closed", 350)};
}

std::string Beside(const std::string& config_path, const std::string& name) {
  return (std::filesystem::path(config_path).parent_path() / name).string();
}

}  // namespace

HardwareConfig HardwareConfig::InProcessSimulation(const std::string& platform_path,
                                                   const std::string& world_path) {
  HardwareConfig c;
  c.source = "built-in simulation";
  c.platform = platform_path;
  c.world = world_path;
  c.arms.backend = "sim";
  c.autopilot.backend = "sim";
  c.camera.backend = "sim";
  return c;
}

bool HardwareConfig::NeedsWorld() const {
  return arms.backend != "scs" || autopilot.backend != "px4" || camera.backend == "sim";
}

HardwareConfig HardwareConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  // `calibration` (the calibration rig: which board, where it is fixed, the
  // wizard's speed and checks) is read by app/calibration/calibration_hardware.h;
  // `bench` (the bench's tag board on the object) by app/commands/bench_stand.h.
  root.RequireOnlyKeys(
      {"platform", "world", "arms", "autopilot", "camera", "health", "calibration", "bench"});
  HardwareConfig c;
  c.source = path;
  c.platform = root.Has("platform") ? root.GetPath("platform") : Beside(path, c.platform);
  c.world = root.Has("world") ? root.GetPath("world") : Beside(path, c.world);

  if (root.Has("arms")) {
    const ConfigNode n = root.Child("arms");
    n.RequireOnlyKeys({"backend", "port", "baud", "reply_timeout_s", "local_echo", "stale_after_s",
                       "max_step_deg", "goal_time_ms", "goal_speed", "rate_hz", "servos",
                       "sim_bus"});
    ArmsHardwareConfig& a = c.arms;
    ScsArmsConfig& s = a.scs;
    a.backend = n.GetString("backend", a.backend);
    s.port = n.GetString("port", s.port);
    s.baud = n.GetInt("baud", s.baud);
    s.reply_timeout_s = n.GetDouble("reply_timeout_s", s.reply_timeout_s);
    s.local_echo = n.GetBool("local_echo", s.local_echo);
    s.stale_after_s = n.GetDouble("stale_after_s", s.stale_after_s);
    s.max_step_rad = n.GetDouble("max_step_deg", s.max_step_rad / kDeg) * kDeg;
    s.goal_time_ms = n.GetInt("goal_time_ms", s.goal_time_ms);
    s.goal_speed = n.GetInt("goal_speed", s.goal_speed);
    s.rate_hz = n.GetDouble("rate_hz", s.rate_hz);
    if (n.Has("servos")) {
      const ConfigNode servos = n.Child("servos");
      servos.RequireOnlyKeys({"left", "right"});
      LoadServos(servos, Side::kLeft, &s);
      LoadServos(servos, Side::kRight, &s);
      a.servos_given = true;
    }
    if (n.Has("sim_bus")) {
      const ConfigNode b = n.Child("sim_bus");
      b.RequireOnlyKeys({"byte_time_s", "return_delay_s", "corrupt_probability", "slow_extra_s",
                         "seed", "silent_ids", "slow_ids", "hot_ids", "low_voltage_ids",
                         "offset_ids", "hot_temperature_c", "low_voltage_v", "offset_deg",
                         "faults_from_s"});
      a.sim_bus.byte_time_s = b.GetDouble("byte_time_s", a.sim_bus.byte_time_s);
      a.sim_bus.return_delay_s = b.GetDouble("return_delay_s", a.sim_bus.return_delay_s);
      a.sim_bus.corrupt_probability =
          b.GetDouble("corrupt_probability", a.sim_bus.corrupt_probability);
      a.sim_bus.slow_extra_s = b.GetDouble("slow_extra_s", a.sim_bus.slow_extra_s);
      a.sim_bus.seed =
          static_cast<std::uint64_t>(b.GetInt("seed", static_cast<int>(a.sim_bus.seed)));
      const std::pair<const char*, std::vector<int>*> id_lists[] = {
          {"silent_ids", &a.sim_bus.silent_ids},
          {"slow_ids", &a.sim_bus.slow_ids},
          {"hot_ids", &a.sim_bus.hot_ids},
          {"low_voltage_ids", &a.sim_bus.low_voltage_ids},
          {"offset_ids", &a.sim_bus.offset_ids}};
      for (const auto& [key, list] : id_lists) {
        if (!b.Has(key)) continue;
        std::vector<int>& ids = *list;
        ids.clear();
        for (double id : b.GetDoubles(key)) {
          if (id != std::floor(id) || id < 0 || id > 253)
            b.Fail(key, "servo ids are whole numbers in [0, 253]");
          ids.push_back(static_cast<int>(id));
        }
      }
      a.sim_bus.faults_from_s = b.GetDouble("faults_from_s", a.sim_bus.faults_from_s);
      a.sim_bus.hot_temperature_c = b.GetInt("hot_temperature_c", a.sim_bus.hot_temperature_c);
      a.sim_bus.low_voltage_v = b.GetDouble("low_voltage_v", a.sim_bus.low_voltage_v);
      a.sim_bus.offset_deg = b.GetDouble("offset_deg", a.sim_bus.offset_deg);
    }
  }
  if (root.Has("autopilot")) {
    const ConfigNode n = root.Child("autopilot");
    n.RequireOnlyKeys({"backend",
                       "link",
                       "udp_local_host",
                       "udp_local_port",
                       "udp_remote_host",
                       "udp_remote_port",
                       "serial_port",
                       "baud",
                       "system_id",
                       "component_id",
                       "target_system",
                       "target_component",
                       "heartbeat_hz",
                       "setpoint_hz",
                       "prestream_s",
                       "command_timeout_s",
                       "command_attempts",
                       "link_timeout_s",
                       "connect_timeout_s",
                       "home_amsl_m",
                       "signing_key_hex",
                       "signing_link_id",
                       "sim_px4"});
    AutopilotHardwareConfig& a = c.autopilot;
    Px4Config& p = a.px4;
    a.backend = n.GetString("backend", a.backend);
    p.link = n.GetString("link", p.link);
    p.udp_local_host = n.GetString("udp_local_host", p.udp_local_host);
    p.udp_local_port = n.GetInt("udp_local_port", p.udp_local_port);
    p.udp_remote_host = n.GetString("udp_remote_host", p.udp_remote_host);
    p.udp_remote_port = n.GetInt("udp_remote_port", p.udp_remote_port);
    p.serial_port = n.GetString("serial_port", p.serial_port);
    p.baud = n.GetInt("baud", p.baud);
    p.system_id = n.GetInt("system_id", p.system_id);
    p.component_id = n.GetInt("component_id", p.component_id);
    p.target_system = n.GetInt("target_system", p.target_system);
    p.target_component = n.GetInt("target_component", p.target_component);
    p.heartbeat_hz = n.GetDouble("heartbeat_hz", p.heartbeat_hz);
    p.setpoint_hz = n.GetDouble("setpoint_hz", p.setpoint_hz);
    p.prestream_s = n.GetDouble("prestream_s", p.prestream_s);
    p.command_timeout_s = n.GetDouble("command_timeout_s", p.command_timeout_s);
    p.command_attempts = n.GetInt("command_attempts", p.command_attempts);
    p.link_timeout_s = n.GetDouble("link_timeout_s", p.link_timeout_s);
    p.connect_timeout_s = n.GetDouble("connect_timeout_s", p.connect_timeout_s);
    p.home_amsl_m = n.GetDouble("home_amsl_m", p.home_amsl_m);
    p.signing_key_hex = n.GetString("signing_key_hex", p.signing_key_hex);
    p.signing_link_id = n.GetInt("signing_link_id", p.signing_link_id);
    if (n.Has("sim_px4")) {
      const ConfigNode f = n.Child("sim_px4");
      f.RequireOnlyKeys({"faults_from_s", "silent", "reject_commands"});
      a.sim_px4.faults_from_s = f.GetDouble("faults_from_s", a.sim_px4.faults_from_s);
      a.sim_px4.silent = f.GetBool("silent", a.sim_px4.silent);
      a.sim_px4.reject_commands = f.GetBool("reject_commands", a.sim_px4.reject_commands);
    }
  }
  if (root.Has("camera")) {
    const ConfigNode n = root.Child("camera");
    n.RequireOnlyKeys({"backend", "path", "serial", "width", "height", "fps", "sim"});
    CameraHardwareConfig& k = c.camera;
    k.backend = n.GetString("backend", k.backend);
    if (n.Has("path")) k.path = n.GetPath("path");
    k.serial = n.GetString("serial", k.serial);
    k.width = n.GetInt("width", k.width);
    k.height = n.GetInt("height", k.height);
    k.fps = n.GetInt("fps", k.fps);
    if (n.Has("sim")) {
      const ConfigNode f = n.Child("sim");
      f.RequireOnlyKeys({"faults_from_s", "frozen", "no_depth"});
      k.sim.faults_from_s = f.GetDouble("faults_from_s", k.sim.faults_from_s);
      k.sim.frozen = f.GetBool("frozen", k.sim.frozen);
      k.sim.no_depth = f.GetBool("no_depth", k.sim.no_depth);
    }
  }
  if (root.Has("health")) {
    const ConfigNode n = root.Child("health");
    DeviceHealthLimits& h = c.health;
    n.RequireOnlyKeys({"servo_max_failed_reads", "servo_max_reading_age_s", "bus_max_error_rate",
                       "bus_error_window_s", "bus_min_exchanges", "servo_min_voltage_v",
                       "servo_max_voltage_v", "servo_max_temperature_c",
                       "autopilot_max_state_age_s", "camera_max_frame_age_s",
                       "camera_max_bad_depth_s"});
    h.servo_max_failed_reads = n.GetInt("servo_max_failed_reads", h.servo_max_failed_reads);
    h.servo_max_reading_age_s = n.GetDouble("servo_max_reading_age_s", h.servo_max_reading_age_s);
    h.bus_max_error_rate = n.GetDouble("bus_max_error_rate", h.bus_max_error_rate);
    h.bus_error_window_s = n.GetDouble("bus_error_window_s", h.bus_error_window_s);
    h.bus_min_exchanges = n.GetInt("bus_min_exchanges", h.bus_min_exchanges);
    h.servo_min_voltage_v = n.GetDouble("servo_min_voltage_v", h.servo_min_voltage_v);
    h.servo_max_voltage_v = n.GetDouble("servo_max_voltage_v", h.servo_max_voltage_v);
    h.servo_max_temperature_c = n.GetDouble("servo_max_temperature_c", h.servo_max_temperature_c);
    h.autopilot_max_state_age_s =
        n.GetDouble("autopilot_max_state_age_s", h.autopilot_max_state_age_s);
    h.camera_max_frame_age_s = n.GetDouble("camera_max_frame_age_s", h.camera_max_frame_age_s);
    h.camera_max_bad_depth_s = n.GetDouble("camera_max_bad_depth_s", h.camera_max_bad_depth_s);
  }
  c.Validate(c.source, "");
  return c;
}

void HardwareConfig::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& f = source;
  CheckFileExists(f, prefix + "platform", platform);
  if (NeedsWorld()) CheckFileExists(f, prefix + "world", world);

  CheckOneOf(f, prefix + "arms.backend", arms.backend, {"scs", "sim-bus", "sim"});
  const ScsArmsConfig& s = arms.scs;
  if (BaudConstant(s.baud) == 0) {
    throw ConfigError(f + ": " + prefix + "arms.baud: " + std::to_string(s.baud) +
                      " is not a standard baud rate");
  }
  CheckRange(f, prefix + "arms.reply_timeout_s", s.reply_timeout_s, 1e-4, 1.0, "s");
  CheckRange(f, prefix + "arms.stale_after_s", s.stale_after_s, 0.01, 10.0, "s");
  CheckRange(f, prefix + "arms.max_step_deg", s.max_step_rad / kDeg, 0.1, 180.0, "deg");
  CheckRange(f, prefix + "arms.goal_time_ms", s.goal_time_ms, 0, 65535, "ms");
  CheckRange(f, prefix + "arms.goal_speed", s.goal_speed, 0, 65535, "");
  CheckRange(f, prefix + "arms.rate_hz", s.rate_hz, 1.0, 1000.0, "Hz");
  std::set<int> ids;
  for (Side side : kSides) {
    const int k = static_cast<int>(side);
    const std::string key = prefix + "arms.servos." + SideName(side);
    if (arms.servos_given) {
      for (std::size_t i = 0; i < s.joints[k].size(); ++i) {
        const ServoCalibration& cal = s.joints[k][i];
        const std::string jkey = key + ".j" + std::to_string(i + 1);
        CheckRange(f, jkey + ".id", cal.id, 0, 253, "");
        if (!ids.insert(cal.id).second)
          throw ConfigError(f + ": " + jkey + ".id: " + std::to_string(cal.id) + " is used twice");
        if (std::abs(cal.angle_at_max_rad - cal.angle_at_min_rad) < 1e-3) {
          throw ConfigError(f + ": " + jkey + ": deg_at_raw_0 and deg_at_raw_1023 must differ");
        }
      }
      const GripperServoConfig& g = s.grippers[k];
      CheckRange(f, key + ".gripper.id", g.id, 0, 253, "");
      if (!ids.insert(g.id).second)
        throw ConfigError(f + ": " + key + ".gripper.id: " + std::to_string(g.id) +
                          " is used twice");
      CheckRange(f, key + ".gripper.raw_open", g.raw_open, 0, 1023, "");
      CheckRange(f, key + ".gripper.raw_closed", g.raw_closed, 0, 1023, "");
      if (g.raw_open == g.raw_closed)
        throw ConfigError(f + ": " + key + ".gripper: raw_open equals raw_closed");
    }
  }
  CheckRange(f, prefix + "arms.sim_bus.byte_time_s", arms.sim_bus.byte_time_s, 0.0, 0.01, "s");
  CheckRange(f, prefix + "arms.sim_bus.return_delay_s", arms.sim_bus.return_delay_s, 0.0, 0.1, "s");
  CheckRange(f, prefix + "arms.sim_bus.corrupt_probability", arms.sim_bus.corrupt_probability, 0.0,
             1.0, "");
  CheckRange(f, prefix + "arms.sim_bus.slow_extra_s", arms.sim_bus.slow_extra_s, 0.0, 1.0, "s");
  CheckRange(f, prefix + "arms.sim_bus.faults_from_s", arms.sim_bus.faults_from_s, 0.0, 1e6, "s");
  CheckRange(f, prefix + "arms.sim_bus.hot_temperature_c", arms.sim_bus.hot_temperature_c, 0, 255,
             "C");
  CheckRange(f, prefix + "arms.sim_bus.low_voltage_v", arms.sim_bus.low_voltage_v, 0.0, 25.0, "V");
  CheckRange(f, prefix + "arms.sim_bus.offset_deg", arms.sim_bus.offset_deg, -220.0, 220.0, "deg");
  CheckRange(f, prefix + "autopilot.sim_px4.faults_from_s", autopilot.sim_px4.faults_from_s, 0.0,
             1e6, "s");
  CheckRange(f, prefix + "camera.sim.faults_from_s", camera.sim.faults_from_s, 0.0, 1e6, "s");
  health.Validate(f, prefix + "health.");

  CheckOneOf(f, prefix + "autopilot.backend", autopilot.backend, {"px4", "sim-px4", "sim"});
  const Px4Config& p = autopilot.px4;
  CheckOneOf(f, prefix + "autopilot.link", p.link, {"udp", "serial"});
  CheckRange(f, prefix + "autopilot.udp_local_port", p.udp_local_port, 0, 65535, "");
  CheckRange(f, prefix + "autopilot.udp_remote_port", p.udp_remote_port, 0, 65535, "");
  if (p.link == "serial" && BaudConstant(p.baud) == 0) {
    throw ConfigError(f + ": " + prefix + "autopilot.baud: " + std::to_string(p.baud) +
                      " is not a standard baud rate");
  }
  CheckRange(f, prefix + "autopilot.system_id", p.system_id, 1, 255, "");
  CheckRange(f, prefix + "autopilot.component_id", p.component_id, 1, 255, "");
  CheckRange(f, prefix + "autopilot.target_system", p.target_system, 1, 255, "");
  CheckRange(f, prefix + "autopilot.target_component", p.target_component, 1, 255, "");
  CheckRange(f, prefix + "autopilot.heartbeat_hz", p.heartbeat_hz, 0.1, 50.0, "Hz");
  CheckRange(f, prefix + "autopilot.setpoint_hz", p.setpoint_hz, 10.0, 200.0, "Hz");
  CheckRange(f, prefix + "autopilot.prestream_s", p.prestream_s, 0.1, 5.0, "s");
  CheckRange(f, prefix + "autopilot.command_timeout_s", p.command_timeout_s, 0.01, 10.0, "s");
  CheckRange(f, prefix + "autopilot.command_attempts", p.command_attempts, 1, 10, "");
  CheckRange(f, prefix + "autopilot.link_timeout_s", p.link_timeout_s, 0.1, 60.0, "s");
  CheckRange(f, prefix + "autopilot.connect_timeout_s", p.connect_timeout_s, 0.1, 120.0, "s");
  CheckRange(f, prefix + "autopilot.signing_link_id", p.signing_link_id, 0, 255, "");
  if (!p.signing_key_hex.empty() && !mavlink::ParseKeyHex(p.signing_key_hex)) {
    throw ConfigError(f + ": " + prefix +
                      "autopilot.signing_key_hex: must be 64 hex digits (32 bytes)");
  }

  CheckOneOf(f, prefix + "camera.backend", camera.backend, {"realsense", "replay", "sim"});
  if (camera.backend == "replay") {
    if (camera.path.empty())
      throw ConfigError(f + ": " + prefix +
                        "camera.path: a replay needs a sequence folder or .bag file");
  }
  CheckRange(f, prefix + "camera.width", camera.width, 160, 1920, "px");
  CheckRange(f, prefix + "camera.height", camera.height, 120, 1080, "px");
  CheckRange(f, prefix + "camera.fps", camera.fps, 1, 90, "Hz");
}

}  // namespace aerograsp
