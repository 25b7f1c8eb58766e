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

namespace {

/// Per-pixel scratch that lives from frame to frame (one per thread: several
/// cameras may run the model at once), so that a frame allocates nothing.
struct Scratch {
  std::vector<float> z;
  std::vector<std::uint8_t> edge, hole;
};

}  // namespace

void SimulateD435(const D435Config& config, const CameraIntrinsics& K, const RenderBuffers& truth,
                  FastRandom* rng, RgbdFrame* frame) {
  const int W = truth.depth_m.width, H = truth.depth_m.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  const float inf = std::numeric_limits<float>::infinity();

  // Colour: additive noise on each channel, written straight from the truth.
  frame->color.width = truth.color.width;
  frame->color.height = truth.color.height;
  frame->color.data.resize(truth.color.data.size());
  if (config.color_noise_levels > 0.0) {
    // Integer noise: 16 random bits pick one of 256 x 256 rounded normal
    // samples, four channels per Next().
    static thread_local std::vector<std::int16_t> table;
    static thread_local double table_sigma = -1.0;
    if (table_sigma != config.color_noise_levels) {
      FastRandom table_rng(0xC010Eull);
      table.resize(1u << 16);
      for (auto& t : table)
        t = static_cast<std::int16_t>(std::lround(config.color_noise_levels * table_rng.Normal()));
      table_sigma = config.color_noise_levels;
    }
    const std::int16_t* noise = table.data();
    auto add_noise = [noise](std::uint8_t value, std::uint64_t bits) {
      const int noisy = value + noise[bits & 0xFFFF];
      return static_cast<std::uint8_t>(noisy < 0 ? 0 : (noisy > 255 ? 255 : noisy));
    };
    const std::uint8_t* in = truth.color.data.data();
    std::uint8_t* out = frame->color.data.data();
    const std::size_t size = frame->color.data.size(), whole = size - size % 4;
    for (std::size_t i = 0; i < whole; i += 4) {
      const std::uint64_t bits = rng->Next();
      out[i] = add_noise(in[i], bits);
      out[i + 1] = add_noise(in[i + 1], bits >> 16);
      out[i + 2] = add_noise(in[i + 2], bits >> 32);
      out[i + 3] = add_noise(in[i + 3], bits >> 48);
    }
    if (whole < size) {  // the last channels take the first bits of one more draw
      std::uint64_t bits = rng->Next();
      for (std::size_t j = whole; j < size; ++j, bits >>= 16) out[j] = add_noise(in[j], bits);
    }
  } else {
    std::copy(truth.color.data.begin(), truth.color.data.end(), frame->color.data.begin());
  }

  // Depth with "nothing hit" as infinitely far, so that silhouettes against the
  // sky are edges.
  static thread_local Scratch scratch;
  scratch.z.resize(N);
  scratch.edge.resize(N);
  scratch.hole.resize(N);
  float* z = scratch.z.data();
  std::uint8_t* edge = scratch.edge.data();
  std::uint8_t* hole = scratch.hole.data();
  const float* depth = truth.depth_m.data.data();
  for (std::size_t i = 0; i < N; ++i) z[i] = depth[i] > 0.0f ? depth[i] : inf;

  // Edges: a depth step to a 4-neighbour (both pixels of the pair are marked).
  const float edge_jump = static_cast<float>(config.edge_jump_m);
  std::fill(edge, edge + N, std::uint8_t{0});
  for (int y = 0; y < H; ++y) {
    const float* row = &z[static_cast<std::size_t>(y) * W];
    std::uint8_t* e = &edge[static_cast<std::size_t>(y) * W];
    for (int x = 0; x + 1 < W; ++x) {
      if (std::abs(row[x + 1] - row[x]) > edge_jump) e[x] = e[x + 1] = 1;
    }
    if (y + 1 < H) {
      const float* below = row + W;
      std::uint8_t* e_below = e + W;
      for (int x = 0; x < W; ++x) {
        if (std::abs(below[x] - row[x]) > edge_jump) e[x] = e_below[x] = 1;
      }
    }
  }

  // Which pixels lose their depth: edges, grazing incidence, dark surfaces.
  // All of the image's draws for holes come before its draws for noise.
  const float cos_start = static_cast<float>(std::cos(config.grazing_start_deg * M_PI / 180.0));
  const float cos_end = static_cast<float>(std::cos(config.grazing_end_deg * M_PI / 180.0));
  const float dark_start = static_cast<float>(config.dark_start);
  const float dark_span = static_cast<float>(std::max(1e-6, 1.0 - config.dark_start));
  const float* cos_incidence = truth.cos_incidence.data.data();
  const float* darkness = truth.darkness.data.data();
  for (std::size_t i = 0; i < N; ++i) {
    hole[i] = 0;
    if (z[i] == inf) continue;
    const float c = cos_incidence[i], dark = darkness[i];
    if (!edge[i] && c >= cos_start && dark <= dark_start) continue;  // the common case
    double p_drop = edge[i] ? config.edge_hole_probability : 0.0;
    if (c < cos_start)
      p_drop = std::max(p_drop, std::min(1.0, double(cos_start - c) / (cos_start - cos_end)));
    if (dark > dark_start)
      p_drop = std::max(p_drop, config.dark_hole_probability * (dark - dark_start) / dark_span);
    if (p_drop > 0.0 && rng->Uniform() < p_drop) hole[i] = 1;
  }

  // Row by row: the stereo shadow, then noise growing with z^2, range limits
  // and quantisation (every depth pixel is written).
  // Stereo shadow: the right imager does not see the background just left of a
  // near object's left edge; the band is as wide as the disparity difference,
  // in pixels of the colour image the depth is aligned to.
  if (frame->depth.width != W || frame->depth.height != H) frame->depth = DepthImage(W, H);
  const double disparity_scale = K.fx * config.baseline_m;
  const float noise_gain =
      static_cast<float>(config.subpixel / (config.DepthFocalPx(W) * config.baseline_m));
  const float inv_scale = static_cast<float>(1.0 / config.depth_scale_m);
  const float min_range = static_cast<float>(config.min_range_m),
              max_range = static_cast<float>(config.max_range_m);
  const float max_units = std::numeric_limits<std::uint16_t>::max();
  for (int y = 0; y < H; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * W;
    const float* zr = &z[row];
    std::uint8_t* h = &hole[row];
    if (config.stereo_shadow) {
      for (int x = 1; x < W; ++x) {
        const float z_near = zr[x], z_far = zr[x - 1];
        if (!(z_far - z_near > edge_jump) || z_near == inf) continue;
        const double band_px =
            disparity_scale * (1.0 / z_near - (z_far == inf ? 0.0 : 1.0 / z_far));
        const int first = std::max(0, x - static_cast<int>(std::ceil(band_px)));
        for (int k = first; k < x; ++k) {
          if (zr[k] > z_near + edge_jump) h[k] = 1;
        }
      }
    }
    std::uint16_t* out = &frame->depth.data[row];
    for (int x = 0; x < W; ++x) {
      const float zi = zr[x];
      out[x] = 0;
      if (h[x] || zi < min_range || zi > max_range) continue;  // also skips inf (no hit)
      const float units = (zi + noise_gain * zi * zi * rng->FastNormal()) * inv_scale + 0.5f;
      if (units >= 1.0f) out[x] = static_cast<std::uint16_t>(std::min(units, max_units));
    }
  }
}

}  // namespace aerograsp
