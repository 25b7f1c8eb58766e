// Publishes a fixed script of telemetry through aerograsp's ROS 2 bridge
// (ros2/ros2_bridge.h) and writes what each topic should carry, in ROS 2's
// field layout, for crosscheck.js to compare with what the independent peer
// (ros2_peer, Fast DDS) received and Foxglove's decoder reads from the bytes.
//   ros2_publish_tool DOMAIN NS DDS_CONFIG EXPECTED.json READY_FILE
// It starts publishing once every topic has a subscriber and the peer has
// created READY_FILE (its readers know our writers: best-effort messages are
// not dropped by a reader that has not yet discovered the writer).
#include <Eigen/Geometry>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "ros2/ros2_bridge.h"

namespace {

using aerograsp::TelemetryTransform;
using Json = nlohmann::json;

constexpr double kStartWallS = 1700000000.25;  // the stamps' origin

Json Stamp(double t_s) {
  // 1700000000.25 + t: whole seconds and nanoseconds (t < 0.75 s past a whole second here).
  const double fraction = 0.25 + t_s;
  const double sec = std::floor(fraction);
  return {{"sec", 1700000000 + static_cast<int>(sec)},
          {"nanosec", static_cast<long>(std::llround((fraction - sec) * 1e9))}};
}

Json Header(double t_s, const std::string& frame) {
  return {{"stamp", Stamp(t_s)}, {"frame_id", frame}};
}

/// A pose as ROS carries it, with the 4x4 matrix it must stand for (checked separately).
Json PoseJson(const Eigen::Isometry3d& aMb, const char* position_key = "position",
              const char* orientation_key = "orientation") {
  const Eigen::Quaterniond q(aMb.rotation());
  Json m = Json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m.push_back(aMb.matrix()(r, c));
  return {
      {position_key,
       {{"x", aMb.translation().x()}, {"y", aMb.translation().y()}, {"z", aMb.translation().z()}}},
      {orientation_key, {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}},
      {"__matrix", m}};
}

Eigen::Isometry3d Pose(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() << x, y, z;
  return p;
}

Json TfJson(double t_s, const std::vector<TelemetryTransform>& transforms) {
  Json list = Json::array();
  for (const TelemetryTransform& tr : transforms) {
    list.push_back({{"header", Header(t_s, tr.parent)},
                    {"child_frame_id", tr.child},
                    {"transform", PoseJson(tr.parentMchild, "translation", "rotation")}});
  }
  return {{"transforms", list}};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: ros2_publish_tool DOMAIN NS DDS_CONFIG EXPECTED.json READY_FILE\n";
    return 1;
  }
  aerograsp::Ros2Config config;
  config.enabled = true;
  config.domain_id = std::stoi(argv[1]);
  config.topic_namespace = argv[2];
  config.dds_config = argv[3];
  config.image_rate_hz = 30;
  config.joint_states_rate_hz = 100;
  const std::string ns = "/" + config.topic_namespace;
  bool failed = false;
  const auto note = [&](const std::string& line) {
    std::cerr << "ros2_publish_tool: " << line << "\n";
    failed = true;
  };
  aerograsp::Ros2Bridge bridge = aerograsp::OpenRos2(config, note, kStartWallS);
  if (!bridge) return 1;
  if (!WaitForSubscribers(bridge, 1, 30.0)) {
    std::cerr << "ros2_publish_tool: no subscriber on every topic within 30 s\n";
    return 1;
  }
  for (int i = 0; !std::filesystem::exists(argv[5]); ++i) {
    if (i == 3000) {
      std::cerr << "ros2_publish_tool: the peer did not get ready within 30 s\n";
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  aerograsp::TelemetrySink& sink = *bridge.sink;
  Json expected = Json::object();
  const auto expect = [&](const std::string& topic, const Json& fields) {
    expected[topic].push_back(fields);
  };

  // Fixed transforms, then one more (a calibration solved): /tf_static carries all of them.
  using namespace aerograsp::telemetry_frame;
  std::vector<TelemetryTransform> fixed = {
      {kMap, kWorld, aerograsp::MapMWorld()},
      {kBody, kCamera, Pose(0.12, 0.0, 0.05, -1.5707963267948966, 0.0, -1.5707963267948966)},
      {kBody, kLeftBase, Pose(0.05, -0.11, 0.08, 0.1, 0.2, 0.3)}};
  sink.StaticTransforms(0.0, fixed);
  expect("/tf_static", TfJson(0.0, {fixed[2], fixed[1], fixed[0]}));  // ordered by child name
  const TelemetryTransform right{kBody, kRightBase, Pose(0.05, 0.11, 0.08, -0.1, 0.2, -0.3)};
  sink.StaticTransforms(0.5, {right});
  expect("/tf_static", TfJson(0.5, {fixed[2], right, fixed[1], fixed[0]}));
  expected["__latest_only"] = {"/tf_static"};

  // Moving transforms.
  const std::vector<TelemetryTransform> moving = {
      {kWorld, kBody, Pose(2.7, 0.01, -2.2, 0.01, -0.02, 0.003)},
      {kLeftBase, kLeftTool, Pose(0.2, 0.01, 0.3, 0.5, -0.4, 1.2)},
      {kWorld, kObject, Pose(3.1, 0.0, -1.6, 0.0, 0.0, 1.5707963267948966)}};
  sink.Transforms(1.0, moving);
  expect("/tf", TfJson(1.0, moving));
  expect("/clock", {{"clock", Stamp(1.0)}});

  // The object, found with a covariance, then lost (only object_found goes out).
  aerograsp::TelemetryObjectPose pose;
  pose.t_s = 1.0333333333333334;
  pose.frame_id = kWorld;
  pose.valid = pose.found = true;
  pose.confidence = 0.93;
  pose.fMo = Pose(3.1001, -0.0002, -1.6003, 0.001, -0.002, 1.571);
  Eigen::Matrix<double, 6, 6> cov;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) cov(r, c) = r == c ? 1e-6 * (r + 1) : 1e-9 * (r + 2 * c);
  pose.covariance = cov;
  sink.ObjectPose(pose);
  expect(ns + "/object_pose", {{"header", Header(pose.t_s, kWorld)}, {"pose", PoseJson(pose.fMo)}});
  Json cov_list = Json::array();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) cov_list.push_back(cov(r, c));
  expect(ns + "/object_pose_covariance",
         {{"header", Header(pose.t_s, kWorld)},
          {"pose", {{"pose", PoseJson(pose.fMo)}, {"covariance", cov_list}}}});
  expect(ns + "/object_found", {{"data", true}});
  aerograsp::TelemetryObjectPose lost = pose;
  lost.t_s = 1.0666666666666667;
  lost.valid = lost.found = false;
  lost.covariance.reset();
  sink.ObjectPose(lost);
  expect(ns + "/object_found", {{"data", false}});

