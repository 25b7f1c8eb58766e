#include "app/commands/robot_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <map>
#include <random>

#include "app/cli_checks.h"
#include "app/report/platform_plot.h"
#include "core/data_dir.h"
#include "core/platform.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kDeg = 180.0 / M_PI;

// Rounding noise (1e-17, -0.0) set to 0 so that it does not print as "-0.00".
Eigen::Vector3d WithoutNoise(const Eigen::Vector3d& v) {
  return v.unaryExpr([](double x) { return std::abs(x) < 1e-9 ? 0.0 : x; });
}

std::string FormatPose(const Eigen::Isometry3d& aMb) {
  const Eigen::Vector3d t = WithoutNoise(aMb.translation());
  const Eigen::Vector3d rpy = WithoutNoise(RpyFromRotation(aMb.linear()) * kDeg);
  return fmt::format("xyz [{:7.4f} {:7.4f} {:7.4f}] m  rpy [{:7.2f} {:7.2f} {:7.2f}] deg", t.x(),
                     t.y(), t.z(), rpy.x(), rpy.y(), rpy.z());
}

std::string FormatVector(const Eigen::Vector3d& v_raw, const char* unit) {
  const Eigen::Vector3d v = WithoutNoise(v_raw);
  return fmt::format("[{:7.4f} {:7.4f} {:7.4f}] {}", v.x(), v.y(), v.z(), unit);
}

std::string DescribeShape(const CollisionShape& s) {
  switch (s.type) {
    case CollisionShape::Type::kBox:
      return fmt::format("box {:.3f} x {:.3f} x {:.3f} m", s.size.x(), s.size.y(), s.size.z());
    case CollisionShape::Type::kCylinder:
      return fmt::format("cylinder r {:.3f} m, length {:.3f} m", s.size.x(), s.size.y());
    case CollisionShape::Type::kSphere:
      return fmt::format("sphere r {:.3f} m", s.size.x());
    case CollisionShape::Type::kMesh:
      return "mesh " + s.mesh_path;
  }
  return "?";
}

void PrintTree(const StaticFrameTree& tree, const std::map<std::string, std::string>& frame_of,
               const Eigen::Isometry3d& dMroot, std::ostream& out) {
  // Depth-first order; indent by depth.
  std::map<std::string, int> depth;
  for (const StaticFrameTree::Link& link : tree.links()) {
    depth[link.name] = link.parent.empty() ? 0 : depth[link.parent] + 1;
    const auto frame = frame_of.find(link.name);
    const std::string label =
        std::string(2 * depth[link.name], ' ') + link.name +
        (frame != frame_of.end() ? " (" + frame->second + ")" : std::string());
    fmt::print(out, "  {:<30} {}\n", label, FormatPose(dMroot * link.rootMlink));
  }
}

void PrintArm(const Platform& platform, Side side, const RobotCommandOptions& options,
              std::ostream& out) {
  const ArmModel& arm = platform.arm(side);
  const char* base_frame = side == Side::kLeft ? "bl" : "br";
  const char* tool_frame = side == Side::kLeft ? "el" : "er";
  fmt::print(out, "\n{} arm: '{}' from {}\n", side == Side::kLeft ? "Left" : "Right", arm.name(),
             arm.source());
  fmt::print(out, "  chain {} ({}) -> {} ({}), {} moving joints\n", arm.base_link(), base_frame,
             arm.tip_link(), tool_frame, arm.dof());
  fmt::print(out, "  dM{}: {}\n", base_frame, FormatPose(platform.dMb(side)));

  std::vector<Eigen::Isometry3d> bMs;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(arm.dof());
  arm.SegmentPoses(zero, &bMs);
  const Eigen::Matrix<double, 6, Eigen::Dynamic> J0 = arm.Jacobian(zero);
  fmt::print(out, "  {:<5} {:<10} {:<27} {:<27} {:>9} {:>9} {:>11}\n", "joint", "type",
             "origin in base at q=0 (m)", "axis in base at q=0", "min deg", "max deg", "max deg/s");
  for (int i = 0; i < arm.dof(); ++i) {
    const bool revolute = arm.joint_type(i) == ArmModel::JointType::kRevolute;
    const double scale = revolute ? kDeg : 1.0;
    const Eigen::Vector3d axis = revolute ? J0.block<3, 1>(3, i) : J0.block<3, 1>(0, i);
    fmt::print(out, "  {:<5} {:<10} {:<27} {:<27} {:9.1f} {:9.1f} {:11.0f}\n", arm.joint_names()[i],
               revolute ? "revolute" : "prismatic", FormatVector(bMs[i + 1].translation(), ""),
               FormatVector(axis, ""), arm.lower_limits()[i] * scale, arm.upper_limits()[i] * scale,
               arm.velocity_limits()[i] * scale);
  }

  // Workspace by sampling the joint limits (fixed seed: the same figures every run).
  std::mt19937 rng(options.seed);
  const Eigen::Vector3d shoulder = arm.ShoulderPosition();
  double max_reach = 0.0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  Eigen::VectorXd q(arm.dof());
  for (int s = 0; s < options.reach_samples; ++s) {
    for (int i = 0; i < arm.dof(); ++i) {
      q[i] =
          std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(rng);
    }
    const Eigen::Vector3d p_b = arm.ForwardKinematics(q).translation();
    max_reach = std::max(max_reach, (p_b - shoulder).norm());
    const Eigen::Vector3d p_d = platform.dMb(side) * p_b;
    lo = lo.cwiseMin(p_d);
    hi = hi.cwiseMax(p_d);
  }
  fmt::print(out, "  shoulder at {} in base; stretched reach {:.3f} m\n",
             FormatVector(shoulder, "m"), arm.StretchedReach());
  fmt::print(
      out,
      "  sampled workspace ({} configurations, seed {}): reach {:.3f} m from the "
      "shoulder; tool in d within x [{:.3f}, {:.3f}] y [{:.3f}, {:.3f}] z [{:.3f}, {:.3f}] m\n",
      options.reach_samples, options.seed, max_reach, lo.x(), hi.x(), lo.y(), hi.y(), lo.z(),
      hi.z());

  const Eigen::VectorXd& home = platform.home(side);
  std::string home_deg;
  for (int i = 0; i < home.size(); ++i)
    home_deg += fmt::format("{}{:.1f}", i ? ", " : "", home[i] * kDeg);
  fmt::print(out, "  home [{}] deg: d M {} {}\n", home_deg, tool_frame,
             FormatPose(platform.dMb(side) * arm.ForwardKinematics(home)));

  double mass = 0.0;
  std::size_t shapes = 0;
  for (const ArmSegment& seg : arm.segments()) {
    mass += seg.mass_kg;
    shapes += seg.collision.size();
  }
  fmt::print(out, "  mass {:.3f} kg (estimate), {} collision shapes on {} segments\n", mass, shapes,
             arm.segments().size());
}

}  // namespace

