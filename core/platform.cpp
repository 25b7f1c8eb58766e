#include "core/platform.h"

#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

ArmMountConfig ReadArm(const ConfigNode& node) {
  node.RequireOnlyKeys({"urdf", "mount_link", "base_link", "tip_link", "home_rad"});
  ArmMountConfig arm;
  arm.urdf = node.GetPath("urdf");
  arm.mount_link = node.GetString("mount_link");
  arm.base_link = node.GetString("base_link", arm.base_link);
  arm.tip_link = node.GetString("tip_link", arm.tip_link);
  arm.home_rad = node.GetDoubles("home_rad");
  return arm;
}

}  // namespace

const char* SideName(Side side) { return kArmNames[static_cast<int>(side)]; }

PlatformConfig PlatformConfig::Load(const std::string& path) {
  const ConfigNode root = ConfigNode::LoadFile(path);
  root.RequireOnlyKeys({"arm_type", "vehicle", "camera", "arms", "gripper"});
  PlatformConfig c;
  c.source = path;
  c.arm_type = root.GetString("arm_type", c.arm_type);

  const ConfigNode vehicle = root.Child("vehicle");
  vehicle.RequireOnlyKeys({"urdf", "body_link", "camera_link", "safe_volume_link", "mass_kg"});
  c.vehicle_urdf = vehicle.GetPath("urdf");
  c.body_link = vehicle.GetString("body_link", c.body_link);
  c.camera_link = vehicle.GetString("camera_link", c.camera_link);
  c.safe_volume_link = vehicle.GetString("safe_volume_link", c.safe_volume_link);
  c.vehicle_mass_kg = vehicle.GetDouble("mass_kg", c.vehicle_mass_kg);

  const ConfigNode camera = root.Child("camera");
  camera.RequireOnlyKeys({"xml", "name"});
  c.camera_xml = camera.GetPath("xml");
  c.camera_name = camera.GetString("name", c.camera_name);

  const ConfigNode arms = root.Child("arms");
  arms.RequireOnlyKeys({"left", "right"});
  c.left = ReadArm(arms.Child("left"));
  c.right = ReadArm(arms.Child("right"));

  if (root.Has("gripper")) {
    const ConfigNode g = root.Child("gripper");
    g.RequireOnlyKeys({"max_aperture_m", "finger_clearance_m", "finger_width_m", "finger_length_m",
                       "close_time_s"});
    c.gripper.max_aperture_m = g.GetDouble("max_aperture_m", c.gripper.max_aperture_m);
    c.gripper.finger_clearance_m = g.GetDouble("finger_clearance_m", c.gripper.finger_clearance_m);
    c.gripper.finger_width_m = g.GetDouble("finger_width_m", c.gripper.finger_width_m);
    c.gripper.finger_length_m = g.GetDouble("finger_length_m", c.gripper.finger_length_m);
    c.gripper.close_time_s = g.GetDouble("close_time_s", c.gripper.close_time_s);
  }
  c.Validate(c.source, "");
  return c;
}

void PlatformConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckOneOf(source, prefix + "arm_type", arm_type, {"4dof", "6dof"});
  CheckFileExists(source, prefix + "vehicle.urdf", vehicle_urdf);
  CheckRange(source, prefix + "vehicle.mass_kg", vehicle_mass_kg, 1e-3, 50.0, "kg");
  CheckFileExists(source, prefix + "camera.xml", camera_xml);
  CheckFileExists(source, prefix + "arms.left.urdf", left.urdf);
  CheckFileExists(source, prefix + "arms.right.urdf", right.urdf);
  CheckRange(source, prefix + "gripper.max_aperture_m", gripper.max_aperture_m, 1e-3, 0.3, "m");
  CheckRange(source, prefix + "gripper.finger_clearance_m", gripper.finger_clearance_m, 0.0, 0.05,
             "m");
  CheckRange(source, prefix + "gripper.finger_width_m", gripper.finger_width_m, 1e-3, 0.1, "m");
  CheckRange(source, prefix + "gripper.finger_length_m", gripper.finger_length_m, 1e-3,
             kLongestFingerM, "m");
  CheckRange(source, prefix + "gripper.close_time_s", gripper.close_time_s, 1e-3, 10.0, "s");
  if (2.0 * gripper.finger_clearance_m >= gripper.max_aperture_m) {
    throw ConfigError(source + ": " + prefix + "gripper.finger_clearance_m: twice the clearance (" +
                      std::to_string(2.0 * gripper.finger_clearance_m) +
                      " m) leaves no room within max_aperture_m");
  }
}

