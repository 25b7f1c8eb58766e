#include "app/commands/bench_stand.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "app/runtime/mission_config.h"
#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

constexpr double kBoardAboveSurfaceM = 0.0005;  // the printed board lies this far above the face

/// Where a ray down the z axis of o first meets the mesh (its top over the origin), m along z_o.
double TopSurfaceAtCentre(const TriangleMesh& mesh_o) {
  const double above_m = mesh_o.BoundsMax().z() + 1.0;
  const std::vector<double> hits =
      IntersectRay(mesh_o, Eigen::Vector3d(0.0, 0.0, above_m), -Eigen::Vector3d::UnitZ());
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
  return MakeTransform(Eigen::Vector3d(0.0, 0.0, TopSurfaceAtCentre(mesh_o) + kBoardAboveSurfaceM),
                       Eigen::Vector3d(M_PI, 0.0, 0.0));
}

Eigen::Isometry3d ScriptedDmo(double t_s, double period_s, double scale) {
  const Eigen::Vector3d centre_d = MissionConfig{}.grasp_dto_m;
  const double w = 2.0 * M_PI / period_s;
  const Eigen::Vector3d p_d =
      centre_d + scale * Eigen::Vector3d(0.06 * std::sin(w * t_s), 0.02 * std::sin(2.0 * w * t_s),
                                         0.02 * std::sin(w * t_s + 1.0));
  Eigen::Matrix3d dRo;  // columns x_o = y_d, y_o = x_d, z_o = -z_d
  dRo << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const double yaw = scale * 0.1 * std::sin(w * t_s + 2.0);
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();
  dMo.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * dRo;
  dMo.translation() = p_d;
  return dMo;
}

void CheckBenchHardware(const HardwareConfig& config) {
  const std::string& f = config.source;
  if (config.camera.backend != "sim") {
    throw ConfigError(
        fmt::format("{}: camera.backend: '{}': the bench moves the object by script in the "
                    "simulated world, which only the "
                    "simulated camera ('sim') sees; a bench with a real camera (the object moved "
                    "by hand) is not supported yet",
                    f, config.camera.backend));
  }
  if (config.arms.backend == "scs") {
    throw ConfigError(
        fmt::format("{}: arms.backend: 'scs' drives the real arms, but the camera is simulated: "
                    "the servo error would compare "
                    "real arms with a simulated object; use 'sim-bus' (the real driver, simulated "
                    "servos) or 'sim'",
                    f));
  }
  if (config.autopilot.backend == "px4") {
    throw ConfigError(fmt::format(
        "{}: autopilot.backend: 'px4' is a real vehicle, but the bench's vehicle is the "
        "simulated one on its stand; use 'sim-px4' or 'sim'",
        f));
  }
}

}  // namespace aerograsp
