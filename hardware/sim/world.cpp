#include "hardware/sim/world.h"

#include <algorithm>
#include <cmath>

#include "core/shape_mesh.h"
#include "core/transforms.h"
#include "hardware/sim/scene.h"

namespace aerograsp {
namespace {

// Independent random streams, so that changing one part of a run (say, the
// number of frames) does not change another (the clutter).
constexpr std::uint64_t kSceneStream = 0x1000;
constexpr std::uint64_t kVehicleStream = 0x2000;

}  // namespace

// ---------------------------------------------------------------------------
// SimArm

SimArm::SimArm(const ArmModel& arm, const ArmsSimConfig& config, const Eigen::VectorXd& q0_rad)
    : arm_(&arm),
      config_(config),
      quantum_rad_(config.position_range_deg * M_PI / 180.0 / (config.position_counts - 1)) {
  q_ = arm.Clamp(q0_rad);
  target_ = q_;
}

double SimArm::Quantise(int joint, double q_rad) const {
  const double lower = arm_->lower_limits()[joint];
  const double counts = std::round((q_rad - lower) / quantum_rad_);
  return lower + std::clamp(counts, 0.0, double(config_.position_counts - 1)) * quantum_rad_;
}

void SimArm::SetTarget(const Eigen::VectorXd& q_rad) {
  if (q_rad.size() != q_.size() || !q_rad.allFinite()) return;  // the bus would reject it
  const Eigen::VectorXd clamped = arm_->Clamp(q_rad);
  for (int i = 0; i < clamped.size(); ++i) target_[i] = Quantise(i, clamped[i]);
}

void SimArm::MoveByHand(const Eigen::VectorXd& q_rad) {
  if (q_rad.size() != q_.size() || !q_rad.allFinite()) return;
  q_ = arm_->Clamp(q_rad);
}

void SimArm::Step(double dt_s) {
  for (int i = 0; i < q_.size(); ++i) {
    const double max_speed = config_.speed_scale * arm_->velocity_limits()[i];
    const double speed = std::clamp((target_[i] - q_[i]) / config_.lag_s, -max_speed, max_speed);
    q_[i] += speed * dt_s;
  }
  q_ = arm_->Clamp(q_);
}

Eigen::VectorXd SimArm::q_measured_rad() const {
  Eigen::VectorXd q(q_.size());
  for (int i = 0; i < q_.size(); ++i) q[i] = Quantise(i, q_[i]);
  return q;
}

// ---------------------------------------------------------------------------
// World

World::World(const WorldConfig& config, std::uint64_t seed)
    : config_(config),
      seed_(seed),
      platform_(Platform::Load(config.platform)),
      object_(ObjectModel::Load(config.object.name)),
      vehicle_(config.vehicle, seed * 0x9E3779B97F4A7C15ull + kVehicleStream) {
  for (Side side : {Side::kLeft, Side::kRight}) {
    arms_.emplace_back(platform_.arm(side), config.arms, platform_.home(side));
    Gripper& g = grippers_[static_cast<int>(side)];
    g.state.aperture_m = platform_.config().gripper.max_aperture_m;
    arm_render_[static_cast<int>(side)] = ArmRenderMeshes(platform_.arm(side));
  }
  static_scene_ = BuildStaticScene(config.scene, seed * 0x9E3779B97F4A7C15ull + kSceneStream);
  object_render_.mesh = object_.mesh_o;
  wMo_ = ObjectOnPipe(config.object.start_along_pipe_m);
  if (config.occluder.enabled) {
    const double side_m = config.occluder.size_m;
    occluder_render_.mesh = MakeBoxMesh(Eigen::Vector3d(side_m, side_m, 0.01));
    occluder_render_.material.albedo = {0.3f, 0.25f, 0.2f};  // a cardboard sheet
  }
}

bool World::occluder_active() const {
  const OccluderConfig& h = config_.occluder;
  if (!h.enabled || now_s_ < h.start_s) return false;
  const double since_s = now_s_ - h.start_s;
  return (h.period_s > 0.0 ? std::fmod(since_s, h.period_s) : since_s) < h.duration_s;
}

Eigen::Isometry3d World::wMh() const {
  const Eigen::Isometry3d wMc_now = wMc();
  Eigen::Isometry3d wMh_now = wMc_now;
  if (occluder_active()) {
    const Eigen::Vector3d to_object_w =
        wMo_ * PlacementCentre(object_.mesh_o) - wMc_now.translation();
    wMh_now.translation() += config_.occluder.distance_m * to_object_w.normalized();
  } else {
    wMh_now.translation() -= wMc_now.linear().col(2);
  }
  return wMh_now;
}

World::~World() = default;

Eigen::Isometry3d World::ObjectOnPipe(double along_m) const {
  const double half_height = 0.5 * object_.dimensions_m.z();  // o: z up
  return PlaceByCentre(
      aerograsp::ObjectOnPipe(config_.scene, half_height, along_m, config_.object.yaw_on_pipe_rad),
      object_.mesh_o);
}

Eigen::Isometry3d World::wMe(Side side) const {
  return wMd() * platform_.dMb(side) *
         platform_.arm(side).ForwardKinematics(arm(side).q_true_rad());
}

std::vector<Eigen::Isometry3d> World::ArmSegmentPoses(Side side) const {
  std::vector<Eigen::Isometry3d> bMs;
  platform_.arm(side).SegmentPoses(arm(side).q_true_rad(), &bMs);
  const Eigen::Isometry3d wMb = wMd() * platform_.dMb(side);
  std::vector<Eigen::Isometry3d> wMs;
  for (std::size_t i = 0; i < arm_render_[static_cast<int>(side)].size(); ++i)
    wMs.push_back(wMb * bMs[i]);
  return wMs;
}

void World::AttachToTool(Side side, const RenderMesh& mesh, const Eigen::Isometry3d& eMm) {
  attachments_.push_back({Attachment::Carrier::kTool, side, mesh, eMm});
}

void World::AttachToObject(const RenderMesh& mesh, const Eigen::Isometry3d& oMm) {
  attachments_.push_back({Attachment::Carrier::kObject, Side::kLeft, mesh, oMm});
}

std::size_t World::AttachToCamera(const RenderMesh& mesh, const Eigen::Isometry3d& cMm) {
  attachments_.push_back({Attachment::Carrier::kCamera, Side::kLeft, mesh, cMm});
  return attachments_.size() - 1;
}

void World::MoveAttachment(std::size_t index, const Eigen::Isometry3d& pMm) {
  attachments_.at(index).pMm = pMm;
}

Eigen::Isometry3d World::wMattachment(const Attachment& attachment) const {
  switch (attachment.carrier) {
    case Attachment::Carrier::kObject:
      return wMo_ * attachment.pMm;
    case Attachment::Carrier::kCamera:
      return wMc() * attachment.pMm;
    case Attachment::Carrier::kTool:
      break;
  }
  return wMe(attachment.side) * attachment.pMm;
}

void World::PlaceObject(const Eigen::Isometry3d& wMo) {
  wMo_ = wMo;
  object_free_ = true;
}

void World::SetGripper(Side side, GripperCommand command) {
  Gripper& g = grippers_[static_cast<int>(side)];
  if (g.command == command) return;
  g.command = command;
  if (command == GripperCommand::kOpen && g.state.holding) {
    g.state.holding = false;
    const bool still_held = grippers_[0].state.holding || grippers_[1].state.holding;
    if (!still_held) {
      // Released: the object falls upright onto the support pipe when its
      // centre is above the pipe (as when one gripper held it where it sat),
      // else to the ground below it (no physics).
      object_free_ = true;
      const SceneConfig& scene = config_.scene;
      const Eigen::Vector3d p_p =
          PipeFrame(scene).inverse() * (wMo_ * PlacementCentre(object_.mesh_o));  // z down
      if (std::abs(p_p.x()) <= 0.5 * scene.pipe_length_m &&
          std::abs(p_p.y()) <= scene.pipe_radius_m && p_p.z() < 0.0) {
        wMo_ = ObjectOnPipe(p_p.x());
      } else {
        const double yaw = std::atan2(wMo_.linear()(1, 0), wMo_.linear()(0, 0));
        const Eigen::Vector3d centre_w = wMo_ * PlacementCentre(object_.mesh_o);
        wMo_ = PlaceByCentre(MakeTransform(Eigen::Vector3d(centre_w.x(), centre_w.y(),
                                                           -0.5 * object_.dimensions_m.z()),
                                           Eigen::Vector3d(M_PI, 0.0, yaw)),
                             object_.mesh_o);
      }
    }
  }
}

double World::ClosingWidth(Side side, bool* spans) const {
  // The fingers are pads along the approach axis z_e: from their tips, 0.02 m
  // beyond the tool point (docs/hardware.md, the tool point), back finger_length_m. They
  // close along the tool x axis and stop on whatever lies between them at any
  // depth of the pads: closing lines every 5 mm along the pads, each as long as
  // the open aperture, in the object frame.
  const GripperConfig& gc = platform_.config().gripper;
  const double open_m = gc.max_aperture_m;
  const Eigen::Isometry3d oMe = wMo_.inverse() * wMe(side);
  const Eigen::Vector3d x_o = oMe.linear().col(0);
  const Eigen::Vector3d z_o = oMe.linear().col(2);
  constexpr double kTipBeyondToolM = 0.02, kStepM = 0.005;
  *spans = false;
  double width = 0.0;
  for (double along = kTipBeyondToolM; along >= kTipBeyondToolM - gc.finger_length_m;
       along -= kStepM) {
    const Eigen::Vector3d start_o = oMe.translation() + along * z_o - 0.5 * open_m * x_o;
    const std::vector<double> hits = IntersectRay(object_.mesh_o, start_o, x_o);
    double first = -1.0, last = -1.0;
    std::size_t inside = 0;
    for (double t : hits) {
      if (t > open_m) break;
      if (first < 0.0) first = t;
      last = t;
      ++inside;
    }
    // This line holds the object between the open pads when both pad
    // positions are outside the (closed) mesh (an even number of crossings
    // beyond each) and it crosses the object.
    const std::size_t after = hits.size() - inside;
    if (!(inside >= 2 && after % 2 == 0 && (inside + after) % 2 == 0)) continue;
    *spans = true;
    // Symmetric fingers touch at the farther of the two surfaces from the axis;
    // over the pads, at the widest part between them.
    width = std::max(width, 2.0 * std::max(0.5 * open_m - first, last - 0.5 * open_m));
  }
  return width;
}

void World::UpdateGripper(Side side, double dt_s) {
  Gripper& g = grippers_[static_cast<int>(side)];
  const GripperConfig& gc = platform_.config().gripper;
  const double rate = gc.max_aperture_m / gc.close_time_s;
  if (g.command == GripperCommand::kOpen) {
    g.state.aperture_m = std::min(gc.max_aperture_m, g.state.aperture_m + rate * dt_s);
    g.state.moving = g.state.aperture_m < gc.max_aperture_m;
    g.state.closed = false;
    g.state.holding = false;
    g.last_contact_m = -1.0;
    return;
  }
  if (g.state.holding) {  // fingers rest on the object
    g.state.moving = false;
    return;
  }
  bool spans = false;
  const double contact = ClosingWidth(side, &spans);
  const double next = std::max(0.0, g.state.aperture_m - rate * dt_s);
  // The pads touch the object when, during this step, the gap between them
  // narrows past its width: they were clear of it at the start of the step
  // (the width where the object was then) and meet it at its end. Relative
  // motion widens the width as the pads close, so comparing both ends with
  // one width would let a pad pass through the object between two steps.
  const bool clear_before = g.state.aperture_m >= contact ||
                            (g.last_contact_m >= 0.0 && g.state.aperture_m >= g.last_contact_m);
  g.last_contact_m = spans ? contact : -1.0;
  if (spans && next <= contact && clear_before) {
    g.eMo = wMe(side).inverse() * wMo_;
    object_free_ = true;
    g.state = {contact, false, true, true};
    return;
  }
  g.state.aperture_m = next;
  g.state.moving = next > 0.0;
  g.state.closed = next <= 0.0;
}

void World::PhysicsStep(double dt_s) {
  vehicle_.Step(now_s_, dt_s);
  for (auto& arm : arms_) arm.Step(dt_s);
  for (Side side : {Side::kLeft, Side::kRight}) UpdateGripper(side, dt_s);
  now_s_ += dt_s;
  // The object: carried by a gripper, else crawling or resting.
  if (grippers_[0].state.holding) {
    wMo_ = wMe(Side::kLeft) * grippers_[0].eMo;
  } else if (grippers_[1].state.holding) {
    wMo_ = wMe(Side::kRight) * grippers_[1].eMo;
  } else if (!knocked_off_ && config_.object.knocked_off_at_s >= 0.0 &&
             now_s_ >= config_.object.knocked_off_at_s) {
    // Knocked off: it lands upright on the ground, half a metre to the side of
    // where it sat on the pipe, and stays there.
    knocked_off_ = true;
    object_free_ = true;
    const Eigen::Vector3d side_w =
        PipeFrame(config_.scene).linear() * Eigen::Vector3d(0.0, 0.5, 0.0);
    const Eigen::Vector3d centre_w = wMo_ * PlacementCentre(object_.mesh_o) + side_w;
    const double yaw = std::atan2(wMo_.linear()(1, 0), wMo_.linear()(0, 0));
    wMo_ = PlaceByCentre(
        MakeTransform(Eigen::Vector3d(centre_w.x(), centre_w.y(), -0.5 * object_.dimensions_m.z()),
                      Eigen::Vector3d(M_PI, 0.0, yaw)),
        object_.mesh_o);
  } else if (!object_free_ && config_.object.motion == "crawl" && config_.object.travel_m > 0.0) {
    // Back and forth between start and start + travel at constant speed.
    const double travel = config_.object.travel_m;
    const double s = std::fmod(config_.object.speed_mps * now_s_, 2.0 * travel);
    wMo_ = ObjectOnPipe(config_.object.start_along_pipe_m + (s <= travel ? s : 2.0 * travel - s));
  }
}

void World::Step(double dt_s) { StepTo(now_s_ + dt_s); }

void World::StepTo(double t_s) {
  const double h = config_.physics_step_s;
  while (now_s_ < t_s - 1e-12) PhysicsStep(std::min(h, t_s - now_s_));
}

}  // namespace aerograsp
