#include "hardware/realsense_camera.h"

#include <cstring>
#include <librealsense2/rs.hpp>

namespace aerograsp {

struct RealSenseCamera::State {
  rs2::pipeline pipeline;
  rs2::pipeline_profile profile;
  rs2::align align{RS2_STREAM_COLOR};
  bool playback = false;
};

RealSenseCamera::RealSenseCamera(const RealSenseOptions& options)
    : state_(std::make_unique<State>()), options_(options) {
  const bool bag = !options.bag_path.empty();
  name_ = bag ? "camera: " + options.bag_path
              : "camera: RealSense" + (options.serial.empty() ? "" : " " + options.serial);
  try {
    rs2::config config;
    if (bag) {
      // The recording decides the streams; take colour and depth as recorded.
      config.enable_device_from_file(options.bag_path, /*repeat_playback=*/false);
      config.enable_stream(RS2_STREAM_COLOR);
      config.enable_stream(RS2_STREAM_DEPTH);
    } else {
      rs2::context context;
      if (context.query_devices().size() == 0)
        throw HardwareError(name_ + ": no RealSense device is connected");
      if (!options.serial.empty()) config.enable_device(options.serial);
      config.enable_stream(RS2_STREAM_COLOR, options.width, options.height, RS2_FORMAT_RGB8,
                           options.fps);
      config.enable_stream(RS2_STREAM_DEPTH, options.width, options.height, RS2_FORMAT_Z16,
                           options.fps);
    }
    state_->profile = state_->pipeline.start(config);
    if (bag) {
      rs2::playback playback = state_->profile.get_device().as<rs2::playback>();
      playback.set_real_time(false);  // every frame, as fast as we read them
      state_->playback = true;
    }
    const rs2_intrinsics k = state_->profile.get_stream(RS2_STREAM_COLOR)
                                 .as<rs2::video_stream_profile>()
                                 .get_intrinsics();
    intrinsics_.width = k.width;
    intrinsics_.height = k.height;
    intrinsics_.fx = k.fx;
    intrinsics_.fy = k.fy;
    intrinsics_.cx = k.ppx;
    intrinsics_.cy = k.ppy;
    depth_scale_m_ = state_->profile.get_device().first<rs2::depth_sensor>().get_depth_scale();
  } catch (const rs2::error& e) {
    throw HardwareError(name_ + ": " + e.what() + " (in " + e.get_failed_function() + ")");
  }
}

RealSenseCamera::~RealSenseCamera() {
  try {
    state_->pipeline.stop();
  } catch (const rs2::error&) {
    // already stopped (end of a bag)
  }
}

bool RealSenseCamera::Grab(RgbdFrame* frame) {
  try {
    rs2::frameset frames;
    if (!state_->pipeline.try_wait_for_frames(&frames,
                                              static_cast<unsigned>(options_.timeout_ms))) {
      if (state_->playback) return false;  // the recording has ended
      throw HardwareError(name_ + ": no frames for " + std::to_string(options_.timeout_ms) + " ms");
    }
    frames = state_->align.process(frames);
    const rs2::video_frame color = frames.get_color_frame();
    const rs2::depth_frame depth = frames.get_depth_frame();
    if (!color || !depth) throw HardwareError(name_ + ": a frame set without colour or depth");
    const int w = color.get_width(), h = color.get_height();
    if (w != intrinsics_.width || h != intrinsics_.height || depth.get_width() != w ||
        depth.get_height() != h) {
      throw HardwareError(name_ + ": frame size differs from the colour stream's intrinsics");
    }
    // Colour: RGB8 live; a bag may hold BGR8 / RGBA8 / BGRA8.
    const rs2_format format = color.get_profile().format();
    int channels = 3;
    bool swap = false;
    switch (format) {
      case RS2_FORMAT_RGB8:
        break;
      case RS2_FORMAT_BGR8:
        swap = true;
        break;
      case RS2_FORMAT_RGBA8:
        channels = 4;
        break;
      case RS2_FORMAT_BGRA8:
        channels = 4;
        swap = true;
        break;
      default:
        throw HardwareError(name_ + ": colour format " + rs2_format_to_string(format) +
                            " is not supported");
    }
    frame->color = ColorImage(w, h);
    const auto* src = static_cast<const std::uint8_t*>(color.get_data());
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* row = src + static_cast<std::size_t>(y) * color.get_stride_in_bytes();
      std::uint8_t* out = frame->color.Row(y);
      for (int x = 0; x < w; ++x, row += channels, out += 3) {
        out[0] = row[swap ? 2 : 0];
        out[1] = row[1];
        out[2] = row[swap ? 0 : 2];
      }
    }
    frame->depth = DepthImage(w, h);
    const auto* dsrc = static_cast<const std::uint8_t*>(depth.get_data());
    for (int y = 0; y < h; ++y) {
      std::memcpy(frame->depth.Row(y),
                  dsrc + static_cast<std::size_t>(y) * depth.get_stride_in_bytes(),
                  static_cast<std::size_t>(w) * sizeof(std::uint16_t));
    }
    frame->index = next_index_++;
    frame->stamp_s = 1e-3 * frames.get_timestamp();
    return true;
  } catch (const rs2::error& e) {
    throw HardwareError(name_ + ": " + e.what() + " (in " + e.get_failed_function() + ")");
  }
}

}  // namespace aerograsp
