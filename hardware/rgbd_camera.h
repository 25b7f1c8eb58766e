// The RGB-D camera as the algorithms see it: timestamped colour and depth
// aligned to colour, with the colour stream's intrinsics and the depth scale.
// Backends: the simulator (hardware/sim/), recorded sequences (replay), and
// the RealSense driver.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/camera_model.h"
#include "core/image.h"

namespace aerograsp {

/// A device or recording that cannot be used; the message names it.
class HardwareError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One frame. The depth image is aligned to the colour image: pixel (u, v) of
/// both sees the same ray of the colour camera c.
struct RgbdFrame {
  std::int64_t index = 0;  ///< frame number from the start of the stream
  double stamp_s = 0.0;    ///< capture time on the stream's clock
  ColorImage color;        ///< RGB
  DepthImage depth;        ///< z along the optical axis in units of depth_scale_m; 0 = no data
};

class RgbdCamera {
 public:
  virtual ~RgbdCamera() = default;
  /// Intrinsics of the colour stream (and of the aligned depth).
  virtual const CameraIntrinsics& intrinsics() const = 0;
  /// Metres per depth unit (the D435 default is 0.001).
  virtual double depth_scale_m() const = 0;
  /// Fills the next frame. Returns false when a finite stream has ended.
  /// @throws HardwareError naming the device or file when a frame cannot be read.
  virtual bool Grab(RgbdFrame* frame) = 0;
};

}  // namespace aerograsp
