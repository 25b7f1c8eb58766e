#include "app/commands/hardware_check_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <exception>
#include <memory>

#include "app/cli_checks.h"
#include "hardware/hardware_config.h"
#include "hardware/hardware_factory.h"
#include "hardware/mavlink/px4_autopilot.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sim/sim_px4.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

std::string Where(const ArmsHardwareConfig& arms) {
  if (arms.backend == "scs")
    return fmt::format("scs on {} at {} baud", arms.scs.port, arms.scs.baud);
  if (arms.backend == "sim-bus") return "simulated SCS bus on a pty";
  return "in-process simulator";
}

std::string Where(const AutopilotHardwareConfig& autopilot) {
  const Px4Config& p = autopilot.px4;
  if (autopilot.backend == "sim-px4") return "simulated PX4 over UDP loopback";
  if (autopilot.backend == "sim") return "in-process simulator";
  if (p.link == "udp") return fmt::format("PX4 over udp {}:{}", p.udp_local_host, p.udp_local_port);
  return fmt::format("PX4 over serial {} at {} baud", p.serial_port, p.baud);
}

std::string Where(const CameraHardwareConfig& camera) {
  if (camera.backend == "replay") return "replay of " + camera.path;
  if (camera.backend == "realsense")
    return "RealSense" + (camera.serial.empty() ? "" : " " + camera.serial);
  return "simulated D435";
}

}  // namespace

int RunHardwareCheck(const HardwareCheckOptions& options, std::ostream& out) {
  const HardwareConfig config = HardwareConfig::Load(options.config_path);
  out << "hardware-check " << options.config_path << "\n";
  std::unique_ptr<World> world;
  if (config.NeedsWorld()) {
    WorldConfig world_config = WorldConfig::Load(config.world);
    world_config.platform = config.platform;
    world = std::make_unique<World>(world_config, options.seed);
  }
  const Platform platform = world ? world->platform() : Platform::Load(config.platform);
  out << fmt::format("  platform   {} arms ({})\n", platform.config().arm_type, config.platform);
  int failed = 0;
  auto report_failure = [&](const char* device, const std::exception& e) {
    out << fmt::format("  {:<10} FAILED: {}\n", device, e.what());
    ++failed;
  };

  try {
    std::unique_ptr<RgbdCamera> camera = OpenCamera(config.camera, world.get());
    RgbdFrame frame;
    const bool got = camera->Grab(&frame);
    const CameraIntrinsics& K = camera->intrinsics();
    out << fmt::format("  {:<10} ok: {}: {}x{}, fx {:.1f} fy {:.1f}, depth scale {} m; {}\n",
                       "camera", Where(config.camera), K.width, K.height, K.fx, K.fy,
                       camera->depth_scale_m(),
                       got ? fmt::format("frame {} grabbed ({}x{})", frame.index, frame.color.width,
                                         frame.color.height)
                           : std::string("the stream is empty"));
  } catch (const std::exception& e) {
    report_failure("camera", e);
  }

  try {
    std::unique_ptr<SimPx4> peer;
    std::unique_ptr<Autopilot> autopilot = OpenAutopilot(config.autopilot, world.get(), &peer);
    auto* px4 = dynamic_cast<Px4Autopilot*>(autopilot.get());
    if (px4) px4->Spin();
    const VehicleState state = autopilot->State();
    out << fmt::format("  {:<10} ok: {}{}: {}, at ({:.2f}, {:.2f}, {:.2f}) m NED, link {}\n",
                       "autopilot", Where(config.autopilot),
                       px4 ? " (" + px4->Describe() + ")" : "", FlightModeName(state.mode),
                       state.wMd.translation().x(), state.wMd.translation().y(),
                       state.wMd.translation().z(), state.link_ok ? "ok" : "LOST");
  } catch (const std::exception& e) {
    report_failure("autopilot", e);
  }

  try {
    std::unique_ptr<SimServoBus> bus;
    std::unique_ptr<ArmsDriver> arms =
        OpenArms(config.arms, platform, world.get(), &bus, /*torque_on=*/false);
    auto* scs = dynamic_cast<ScsArmsDriver*>(arms.get());
    if (!scs) {
      out << fmt::format("  {:<10} ok: {}\n", "arms", Where(config.arms));
    } else {
      // One cycle per servo, so each one's load, voltage and temperature are read once.
      const std::size_t servos = scs->servo_statuses().size();
      for (std::size_t i = 0; i < servos; ++i) scs->Cycle();
      out << fmt::format("  {:<10} ok: {}: {} servos answer (torque left off)\n", "arms",
                         Where(config.arms), servos);
      for (const ScsServoStatus& s : scs->servo_statuses()) {
        out << fmt::format(
            "             {:<14} id {:>3}  raw {:>4}  load {:>5}  {:.1f} V  {} C{}\n", s.name, s.id,
            s.raw_position, s.load, s.voltage_v, s.temperature_c,
            s.error ? "  errors: " + scs::ErrorBitsText(s.error) : "");
      }
    }
  } catch (const std::exception& e) {
    report_failure("arms", e);
  }

  out << (failed == 0 ? "  result: every device answers\n"
                      : fmt::format("  result: {} of 3 devices FAILED\n", failed));
  return failed;
}

void AddHardwareCheckOptions(CLI::App* cmd, HardwareCheckOptions* o) {
  cmd->add_option("--hardware", o->config_path,
                  "Hardware YAML (e.g. data/config/hardware_sim.yaml)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--seed", o->seed, "World seed of simulated devices")
      ->capture_default_str()
      ->check(cli::Seed());
}

}  // namespace aerograsp
