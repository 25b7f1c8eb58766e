// The simulated world: vehicle, both arms with their grippers, the object on
// its pipe, and the static scene, stepped deterministically on a simulated
// clock (faster than real time; the same seed gives the same run).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/object_model.h"
#include "core/platform.h"
#include "hardware/arms_driver.h"
#include "hardware/sim/rgbd_renderer.h"
#include "hardware/sim/sim_vehicle.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {

/// One arm's servos: each joint follows its target with a first-order lag and
/// a speed limit; targets and readings are quantised like the Feetech servos
/// (docs/hardware.md: 10 bits over about 220 deg, counted from the lower limit).
class SimArm {
 public:
  SimArm(const ArmModel& arm, const ArmsSimConfig& config, const Eigen::VectorXd& q0_rad);
  void SetTarget(const Eigen::VectorXd& q_rad);
  void Step(double dt_s);
  /// A person moves the arm (clamped to its limits): it stays there while its
  /// servos are limp (the simulated bus's torque off); powered, it returns to its target.
  void MoveByHand(const Eigen::VectorXd& q_rad);
  const Eigen::VectorXd& q_true_rad() const { return q_; }
  /// What the servos report: the true position quantised.
  Eigen::VectorXd q_measured_rad() const;
  const Eigen::VectorXd& target_rad() const { return target_; }
  /// Angle of one position count (rad).
  double quantum_rad() const { return quantum_rad_; }

 private:
  double Quantise(int joint, double q_rad) const;
  const ArmModel* arm_;
  ArmsSimConfig config_;
  double quantum_rad_;
  Eigen::VectorXd q_, target_;
};

class World {
 public:
  /// Loads the platform and the object named in the config.
  /// @throws ConfigError / MeshError / UrdfError naming the file.
  World(const WorldConfig& config, std::uint64_t seed);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const WorldConfig& config() const { return config_; }
  const Platform& platform() const { return platform_; }
  const ObjectModel& object() const { return object_; }
  std::uint64_t seed() const { return seed_; }

  double now_s() const { return now_s_; }
  /// Advances the clock by dt_s in physics steps (the last one shortened to land on time).
  void Step(double dt_s);
  /// Advances to t_s (no-op when t_s <= now).
  void StepTo(double t_s);

  SimVehicle& vehicle() { return vehicle_; }
  const SimVehicle& vehicle() const { return vehicle_; }
  SimArm& arm(Side side) { return arms_[static_cast<int>(side)]; }
  const SimArm& arm(Side side) const { return arms_[static_cast<int>(side)]; }
  /// Opening the last gripper that holds the object releases it: it falls
  /// upright onto the support pipe when its centre is above the pipe, else to
  /// the ground (no physics), and stays there.
  void SetGripper(Side side, GripperCommand command);
  GripperState gripper(Side side) const { return grippers_[static_cast<int>(side)].state; }

  /// Ground truth.
  Eigen::Isometry3d wMd() const { return vehicle_.State().wMd; }
  Eigen::Isometry3d wMc() const { return wMd() * platform_.dMc(); }
  Eigen::Isometry3d wMo() const { return wMo_; }
  /// The tool point of an arm in the world, at the arm's true joint positions.
  Eigen::Isometry3d wMe(Side side) const;
  /// Which gripper holds the object (both may); the object moves with the left one first.
  bool held_by(Side side) const { return grippers_[static_cast<int>(side)].state.holding; }

  /// The static scene (ground, pipe and its posts, clutter), in w, for rendering.
  const std::vector<RenderMesh>& static_scene() const { return static_scene_; }
  /// The object's render mesh in frame o.
  const RenderMesh& object_render_mesh() const { return object_render_; }
  /// Render meshes of one arm's segments, each in its segment frame (ArmModel::SegmentPoses).
  const std::vector<RenderMesh>& arm_render_meshes(Side side) const {
    return arm_render_[static_cast<int>(side)];
  }
  /// wMseg for each segment of an arm, matching arm_render_meshes.
  std::vector<Eigen::Isometry3d> ArmSegmentPoses(Side side) const;

  /// Moves the object to wMo (a hand placing it on a bench); it then stays
  /// there (no crawling) until a gripper takes it.
  void PlaceObject(const Eigen::Isometry3d& wMo);

  /// A mesh carried by an arm's tool frame e (a tag board on the gripper), by
  /// the object o (a tag board on a bench object) or held in front of the
  /// camera c (a board a person shows to the camera): pMm places the mesh frame
  /// m in its carrier p. Rendered by SimCamera.
  struct Attachment {
    enum class Carrier { kTool, kObject, kCamera };
    Carrier carrier = Carrier::kTool;
    Side side = Side::kLeft;  ///< the arm, when carried by a tool
    RenderMesh mesh;
    Eigen::Isometry3d pMm = Eigen::Isometry3d::Identity();
  };
  void AttachToTool(Side side, const RenderMesh& mesh, const Eigen::Isometry3d& eMm);
  void AttachToObject(const RenderMesh& mesh, const Eigen::Isometry3d& oMm);
  /// Returns the attachment's index, for MoveAttachment.
  std::size_t AttachToCamera(const RenderMesh& mesh, const Eigen::Isometry3d& cMm);
  /// Places attachment `index` at pMm in its carrier.
  /// @throws std::out_of_range for an index that names no attachment.
  void MoveAttachment(std::size_t index, const Eigen::Isometry3d& pMm);
  const std::vector<Attachment>& attachments() const { return attachments_; }
  /// Where an attachment's mesh frame is now, in w.
  Eigen::Isometry3d wMattachment(const Attachment& attachment) const;

  /// The occluder (WorldConfig::occluder): its panel, whether it hides the
  /// object now, and wMh, its pose: on the line from the camera to the object
  /// at distance_m, parallel to the image plane, while it hides the object;
  /// 1 m behind the camera otherwise (out of every view).
  const RenderMesh& occluder_render_mesh() const { return occluder_render_; }
  bool occluder_active() const;
  Eigen::Isometry3d wMh() const;

  /// Where the object rests on the pipe at `along_m` from the pipe's centre.
  Eigen::Isometry3d ObjectOnPipe(double along_m) const;

 private:
  struct Gripper {
    GripperCommand command = GripperCommand::kOpen;
    GripperState state;
    Eigen::Isometry3d eMo = Eigen::Isometry3d::Identity();
    /// The object's width between the pads at the end of the last step, m;
    /// negative when the pads did not span it then.
    double last_contact_m = -1.0;
  };
  void PhysicsStep(double dt_s);
  void UpdateGripper(Side side, double dt_s);
  double ClosingWidth(Side side, bool* spans) const;

  WorldConfig config_;
  std::uint64_t seed_;
  Platform platform_;
  ObjectModel object_;
  SimVehicle vehicle_;
  std::vector<SimArm> arms_;
  std::array<Gripper, 2> grippers_;
  double now_s_ = 0.0;
  Eigen::Isometry3d wMo_ = Eigen::Isometry3d::Identity();
  bool object_free_ = false;  // grasped once: no longer crawls
  bool knocked_off_ = false;  // config_.object.knocked_off_at_s has come
  std::vector<RenderMesh> static_scene_;
  RenderMesh object_render_;
  RenderMesh occluder_render_;
  std::array<std::vector<RenderMesh>, 2> arm_render_;
  std::vector<Attachment> attachments_;
};

}  // namespace aerograsp
