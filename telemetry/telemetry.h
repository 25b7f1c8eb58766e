// What aerograsp tells other programs while it runs, and what they may tell it.
//
// Output: `mission`, `bench`, `replay` and `calibrate` call a TelemetrySink as
// they run: the object's pose, both arms' joints and grippers, the transforms
// between the frames, the state machines' transitions with their causes, the
// followed grasp pair, the camera's images and the log lines. Sinks write an
// MCAP file (telemetry/mcap_sink.h) or publish on a network; FanOutSink hands
// every call to several of them.
//
// Input: an EmergencyStopSource that the mission loop polls once per servo
// cycle; a request stops both arms and holds the vehicle, as the mission's own
// emergency does, with the source in the log.
//
// Conventions of every call:
// - Time: `t_s` is the command's clock in seconds: mission time from the start
//   (the simulated clock in simulation, the wall clock since the start on
//   hardware); in replay the recording's stamps. It never decreases from one
//   call to the next of the same kind.
// - Units SI: m, rad, m/s, rad/s; covariances m^2 and rad^2.
// - Poses are `parentMchild`: the child frame expressed in the parent frame.
// - Frames are named as in data/robots/vehicle.urdf and ROS (the names below
//   are the `frame_id` / `child_frame_id` on the wire). The letters of
//   core/frames.h in brackets:
//     world           [w]  PX4's local frame, NED (x north, y east, z down)
//     map                  the same origin, ENU (x east, y north, z up), the
//                          parent of world, for viewers that expect z up
//     body            [d]  the vehicle body, FRD (x forward, y right, z down)
//     camera_optical  [c]  z along the view, x right, y down in the image
//     arm_left_mount  [bl] the left arm's base (arm_right_mount [br])
//     arm_left_tool   [el] the tool point between the left fingers; z the
//                          approach axis (arm_right_tool [er])
//     object          [o]  the object model's frame
//     tag_board       [t]  the calibration or bench tag board, as the camera sees it
//     object_truth         the object's true pose (simulation and recordings
//                          with a ground truth), beside the estimate
// - Calls come from one thread at a time (the command's loop), never
//   concurrently; a sink must not block the loop for long (no network round
//   trips, no fsync) and must not throw: it reports its own failures once,
//   through the `note` callback it was built with, and goes on without them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/image.h"

namespace aerograsp {

/// The frame names on the wire (see the table above).
namespace telemetry_frame {
inline constexpr const char* kMap = "map";
inline constexpr const char* kWorld = "world";
inline constexpr const char* kBody = "body";
inline constexpr const char* kCamera = "camera_optical";
inline constexpr const char* kLeftBase = "arm_left_mount";
inline constexpr const char* kRightBase = "arm_right_mount";
inline constexpr const char* kLeftTool = "arm_left_tool";
inline constexpr const char* kRightTool = "arm_right_tool";
inline constexpr const char* kObject = "object";
inline constexpr const char* kObjectTruth = "object_truth";
inline constexpr const char* kTagBoard = "tag_board";
}  // namespace telemetry_frame

/// The object as perception sees it, once per processed camera frame.
struct TelemetryObjectPose {
  double t_s = 0.0;  ///< when the frame was taken
  /// The frame the pose and covariance are in: world in the mission (the
  /// filter runs there), camera_optical in bench and replay.
  std::string frame_id;
  bool valid = false;       ///< a pose exists (false: `fMo` is meaningless)
  bool found = false;       ///< tracked on this frame (false: lost, `fMo` is the last estimate)
  double confidence = 0.0;  ///< [0, 1]
  Eigen::Isometry3d fMo = Eigen::Isometry3d::Identity();  ///< the object in frame_id
  /// 6x6 covariance of [x, y, z, rotation about x, y, z] in frame_id (m^2,
  /// rad^2; the rotation error on the left: fRo = Exp(dtheta) * fRo_hat), the
  /// layout of ROS's PoseWithCovariance. Absent when perception has none.
  std::optional<Eigen::Matrix<double, 6, 6>> covariance;
};

/// One arm and its gripper.
struct TelemetryArmState {
  std::string arm;                       ///< "left" | "right"
  std::vector<std::string> joint_names;  ///< as in the arm's URDF (j0, j1, ...)
  Eigen::VectorXd position_rad;          ///< measured, one per name
  Eigen::VectorXd velocity_radps;        ///< one per name; empty when unknown
  Eigen::VectorXd target_rad;            ///< the last command sent; empty when none
  double gripper_aperture_m = 0.0;       ///< opening between the finger pads
  bool gripper_closed = false;           ///< the last command was close and the fingers stopped
  bool gripper_holding = false;          ///< closed on the object
};

/// Both arms at one instant (the servo rate in the mission and bench).
struct TelemetryArms {
  double t_s = 0.0;
  TelemetryArmState arms[2];  ///< 0 left, 1 right
};

/// One rigid transform between two named frames.
struct TelemetryTransform {
  std::string parent;  ///< frame_id
  std::string child;   ///< child_frame_id
  Eigen::Isometry3d parentMchild = Eigen::Isometry3d::Identity();
};

/// A state machine changed state (machines: global, vehicle, vision, planner,
/// arms; the calibration wizard: calibrate, with preflight, moving or
/// hand-guided, solving, done, stopped).
struct TelemetryTransition {
  double t_s = 0.0;
  std::string machine;
  std::string from, to;
  std::string cause;  ///< the signal or condition, one line
};

/// The followed dual grasp: contact-pair indices of the planner's contact set
/// per arm (-1: none followed).
struct TelemetryGraspPair {
  double t_s = 0.0;
  int left_pair = -1, right_pair = -1;
  std::string reason;  ///< why this pair, one line
};

/// One camera frame. The pointers are valid during the call only: a sink that
/// keeps an image copies (or encodes) it before returning.
struct TelemetryImage {
  double t_s = 0.0;  ///< when the frame was taken
  std::string frame_id = telemetry_frame::kCamera;
  CameraIntrinsics K;                 ///< pinhole, pixels, of the colour image
  const ColorImage* color = nullptr;  ///< RGB, 8 bits
  const DepthImage* depth = nullptr;  ///< aligned to colour; null when the command has none
  double depth_scale_m = 0.001;       ///< metres per depth unit
};

/// Severity of a log line (the levels of ROS's rcl_interfaces/Log).
enum class TelemetryLevel { kDebug, kInfo, kWarn, kError, kFatal };

/// Where the calls go. Every call has the conventions of the file comment.
class TelemetrySink {
 public:
  virtual ~TelemetrySink() = default;

