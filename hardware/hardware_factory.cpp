#include "hardware/hardware_factory.h"

#include <chrono>

#include "hardware/mavlink/px4_autopilot.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/sequence.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/sim_px4.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"
#ifdef AEROGRASP_HAVE_REALSENSE
#include "hardware/realsense_camera.h"
#endif

namespace aerograsp {
namespace {

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

void RequireWorld(World* world, const std::string& device) {
  if (!world) throw HardwareError(device + ": a simulated backend needs the simulated world");
}

}  // namespace

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool HaveRealSense() {
#ifdef AEROGRASP_HAVE_REALSENSE
  return true;
#else
  return false;
#endif
}

std::unique_ptr<RgbdCamera> OpenCamera(const CameraHardwareConfig& config, World* world) {
  if (config.backend == "sim") {
    RequireWorld(world, "camera");
    return std::make_unique<SimCamera>(world, config.sim);
  }
  const bool bag = config.backend == "replay" && EndsWith(config.path, ".bag");
  if (config.backend == "replay" && !bag) return std::make_unique<ReplayCamera>(config.path);
#ifdef AEROGRASP_HAVE_REALSENSE
  RealSenseOptions options;
  options.serial = config.serial;
  options.bag_path = bag ? config.path : "";
  options.width = config.width;
  options.height = config.height;
  options.fps = config.fps;
  return std::make_unique<RealSenseCamera>(options);
#else
  throw HardwareError(
      std::string("camera: ") + (bag ? config.path + ": replaying a .bag" : "a RealSense") +
      " needs librealsense2, which this build was configured without (README: Hardware)");
#endif
}

std::unique_ptr<Autopilot> OpenAutopilot(const AutopilotHardwareConfig& config, World* world,
                                         std::unique_ptr<SimPx4>* peer) {
  if (config.backend == "sim") {
    RequireWorld(world, "autopilot");
    return std::make_unique<SimAutopilot>(world);
  }
  Px4Config px4 = config.px4;
  std::unique_ptr<MavlinkLink> link;
  Px4Autopilot::Clock clock = SteadySeconds;
  if (config.backend == "sim-px4") {
    RequireWorld(world, "autopilot");
    SimPx4Config peer_config;
    peer_config.system_id = px4.target_system;
    peer_config.component_id = px4.target_component;
    peer_config.home_amsl_m = px4.home_amsl_m;
    peer_config.signing_key_hex = px4.signing_key_hex;
    peer_config.faults = config.sim_px4;
    *peer = std::make_unique<SimPx4>(world, peer_config);
    link = std::make_unique<UdpLink>("127.0.0.1", 0, "127.0.0.1", (*peer)->port(), "autopilot");
    clock = [world] { return world->now_s(); };
  } else if (px4.link == "udp") {
    link = std::make_unique<UdpLink>(px4.udp_local_host, px4.udp_local_port, px4.udp_remote_host,
                                     px4.udp_remote_port, "autopilot");
  } else {
    link = std::make_unique<SerialLink>(px4.serial_port, px4.baud, "autopilot");
  }
  auto client = std::make_unique<Px4Autopilot>(std::move(link), px4, clock);
  client->Connect();
  return client;
}

std::unique_ptr<ArmsDriver> OpenArms(const ArmsHardwareConfig& config, const Platform& platform,
                                     World* world, std::unique_ptr<SimServoBus>* bus,
                                     bool torque_on) {
  if (config.backend == "sim") {
    RequireWorld(world, "arms");
    return std::make_unique<SimArmsDriver>(world);
  }
  ScsArmsConfig scs = config.scs;
  if (!config.servos_given) {
    const ScsArmsConfig defaults = ScsArmsConfig::Default(platform);
    scs.joints = defaults.joints;
    scs.grippers = defaults.grippers;
  }
  scs.torque_on_start = torque_on;
  ScsArmsDriver::Clock clock = SteadySeconds;
  if (config.backend == "sim-bus") {
    RequireWorld(world, "arms");
    *bus = std::make_unique<SimServoBus>(world, scs, config.sim_bus);
    scs.port = (*bus)->port_path();
    clock = [world] { return world->now_s(); };
  }
  return std::make_unique<ScsArmsDriver>(platform, scs, clock);
}

std::unique_ptr<Hardware> Hardware::Open(const HardwareConfig& config, std::uint64_t seed,
                                         const std::function<void(WorldConfig*)>& adjust_world) {
  std::unique_ptr<Hardware> hw(new Hardware());
  if (config.NeedsWorld()) {
    WorldConfig world_config = WorldConfig::Load(config.world);
    world_config.platform = config.platform;
    if (adjust_world) {
      adjust_world(&world_config);
      world_config.Validate(world_config.source, "");
    }
    hw->world_ = std::make_unique<World>(world_config, seed);
    hw->platform_ = std::make_unique<Platform>(hw->world_->platform());
  } else {
    hw->platform_ = std::make_unique<Platform>(Platform::Load(config.platform));
  }
  hw->camera_ = OpenCamera(config.camera, hw->world_.get());
  hw->autopilot_ = OpenAutopilot(config.autopilot, hw->world_.get(), &hw->sim_px4_);
  hw->px4_ = dynamic_cast<Px4Autopilot*>(hw->autopilot_.get());
  hw->arms_ = OpenArms(config.arms, *hw->platform_, hw->world_.get(), &hw->sim_bus_, false);
  hw->scs_arms_ = dynamic_cast<ScsArmsDriver*>(hw->arms_.get());
  // Everything answered: now the servos may hold their positions.
  if (hw->scs_arms_ && hw->scs_arms_->SetTorque(true) != BusStatus::kOk) {
    throw HardwareError("servo bus " + config.arms.scs.port + ": torque could not be enabled");
  }
  return hw;
}

Hardware::~Hardware() {
  // Drivers first (they talk to the peers), then the peers, then the world.
  arms_.reset();
  autopilot_.reset();
  camera_.reset();
  sim_bus_.reset();
  sim_px4_.reset();
}

void Hardware::StepSimulation(double dt_s) {
  if (scs_arms_) scs_arms_->Cycle();
  if (sim_bus_) sim_bus_->SyncWithWorld();
  if (sim_px4_) {
    sim_px4_->StepWorld(dt_s);
  } else if (world_) {
    world_->Step(dt_s);
  }
  if (px4_) {
    px4_->Spin();
    if (sim_px4_)
      sim_px4_->WaitForSetpoints(px4_->setpoints_sent(), 0.2);  // each counts at its own time
  }
}

double Hardware::FirstSimulatedFaultS() const {
  double first = -1.0;
  const auto earliest = [&first](double t) {
    if (t >= 0.0 && (first < 0.0 || t < first)) first = t;
  };
  if (sim_bus_) earliest(sim_bus_->faults_on_since_s());
  if (sim_px4_) earliest(sim_px4_->first_fault_s());
  if (const auto* camera = dynamic_cast<const SimCamera*>(camera_.get()))
    earliest(camera->first_fault_s());
  return first;
}

void Hardware::StartDriverThreads() {
  if (scs_arms_) scs_arms_->StartThread();
  if (px4_) px4_->StartThread();
}

}  // namespace aerograsp
