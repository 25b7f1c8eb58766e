#include "core/arm_model.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fstream>
#include <mutex>
#include <sstream>

namespace aerograsp {
namespace {

// urdfdom reports why a file is rejected only through console_bridge; collect
// those messages so the exception can say what was wrong.
class CollectingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

urdf::ModelInterfaceSharedPtr ParseUrdf(const std::string& xml, const std::string& source) {
  static std::mutex mutex;  // console_bridge's handler is process-wide
  std::lock_guard<std::mutex> lock(mutex);
  CollectingHandler handler;
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  std::string error;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    error = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    const std::string why = !error.empty() ? error : handler.messages;
    throw UrdfError(source + ": not a valid URDF" + (why.empty() ? "" : ": " + why));
  }
  return model;
}

std::string ReadUrdfFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UrdfError(path + ": cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

Eigen::Isometry3d ToIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  M.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return M;
}

std::string ListLinks(const urdf::ModelInterface& model) {
  std::string list;
  for (const auto& kv : model.links_) list += (list.empty() ? "" : ", ") + kv.first;
  return list;
}

std::string FormatLimit(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// Appends the link's collision shapes to `shapes`, with segMl the link in their frame.
void AppendCollision(const urdf::Link& link, const Eigen::Isometry3d& segMl,
                     std::vector<CollisionShape>* shapes) {
  for (const urdf::CollisionSharedPtr& c : link.collision_array) {
    if (!c || !c->geometry) continue;
    CollisionShape shape;
    shape.segMs = segMl * ToIsometry(c->origin);
    switch (c->geometry->type) {
      case urdf::Geometry::BOX: {
        const auto& b = static_cast<const urdf::Box&>(*c->geometry);
        shape.type = CollisionShape::Type::kBox;
        shape.size = {b.dim.x, b.dim.y, b.dim.z};
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& cy = static_cast<const urdf::Cylinder&>(*c->geometry);
        shape.type = CollisionShape::Type::kCylinder;
        shape.size = {cy.radius, cy.length, 0.0};
        break;
      }
      case urdf::Geometry::SPHERE: {
        const auto& s = static_cast<const urdf::Sphere&>(*c->geometry);
        shape.type = CollisionShape::Type::kSphere;
        shape.size = {s.radius, 0.0, 0.0};
        break;
      }
      case urdf::Geometry::MESH: {
        const auto& m = static_cast<const urdf::Mesh&>(*c->geometry);
        shape.type = CollisionShape::Type::kMesh;
        shape.size = {m.scale.x, m.scale.y, m.scale.z};
        shape.mesh_path = m.filename;
        break;
      }
    }
    shapes->push_back(shape);
  }
}

// Adds the link's collision shapes and mass to `segment`, with segMl the link in the segment.
void AddLink(const urdf::Link& link, const Eigen::Isometry3d& segMl, ArmSegment* segment) {
  segment->link_names.push_back(link.name);
  if (link.inertial) segment->mass_kg += link.inertial->mass;
  AppendCollision(link, segMl, &segment->collision);
}

void AddStaticSubtree(const urdf::Link& link, const std::string& source,
                      const Eigen::Isometry3d& rootMlink, std::vector<StaticFrameTree::Link>* out) {
  StaticFrameTree::Link entry;
  entry.name = link.name;
  entry.parent = link.parent_joint ? link.parent_joint->parent_link_name : "";
  entry.rootMlink = rootMlink;
  AppendCollision(link, Eigen::Isometry3d::Identity(), &entry.collision);
  out->push_back(entry);
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const urdf::JointSharedPtr& j = child->parent_joint;
    if (j->type != urdf::Joint::FIXED) {
      throw UrdfError(source + ": joint '" + j->name +
                      "' is not fixed: the vehicle's frame tree must be static");
    }
    AddStaticSubtree(*child, source, rootMlink * ToIsometry(j->parent_to_joint_origin_transform),
                     out);
  }
}

// Adds `link` and every link hanging below it through fixed joints only.
void AddFixedSubtree(const urdf::Link& link, const Eigen::Isometry3d& segMl, ArmSegment* segment) {
  AddLink(link, segMl, segment);
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const urdf::JointSharedPtr& j = child->parent_joint;
    if (!j || j->type != urdf::Joint::FIXED) continue;
    AddFixedSubtree(*child, segMl * ToIsometry(j->parent_to_joint_origin_transform), segment);
  }
}

}  // namespace

ArmModel ArmModel::FromUrdfFile(const std::string& path, const std::string& base_link,
                                const std::string& tip_link) {
  return FromUrdfString(ReadUrdfFile(path), path, base_link, tip_link);
}

