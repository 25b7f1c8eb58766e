#include "hardware/sim/world_config.h"

#include <cmath>

#include "core/config.h"

namespace aerograsp {
namespace {

Eigen::Vector3d GetVector3Or(const ConfigNode& node, const std::string& key,
                             const Eigen::Vector3d& fallback) {
  return node.Has(key) ? node.GetVector3(key) : fallback;
}

}  // namespace

WorldConfig WorldConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys(
      {"platform", "physics_step_s", "scene", "object", "vehicle", "arms", "camera", "occluder"});
  WorldConfig c;
  c.source = path;
  if (root.Has("platform")) c.platform = root.GetPath("platform");
  c.physics_step_s = root.GetDouble("physics_step_s", c.physics_step_s);

  if (root.Has("scene")) {
    const ConfigNode n = root.Child("scene");
    n.RequireOnlyKeys({"pipe_center_w_m", "pipe_yaw_rad", "pipe_radius_m", "pipe_length_m",
                       "clutter_count", "clutter_radius_m", "ground_tile_m"});
    SceneConfig& s = c.scene;
    s.pipe_center_w_m = GetVector3Or(n, "pipe_center_w_m", s.pipe_center_w_m);
    s.pipe_yaw_rad = n.GetDouble("pipe_yaw_rad", s.pipe_yaw_rad);
    s.pipe_radius_m = n.GetDouble("pipe_radius_m", s.pipe_radius_m);
    s.pipe_length_m = n.GetDouble("pipe_length_m", s.pipe_length_m);
    s.clutter_count = n.GetInt("clutter_count", s.clutter_count);
    s.clutter_radius_m = n.GetDouble("clutter_radius_m", s.clutter_radius_m);
    s.ground_tile_m = n.GetDouble("ground_tile_m", s.ground_tile_m);
  }
  if (root.Has("object")) {
    const ConfigNode n = root.Child("object");
    n.RequireOnlyKeys({"name", "motion", "start_along_pipe_m", "speed_mps", "travel_m",
                       "yaw_on_pipe_rad", "knocked_off_at_s"});
    ObjectMotionConfig& o = c.object;
    o.name = n.GetString("name", o.name);
    o.motion = n.GetString("motion", o.motion);
    o.start_along_pipe_m = n.GetDouble("start_along_pipe_m", o.start_along_pipe_m);
    o.speed_mps = n.GetDouble("speed_mps", o.speed_mps);
    o.travel_m = n.GetDouble("travel_m", o.travel_m);
    o.yaw_on_pipe_rad = n.GetDouble("yaw_on_pipe_rad", o.yaw_on_pipe_rad);
    o.knocked_off_at_s = n.GetDouble("knocked_off_at_s", o.knocked_off_at_s);
  }
  if (root.Has("vehicle")) {
    const ConfigNode n = root.Child("vehicle");
    n.RequireOnlyKeys({"start", "start_w_m", "start_yaw_rad", "sway_amplitude_m",
                       "sway_frequency_hz", "tilt_amplitude_rad", "gust_rate_hz", "gust_speed_mps",
                       "drift_std_m", "drift_time_constant_s", "response_time_s", "delay_s",
                       "max_speed_mps", "offboard_timeout_s", "landed_height_m"});
    VehicleSimConfig& v = c.vehicle;
    v.start = n.GetString("start", v.start);
    v.start_w_m = GetVector3Or(n, "start_w_m", v.start_w_m);
    v.start_yaw_rad = n.GetDouble("start_yaw_rad", v.start_yaw_rad);
    v.sway_amplitude_m = GetVector3Or(n, "sway_amplitude_m", v.sway_amplitude_m);
    v.sway_frequency_hz = GetVector3Or(n, "sway_frequency_hz", v.sway_frequency_hz);
    v.tilt_amplitude_rad = n.GetDouble("tilt_amplitude_rad", v.tilt_amplitude_rad);
    v.gust_rate_hz = n.GetDouble("gust_rate_hz", v.gust_rate_hz);
    v.gust_speed_mps = n.GetDouble("gust_speed_mps", v.gust_speed_mps);
    v.drift_std_m = n.GetDouble("drift_std_m", v.drift_std_m);
    v.drift_time_constant_s = n.GetDouble("drift_time_constant_s", v.drift_time_constant_s);
    v.response_time_s = n.GetDouble("response_time_s", v.response_time_s);
    v.delay_s = n.GetDouble("delay_s", v.delay_s);
    v.max_speed_mps = n.GetDouble("max_speed_mps", v.max_speed_mps);
    v.offboard_timeout_s = n.GetDouble("offboard_timeout_s", v.offboard_timeout_s);
    v.landed_height_m = n.GetDouble("landed_height_m", v.landed_height_m);
  }
  if (root.Has("arms")) {
    const ConfigNode n = root.Child("arms");
    n.RequireOnlyKeys({"lag_s", "speed_scale", "position_counts", "position_range_deg"});
    ArmsSimConfig& a = c.arms;
    a.lag_s = n.GetDouble("lag_s", a.lag_s);
    a.speed_scale = n.GetDouble("speed_scale", a.speed_scale);
    a.position_counts = n.GetInt("position_counts", a.position_counts);
    a.position_range_deg = n.GetDouble("position_range_deg", a.position_range_deg);
  }
  if (root.Has("camera")) {
    const ConfigNode n = root.Child("camera");
    n.RequireOnlyKeys({"frame_rate_hz", "image_scale", "d435", "light_azimuth_deg",
                       "light_elevation_deg", "light_intensity", "ambient", "light_variation"});
    CameraSimConfig& k = c.camera;
    k.frame_rate_hz = n.GetDouble("frame_rate_hz", k.frame_rate_hz);
    k.image_scale = n.GetDouble("image_scale", k.image_scale);
    if (n.Has("d435")) k.d435 = D435Config::FromNode(n.Child("d435"));
    k.light_azimuth_deg = n.GetDouble("light_azimuth_deg", k.light_azimuth_deg);
    k.light_elevation_deg = n.GetDouble("light_elevation_deg", k.light_elevation_deg);
    k.light_intensity = n.GetDouble("light_intensity", k.light_intensity);
    k.ambient = n.GetDouble("ambient", k.ambient);
    k.light_variation = n.GetDouble("light_variation", k.light_variation);
  }
  if (root.Has("occluder")) {
    const ConfigNode n = root.Child("occluder");
    n.RequireOnlyKeys({"enabled", "start_s", "duration_s", "period_s", "distance_m", "size_m"});
    OccluderConfig& h = c.occluder;
    h.enabled = n.GetBool("enabled", true);
    h.start_s = n.GetDouble("start_s", h.start_s);
    h.duration_s = n.GetDouble("duration_s", h.duration_s);
    h.period_s = n.GetDouble("period_s", h.period_s);
    h.distance_m = n.GetDouble("distance_m", h.distance_m);
    h.size_m = n.GetDouble("size_m", h.size_m);
  }
  c.Validate(c.source, "");
  return c;
}

