// aerograsp's side of the MCAP check (run_check.sh): writes MCAP files through
// the real McapSink for the independent reader (check_mcap.js) to open.
//   mcap_check_tool write DIR COMPRESSION
//       DIR/telemetry.mcap with one call of every kind (and a few more), and
//       DIR/expected.json: the fields each ROS 2 message must decode to
//   mcap_check_tool full-disk DIR
//       in a child process limited to 300 kB of file (RLIMIT_FSIZE), writes
//       telemetry until the limit stops the file: the sink must say so once and
//       go on; DIR/full.mcap keeps its complete chunks
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "telemetry/mcap_sink.h"
#include "telemetry/mcap_writer.h"
#include "telemetry/telemetry.h"

namespace {

using aerograsp::ColorImage;
using aerograsp::DepthImage;
using aerograsp::TelemetryTransform;
using nlohmann::json;

json Stamp(double t_s) {
  const auto ns = static_cast<std::int64_t>(std::llround(t_s * 1e9));
  return {{"sec", ns / 1000000000}, {"nanosec", ns % 1000000000}};
}

json Header(double t_s, const std::string& frame_id) {
  return {{"stamp", Stamp(t_s)}, {"frame_id", frame_id}};
}

json Pose(const Eigen::Isometry3d& aMb, const char* position_key, const char* rotation_key) {
  const Eigen::Vector3d p = aMb.translation();
  const Eigen::Quaterniond q(aMb.rotation());
  return {{position_key, {{"x", p.x()}, {"y", p.y()}, {"z", p.z()}}},
          {rotation_key, {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}}};
}

Eigen::Isometry3d Transform(double x, double y, double z, double angle,
                            const Eigen::Vector3d& axis) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.translation() = Eigen::Vector3d(x, y, z);
  m.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  return m;
}

json TfMessage(double t_s, const std::vector<TelemetryTransform>& transforms) {
  json list = json::array();
  for (const TelemetryTransform& t : transforms) {
    list.push_back({{"header", Header(t_s, t.parent)},
                    {"child_frame_id", t.child},
                    {"transform", Pose(t.parentMchild, "translation", "rotation")}});
  }
  return {{"transforms", list}};
}

json Log(double t_s, int level, const std::string& name, const std::string& msg) {
  return {{"stamp", Stamp(t_s)}, {"level", level}, {"name", name}, {"msg", msg},
          {"file", ""},          {"function", ""}, {"line", 0}};
}

