// The platform: the vehicle's static frame tree, the two arms mounted on it,
// the camera and the gripper, as one immutable description built from a
// platform YAML (data/config/platform_4dof.yaml is the reference).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/arm_model.h"
#include "core/camera_model.h"

namespace aerograsp {

/// One arm's mount on the vehicle.
struct ArmMountConfig {
  std::string urdf;                    ///< arm URDF, resolved against the config's folder
  std::string mount_link;              ///< vehicle link the arm base is bolted to (= bl or br)
  std::string base_link{"base_link"};  ///< chain start in the arm URDF
  std::string tip_link{"tool"};        ///< chain end: the tool point e
  std::vector<double> home_rad;        ///< home joint positions (rad), one per joint, within limits
};

/// The longest finger pads a platform file may give, m (GripperConfig::finger_length_m's bound).
inline constexpr double kLongestFingerM = 0.3;

/// The two-finger gripper (docs/hardware.md: aperture not published; 0.10-0.15 m).
struct GripperConfig {
  double max_aperture_m{0.12};  ///< opening between the finger pads when open, (0, 0.3] m
  /// free space each side of the object when closing, [0, 0.05] m
  double finger_clearance_m{0.01};
  double finger_width_m{0.03};   ///< pad width across the closing direction, (0, 0.1] m
  double finger_length_m{0.12};  ///< pad length along the approach axis, (0, 0.3] m
  double close_time_s{0.8};      ///< full open to closed, (0, 10] s
};

/// What a gripper is told: the servo layer decides it, the arms driver carries it out.
enum class GripperCommand { kOpen, kClose };

struct PlatformConfig {
  std::string source;                         ///< the file it was read from (for messages)
  std::string arm_type{"4dof"};               ///< "4dof" or "6dof"
  std::string vehicle_urdf;                   ///< static frame tree of the body (all fixed joints)
  std::string body_link{"body"};              ///< frame d
  std::string camera_link{"camera_optical"};  ///< frame c
  std::string safe_volume_link{"safe_volume"};  ///< link whose collision shapes the arms must avoid
  std::string camera_xml;                       ///< ViSP camera XML of the colour stream
  std::string camera_name{"d435_color"};        ///< camera name inside camera_xml
  double vehicle_mass_kg{3.75};                 ///< with arms, (0, 50] kg
  ArmMountConfig left, right;
  GripperConfig gripper;

  /// Reads a platform YAML; relative paths are resolved against its folder.
  /// @throws ConfigError "<file>: <key>: ..." for a missing file or key, a wrong
  /// type, an unknown key, or any value Validate rejects.
  static PlatformConfig Load(const std::string& path);
  /// Checks ranges and that the referenced files exist. `source` is the file
  /// (Load passes `this->source`), `prefix` the key path of this tree in it,
  /// ending in "." ("" at the top). @throws ConfigError
  /// "<source>: <prefix><key>: ..." naming the bound.
  void Validate(const std::string& source, const std::string& prefix) const;
};

/// Which arm. Left is at -y in the FRD body frame.
enum class Side { kLeft = 0, kRight = 1 };
/// Both arms in index order (arrays indexed by arm: 0 left, 1 right).
inline constexpr Side kSides[2] = {Side::kLeft, Side::kRight};
/// Their names, "left" and "right", in the same order.
inline constexpr const char* kArmNames[2] = {"left", "right"};
/// kArmNames of `side`.
const char* SideName(Side side);

class Platform {
 public:
  /// PlatformConfig::Load then FromConfig.
  static Platform Load(const std::string& config_path);
  /// Builds the models. @throws ConfigError / UrdfError naming the file and key
  /// when a link is missing, a home vector has the wrong size or is out of limits.
  static Platform FromConfig(const PlatformConfig& config);

  /// A copy with one arm's base at dMb (a calibration's, e.g. dMc * cMb from
  /// `aerograsp calibrate`) instead of the URDF's mount; vehicle() keeps the
  /// nominal tree. @throws std::invalid_argument when dMb is not a rigid transform.
  Platform WithArmBase(Side side, const Eigen::Isometry3d& dMb) const;

  const PlatformConfig& config() const { return config_; }
  const StaticFrameTree& vehicle() const { return vehicle_; }
  const ArmModel& arm(Side side) const { return arms_[static_cast<int>(side)]; }
  /// dMb: the arm base (bl or br) in the body frame.
  const Eigen::Isometry3d& dMb(Side side) const { return dMb_[static_cast<int>(side)]; }
  /// dMc: the camera optical frame in the body frame (nominal; calibration overrides it).
  const Eigen::Isometry3d& dMc() const { return dMc_; }
  const CameraIntrinsics& camera() const { return camera_; }
  /// Home joint positions (rad).
  const Eigen::VectorXd& home(Side side) const { return home_[static_cast<int>(side)]; }
  /// Collision shapes of the safe volume, in the body frame d.
  const std::vector<CollisionShape>& safe_volume_d() const { return safe_volume_d_; }

 private:
  PlatformConfig config_;
  StaticFrameTree vehicle_;
  ArmModel arms_[2];
  Eigen::Isometry3d dMb_[2];
  Eigen::Isometry3d dMc_ = Eigen::Isometry3d::Identity();
  CameraIntrinsics camera_;
  Eigen::VectorXd home_[2];
  std::vector<CollisionShape> safe_volume_d_;
};

}  // namespace aerograsp
