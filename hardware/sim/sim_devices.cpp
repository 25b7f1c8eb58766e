#include "hardware/sim/sim_devices.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "hardware/sim/d435_model.h"

namespace aerograsp {
namespace {

constexpr std::uint64_t kCameraStream = 0x3000;
constexpr double kLightPeriod_s = 23.0;  // slow change of the light (clouds)

}  // namespace

SimCamera::SimCamera(World* world, const SimCameraFaults& faults)
    : world_(world),
      K_(world->platform().camera().Scaled(world->config().camera.image_scale)),
      rng_(world->seed() * 0x9E3779B97F4A7C15ull + kCameraStream),
      faults_(faults) {
  for (const RenderMesh& mesh : world->static_scene())
    renderer_.AddMesh(mesh, RgbdRenderer::Motion::kStatic);
  object_id_ = renderer_.AddMesh(world->object_render_mesh());
  for (Side side : {Side::kLeft, Side::kRight}) {
    for (const RenderMesh& mesh : world->arm_render_meshes(side)) {
      arm_ids_[static_cast<int>(side)].push_back(renderer_.AddMesh(mesh));
    }
  }
  if (world->config().occluder.enabled)
    occluder_id_ = renderer_.AddMesh(world->occluder_render_mesh());
}

SimCamera::~SimCamera() = default;

const CameraIntrinsics& SimCamera::intrinsics() const { return K_; }

double SimCamera::depth_scale_m() const { return world_->config().camera.d435.depth_scale_m; }

bool SimCamera::Grab(RgbdFrame* frame) {
  const bool faulty = world_->now_s() >= faults_.faults_from_s;
  if (faulty && faults_.frozen && have_last_frame_) {
    if (first_fault_s_ < 0.0) first_fault_s_ = world_->now_s();
    *frame = last_frame_;
    return true;
  }
  const CameraSimConfig& config = world_->config().camera;
  renderer_.SetPose(object_id_, world_->wMo());
  if (occluder_id_ >= 0) renderer_.SetPose(occluder_id_, world_->wMh());
  for (Side side : {Side::kLeft, Side::kRight}) {
    const std::vector<Eigen::Isometry3d> wMs = world_->ArmSegmentPoses(side);
    const auto& ids = arm_ids_[static_cast<int>(side)];
    for (std::size_t i = 0; i < ids.size(); ++i) renderer_.SetPose(ids[i], wMs[i]);
  }
  const auto& attachments = world_->attachments();
  while (attachment_ids_.size() < attachments.size()) {
    attachment_ids_.push_back(renderer_.AddMesh(attachments[attachment_ids_.size()].mesh));
  }
  for (std::size_t i = 0; i < attachments.size(); ++i) {
    renderer_.SetPose(attachment_ids_[i], world_->wMattachment(attachments[i]));
  }
  const double t = world_->now_s();
  const double az = config.light_azimuth_deg * M_PI / 180.0;
  const double el = config.light_elevation_deg * M_PI / 180.0;
  lighting_.to_light_w =
      Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
  lighting_.intensity = config.light_intensity *
                        (1.0 + config.light_variation * std::sin(2.0 * M_PI * t / kLightPeriod_s));
  lighting_.ambient = config.ambient;
  const auto t0 = std::chrono::steady_clock::now();
  renderer_.Render(world_->wMc(), intrinsics(), lighting_, &truth_);
  const auto t1 = std::chrono::steady_clock::now();
  SimulateD435(config.d435, intrinsics(), truth_, &rng_, frame);
  render_s_ = std::chrono::duration<double>(t1 - t0).count();
  model_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  frame->index = next_index_++;
  frame->stamp_s = t;
  if (faulty && faults_.no_depth) {
    if (first_fault_s_ < 0.0) first_fault_s_ = t;
    std::fill(frame->depth.data.begin(), frame->depth.data.end(), std::uint16_t{0});
  }
  if (faults_.frozen) {
    last_frame_ = *frame;
    have_last_frame_ = true;
  }
  return true;
}

void SimArmsDriver::SetJointTargets(Side side, const Eigen::VectorXd& q_rad) {
  world_->arm(side).SetTarget(q_rad);
}

Eigen::VectorXd SimArmsDriver::JointPositions(Side side) const {
  return world_->arm(side).q_measured_rad();
}

void SimArmsDriver::SetGripper(Side side, GripperCommand command) {
  world_->SetGripper(side, command);
}

GripperState SimArmsDriver::Gripper(Side side) const { return world_->gripper(side); }

void SimArmsDriver::Stop() {
  for (Side side : {Side::kLeft, Side::kRight}) {
    world_->arm(side).SetTarget(world_->arm(side).q_measured_rad());
  }
}

VehicleState SimAutopilot::State() const { return world_->vehicle().State(); }
CommandAck SimAutopilot::Arm() { return world_->vehicle().Arm(); }
CommandAck SimAutopilot::Disarm() { return world_->vehicle().Disarm(); }
CommandAck SimAutopilot::Takeoff(double altitude_m) {
  return world_->vehicle().Takeoff(altitude_m);
}
CommandAck SimAutopilot::Land() { return world_->vehicle().Land(); }
CommandAck SimAutopilot::Hold() { return world_->vehicle().Hold(); }
CommandAck SimAutopilot::SetPositionTarget(const Eigen::Vector3d& p_w, double yaw_rad) {
  return world_->vehicle().SetPositionTarget(world_->now_s(), p_w, yaw_rad);
}

}  // namespace aerograsp
