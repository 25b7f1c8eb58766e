#include "hardware/sim/d435_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace aerograsp {

D435Config D435Config::FromNode(const ConfigNode& node) {
  node.RequireOnlyKeys({"depth_scale_m", "min_range_m", "max_range_m", "baseline_m",
                        "depth_hfov_deg", "subpixel", "grazing_start_deg", "grazing_end_deg",
                        "edge_jump_m", "edge_hole_probability", "dark_start",
                        "dark_hole_probability", "stereo_shadow", "color_noise_levels"});
  D435Config c;
  c.depth_scale_m = node.GetDouble("depth_scale_m", c.depth_scale_m);
  c.min_range_m = node.GetDouble("min_range_m", c.min_range_m);
  c.max_range_m = node.GetDouble("max_range_m", c.max_range_m);
  c.baseline_m = node.GetDouble("baseline_m", c.baseline_m);
  c.depth_hfov_deg = node.GetDouble("depth_hfov_deg", c.depth_hfov_deg);
  c.subpixel = node.GetDouble("subpixel", c.subpixel);
  c.grazing_start_deg = node.GetDouble("grazing_start_deg", c.grazing_start_deg);
  c.grazing_end_deg = node.GetDouble("grazing_end_deg", c.grazing_end_deg);
  c.edge_jump_m = node.GetDouble("edge_jump_m", c.edge_jump_m);
  c.edge_hole_probability = node.GetDouble("edge_hole_probability", c.edge_hole_probability);
  c.dark_start = node.GetDouble("dark_start", c.dark_start);
  c.dark_hole_probability = node.GetDouble("dark_hole_probability", c.dark_hole_probability);
  c.stereo_shadow = node.GetBool("stereo_shadow", c.stereo_shadow);
  c.color_noise_levels = node.GetDouble("color_noise_levels", c.color_noise_levels);
  c.Validate(node.source(), node.KeyPath(""));
  return c;
}

void D435Config::Validate(const std::string& source, const std::string& prefix) const {
  auto key = [&prefix](const char* name) { return prefix + name; };
  CheckRange(source, key("depth_scale_m"), depth_scale_m, 1e-6, 0.01, "m");
  CheckRange(source, key("min_range_m"), min_range_m, 0.05, 2.0, "m");
  CheckRange(source, key("max_range_m"), max_range_m, min_range_m + 1e-6, 20.0, "m");
  CheckRange(source, key("baseline_m"), baseline_m, 1e-3, 0.2, "m");
  CheckRange(source, key("depth_hfov_deg"), depth_hfov_deg, 30.0, 120.0, "deg");
  CheckRange(source, key("subpixel"), subpixel, 0.0, 1.0, "px");
  CheckRange(source, key("grazing_start_deg"), grazing_start_deg, 0.0, 89.9, "deg");
  CheckRange(source, key("grazing_end_deg"), grazing_end_deg, grazing_start_deg + 1e-6, 90.0,
             "deg");
  CheckRange(source, key("edge_jump_m"), edge_jump_m, 1e-4, 1.0, "m");
  CheckRange(source, key("edge_hole_probability"), edge_hole_probability, 0.0, 1.0, "");
  CheckRange(source, key("dark_start"), dark_start, 0.0, 1.0, "");
  CheckRange(source, key("dark_hole_probability"), dark_hole_probability, 0.0, 1.0, "");
  CheckRange(source, key("color_noise_levels"), color_noise_levels, 0.0, 50.0, "");
}

double D435Config::DepthFocalPx(int width_px) const {
  return 0.5 * width_px / std::tan(0.5 * depth_hfov_deg * M_PI / 180.0);
}

double D435Config::DepthNoiseStdM(double z_m, int width_px) const {
  return z_m * z_m * subpixel / (DepthFocalPx(width_px) * baseline_m);
}