void RunRobotCommand(const RobotCommandOptions& options, std::ostream& out) {
  const Platform platform = Platform::Load(options.config_path);
  const PlatformConfig& c = platform.config();
  fmt::print(out, "Platform {} ({} arms)\n", c.source, c.arm_type);

  fmt::print(out, "\nVehicle frame tree from {} (poses in d = '{}', FRD):\n", c.vehicle_urdf,
             c.body_link);
  const std::map<std::string, std::string> frame_of = {{c.body_link, "d"},
                                                       {c.camera_link, "c"},
                                                       {c.left.mount_link, "bl"},
                                                       {c.right.mount_link, "br"}};
  const Eigen::Isometry3d dMroot = platform.vehicle().Get(c.body_link).rootMlink.inverse();
  PrintTree(platform.vehicle(), frame_of, dMroot, out);

  const CameraIntrinsics& K = platform.camera();
  const Eigen::Vector3d view_d = platform.dMc().linear().col(2);
  fmt::print(out,
             "\nCamera '{}' from {}: {}x{} px, fx {:.1f} fy {:.1f} cx {:.1f} cy {:.1f} px, "
             "FOV {:.1f} x {:.1f} deg; looks along {} in d ({:.1f} deg below the x axis)\n",
             c.camera_name, c.camera_xml, K.width, K.height, K.fx, K.fy, K.cx, K.cy,
             K.HorizontalFovDeg(), K.VerticalFovDeg(), FormatVector(view_d, ""),
             std::asin(std::clamp(view_d.z(), -1.0, 1.0)) * kDeg);

  fmt::print(out, "\nSafe volume ('{}', never entered by the arms):\n", c.safe_volume_link);
  for (const CollisionShape& s : platform.safe_volume_d()) {
    fmt::print(out, "  {} at {}\n", DescribeShape(s), FormatPose(s.segMs));
  }
  fmt::print(out,
             "\nGripper: max aperture {:.3f} m, clearance {:.3f} m per side, pads {:.3f} x {:.3f} "
             "m, closes in {:.2f} s\n",
             c.gripper.max_aperture_m, c.gripper.finger_clearance_m, c.gripper.finger_width_m,
             c.gripper.finger_length_m, c.gripper.close_time_s);

  PrintArm(platform, Side::kLeft, options, out);
  PrintArm(platform, Side::kRight, options, out);

  if (!options.plot_path.empty()) {
    WritePlatformPlot(platform, platform.home(Side::kLeft), platform.home(Side::kRight),
                      options.plot_path);
    fmt::print(out, "\nWrote {} (arms at home)\n", options.plot_path);
  }
}

void AddRobotOptions(CLI::App* cmd, RobotCommandOptions* o) {
  o->config_path = DataPath("config/platform_4dof.yaml");
  cmd->add_option("config", o->config_path, "Platform YAML")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  cmd->add_option("--samples", o->reach_samples,
                  "Random configurations sampled for the workspace figures")
      ->capture_default_str()
      ->check(cli::Range(1, 10000000));
  cmd->add_option("--seed", o->seed, "Seed of the workspace samples")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--plot", o->plot_path,
                  "Write a PNG of the platform (side and front views, arms at home)");
}

}  // namespace aerograsp