ArmModel ArmModel::FromUrdfString(const std::string& urdf_xml, const std::string& source,
                                  const std::string& base_link, const std::string& tip_link) {
  const urdf::ModelInterfaceSharedPtr model = ParseUrdf(urdf_xml, source);
  const urdf::LinkConstSharedPtr base = model->getLink(base_link);
  if (!base) {
    throw UrdfError(source + ": no link named '" + base_link + "' (links: " + ListLinks(*model) +
                    ")");
  }
  const urdf::LinkConstSharedPtr tip = model->getLink(tip_link);
  if (!tip) {
    throw UrdfError(source + ": no link named '" + tip_link + "' (links: " + ListLinks(*model) +
                    ")");
  }

  // Walk from the tip up to the base; the joints come out tip first.
  std::vector<urdf::JointConstSharedPtr> path;
  for (urdf::LinkConstSharedPtr link = tip; link != base;) {
    const urdf::JointConstSharedPtr j = link->parent_joint;
    if (!j) {
      throw UrdfError(source + ": link '" + tip_link + "' is not below link '" + base_link +
                      "': no serial chain joins them");
    }
    path.push_back(j);
    link = model->getLink(j->parent_link_name);
  }
  std::reverse(path.begin(), path.end());

  ArmModel arm;
  arm.name_ = model->getName();
  arm.source_ = source;
  arm.base_link_ = base_link;
  arm.tip_link_ = tip_link;

  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();  // fixed offsets since the last joint
  std::vector<double> lower, upper, velocity;
  for (const urdf::JointConstSharedPtr& j : path) {
    const Eigen::Isometry3d parentMjoint = ToIsometry(j->parent_to_joint_origin_transform);
    const std::string where = source + ": joint '" + j->name + "'";
    switch (j->type) {
      case urdf::Joint::FIXED:
        pending = pending * parentMjoint;
        continue;
      case urdf::Joint::FLOATING:
      case urdf::Joint::PLANAR:
      case urdf::Joint::UNKNOWN:
        throw UrdfError(where +
                        " is floating or planar: a serial arm needs revolute, "
                        "continuous, prismatic or fixed joints between '" +
                        base_link + "' and '" + tip_link + "'");
      default:
        break;
    }
    Joint joint;
    joint.type = j->type == urdf::Joint::PRISMATIC ? JointType::kPrismatic : JointType::kRevolute;
    joint.parentMjoint = pending * parentMjoint;
    pending.setIdentity();
    const Eigen::Vector3d axis(j->axis.x, j->axis.y, j->axis.z);
    if (!(axis.norm() > 1e-9)) throw UrdfError(where + " has a zero axis");
    joint.axis = axis.normalized();

    double lo = -INFINITY, hi = INFINITY, vel = INFINITY;
    if (j->type != urdf::Joint::CONTINUOUS) {
      if (!j->limits) throw UrdfError(where + " has no <limit>");
      lo = j->limits->lower;
      hi = j->limits->upper;
      if (!(lo < hi)) {
        throw UrdfError(where + " has lower limit " + FormatLimit(lo) + " >= upper limit " +
                        FormatLimit(hi));
      }
    }
    if (j->limits) {
      vel = j->limits->velocity;
      if (!(vel > 0.0)) {
        throw UrdfError(where + " has velocity limit " + FormatLimit(vel) + ": must be positive");
      }
    }
    arm.joints_.push_back(joint);
    arm.joint_names_.push_back(j->name);
    lower.push_back(lo);
    upper.push_back(hi);
    velocity.push_back(vel);
  }
  if (arm.joints_.empty()) {
    throw UrdfError(source + ": no moving joint between '" + base_link + "' and '" + tip_link +
                    "'");
  }
  arm.lastMtip_ = pending;
  arm.lower_ = Eigen::Map<Eigen::VectorXd>(lower.data(), lower.size());
  arm.upper_ = Eigen::Map<Eigen::VectorXd>(upper.data(), upper.size());
  arm.velocity_ = Eigen::Map<Eigen::VectorXd>(velocity.data(), velocity.size());

  // Segments: the base and the child link of each moving joint, with what hangs
  // below them through fixed joints.
  arm.segments_.resize(arm.joints_.size() + 1);
  AddFixedSubtree(*base, Eigen::Isometry3d::Identity(), &arm.segments_[0]);
  std::size_t segment = 0;
  for (const urdf::JointConstSharedPtr& j : path) {
    if (j->type == urdf::Joint::FIXED) continue;
    ++segment;
    AddFixedSubtree(*model->getLink(j->child_link_name), Eigen::Isometry3d::Identity(),
                    &arm.segments_[segment]);
  }
  return arm;
}

void ArmModel::MoveJoint(const Joint& joint, double q, Eigen::Isometry3d* bMj) {
  if (joint.type == JointType::kRevolute) {
    bMj->rotate(Eigen::AngleAxisd(q, joint.axis));
  } else {
    bMj->translate(joint.axis * q);
  }
}

bool ArmModel::WithinLimits(const Eigen::VectorXd& q, double tolerance) const {
  if (q.size() != dof() || !q.allFinite()) return false;
  return ((q.array() >= lower_.array() - tolerance) && (q.array() <= upper_.array() + tolerance))
      .all();
}