void SimulateD435(const D435Config& config, const CameraIntrinsics& K, const RenderBuffers& truth,
                  FastRandom* rng, RgbdFrame* frame) {
  const int W = truth.depth_m.width, H = truth.depth_m.height;
  const float inf = std::numeric_limits<float>::infinity();
  // Treat "nothing hit" as infinitely far, so that silhouettes against the sky are edges.
  auto z_at = [&](int x, int y) {
    const float z = truth.depth_m.at(x, y);
    return z > 0.0f ? z : inf;
  };

  // Colour: additive noise on each channel.
  frame->color = truth.color;
  if (config.color_noise_levels > 0.0) {
    const float sigma = static_cast<float>(config.color_noise_levels);
    for (auto& value : frame->color.data) {
      const float noisy = value + sigma * rng->FastNormal();
      value = static_cast<std::uint8_t>(std::clamp(noisy + 0.5f, 0.0f, 255.0f));
    }
  }

  // Which pixels lose their depth.
  Image<std::uint8_t, 1> hole(W, H, 0);
  const float edge_jump = static_cast<float>(config.edge_jump_m);
  const double cos_start = std::cos(config.grazing_start_deg * M_PI / 180.0);
  const double cos_end = std::cos(config.grazing_end_deg * M_PI / 180.0);
  const double dark_span = std::max(1e-6, 1.0 - config.dark_start);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const float z = truth.depth_m.at(x, y);
      if (z <= 0.0f) continue;
      double p_drop = 0.0;
      const double c = truth.cos_incidence.at(x, y);
      if (c < cos_start) p_drop = std::min(1.0, (cos_start - c) / (cos_start - cos_end));
      const double dark = truth.darkness.at(x, y);
      if (dark > config.dark_start) {
        p_drop = std::max(p_drop, config.dark_hole_probability * (dark - config.dark_start) / dark_span);
      }
      const bool edge = (x > 0 && std::abs(z_at(x - 1, y) - z) > edge_jump) ||
                        (x + 1 < W && std::abs(z_at(x + 1, y) - z) > edge_jump) ||
                        (y > 0 && std::abs(z_at(x, y - 1) - z) > edge_jump) ||
                        (y + 1 < H && std::abs(z_at(x, y + 1) - z) > edge_jump);
      if (edge) p_drop = std::max(p_drop, config.edge_hole_probability);
      if (p_drop > 0.0 && rng->Uniform() < p_drop) hole.at(x, y) = 1;
    }
  }
  // Stereo shadow: the right imager does not see the background just left of a
  // near object's left edge; the band is as wide as the disparity difference,
  // in pixels of the colour image the depth is aligned to.
  if (config.stereo_shadow) {
    const double disparity_scale = K.fx * config.baseline_m;
    for (int y = 0; y < H; ++y) {
      for (int x = 1; x < W; ++x) {
        const float z_near = z_at(x, y), z_far = z_at(x - 1, y);
        if (!(z_far - z_near > edge_jump) || !std::isfinite(z_near)) continue;
        const double band_px = disparity_scale * (1.0 / z_near - (std::isfinite(z_far) ? 1.0 / z_far : 0.0));
        const int first = std::max(0, x - static_cast<int>(std::ceil(band_px)));
        for (int k = first; k < x; ++k) {
          if (z_at(k, y) > z_near + edge_jump) hole.at(k, y) = 1;
        }
      }
    }
  }

  // Noise, range limits, quantisation.
  frame->depth = DepthImage(W, H, 0);
  const double noise_gain = config.subpixel / (config.DepthFocalPx(W) * config.baseline_m);
  const double max_units = std::numeric_limits<std::uint16_t>::max();
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const double z = truth.depth_m.at(x, y);
      if (z <= 0.0 || hole.at(x, y) || z < config.min_range_m || z > config.max_range_m) continue;
      const double noisy = z + noise_gain * z * z * rng->FastNormal();
      const double units = std::round(noisy / config.depth_scale_m);
      if (units >= 1.0) frame->depth.at(x, y) = static_cast<std::uint16_t>(std::min(units, max_units));
    }
  }
}

}  // namespace aerograsp