  /// The fixed transforms, once before the first other call and again when
  /// one changes (a calibration solved): map->world, body->camera_optical,
  /// body->arm_left_mount, body->arm_right_mount.
  virtual void StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) = 0;
  /// The moving ones: world->body (the vehicle's estimate), each mount->tool
  /// (forward kinematics of the measured joints) and the object (world->object
  /// in the mission, camera_optical->object in bench and replay) while a pose
  /// exists.
  virtual void Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) = 0;
  virtual void ObjectPose(const TelemetryObjectPose& pose) = 0;
  virtual void Arms(const TelemetryArms& arms) = 0;
  virtual void Transition(const TelemetryTransition& transition) = 0;
  virtual void GraspPair(const TelemetryGraspPair& pair) = 0;
  virtual void Image(const TelemetryImage& image) = 0;
  /// One line of the command's log (`name`: the logger, e.g. "mission").
  virtual void Log(double t_s, TelemetryLevel level, const std::string& name,
                   const std::string& line) = 0;
  /// The command ended: write out what is buffered. Later calls are ignored.
  virtual void Close() = 0;
};

/// Hands every call to each of its sinks, in the order they were added.
class FanOutSink final : public TelemetrySink {
 public:
  void Add(std::unique_ptr<TelemetrySink> sink);
  bool empty() const { return sinks_.empty(); }

  void StaticTransforms(double t_s, const std::vector<TelemetryTransform>& transforms) override;
  void Transforms(double t_s, const std::vector<TelemetryTransform>& transforms) override;
  void ObjectPose(const TelemetryObjectPose& pose) override;
  void Arms(const TelemetryArms& arms) override;
  void Transition(const TelemetryTransition& transition) override;
  void GraspPair(const TelemetryGraspPair& pair) override;
  void Image(const TelemetryImage& image) override;
  void Log(double t_s, TelemetryLevel level, const std::string& name,
           const std::string& line) override;
  void Close() override;

 private:
  std::vector<std::unique_ptr<TelemetrySink>> sinks_;
};

/// map->world, the same origin: world's x (north) is map's y, world's y
/// (east) map's x, world's z (down) map's -z.
Eigen::Isometry3d MapMWorld();

// ---- Input: emergency stop ------------------------------------------------------

/// What a poll found.
struct EmergencyStopPoll {
  /// A stop is requested (from the first request on: the mission latches its
  /// emergency, nothing releases it).
  bool stop = false;
  std::string source;  ///< who asked, e.g. "ros2 /aerograsp/emergency_stop"
  std::string reason;  ///< one line, may be empty
  /// Lines for the mission log (a malformed message, a lost link), each said
  /// once by the source.
  std::vector<std::string> notes;
};

/// A source of emergency stops outside the mission (a ROS 2 topic, a button).
class EmergencyStopSource {
 public:
  virtual ~EmergencyStopSource() = default;
  /// Called by the mission loop once per servo cycle at mission time `t_s`;
  /// must return at once (no waiting on a network).
  virtual EmergencyStopPoll Poll(double t_s) = 0;
};

/// A stop that any thread requests (a network listener, a signal handler
/// through a flag) and the loop picks up at its next poll. Thread-safe.
class EmergencyStopLatch final : public EmergencyStopSource {
 public:
  /// Requests a stop; the first request's source and reason are kept.
  void Request(const std::string& source, const std::string& reason);
  /// A line for the mission log at the next poll.
  void Note(const std::string& line);
  EmergencyStopPoll Poll(double t_s) override;

 private:
  std::mutex mutex_;
  bool requested_ = false;
  std::string source_, reason_;
  std::vector<std::string> notes_;
};

}  // namespace aerograsp
