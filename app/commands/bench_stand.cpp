#include "app/commands/bench_stand.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "core/config.h"
#include "core/object_model.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kBoardAboveSurfaceM = 0.0005;  // the printed board lies this far above the face
constexpr double kDeg = M_PI / 180.0;

/// Where a ray down z_o through (x, y) first meets the mesh (its top there), m along z_o.
double TopSurfaceAt(const TriangleMesh& mesh_o, double x, double y) {
  const double above_m = mesh_o.BoundsMax().z() + 1.0;
  const std::vector<double> hits =
      IntersectRay(mesh_o, Eigen::Vector3d(x, y, above_m), -Eigen::Vector3d::UnitZ());
  return hits.empty() ? mesh_o.BoundsMax().z() : above_m - hits.front();
}

}  // namespace

TagBoardConfig BenchBoard() {
  TagBoardConfig board;
  board.rows = 1;
  board.cols = 3;
  board.tag_size_m = 0.036;
  board.spacing_m = 0.008;
  board.margin_m = 0.004;
  board.first_id = 20;
  return board;
}

Eigen::Isometry3d DefaultBoardOnObject(const TriangleMesh& mesh_o) {
  const Eigen::Vector3d centre_o = PlacementCentre(mesh_o);
  return MakeTransform(
      Eigen::Vector3d(centre_o.x(), centre_o.y(),
                      TopSurfaceAt(mesh_o, centre_o.x(), centre_o.y()) + kBoardAboveSurfaceM),
      Eigen::Vector3d(M_PI, 0.0, 0.0));
}

BenchRig BenchRig::Load(const std::string& hardware_path) {
  BenchRig r;
  r.source = hardware_path;
  const ConfigNode root = ConfigNode::LoadFile(hardware_path);
  if (!root.Has("bench")) return r;
  const ConfigNode n = root.Child("bench");
  n.RequireOnlyKeys({"board", "board_on_object_xyz_m", "board_on_object_rpy_deg"});
  if (n.Has("board")) r.board = TagBoardConfig::FromNode(n.Child("board"));
  if (n.Has("board_on_object_xyz_m") != n.Has("board_on_object_rpy_deg")) {
    n.Fail(n.Has("board_on_object_xyz_m") ? "board_on_object_rpy_deg" : "board_on_object_xyz_m",
           "missing: the board's place on the object needs both its position and orientation");
  }
  if (n.Has("board_on_object_xyz_m")) {
    r.oMt = MakeTransform(n.GetVector3("board_on_object_xyz_m"),
                          Eigen::Vector3d(n.GetVector3("board_on_object_rpy_deg") * kDeg));
  }
  r.Validate(hardware_path, "bench.");
  return r;
}

void BenchRig::Validate(const std::string& source, const std::string& prefix) const {
  board.Validate(source, prefix + "board.");
  if (oMt) {
    CheckRange(source, prefix + "board_on_object_xyz_m", Eigen::Vector3d(oMt->translation()), -1.0,
               1.0, "m");
  }
}

Eigen::Isometry3d ScriptedDmo(double t_s, double period_s, double scale,
                              const Eigen::Vector3d& grasp_dto_m, const Eigen::Vector3d& centre_o) {
  const Eigen::Vector3d& centre_d = grasp_dto_m;
  const double w = 2.0 * M_PI / period_s;
  const Eigen::Vector3d p_d =
      centre_d + scale * Eigen::Vector3d(0.06 * std::sin(w * t_s), 0.02 * std::sin(2.0 * w * t_s),
                                         0.02 * std::sin(w * t_s + 1.0));
  Eigen::Matrix3d dRo;  // columns x_o = y_d, y_o = x_d, z_o = -z_d
  dRo << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const double yaw = scale * 0.1 * std::sin(w * t_s + 2.0);
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();
  dMo.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * dRo;
  dMo.translation() = p_d - dMo.linear() * centre_o;  // the centre on the path
  return dMo;
}

void CheckBenchHardware(const HardwareConfig& config) {
  const std::string& f = config.source;
  if (config.camera.backend == "replay") {
    throw ConfigError(
        fmt::format("{}: camera.backend: 'replay': the arms cannot servo to a recording; measure "
                    "perception on a recorded sequence with `aerograsp replay`",
                    f));
  }
  const bool real_camera = config.camera.backend == "realsense";
  if (config.arms.backend == "scs" && !real_camera) {
    throw ConfigError(
        fmt::format("{}: arms.backend: 'scs' drives the real arms, but camera.backend '{}' is "
                    "simulated: the real arms would servo to a simulated object; use "
                    "camera.backend 'realsense' (the object moved by hand in front of it), or "
                    "'sim-bus' / 'sim' arms",
                    f, config.camera.backend));
  }
  if (config.autopilot.backend == "px4" && !real_camera) {
    throw ConfigError(fmt::format(
        "{}: autopilot.backend: 'px4' is a real vehicle, but the simulated camera looks from the "
        "simulated vehicle on its stand; use 'sim-px4' or 'sim'",
        f));
  }
}

}  // namespace aerograsp