  // Both arms: measured joints with velocities, targets, grippers.
  aerograsp::TelemetryArms arms;
  arms.t_s = 1.01;
  for (int a = 0; a < 2; ++a) {
    aerograsp::TelemetryArmState& arm = arms.arms[a];
    arm.arm = a == 0 ? "left" : "right";
    arm.joint_names = {"j0", "j1", "j2", "j3"};
    arm.position_rad = Eigen::Vector4d(0.1, -0.2, 0.3, -0.4) * (a + 1);
    arm.velocity_radps = Eigen::Vector4d(0.01, 0.02, -0.03, 0.04) * (a + 1);
    arm.target_rad = Eigen::Vector4d(0.11, -0.21, 0.31, -0.41) * (a + 1);
    arm.gripper_aperture_m = 0.06 - 0.02 * a;
    arm.gripper_closed = a == 1;
  }
  sink.Arms(arms);
  Json names = Json::array(), position = Json::array(), velocity = Json::array();
  Json target_names = Json::array(), targets = Json::array();
  for (int a = 0; a < 2; ++a) {
    const aerograsp::TelemetryArmState& arm = arms.arms[a];
    for (int j = 0; j < 4; ++j) {
      names.push_back("arm_" + arm.arm + "_j" + std::to_string(j));
      target_names.push_back("arm_" + arm.arm + "_j" + std::to_string(j));
      position.push_back(arm.position_rad[j]);
      velocity.push_back(arm.velocity_radps[j]);
      targets.push_back(arm.target_rad[j]);
    }
    names.push_back("arm_" + arm.arm + "_gripper");
    position.push_back(arm.gripper_aperture_m);
    velocity.push_back(0.0);
  }
  expect(ns + "/joint_states", {{"header", Header(arms.t_s, "")},
                                {"name", names},
                                {"position", position},
                                {"velocity", velocity},
                                {"effort", Json::array()}});
  expect(ns + "/joint_targets", {{"header", Header(arms.t_s, "")},
                                 {"name", target_names},
                                 {"position", targets},
                                 {"velocity", Json::array()},
                                 {"effort", Json::array()}});
  expect("/clock", {{"clock", Stamp(arms.t_s)}});

