// The D435's imperfections applied to a noise-free render (docs/hardware.md, Camera):
// depth noise growing with z^2, quantisation to the depth unit, holes at depth
// discontinuities (including the stereo shadow left of near objects), at
// grazing angles and on dark surfaces, nothing outside [min, max] range; and
// a little colour noise.
#pragma once

#include <string>

#include "core/config.h"
#include "core/random.h"
#include "hardware/rgbd_camera.h"
#include "hardware/sim/rgbd_renderer.h"

namespace aerograsp {

struct D435Config {
  double depth_scale_m{0.001};     ///< metres per depth unit, (0, 0.01]
  double min_range_m{0.2};         ///< nothing closer (D435: ~0.2 m at 640x480), [0.05, 2] m
  double max_range_m{6.0};         ///< nothing farther, (min_range_m, 20] m
  double baseline_m{0.050};        ///< stereo baseline (D435), (0, 0.2] m
  double depth_hfov_deg{87.0};     ///< depth imager horizontal field of view (D435), [30, 120] deg
  double subpixel{0.08};           ///< disparity RMS (D435), [0, 1] px
  double grazing_start_deg{70.0};  ///< incidence beyond which depth starts to drop out, [0, 90) deg
  /// Incidence beyond which depth is always missing, (start, 90] deg
  double grazing_end_deg{85.0};
  double edge_jump_m{0.03};  ///< depth step between neighbours that counts as an edge, (0, 1] m
  double edge_hole_probability{0.5};  ///< chance that an edge pixel has no depth, [0, 1]
  double dark_start{0.85};            ///< darkness (1 - luminance) where dropouts start, [0, 1]
  double dark_hole_probability{0.5};  ///< dropout chance on a black surface, [0, 1]
  bool stereo_shadow{true};  ///< invalid band left of near objects (left imager is the reference)
  double color_noise_levels{2.0};  ///< colour noise standard deviation, [0, 50] levels of 255

  /// Reads the fields present in `node` (a map; unknown keys are rejected).
  static D435Config FromNode(const ConfigNode& node);
  /// @throws ConfigError naming `source`, the key (under `prefix`) and the bound.
  void Validate(const std::string& source, const std::string& prefix) const;

  /// Focal length of the depth imager in pixels of an image `width_px` wide.
  double DepthFocalPx(int width_px) const;
  /// Depth noise standard deviation at range z (m): z^2 * subpixel / (f * b).
  double DepthNoiseStdM(double z_m, int width_px) const;
};

/// Fills frame->color and frame->depth from the noise-free buffers rendered
/// with intrinsics K. The same buffers and generator state give the same frame.
void SimulateD435(const D435Config& config, const CameraIntrinsics& K, const RenderBuffers& truth,
                  FastRandom* rng, RgbdFrame* frame);

}  // namespace aerograsp