void WorldConfig::Validate(const std::string& source, const std::string& prefix) const {
  const std::string& src = source;
  CheckFileExists(src, prefix + "platform", platform);
  CheckRange(src, prefix + "physics_step_s", physics_step_s, 1e-5, 0.05, "s");

  CheckRange(src, prefix + "scene.pipe_center_w_m", scene.pipe_center_w_m, -100.0, 100.0, "m");
  CheckRange(src, prefix + "scene.pipe_yaw_rad", scene.pipe_yaw_rad, -M_PI, M_PI, "rad");
  CheckRange(src, prefix + "scene.pipe_radius_m", scene.pipe_radius_m, 1e-3, 1.0, "m");
  CheckRange(src, prefix + "scene.pipe_length_m", scene.pipe_length_m, 0.01, 50.0, "m");
  CheckRange(src, prefix + "scene.clutter_count", scene.clutter_count, 0, 200, "");
  CheckRange(src, prefix + "scene.clutter_radius_m", scene.clutter_radius_m, 0.01, 50.0, "m");
  CheckRange(src, prefix + "scene.ground_tile_m", scene.ground_tile_m, 1e-3, 10.0, "m");
  if (scene.pipe_center_w_m.z() + scene.pipe_radius_m >= 0.0) {
    CheckRange(src, prefix + "scene.pipe_center_w_m[2]", scene.pipe_center_w_m.z(), -100.0,
               -scene.pipe_radius_m, "m (the pipe must be above the ground, NED z < 0)");
  }

  CheckOneOf(src, prefix + "object.motion", object.motion, {"static", "crawl"});
  CheckRange(src, prefix + "object.start_along_pipe_m", object.start_along_pipe_m,
             -0.5 * scene.pipe_length_m, 0.5 * scene.pipe_length_m, "m");
  CheckRange(src, prefix + "object.speed_mps", object.speed_mps, 0.0, 1.0, "m/s");
  CheckRange(src, prefix + "object.travel_m", object.travel_m, 0.0,
             0.5 * scene.pipe_length_m - object.start_along_pipe_m, "m");
  CheckRange(src, prefix + "object.yaw_on_pipe_rad", object.yaw_on_pipe_rad, -M_PI, M_PI, "rad");
  CheckRange(src, prefix + "object.knocked_off_at_s", object.knocked_off_at_s, -1.0, 1e6, "s");

  CheckOneOf(src, prefix + "vehicle.start", vehicle.start, {"hover", "ground"});
  CheckRange(src, prefix + "vehicle.start_w_m", vehicle.start_w_m, -1000.0, 1000.0, "m");
  CheckRange(src, prefix + "vehicle.start_yaw_rad", vehicle.start_yaw_rad, -M_PI, M_PI, "rad");
  CheckRange(src, prefix + "vehicle.sway_amplitude_m", vehicle.sway_amplitude_m, 0.0, 1.0, "m");
  CheckRange(src, prefix + "vehicle.sway_frequency_hz", vehicle.sway_frequency_hz, 0.0, 5.0, "Hz");
  CheckRange(src, prefix + "vehicle.tilt_amplitude_rad", vehicle.tilt_amplitude_rad, 0.0, 0.3,
             "rad");
  CheckRange(src, prefix + "vehicle.gust_rate_hz", vehicle.gust_rate_hz, 0.0, 10.0, "Hz");
  CheckRange(src, prefix + "vehicle.gust_speed_mps", vehicle.gust_speed_mps, 0.0, 5.0, "m/s");
  CheckRange(src, prefix + "vehicle.drift_std_m", vehicle.drift_std_m, 0.0, 1.0, "m");
  CheckRange(src, prefix + "vehicle.drift_time_constant_s", vehicle.drift_time_constant_s, 1e-3,
             1000.0, "s");
  CheckRange(src, prefix + "vehicle.response_time_s", vehicle.response_time_s, 1e-3, 10.0, "s");
  CheckRange(src, prefix + "vehicle.delay_s", vehicle.delay_s, 0.0, 2.0, "s");
  CheckRange(src, prefix + "vehicle.max_speed_mps", vehicle.max_speed_mps, 1e-3, 20.0, "m/s");
  CheckRange(src, prefix + "vehicle.offboard_timeout_s", vehicle.offboard_timeout_s, 1e-3, 10.0,
             "s");
  CheckRange(src, prefix + "vehicle.landed_height_m", vehicle.landed_height_m, 0.0, 2.0, "m");

  CheckRange(src, prefix + "arms.lag_s", arms.lag_s, 1e-4, 2.0, "s");
  CheckRange(src, prefix + "arms.speed_scale", arms.speed_scale, 1e-3, 2.0, "");
  CheckRange(src, prefix + "arms.position_counts", arms.position_counts, 2, 65536, "");
  CheckRange(src, prefix + "arms.position_range_deg", arms.position_range_deg, 1.0, 360.0, "deg");

  CheckRange(src, prefix + "camera.frame_rate_hz", camera.frame_rate_hz, 0.1, 300.0, "Hz");
  if (camera.image_scale != 1.0 && camera.image_scale != 0.5) {
    throw ConfigError(src + ": " + prefix +
                      "camera.image_scale: " + std::to_string(camera.image_scale) +
                      " is not 1 or 0.5 (the D435 streams 640x480 and 320x240)");
  }
  camera.d435.Validate(src, prefix + "camera.d435.");
  CheckRange(src, prefix + "camera.light_elevation_deg", camera.light_elevation_deg, 1.0, 90.0,
             "deg");
  CheckRange(src, prefix + "camera.light_intensity", camera.light_intensity, 0.0, 2.0, "");
  CheckRange(src, prefix + "camera.ambient", camera.ambient, 0.0, 1.0, "");
  CheckRange(src, prefix + "camera.light_variation", camera.light_variation, 0.0, 0.5, "");

  CheckRange(src, prefix + "occluder.start_s", occluder.start_s, 0.0, 1e6, "s");
  CheckRange(src, prefix + "occluder.duration_s", occluder.duration_s, 1e-3, 1e6, "s");
  if (occluder.period_s != 0.0) {
    CheckRange(src, prefix + "occluder.period_s", occluder.period_s, occluder.duration_s + 1e-3,
               1e6, "s (0 hides once; else longer than duration_s)");
  }
  CheckRange(src, prefix + "occluder.distance_m", occluder.distance_m, 0.2, 2.0, "m");
  CheckRange(src, prefix + "occluder.size_m", occluder.size_m, 1e-3, 5.0, "m");
}

}  // namespace aerograsp
