// The simulator behind the hardware interfaces: a camera that renders the
// world, the arms' servos, and the autopilot. Each wraps a World it does not
// own; none of them advances the clock (the caller steps the world).
#pragma once

#include <memory>

#include "core/random.h"
#include "hardware/arms_driver.h"
#include "hardware/autopilot.h"
#include "hardware/rgbd_camera.h"
#include "hardware/sim/world.h"

namespace aerograsp {

/// Faults of the simulated camera, from faults_from_s of the simulated clock on.
struct SimCameraFaults {
  double faults_from_s{0.0};  ///< >= 0 s
  bool frozen{false};         ///< Grab returns the last frame again (same index and stamp)
  bool no_depth{false};       ///< every depth pixel 0 (no data)
};

/// Renders the world as the D435 on the vehicle sees it at the world's
/// current time: colour and aligned depth with the D435 model applied.
class SimCamera : public RgbdCamera {
 public:
  explicit SimCamera(World* world, const SimCameraFaults& faults = {});
  ~SimCamera() override;
  const CameraIntrinsics& intrinsics() const override;
  double depth_scale_m() const override;
  /// Never ends: renders a frame at the world's present time.
  bool Grab(RgbdFrame* frame) override;
  /// The noise-free buffers of the last Grab (ground truth for tests and labels).
  const RenderBuffers& last_truth() const { return truth_; }
  /// The lighting of the last Grab.
  const Lighting& last_lighting() const { return lighting_; }
  /// Renderer ids: the object's (for labels), arms' segments after it.
  int object_render_id() const { return object_id_; }
  /// Wall time of the last Grab's ray casting and of its D435 model, seconds.
  double last_render_s() const { return render_s_; }
  double last_sensor_model_s() const { return model_s_; }
  /// Simulated time of the first frame a fault changed; < 0: none (yet).
  double first_fault_s() const { return first_fault_s_; }

 private:
  World* world_;
  CameraIntrinsics K_;  // the platform's, scaled by the world's camera.image_scale
  RgbdRenderer renderer_;
  FastRandom rng_;
  int object_id_ = -1;
  std::vector<int> arm_ids_[2];
  int occluder_id_ = -1;             // when the world has an occluder
  std::vector<int> attachment_ids_;  // one per World::attachments(), added as they appear
  std::int64_t next_index_ = 0;
  RenderBuffers truth_;
  Lighting lighting_;
  double render_s_ = 0.0, model_s_ = 0.0;
  SimCameraFaults faults_;
  RgbdFrame last_frame_;  // kept when a freeze is configured
  bool have_last_frame_ = false;
  double first_fault_s_ = -1.0;
};

class SimArmsDriver : public ArmsDriver {
 public:
  explicit SimArmsDriver(World* world) : world_(world) {}
  void SetJointTargets(Side side, const Eigen::VectorXd& q_rad) override;
  Eigen::VectorXd JointPositions(Side side) const override;
  void SetGripper(Side side, GripperCommand command) override;
  GripperState Gripper(Side side) const override;
  void Stop() override;

 private:
  World* world_;
};

class SimAutopilot : public Autopilot {
 public:
  explicit SimAutopilot(World* world) : world_(world) {}
  VehicleState State() const override;
  CommandAck Arm() override;
  CommandAck Disarm() override;
  CommandAck Takeoff(double altitude_m) override;
  CommandAck Land() override;
  CommandAck Hold() override;
  CommandAck SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) override;

 private:
  World* world_;
};

}  // namespace aerograsp
