#include "app/calibration/calibration_file.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

Eigen::Isometry3d ReadTransform(const ConfigNode& root, const std::string& path,
                                const std::string& key) {
  std::vector<double> m;
  try {
    m = YAML::LoadFile(path)[key].as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    root.Fail(key, "expected a list of 16 numbers (a 4x4 matrix, row by row)");
  }
  if (m.size() != 16)
    root.Fail(key,
              "expected 16 numbers (a 4x4 matrix, row by row), got " + std::to_string(m.size()));
  Eigen::Isometry3d aMb;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) aMb.matrix()(r, c) = m[4 * r + c];
  }
  if (!IsValidTransform(aMb, 1e-5) ||
      !aMb.matrix().row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1))) {
    root.Fail(key,
              "not a rigid transform (the rotation must be orthonormal with determinant +1, the "
              "last row 0 0 0 1)");
  }
  return aMb;
}

}  // namespace

std::vector<double> FlattenRowMajor(const Eigen::Isometry3d& aMb) {
  std::vector<double> v;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) v.push_back(aMb.matrix()(r, c));
  }
  return v;
}

namespace {

std::ostringstream Precise() {
  std::ostringstream s;
  s.precision(std::numeric_limits<double>::max_digits10);
  return s;
}

}  // namespace

std::string UrdfFixedJoint(const std::string& joint, const std::string& parent,
                           const std::string& child, const Eigen::Isometry3d& parentMchild) {
  const Eigen::Vector3d t = parentMchild.translation();
  const Eigen::Vector3d rpy = RpyFromRotation(parentMchild.linear());
  std::ostringstream s = Precise();
  s << "<joint name=\"" << joint << "\" type=\"fixed\">\n"
    << "  <parent link=\"" << parent << "\"/>\n"
    << "  <child link=\"" << child << "\"/>\n"
    << "  <origin xyz=\"" << t.x() << " " << t.y() << " " << t.z() << "\" rpy=\"" << rpy.x() << " "
    << rpy.y() << " " << rpy.z() << "\"/>\n"
    << "</joint>\n";
  return s.str();
}

std::string StaticTransformPublisherArgs(const std::string& parent, const std::string& child,
                                         const Eigen::Isometry3d& parentMchild) {
  const Eigen::Vector3d t = parentMchild.translation();
  const Eigen::Vector4d q = QuaternionWxyz(parentMchild);
  std::ostringstream s = Precise();
  s << "--x " << t.x() << " --y " << t.y() << " --z " << t.z() << " --qx " << q[1] << " --qy "
    << q[2] << " --qz " << q[3] << " --qw " << q[0] << " --frame-id " << parent
    << " --child-frame-id " << child;
  return s.str();
}

void WriteRosFrames(const std::string& folder, const std::string& stem, const std::string& parent,
                    const std::string& child, const Eigen::Isometry3d& parentMchild,
                    const std::string& comment) {
  const std::string urdf = (std::filesystem::path(folder) / (stem + ".urdf")).string();
  std::ofstream u(urdf);
  u << "<!-- " << comment << "\n     parent: " << parent << ", child: " << child
    << "; origin: the child frame in the parent frame (m, rad). -->\n"
    << UrdfFixedJoint(parent + "_to_" + child, parent, child, parentMchild);
  if (!u) throw std::runtime_error(urdf + ": cannot be written");
  const std::string sh = (std::filesystem::path(folder) / (stem + "_tf.sh")).string();
  std::ofstream t(sh);
  t << "#!/bin/sh\n# " << comment << "\n# " << child << " in " << parent
    << " (m; quaternion x y z w).\n"
    << "exec ros2 run tf2_ros static_transform_publisher "
    << StaticTransformPublisherArgs(parent, child, parentMchild) << "\n";
  if (!t) throw std::runtime_error(sh + ": cannot be written");
}

std::string ArmBaseFrame(Side side) { return std::string("arm_") + SideName(side) + "_mount"; }

ArmCalibration ArmCalibration::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys(
      {"arm", "method", "cMb", "dMb", "eMt", "residual_mm", "residual_deg", "samples"});
  ArmCalibration c;
  c.source = path;
  const std::string arm = root.GetString("arm");
  if (arm == "left") {
    c.side = Side::kLeft;
  } else if (arm == "right") {
    c.side = Side::kRight;
  } else {
    root.Fail("arm", "'" + arm + "' is not left or right");
  }
  c.method = root.GetString("method", "");
  c.cMb = ReadTransform(root, path, "cMb");
  if (root.Has("dMb")) c.dMb = ReadTransform(root, path, "dMb");
  if (root.Has("eMt")) c.eMt = ReadTransform(root, path, "eMt");
  c.residual_mm = root.GetDouble("residual_mm", 0.0);
  c.residual_deg = root.GetDouble("residual_deg", 0.0);
  c.samples = root.GetString("samples", c.samples);
  return c;
}

void ArmCalibration::Write(const std::string& path) const {
  YAML::Emitter y;
  y.SetDoublePrecision(12);
  y << YAML::BeginMap;
  y << YAML::Key << "arm" << YAML::Value << SideName(side);
  y << YAML::Key << "method" << YAML::Value << method;
  y << YAML::Key << "cMb" << YAML::Value << YAML::Flow << FlattenRowMajor(cMb);
  y << YAML::Key << "dMb" << YAML::Value << YAML::Flow << FlattenRowMajor(dMb);
  y << YAML::Key << "eMt" << YAML::Value << YAML::Flow << FlattenRowMajor(eMt);
  y << YAML::Key << "residual_mm" << YAML::Value << residual_mm;
  y << YAML::Key << "residual_deg" << YAML::Value << residual_deg;
  y << YAML::Key << "samples" << YAML::Value << samples;
  y << YAML::EndMap;
  std::ofstream file(path);
  file << "# aerograsp camera-to-arm calibration (cMb: arm base in the camera frame; dMb through "
          "the nominal "
          "dMc).\n"
       << y.c_str() << "\n";
  if (!file) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace aerograsp