int Write(const std::filesystem::path& dir, const std::string& compression) {
  aerograsp::McapConfig config;
  config.compression = compression;
  config.depth = true;
  config.image_rate_hz = 10.0;
  config.state_rate_hz = 1000.0;
  config.chunk_size_kib = 16;  // several chunks
  json expected = json::array();
  const auto expect = [&](const std::string& topic, int index, json fields) {
    expected.push_back({{"topic", topic}, {"index", index}, {"fields", std::move(fields)}});
  };
  std::string notes;
  {
    aerograsp::McapSink sink((dir / "telemetry.mcap").string(), config,
                             [&](const std::string& line) { notes += line + "\n"; });
    namespace frame = aerograsp::telemetry_frame;
    const std::vector<TelemetryTransform> fixed = {
        {frame::kMap, frame::kWorld, aerograsp::MapMWorld()},
        {frame::kBody, frame::kCamera, Transform(0.12, 0.0, 0.05, 1.2, {1, 0.1, 0.9})}};
    sink.StaticTransforms(0.0, fixed);
    expect("/tf_static", 0, TfMessage(0.0, fixed));

    // Arms and moving transforms over 2 s at 100 Hz.
    for (int k = 0; k < 200; ++k) {
      const double t = 0.01 * k;
      aerograsp::TelemetryArms arms;
      arms.t_s = t;
      for (int a = 0; a < 2; ++a) {
        auto& arm = arms.arms[a];
        arm.arm = a == 0 ? "left" : "right";
        arm.joint_names = {"j0", "j1", "j2", "j3"};
        arm.position_rad = Eigen::Vector4d(0.1 * a, -0.5 + t, 0.25, std::sin(t));
        // Velocities on every other cycle (both arms), targets on the right arm.
        if (k % 2 == 0) arm.velocity_radps = Eigen::Vector4d(0.0, 1.0 + a, 0.0, std::cos(t));
        if (a == 1) arm.target_rad = Eigen::Vector4d(0.2, -0.4, 0.3, 0.5 * t);
        arm.gripper_aperture_m = 0.04 - 0.001 * k / 10;
      }
      sink.Arms(arms);
      const std::vector<TelemetryTransform> moving = {
          {frame::kWorld, frame::kBody, Transform(1.0 + t, -2.0, -2.2, 0.1 * t, {0, 0, 1})},
          {frame::kLeftBase, frame::kLeftTool,
           Transform(0.1, 0.02, 0.3 - 0.01 * t, 0.3, {0, 1, 0})}};
      sink.Transforms(t, moving);
      if (k == 37) {
        expect("/tf", 37, TfMessage(t, moving));
        const json names = {"arm_left_j0",      "arm_left_j1",      "arm_left_j2",  "arm_left_j3",
                            "arm_left_gripper", "arm_right_j0",     "arm_right_j1", "arm_right_j2",
                            "arm_right_j3",     "arm_right_gripper"};
        const json positions = {0.0, -0.5 + t, 0.25, std::sin(t), arms.arms[0].gripper_aperture_m,
                                0.1, -0.5 + t, 0.25, std::sin(t), arms.arms[1].gripper_aperture_m};
        expect("/aerograsp/joint_states", 37,
               {{"header", Header(t, "")},
                {"name", names},
                {"position", positions},
                {"velocity", json::array()},  // odd cycle: no velocities
                {"effort", json::array()}});
        expect("/aerograsp/joint_targets", 37,
               {{"header", Header(t, "")},
                {"name", {"arm_right_j0", "arm_right_j1", "arm_right_j2", "arm_right_j3"}},
                {"position", {0.2, -0.4, 0.3, 0.5 * t}},
                {"velocity", json::array()},
                {"effort", json::array()}});
      }
      if (k == 38) {
        expect("/aerograsp/joint_states", 38,
               {{"header", Header(t, "")},
                {"name",
                 {"arm_left_j0", "arm_left_j1", "arm_left_j2", "arm_left_j3", "arm_left_gripper",
                  "arm_right_j0", "arm_right_j1", "arm_right_j2", "arm_right_j3",
                  "arm_right_gripper"}},
                {"position",
                 {0.0, -0.5 + t, 0.25, std::sin(t), arms.arms[0].gripper_aperture_m, 0.1, -0.5 + t,
                  0.25, std::sin(t), arms.arms[1].gripper_aperture_m}},
                {"velocity",
                 {0.0, 1.0, 0.0, std::cos(t), nullptr, 0.0, 2.0, 0.0, std::cos(t), nullptr}},
                {"effort", json::array()}});
      }
    }

    aerograsp::TelemetryObjectPose pose;
    pose.t_s = 1.25;
    pose.frame_id = frame::kWorld;
    pose.valid = pose.found = true;
    pose.confidence = 0.9;
    pose.fMo = Transform(2.7, 0.05, -0.3, 2.0, {0.2, -1, 0.4});
    Eigen::Matrix<double, 6, 6> covariance;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) covariance(r, c) = 1e-4 * (r + 1) + 1e-6 * c;
    pose.covariance = covariance;
    sink.ObjectPose(pose);
    json row_major = json::array();
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) row_major.push_back(covariance(r, c));
    expect("/aerograsp/object_pose_covariance", 0,
           {{"header", Header(1.25, "world")},
            {"pose",
             {{"pose", Pose(pose.fMo, "position", "orientation")}, {"covariance", row_major}}}});
    expect("/aerograsp/object_found", 0, {{"data", true}});
    pose.t_s = 1.2834;
    pose.valid = pose.found = false;  // no pose: only "not found"
    sink.ObjectPose(pose);
    expect("/aerograsp/object_found", 1, {{"data", false}});

    aerograsp::TelemetryTransition transition{1.5, "vision", "found", "lost",
                                              "pose lost (confidence 0.12)"};
    sink.Transition(transition);
    expect("/aerograsp/transitions", 0,
           {{"data", "vision: found -> lost: pose lost (confidence 0.12)"}});
    expect("/rosout", 0,
           Log(1.5, 20, "aerograsp.vision", "found -> lost: pose lost (confidence 0.12)"));
    sink.Log(1.6, aerograsp::TelemetryLevel::kError, "mission", "emergency stop requested by test");
    expect("/rosout", 1, Log(1.6, 40, "aerograsp.mission", "emergency stop requested by test"));
    sink.GraspPair({1.7, 72, 61, "pairs L72 R61 of 10 ranked"});
    expect("/aerograsp/grasp_pair", 0, {{"data", "left 72 right 61: pairs L72 R61 of 10 ranked"}});

    ColorImage color(64, 48);
    DepthImage depth(64, 48);
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        color.at(x, y, 0) = static_cast<std::uint8_t>(4 * x);
        color.at(x, y, 1) = static_cast<std::uint8_t>(5 * y);
        color.at(x, y, 2) = 128;
        depth.at(x, y) = static_cast<std::uint16_t>(500 + 7 * x + 300 * y);
      }
    }
    aerograsp::TelemetryImage image;
    image.t_s = 1.8;
    image.K.width = 64, image.K.height = 48, image.K.fx = 60.5, image.K.fy = 61.5;
    image.K.cx = 31.5, image.K.cy = 23.5;
    image.color = &color;
    image.depth = &depth;
    sink.Image(image);
    image.t_s = 1.81;  // within the image period: skipped
    sink.Image(image);
    std::vector<std::uint8_t> depth_bytes;
    for (std::uint16_t d : depth.data)
      depth_bytes.push_back(d & 0xff), depth_bytes.push_back(d >> 8);
    expect("/aerograsp/camera/color/image_raw/compressed", 0,
           {{"header", Header(1.8, "camera_optical")},
            {"format", "jpeg"},
            {"data", {{"$jpeg", true}}}});
    expect(
        "/aerograsp/camera/color/camera_info", 0,
        {{"header", Header(1.8, "camera_optical")},
         {"height", 48},
         {"width", 64},
         {"distortion_model", "plumb_bob"},
         {"d", {0.0, 0.0, 0.0, 0.0, 0.0}},
         {"k", {60.5, 0.0, 31.5, 0.0, 61.5, 23.5, 0.0, 0.0, 1.0}},
         {"r", {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}},
         {"p", {60.5, 0.0, 31.5, 0.0, 0.0, 61.5, 23.5, 0.0, 0.0, 0.0, 1.0, 0.0}},
         {"binning_x", 0},
         {"binning_y", 0},
         {"roi",
          {{"x_offset", 0}, {"y_offset", 0}, {"height", 0}, {"width", 0}, {"do_rectify", false}}}});
    expect("/aerograsp/camera/depth/image_raw", 0,
           {{"header", Header(1.8, "camera_optical")},
            {"height", 48},
            {"width", 64},
            {"encoding", "16UC1"},
            {"is_bigendian", 0},
            {"step", 128},
            {"data",
             {{"$bytes_length", depth_bytes.size()},
              {"$bytes_crc32", aerograsp::Crc32(depth_bytes.data(), depth_bytes.size())}}}});
    sink.Close();
    if (sink.writer().failed()) {
      std::cerr << "mcap_check_tool: " << sink.writer().error() << "\n";
      return 1;
    }
  }
  if (!notes.empty()) {
    std::cerr << "mcap_check_tool: unexpected notes: " << notes;
    return 1;
  }
  const json counts = {
      {"/tf_static", 1},
      {"/tf", 200},
      {"/aerograsp/joint_states", 200},
      {"/aerograsp/joint_targets", 200},
      {"/aerograsp/object_pose_covariance", 1},
      {"/aerograsp/object_found", 2},
      {"/rosout", 2},
      {"/aerograsp/transitions", 1},
      {"/aerograsp/grasp_pair", 1},
      {"/aerograsp/camera/color/image_raw/compressed", 1},  // the second within 0.1 s
      {"/aerograsp/camera/color/camera_info", 1},
      {"/aerograsp/camera/depth/image_raw", 1}};
  std::ofstream(dir / "expected.json") << json{{"messages", expected}, {"counts", counts}}.dump(1);
  return 0;
}