Eigen::VectorXd ArmModel::Clamp(const Eigen::VectorXd& q) const {
  return q.cwiseMax(lower_).cwiseMin(upper_);
}

void ArmModel::SegmentPoses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* bMs) const {
  assert(q.size() == dof());
  bMs->resize(joints_.size() + 2);
  Eigen::Isometry3d bMj = Eigen::Isometry3d::Identity();
  (*bMs)[0] = bMj;
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    bMj = bMj * joints_[i].parentMjoint;
    MoveJoint(joints_[i], q[i], &bMj);
    (*bMs)[i + 1] = bMj;
  }
  (*bMs)[joints_.size() + 1] = bMj * lastMtip_;
}

Eigen::Isometry3d ArmModel::ForwardKinematics(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d bMe;
  Kinematics(q, &bMe, nullptr);
  return bMe;
}

void ArmModel::Kinematics(const Eigen::VectorXd& q, Eigen::Isometry3d* bMe,
                          Eigen::Matrix<double, 6, Eigen::Dynamic>* J_b) const {
  assert(q.size() == dof());
  const int n = dof();
  // Joint axes and origins in the base frame, then the tip.
  Eigen::Matrix<double, 3, Eigen::Dynamic> axes(3, n), origins(3, n);
  Eigen::Isometry3d bMj = Eigen::Isometry3d::Identity();
  for (int i = 0; i < n; ++i) {
    const Joint& joint = joints_[i];
    bMj = bMj * joint.parentMjoint;
    axes.col(i) = bMj.linear() * joint.axis;
    origins.col(i) = bMj.translation();
    MoveJoint(joint, q[i], &bMj);
  }
  *bMe = bMj * lastMtip_;
  if (!J_b) return;
  J_b->resize(6, n);
  const Eigen::Vector3d p_e = bMe->translation();
  for (int i = 0; i < n; ++i) {
    if (joints_[i].type == JointType::kRevolute) {
      J_b->block<3, 1>(0, i) = axes.col(i).cross(p_e - origins.col(i));
      J_b->block<3, 1>(3, i) = axes.col(i);
    } else {
      J_b->block<3, 1>(0, i) = axes.col(i);
      J_b->block<3, 1>(3, i).setZero();
    }
  }
}

Eigen::Matrix<double, 6, Eigen::Dynamic> ArmModel::Jacobian(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d bMe;
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, dof());
  Kinematics(q, &bMe, &J);
  return J;
}

double ArmModel::StretchedReach() const {
  std::vector<Eigen::Isometry3d> bMs;
  SegmentPoses(Eigen::VectorXd::Zero(dof()), &bMs);
  const Eigen::Vector3d shoulder = ShoulderPosition();
  double reach = 0.0;
  Eigen::Vector3d previous = shoulder;
  bool started = false;
  for (std::size_t i = 1; i < bMs.size(); ++i) {
    const Eigen::Vector3d p = bMs[i].translation();
    if (!started) {
      started = (p - shoulder).norm() < 1e-12;
      if (!started) continue;
    }
    reach += (p - previous).norm();
    previous = p;
  }
  return reach;
}

Eigen::Vector3d ArmModel::ShoulderPosition() const {
  // The first joint whose axis is not along the line from the base origin to it
  // (a base yaw's position along its own axis does not matter for reach).
  std::vector<Eigen::Isometry3d> bMs;
  SegmentPoses(Eigen::VectorXd::Zero(dof()), &bMs);
  for (int i = 0; i < dof(); ++i) {
    const Eigen::Isometry3d& bMj = bMs[i + 1];
    const Eigen::Vector3d axis = bMj.linear() * joints_[i].axis;
    const Eigen::Vector3d p = bMj.translation();
    if (p.norm() < 1e-12 || axis.cross(p.normalized()).norm() > 1e-6) return p;
  }
  return bMs.back().translation();
}

StaticFrameTree StaticFrameTree::FromUrdfFile(const std::string& path) {
  return FromUrdfString(ReadUrdfFile(path), path);
}

StaticFrameTree StaticFrameTree::FromUrdfString(const std::string& urdf_xml,
                                                const std::string& source) {
  const urdf::ModelInterfaceSharedPtr model = ParseUrdf(urdf_xml, source);
  StaticFrameTree tree;
  tree.source_ = source;
  AddStaticSubtree(*model->getRoot(), source, Eigen::Isometry3d::Identity(), &tree.links_);
  return tree;
}

const StaticFrameTree::Link* StaticFrameTree::Find(const std::string& name) const {
  for (const Link& link : links_) {
    if (link.name == name) return &link;
  }
  return nullptr;
}

const StaticFrameTree::Link& StaticFrameTree::Get(const std::string& name) const {
  if (const Link* link = Find(name)) return *link;
  std::string list;
  for (const Link& link : links_) list += (list.empty() ? "" : ", ") + link.name;
  throw UrdfError(source_ + ": no link named '" + name + "' (links: " + list + ")");
}

}  // namespace aerograsp
