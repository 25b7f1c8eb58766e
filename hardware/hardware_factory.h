// Builds the devices a HardwareConfig names: real drivers, the real drivers
// against simulated peers (servo bus on a pty, PX4 over UDP loopback), or the
// in-process simulator, and the World behind every simulated one.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/platform.h"
#include "hardware/arms_driver.h"
#include "hardware/autopilot.h"
#include "hardware/hardware_config.h"
#include "hardware/rgbd_camera.h"

namespace aerograsp {

class World;
struct WorldConfig;
class SimServoBus;
class SimPx4;
class ScsArmsDriver;
class Px4Autopilot;

/// Seconds on a steady clock, for the real devices' drivers.
double SteadySeconds();

class Hardware {
 public:
  /// The World (for simulated backends), then the devices in the order camera,
  /// autopilot, arms; each is opened and checked before the next, and the
  /// servos' torque is enabled only when every device is open, so a missing
  /// device stops the run before anything moves.
  /// @throws HardwareError naming the device and its port or path; ConfigError /
  /// MeshError from the platform and world files.
  /// `adjust_world`, when given, may change the world's settings after they are
  /// read and before the world is built (a mission's object, motion, sway).
  static std::unique_ptr<Hardware> Open(const HardwareConfig& config, std::uint64_t seed,
                                        const std::function<void(WorldConfig*)>& adjust_world = {});
  ~Hardware();
  Hardware(const Hardware&) = delete;
  Hardware& operator=(const Hardware&) = delete;

  const Platform& platform() const { return *platform_; }
  /// From now on platform() has this arm's base at dMb (a calibration's; the
  /// simulated world keeps its own, true, platform). The drivers' references
  /// to platform() stay valid. @throws std::invalid_argument for a non-rigid dMb.
  void SetArmBase(Side side, const Eigen::Isometry3d& dMb) {
    *platform_ = platform_->WithArmBase(side, dMb);
  }
  /// Null when every device is real.
  World* world() { return world_.get(); }
  ArmsDriver& arms() { return *arms_; }
  Autopilot& autopilot() { return *autopilot_; }
  RgbdCamera& camera() { return *camera_; }
  /// The SCS driver / PX4 client when those backends are used (else null).
  ScsArmsDriver* scs_arms() { return scs_arms_; }
  Px4Autopilot* px4() { return px4_; }

  /// Simulated runs, on the owner's thread: the bus cycle, the simulated bus's
  /// turn, the world's step of dt_s (through the simulated PX4 when it is used)
  /// and the PX4 client's spin, in that order: deterministic on the simulated clock.
  void StepSimulation(double dt_s);
  /// Real runs: the arm driver's bus loop and the MAVLink client on their threads.
  void StartDriverThreads();
  /// Simulated runs: when a fault the hardware file sets on a simulated device
  /// first showed (simulated time: a servo bus fault switched on, the PX4 fell
  /// silent or refused a command, a camera frame frozen or without depth); < 0: none.
  double FirstSimulatedFaultS() const;

 private:
  Hardware() = default;
  std::unique_ptr<Platform> platform_;
  std::unique_ptr<World> world_;
  std::unique_ptr<SimServoBus> sim_bus_;
  std::unique_ptr<SimPx4> sim_px4_;
  std::unique_ptr<RgbdCamera> camera_;
  std::unique_ptr<Autopilot> autopilot_;
  std::unique_ptr<ArmsDriver> arms_;
  ScsArmsDriver* scs_arms_ = nullptr;
  Px4Autopilot* px4_ = nullptr;
};

/// One device at a time (hardware-check): each needs the world for simulated backends.
/// @throws HardwareError naming the device and its port or path.
std::unique_ptr<RgbdCamera> OpenCamera(const CameraHardwareConfig& config, World* world);
/// For "sim-px4", `peer` receives the simulated PX4 the client talks to.
std::unique_ptr<Autopilot> OpenAutopilot(const AutopilotHardwareConfig& config, World* world,
                                         std::unique_ptr<SimPx4>* peer);
/// For "sim-bus", `bus` receives the simulated bus. Torque stays as the servos
/// had it unless `torque_on`.
std::unique_ptr<ArmsDriver> OpenArms(const ArmsHardwareConfig& config, const Platform& platform,
                                     World* world, std::unique_ptr<SimServoBus>* bus,
                                     bool torque_on);

/// Whether this build can talk to a RealSense (librealsense2 found at configure time).
bool HaveRealSense();

}  // namespace aerograsp