/// The child: telemetry into a file the size limit stops; exit 0 when the sink
/// said so exactly once and went on, 2 otherwise.
int FillUntilFull(const std::filesystem::path& dir) {
  signal(SIGXFSZ, SIG_IGN);  // past the limit, write() fails with EFBIG instead of a signal
  rlimit limit{300 * 1000, 300 * 1000};
  if (setrlimit(RLIMIT_FSIZE, &limit) != 0) return 3;
  aerograsp::McapConfig config;
  config.compression = "none";
  config.chunk_size_kib = 16;
  config.state_rate_hz = 1000.0;
  int notes = 0;
  std::string note;
  aerograsp::McapSink sink((dir / "full.mcap").string(), config, [&](const std::string& line) {
    ++notes;
    note = line;
  });
  sink.StaticTransforms(0.0, {{"map", "world", aerograsp::MapMWorld()}});
  int calls = 0;
  for (int k = 0; k < 20000; ++k) {  // about 3 MB: ten times the limit
    aerograsp::TelemetryArms arms;
    arms.t_s = 0.01 * k;
    for (auto& arm : arms.arms) {
      arm.arm = &arm == &arms.arms[0] ? "left" : "right";
      arm.joint_names = {"j0", "j1", "j2", "j3"};
      arm.position_rad = Eigen::Vector4d::Constant(0.001 * k);
    }
    sink.Arms(arms);
    sink.Log(arms.t_s, aerograsp::TelemetryLevel::kInfo, "mission", "cycle " + std::to_string(k));
    ++calls;
  }
  sink.Close();
  std::cout << "notes: " << notes << "\nnote: " << note << "\ncalls: " << calls
            << "\nbytes: " << sink.writer().bytes_written() << "\n";
  return notes == 1 && sink.writer().failed() && calls == 20000 ? 0 : 2;
}

int FullDisk(const std::filesystem::path& dir) {
  const pid_t child = fork();
  if (child < 0) return 1;
  if (child == 0) _exit(FillUntilFull(dir));
  int status = 0;
  waitpid(child, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::cerr << "mcap_check_tool: the writing child failed (status " << status << ")\n";
    return 1;
  }
  const auto size = std::filesystem::file_size(dir / "full.mcap");
  if (size == 0 || size > 300 * 1000) {
    std::cerr << "mcap_check_tool: full.mcap has " << size << " bytes\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "write" && argc == 4) return Write(argv[2], argv[3]);
  if (mode == "full-disk" && argc == 3) return FullDisk(argv[2]);
  std::cerr << "usage: mcap_check_tool write DIR none|lz4|zstd | full-disk DIR\n";
  return 2;
}
