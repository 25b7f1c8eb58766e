// What `mission`, `bench`, `replay` and `calibrate` hand to their telemetry
// (telemetry/telemetry.h), built in one place from the platform, the arms and
// perception's estimate.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/platform.h"
#include "telemetry/telemetry.h"

namespace aerograsp {

class ArmsDriver;
struct ObjectEstimate;
struct RgbdFrame;

/// The fixed frames: map->world, body->camera_optical and body->each arm
/// mount (the platform's, or the calibrated ones it was given).
std::vector<TelemetryTransform> PlatformStaticFrames(const Platform& platform);

/// Both arms at their measured joints `q` (rad, 0 left, 1 right) with their
/// grippers read from `arms`.
TelemetryArms ArmsState(double t_s, const Platform& platform, const Eigen::VectorXd q[2],
                        const ArmsDriver& arms);

/// Each arm mount->tool at the joints `q` (forward kinematics).
std::vector<TelemetryTransform> ToolFrames(const Platform& platform, const Eigen::VectorXd q[2]);

/// One processed camera frame taken at `t_s`: the object's estimate in
/// `frame_id` (the frame the tracker's filter ran in) with its covariance, then
/// the frame's images.
void PublishPerceivedFrame(TelemetrySink* sink, double t_s, const std::string& frame_id,
                           const ObjectEstimate& estimate, bool found, const RgbdFrame& frame,
                           const CameraIntrinsics& K, double depth_scale_m);

}  // namespace aerograsp
