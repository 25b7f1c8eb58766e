#include "app/runtime/telemetry_frames.h"

#include "detection/object_tracker.h"
#include "hardware/arms_driver.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

std::vector<TelemetryTransform> PlatformStaticFrames(const Platform& platform) {
  return {{telemetry_frame::kMap, telemetry_frame::kWorld, MapMWorld()},
          {telemetry_frame::kBody, telemetry_frame::kCamera, platform.dMc()},
          {telemetry_frame::kBody, telemetry_frame::kLeftBase, platform.dMb(Side::kLeft)},
          {telemetry_frame::kBody, telemetry_frame::kRightBase, platform.dMb(Side::kRight)}};
}

TelemetryArms ArmsState(double t_s, const Platform& platform, const Eigen::VectorXd q[2],
                        const ArmsDriver& arms) {
  TelemetryArms state;
  state.t_s = t_s;
  for (int a = 0; a < 2; ++a) {
    TelemetryArmState& arm = state.arms[a];
    arm.arm = SideName(kSides[a]);
    arm.joint_names = platform.arm(kSides[a]).joint_names();
    arm.position_rad = q[a];
    const GripperState gripper = arms.Gripper(kSides[a]);
    arm.gripper_aperture_m = gripper.aperture_m;
    arm.gripper_closed = gripper.closed;
    arm.gripper_holding = gripper.holding;
  }
  return state;
}

std::vector<TelemetryTransform> ToolFrames(const Platform& platform, const Eigen::VectorXd q[2]) {
  return {{telemetry_frame::kLeftBase, telemetry_frame::kLeftTool,
           platform.arm(Side::kLeft).ForwardKinematics(q[0])},
          {telemetry_frame::kRightBase, telemetry_frame::kRightTool,
           platform.arm(Side::kRight).ForwardKinematics(q[1])}};
}

void PublishPerceivedFrame(TelemetrySink* sink, double t_s, const std::string& frame_id,
                           const ObjectEstimate& estimate, bool found, const RgbdFrame& frame,
                           const CameraIntrinsics& K, double depth_scale_m) {
  TelemetryObjectPose pose;
  pose.t_s = t_s;
  pose.frame_id = frame_id;
  pose.valid = estimate.valid;
  pose.found = found;
  pose.confidence = estimate.confidence;
  pose.fMo = estimate.fMo;
  if (estimate.valid) pose.covariance = estimate.covariance;
  sink->ObjectPose(pose);
  TelemetryImage image;
  image.t_s = t_s;
  image.K = K;
  image.color = &frame.color;
  if (!frame.depth.empty()) image.depth = &frame.depth;
  image.depth_scale_m = depth_scale_m;
  sink->Image(image);
}

}  // namespace aerograsp
