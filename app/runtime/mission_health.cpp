#include "app/runtime/mission_health.h"

namespace aerograsp {

/// Forwards every call to the device; a refused command in flight becomes a
/// fault for the next poll.
class MissionHealth::CheckedAutopilot : public Autopilot {
 public:
  CheckedAutopilot(Autopilot* device, MissionHealth* owner) : device_(device), owner_(owner) {}
  VehicleState State() const override { return device_->State(); }
  CommandAck Arm() override { return Check("arm", device_->Arm()); }
  CommandAck Disarm() override { return Check("disarm", device_->Disarm()); }
  CommandAck Takeoff(double altitude_m) override {
    return Check("take-off", device_->Takeoff(altitude_m));
  }
  CommandAck Land() override { return Check("land", device_->Land()); }
  CommandAck Hold() override { return Check("hold", device_->Hold()); }
  CommandAck SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) override {
    return Check("the position setpoint", device_->SetPositionTarget(p_w, yaw_rad));
  }

 private:
  CommandAck Check(const std::string& command, CommandAck ack) {
    for (DeviceFault& f : owner_->health_.CommandAnswered(command, ack, device_->State().mode))
      owner_->refusals_.push_back(std::move(f));
    return ack;
  }
  Autopilot* device_;
  MissionHealth* owner_;
};

MissionHealth::MissionHealth(Hardware* hw, const DeviceHealthLimits& limits)
    : hw_(hw),
      health_(limits),
      autopilot_(std::make_unique<CheckedAutopilot>(&hw->autopilot(), this)) {}

MissionHealth::~MissionHealth() = default;

Autopilot* MissionHealth::autopilot() { return autopilot_.get(); }

std::vector<DeviceFault> MissionHealth::Poll(double now_s) {
  std::vector<DeviceFault> faults = std::move(refusals_);
  refusals_.clear();
  if (ScsArmsDriver* scs = hw_->scs_arms()) {
    for (DeviceFault& f : health_.Servos(now_s, scs->servo_statuses(), scs->counters()))
      faults.push_back(std::move(f));
  }
  for (DeviceFault& f : health_.Autopilot(now_s, hw_->autopilot().State()))
    faults.push_back(std::move(f));
  return faults;
}

std::vector<DeviceFault> MissionHealth::Frame(double now_s, const RgbdFrame& frame) {
  return health_.Frame(now_s, frame.stamp_s, DepthHasData(frame.depth));
}

}  // namespace aerograsp
