// Serial arm model read from a URDF with urdfdom: the chain from a named base
// link to a named tip link, forward kinematics, the geometric Jacobian and the
// joint limits. The model is immutable once built (description, not state):
// per-cycle state (joint positions) is passed in.
#pragma once

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>
#include <vector>

namespace aerograsp {

/// A URDF that cannot be used as asked; the message starts with its path.
class UrdfError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Simple collision geometry of a link, as URDF describes it.
struct CollisionShape {
  enum class Type { kBox, kCylinder, kSphere, kMesh };
  Type type = Type::kBox;
  /// Box: full extents x, y, z (m). Cylinder: radius, length (along z), 0.
  /// Sphere: radius, 0, 0. Mesh: scale factors.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  std::string mesh_path;  ///< for kMesh, as written in the URDF
  /// The shape's frame s in the frame of the segment that carries it.
  Eigen::Isometry3d segMs = Eigen::Isometry3d::Identity();
};

/// A rigid part of the chain: segment 0 is fixed to the base; segment i >= 1
/// moves with joint i-1 (its frame is that joint's frame). Links attached by
/// fixed joints (the gripper, the fingers) are merged into their segment.
struct ArmSegment {
  std::vector<std::string> link_names;
  std::vector<CollisionShape> collision;
  double mass_kg = 0.0;
};

class ArmModel {
 public:
  enum class JointType { kRevolute, kPrismatic };

  /// Reads `path` and builds the chain from `base_link` to `tip_link`.
  /// @throws UrdfError naming the file when it cannot be read or parsed, a link
  /// is missing (the message lists the links there are), tip is not below base,
  /// a joint on the chain is floating or planar, a revolute or prismatic joint
  /// has lower > upper, a zero range, a non-positive velocity limit or a zero axis,
  /// or the chain has no moving joint.
  static ArmModel FromUrdfFile(const std::string& path, const std::string& base_link,
                               const std::string& tip_link);
  /// As FromUrdfFile, from XML text; `source` names it in messages.
  static ArmModel FromUrdfString(const std::string& urdf_xml, const std::string& source,
                                 const std::string& base_link, const std::string& tip_link);

  const std::string& name() const { return name_; }
  const std::string& source() const { return source_; }
  const std::string& base_link() const { return base_link_; }
  const std::string& tip_link() const { return tip_link_; }
  int dof() const { return static_cast<int>(joints_.size()); }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  JointType joint_type(int i) const { return joints_[i].type; }
  /// Position limits (rad or m) and speed limits (rad/s or m/s), size dof().
  const Eigen::VectorXd& lower_limits() const { return lower_; }
  const Eigen::VectorXd& upper_limits() const { return upper_; }
  const Eigen::VectorXd& velocity_limits() const { return velocity_; }
  /// Joint i's frame at q_i = 0, expressed in joint i-1's frame (moved by
  /// q_{i-1}; the base frame for i = 0), and joint i's unit axis in its own
  /// frame: the chain as another kinematics library (KDL) needs it.
  const Eigen::Isometry3d& joint_origin(int i) const { return joints_[i].parentMjoint; }
  const Eigen::Vector3d& joint_axis(int i) const { return joints_[i].axis; }
  /// The tip link in the last joint's frame.
  const Eigen::Isometry3d& tip_offset() const { return lastMtip_; }
  /// Segments 0..dof() (see ArmSegment).
  const std::vector<ArmSegment>& segments() const { return segments_; }

  /// True when every q_i is within [lower_i - tol, upper_i + tol] and finite.
  bool WithinLimits(const Eigen::VectorXd& q, double tolerance = 0.0) const;
  /// q clamped into the limits.
  Eigen::VectorXd Clamp(const Eigen::VectorXd& q) const;

  /// bMe: the tip link in the base link, for joint positions q (size dof()).
  Eigen::Isometry3d ForwardKinematics(const Eigen::VectorXd& q) const;

  /// bMs for every segment frame (size dof() + 1), then bMe last (size dof() + 2).
  void SegmentPoses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* bMs) const;

  /// The 6 x dof geometric Jacobian of the tip, expressed in the base frame,
  /// rows (v_x, v_y, v_z, w_x, w_y, w_z): the tip origin's linear velocity and
  /// the tip's angular velocity for joint velocities dq.
  Eigen::Matrix<double, 6, Eigen::Dynamic> Jacobian(const Eigen::VectorXd& q) const;
  /// ForwardKinematics and Jacobian in one pass (the servo loop's hot path).
  void Kinematics(const Eigen::VectorXd& q, Eigen::Isometry3d* bMe,
                  Eigen::Matrix<double, 6, Eigen::Dynamic>* J_b) const;

  /// Sum of the distances between consecutive joint origins from the first
  /// moving joint to the tip: the stretched reach (m).
  double StretchedReach() const;
  /// Origin of the first joint whose axis is not collinear with the line
  /// through the base (the shoulder pitch for these arms), in the base frame.
  Eigen::Vector3d ShoulderPosition() const;

 private:
  struct Joint {
    JointType type = JointType::kRevolute;
    Eigen::Isometry3d parentMjoint = Eigen::Isometry3d::Identity();  // at q = 0
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();                 // in the joint frame
  };
  /// Applies the joint's motion q to the joint's zero-position frame bMj.
  static void MoveJoint(const Joint& joint, double q, Eigen::Isometry3d* bMj);

  std::string name_, source_, base_link_, tip_link_;
  std::vector<Joint> joints_;
  std::vector<std::string> joint_names_;
  Eigen::Isometry3d lastMtip_ = Eigen::Isometry3d::Identity();
  Eigen::VectorXd lower_, upper_, velocity_;
  std::vector<ArmSegment> segments_;
};

}  // namespace aerograsp

namespace aerograsp {

/// A URDF whose joints are all fixed (the vehicle body with its mounts): every
/// link's pose in the root link.
class StaticFrameTree {
 public:
  struct Link {
    std::string name;
    std::string parent;  ///< "" for the root
    Eigen::Isometry3d rootMlink = Eigen::Isometry3d::Identity();
    std::vector<CollisionShape> collision;  ///< shapes in the link frame (segMs = linkMs)
  };

  /// @throws UrdfError naming the file when it cannot be read or parsed, or has a
  /// joint that is not fixed.
  static StaticFrameTree FromUrdfFile(const std::string& path);
  static StaticFrameTree FromUrdfString(const std::string& urdf_xml, const std::string& source);

  const std::string& source() const { return source_; }
  const std::string& root() const { return links_.front().name; }
  /// Links in depth-first order from the root.
  const std::vector<Link>& links() const { return links_; }
  /// nullptr when there is no such link.
  const Link* Find(const std::string& name) const;
  /// @throws UrdfError naming the file and listing the links when it is missing.
  const Link& Get(const std::string& name) const;

 private:
  std::string source_;
  std::vector<Link> links_;
};

}  // namespace aerograsp