Platform Platform::Load(const std::string& config_path) {
  return FromConfig(PlatformConfig::Load(config_path));
}

namespace {

// Runs `load`, prefixing any error with the config file and the key that led to it.
template <typename Load>
auto ForKey(const PlatformConfig& config, const std::string& key, Load load) -> decltype(load()) {
  try {
    return load();
  } catch (const std::exception& e) {
    throw ConfigError(config.source + ": " + key + ": " + e.what());
  }
}

}  // namespace

Platform Platform::WithArmBase(Side side, const Eigen::Isometry3d& dMb) const {
  if (!IsValidTransform(dMb, 1e-5)) {
    throw std::invalid_argument(std::string("the ") + SideName(side) +
                                " arm's base dMb is not a rigid transform");
  }
  Platform copy = *this;
  copy.dMb_[static_cast<int>(side)] = dMb;
  return copy;
}

Platform Platform::FromConfig(const PlatformConfig& config) {
  config.Validate(config.source, "");
  Platform p;
  p.config_ = config;
  p.vehicle_ = ForKey(config, "vehicle.urdf",
                      [&] { return StaticFrameTree::FromUrdfFile(config.vehicle_urdf); });
  const auto link = [&](const std::string& key, const std::string& name) -> const auto& {
    return ForKey(config, key,
                  [&]() -> const StaticFrameTree::Link& { return p.vehicle_.Get(name); });
  };
  const Eigen::Isometry3d dMroot = link("vehicle.body_link", config.body_link).rootMlink.inverse();
  p.dMc_ = dMroot * link("vehicle.camera_link", config.camera_link).rootMlink;
  const StaticFrameTree::Link& safe = link("vehicle.safe_volume_link", config.safe_volume_link);
  if (safe.collision.empty()) {
    throw ConfigError(config.source + ": vehicle.safe_volume_link: link '" + safe.name + "' in " +
                      config.vehicle_urdf + " has no collision geometry");
  }
  for (CollisionShape shape : safe.collision) {
    shape.segMs = dMroot * safe.rootMlink * shape.segMs;
    p.safe_volume_d_.push_back(shape);
  }
  p.camera_ = ForKey(config, "camera.xml",
                     [&] { return LoadCameraXml(config.camera_xml, config.camera_name); });

  const std::size_t expected_dof = config.arm_type == "4dof" ? 4 : 6;
  for (Side side : kSides) {
    const int i = static_cast<int>(side);
    const ArmMountConfig& mount = side == Side::kLeft ? config.left : config.right;
    const std::string key = std::string("arms.") + SideName(side);
    p.arms_[i] = ForKey(config, key + ".urdf", [&] {
      return ArmModel::FromUrdfFile(mount.urdf, mount.base_link, mount.tip_link);
    });
    const ArmModel& arm = p.arms_[i];
    if (static_cast<std::size_t>(arm.dof()) != expected_dof) {
      throw ConfigError(config.source + ": " + key + ".urdf: " + mount.urdf + " has " +
                        std::to_string(arm.dof()) + " moving joints but arm_type is " +
                        config.arm_type);
    }
    p.dMb_[i] = dMroot * link(key + ".mount_link", mount.mount_link).rootMlink;
    if (mount.home_rad.size() != expected_dof) {
      throw ConfigError(config.source + ": " + key + ".home_rad: expected " +
                        std::to_string(expected_dof) + " values, got " +
                        std::to_string(mount.home_rad.size()));
    }
    p.home_[i] = Eigen::Map<const Eigen::VectorXd>(mount.home_rad.data(), expected_dof);
    for (std::size_t j = 0; j < expected_dof; ++j) {
      CheckRange(config.source, key + ".home_rad[" + std::to_string(j) + "]", mount.home_rad[j],
                 arm.lower_limits()[j], arm.upper_limits()[j], "rad");
    }
  }
  return p;
}

}  // namespace aerograsp
