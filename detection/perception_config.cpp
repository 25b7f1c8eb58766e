#include "detection/perception_config.h"

#include <cstdint>
#include <limits>
#include <stdexcept>

#include "core/config.h"

namespace aerograsp {
namespace {

/// A seed: an integer in [0, INT_MAX] (what ConfigNode reads as an integer).
std::uint64_t GetSeed(const ConfigNode& node, const std::string& key, std::uint64_t default_value) {
  if (!node.Has(key)) return default_value;
  const int seed = node.GetInt(key);
  CheckRange(node.source(), node.KeyPath(key), seed, 0, std::numeric_limits<int>::max(), "");
  return static_cast<std::uint64_t>(seed);
}

void ReadModel(const ConfigNode& n, ModelCloudOptions* m) {
  n.RequireOnlyKeys({"spacing_m", "cell_m", "margin_m", "seed"});
  m->spacing_m = n.GetDouble("spacing_m", m->spacing_m);
  m->cell_m = n.GetDouble("cell_m", m->cell_m);
  m->margin_m = n.GetDouble("margin_m", m->margin_m);
  m->seed = GetSeed(n, "seed", m->seed);
}

void ReadCloud(const ConfigNode& n, SceneCloudOptions* c) {
  n.RequireOnlyKeys(
      {"target_points", "min_depth_m", "max_depth_m", "normal_radius_m", "max_normal_jump_m"});
  c->target_points = n.GetInt("target_points", c->target_points);
  c->min_depth_m = n.GetDouble("min_depth_m", c->min_depth_m);
  c->max_depth_m = n.GetDouble("max_depth_m", c->max_depth_m);
  c->normal_radius_m = n.GetDouble("normal_radius_m", c->normal_radius_m);
  c->max_normal_jump_m = n.GetDouble("max_normal_jump_m", c->max_normal_jump_m);
}

void ReadIcp(const ConfigNode& n, IcpOptions* i) {
  n.RequireOnlyKeys({"max_iterations", "start_distance_m", "end_distance_m", "depth_noise_per_m2",
                     "min_normal_cos", "min_normal_cos_without_color", "max_color_distance",
                     "point_to_point_weight", "damping", "converged_step_m", "min_inliers"});
  i->max_iterations = n.GetInt("max_iterations", i->max_iterations);
  i->start_distance_m = n.GetDouble("start_distance_m", i->start_distance_m);
  i->end_distance_m = n.GetDouble("end_distance_m", i->end_distance_m);
  i->depth_noise_per_m2 = n.GetDouble("depth_noise_per_m2", i->depth_noise_per_m2);
  i->min_normal_cos = n.GetDouble("min_normal_cos", i->min_normal_cos);
  i->min_normal_cos_without_color =
      n.GetDouble("min_normal_cos_without_color", i->min_normal_cos_without_color);
  i->max_color_distance = n.GetDouble("max_color_distance", i->max_color_distance);
  i->point_to_point_weight = n.GetDouble("point_to_point_weight", i->point_to_point_weight);
  i->damping = n.GetDouble("damping", i->damping);
  i->converged_step_m = n.GetDouble("converged_step_m", i->converged_step_m);
  i->min_inliers = n.GetInt("min_inliers", i->min_inliers);
}

void ReadGlobal(const ConfigNode& n, GlobalRegistrationOptions* g) {
  n.RequireOnlyKeys({"voxel_m", "feature_radius_m", "max_iterations", "attempts", "orientations",
                     "refined_orientations", "inlier_fraction", "seed", "work_per_frame",
                     "whole_frame_features"});
  g->voxel_m = n.GetDouble("voxel_m", g->voxel_m);
  g->feature_radius_m = n.GetDouble("feature_radius_m", g->feature_radius_m);
  g->max_iterations = n.GetInt("max_iterations", g->max_iterations);
  g->attempts = n.GetInt("attempts", g->attempts);
  g->whole_frame_features = n.GetBool("whole_frame_features", g->whole_frame_features);
  g->orientations = n.GetInt("orientations", g->orientations);
  g->refined_orientations = n.GetInt("refined_orientations", g->refined_orientations);
  g->inlier_fraction = n.GetDouble("inlier_fraction", g->inlier_fraction);
  g->seed = GetSeed(n, "seed", g->seed);
  if (n.Has("work_per_frame")) g->work_per_frame = n.GetInt("work_per_frame");
}

void ReadEkf(const ConfigNode& n, PoseEkfOptions* e) {
  n.RequireOnlyKeys({"accel_noise_mps2", "angular_accel_noise_radps2", "init_position_std_m",
                     "init_rotation_std_rad", "init_velocity_std_mps",
                     "init_angular_velocity_std_radps", "gate_nis", "max_predict_dt_s"});
  e->accel_noise_mps2 = n.GetDouble("accel_noise_mps2", e->accel_noise_mps2);
  e->angular_accel_noise_radps2 =
      n.GetDouble("angular_accel_noise_radps2", e->angular_accel_noise_radps2);
  e->init_position_std_m = n.GetDouble("init_position_std_m", e->init_position_std_m);
  e->init_rotation_std_rad = n.GetDouble("init_rotation_std_rad", e->init_rotation_std_rad);
  e->init_velocity_std_mps = n.GetDouble("init_velocity_std_mps", e->init_velocity_std_mps);
  e->init_angular_velocity_std_radps =
      n.GetDouble("init_angular_velocity_std_radps", e->init_angular_velocity_std_radps);
  e->gate_nis = n.GetDouble("gate_nis", e->gate_nis);
  e->max_predict_dt_s = n.GetDouble("max_predict_dt_s", e->max_predict_dt_s);
}

void ReadTrack(const ConfigNode& n, TrackMonitorOptions* t) {
  n.RequireOnlyKeys({"find_confidence", "keep_confidence", "frames_to_find", "frames_to_refind",
                     "frames_to_lose"});
  t->find_confidence = n.GetDouble("find_confidence", t->find_confidence);
  t->keep_confidence = n.GetDouble("keep_confidence", t->keep_confidence);
  t->frames_to_find = n.GetInt("frames_to_find", t->frames_to_find);
  t->frames_to_refind = n.GetInt("frames_to_refind", t->frames_to_refind);
  t->frames_to_lose = n.GetInt("frames_to_lose", t->frames_to_lose);
}

void ReadSegment(const ConfigNode& n, SegmentationOptions* g) {
  n.RequireOnlyKeys({"max_surfaces", "surface_iterations", "surface_tolerance_m", "surface_extent",
                     "cluster_gap_m", "max_candidates", "seed"});
  g->max_surfaces = n.GetInt("max_surfaces", g->max_surfaces);
  g->surface_iterations = n.GetInt("surface_iterations", g->surface_iterations);
  g->surface_tolerance_m = n.GetDouble("surface_tolerance_m", g->surface_tolerance_m);
  g->surface_extent = n.GetDouble("surface_extent", g->surface_extent);
  g->cluster_gap_m = n.GetDouble("cluster_gap_m", g->cluster_gap_m);
  g->max_candidates = n.GetInt("max_candidates", g->max_candidates);
  g->seed = GetSeed(n, "seed", g->seed);
}

void ReadSelfFilter(const ConfigNode& n, SelfFilterOptions* f) {
  n.RequireOnlyKeys(
      {"enabled", "drop_from_depth", "drop_from_cloud", "in_support", "in_slide", "margin_m"});
  f->enabled = n.GetBool("enabled", f->enabled);
  f->drop_from_depth = n.GetBool("drop_from_depth", f->drop_from_depth);
  f->drop_from_cloud = n.GetBool("drop_from_cloud", f->drop_from_cloud);
  f->in_support = n.GetBool("in_support", f->in_support);
  f->in_slide = n.GetBool("in_slide", f->in_slide);
  f->margin_m = n.GetDouble("margin_m", f->margin_m);
}

}  // namespace

PerceptionOptions LoadPerceptionOptions(const std::string& path,
                                        const PerceptionOptions& defaults) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"model",
                        "cloud",
                        "icp",
                        "global",
                        "segment",
                        "ekf",
                        "track",
                        "self_filter",
                        "min_detection_score",
                        "box_margin",
                        "near_centre_quantile",
                        "min_support_ratio",
                        "min_coverage",
                        "min_box_overlap",
                        "min_box_cover",
                        "min_cloud_points",
                        "whole_frame_points",
                        "detect_every_frames",
                        "frames_without_box_to_search_frame",
                        "lost_search_every_frames",
                        "min_global_range_m",
                        "max_global_range_m",
                        "reacquire_radius_m",
                        "reacquire_speed_mps",
                        "measurement_position_std_m",
                        "measurement_rotation_std_rad",
                        "gated_frames_to_reset",
                        "weak_direction_ratio",
                        "weak_direction_std_m",
                        "weak_direction_min_drop"});
  PerceptionOptions o = defaults;
  if (root.Has("model")) ReadModel(root.Child("model"), &o.model);
  if (root.Has("cloud")) ReadCloud(root.Child("cloud"), &o.cloud);
  if (root.Has("icp")) ReadIcp(root.Child("icp"), &o.icp);
  if (root.Has("global")) ReadGlobal(root.Child("global"), &o.global);
  if (root.Has("segment")) ReadSegment(root.Child("segment"), &o.segment);
  if (root.Has("ekf")) ReadEkf(root.Child("ekf"), &o.ekf);
  if (root.Has("track")) ReadTrack(root.Child("track"), &o.track);
  if (root.Has("self_filter")) ReadSelfFilter(root.Child("self_filter"), &o.self_filter);
  o.min_detection_score =
      static_cast<float>(root.GetDouble("min_detection_score", o.min_detection_score));
  o.box_margin = root.GetDouble("box_margin", o.box_margin);
  o.near_centre_quantile = root.GetDouble("near_centre_quantile", o.near_centre_quantile);
  o.min_support_ratio = root.GetDouble("min_support_ratio", o.min_support_ratio);
  o.min_coverage = root.GetDouble("min_coverage", o.min_coverage);
  o.min_box_overlap = root.GetDouble("min_box_overlap", o.min_box_overlap);
  o.min_box_cover = root.GetDouble("min_box_cover", o.min_box_cover);
  o.min_cloud_points = root.GetInt("min_cloud_points", o.min_cloud_points);
  o.whole_frame_points = root.GetInt("whole_frame_points", o.whole_frame_points);
  o.detect_every_frames = root.GetInt("detect_every_frames", o.detect_every_frames);
  o.frames_without_box_to_search_frame =
      root.GetInt("frames_without_box_to_search_frame", o.frames_without_box_to_search_frame);
  o.lost_search_every_frames = root.GetInt("lost_search_every_frames", o.lost_search_every_frames);
  o.min_global_range_m = root.GetDouble("min_global_range_m", o.min_global_range_m);
  o.max_global_range_m = root.GetDouble("max_global_range_m", o.max_global_range_m);
  o.reacquire_radius_m = root.GetDouble("reacquire_radius_m", o.reacquire_radius_m);
  o.reacquire_speed_mps = root.GetDouble("reacquire_speed_mps", o.reacquire_speed_mps);
  o.measurement_position_std_m =
      root.GetDouble("measurement_position_std_m", o.measurement_position_std_m);
  o.measurement_rotation_std_rad =
      root.GetDouble("measurement_rotation_std_rad", o.measurement_rotation_std_rad);
  o.gated_frames_to_reset = root.GetInt("gated_frames_to_reset", o.gated_frames_to_reset);
  o.weak_direction_ratio = root.GetDouble("weak_direction_ratio", o.weak_direction_ratio);
  o.weak_direction_std_m = root.GetDouble("weak_direction_std_m", o.weak_direction_std_m);
  o.weak_direction_min_drop = root.GetInt("weak_direction_min_drop", o.weak_direction_min_drop);

  o.Validate(path, "");
  return o;
}

}  // namespace aerograsp