  // A transition and the followed pair.
  sink.Transition({1.2, "planner", "planning", "servoing", "dual grasp 3 of 41 feasible"});
  expect(ns + "/transitions",
         {{"data", "planner: planning -> servoing: dual grasp 3 of 41 feasible"}});
  sink.GraspPair({1.2, 12, 40, "best ranked"});
  expect(ns + "/grasp_pair", {{"data", "left 12 right 40: best ranked"}});

  // A small image with depth in millimetres.
  aerograsp::ColorImage color(4, 3);
  for (std::size_t i = 0; i < color.data.size(); ++i) color.data[i] = static_cast<uint8_t>(7 * i);
  aerograsp::DepthImage depth(4, 3);
  for (std::size_t i = 0; i < depth.data.size(); ++i)
    depth.data[i] = static_cast<uint16_t>(400 + 300 * i);
  aerograsp::TelemetryImage image;
  image.t_s = 1.1;
  image.K.width = 4;
  image.K.height = 3;
  image.K.fx = 3.5;
  image.K.fy = 3.25;
  image.K.cx = 2.0;
  image.K.cy = 1.5;
  image.color = &color;
  image.depth = &depth;
  sink.Image(image);
  Json color_bytes(color.data), depth_bytes = Json::array();
  for (uint16_t d : depth.data) {
    depth_bytes.push_back(d & 0xff);  // little endian, as the header says (is_bigendian 0)
    depth_bytes.push_back(d >> 8);
  }
  expect(ns + "/camera/color/image_raw", {{"header", Header(1.1, kCamera)},
                                          {"height", 3},
                                          {"width", 4},
                                          {"encoding", "rgb8"},
                                          {"is_bigendian", 0},
                                          {"step", 12},
                                          {"data", color_bytes}});
  expect(ns + "/camera/depth/image_raw", {{"header", Header(1.1, kCamera)},
                                          {"height", 3},
                                          {"width", 4},
                                          {"encoding", "16UC1"},
                                          {"is_bigendian", 0},
                                          {"step", 8},
                                          {"data", depth_bytes}});
  expect(
      ns + "/camera/color/camera_info",
      {{"header", Header(1.1, kCamera)},
       {"height", 3},
       {"width", 4},
       {"distortion_model", "plumb_bob"},
       {"d", {0, 0, 0, 0, 0}},
       {"k", {3.5, 0, 2.0, 0, 3.25, 1.5, 0, 0, 1}},
       {"r", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
       {"p", {3.5, 0, 2.0, 0, 0, 3.25, 1.5, 0, 0, 0, 1, 0}},
       {"binning_x", 0},
       {"binning_y", 0},
       {"roi",
        {{"x_offset", 0}, {"y_offset", 0}, {"height", 0}, {"width", 0}, {"do_rectify", false}}}});

  // Log lines, the last one ends the peer's recording.
  sink.Log(1.3, aerograsp::TelemetryLevel::kWarn, "mission", "object lost for 0.5 s");
  expect("/rosout", {{"stamp", Stamp(1.3)},
                     {"level", 30},
                     {"name", "aerograsp.mission"},
                     {"msg", "object lost for 0.5 s"},
                     {"file", ""},
                     {"function", ""},
                     {"line", 0}});
  sink.Log(1.4, aerograsp::TelemetryLevel::kInfo, "mission", "crosscheck done");
  expect("/rosout", {{"stamp", Stamp(1.4)},
                     {"level", 20},
                     {"name", "aerograsp.mission"},
                     {"msg", "crosscheck done"},
                     {"file", ""},
                     {"function", ""},
                     {"line", 0}});
  sink.Close();  // waits for the reliable messages to be acknowledged

  std::ofstream out(argv[4]);
  out << expected.dump(1) << "\n";
  if (!out) {
    std::cerr << "ros2_publish_tool: cannot write " << argv[4] << "\n";
    return 1;
  }
  return failed ? 1 : 0;
}
