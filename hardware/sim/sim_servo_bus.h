// A simulated Feetech SCS bus on a pseudo-terminal: every servo of both arms
// with its register map, answering PING / READ / WRITE / SYNC_WRITE as the
// real ones do (a READ gets the registers it names, a WRITE an empty status;
// an instruction it does not know gets an instruction-error status, a range
// past the register map a range-error one; a malformed packet, a broadcast
// or an absent servo no reply), with the wire's timing (byte time at 1 Mbaud, the servos'
// return delay) and configurable faults (silent servos, corrupted reply
// bytes, slow replies). The driver opens port_path() like a real adapter.
//
// Timing: the wire runs on the simulation's clock, not the wall clock. The
// bus keeps when the wire is free and when the driver sent its request, and
// from the driver's reply timeout (`servos.reply_timeout_s`) knows what the
// driver hears while it waits: every reply due by then, in order, up to the
// one it accepts. Those bytes are written at once; a reply due later (a slow
// servo) stays on its way and reaches a later exchange, where the driver
// skips it as a stale reply, or is discarded when it comes while the driver
// is not listening. So the bus never sleeps: a simulation is not held to
// real time by it, and a loaded machine does not make its replies late (only
// a bus thread kept off a core for longer than the reply timeout does).
//
// Threading: the bus serves the pty on its own thread. It has to: the driver
// blocks in a read with a timeout while the reply is due, exactly as on the
// real bus, so the peer must answer concurrently. The thread touches only the
// register map. The World is read and written by SyncWithWorld(), which the
// owner calls on its own thread between World::Step calls, so the simulated
// world stays deterministic on its simulated clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/random.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/scs/scs_protocol.h"
#include "hardware/serial_port.h"
#include "hardware/sim/world.h"

namespace aerograsp {

struct SimServoBusConfig {
  /// wire time of a byte (1 Mbaud, 8N1 = 10 bits), [0, 0.01] s; 0 = instant
  double byte_time_s{10e-6};
  double return_delay_s{20e-6};      ///< servo's delay before it replies, [0, 0.1] s
  std::vector<int> silent_ids;       ///< servos that do not answer (nor obey)
  std::vector<int> slow_ids;         ///< servos that answer late
  std::vector<int> hot_ids;          ///< servos that report hot_temperature_c
  std::vector<int> low_voltage_ids;  ///< servos that report low_voltage_v
  std::vector<int> offset_ids;       ///< servos whose position reading is offset_deg off
  double faults_from_s{0.0};        ///< simulated time from which every fault below applies, >= 0 s
  double slow_extra_s{0.02};        ///< how late, [0, 1] s
  double corrupt_probability{0.0};  ///< chance that a reply byte has a bit flipped, [0, 1]
  int hot_temperature_c{85};        ///< [0, 255] C
  double low_voltage_v{5.0};        ///< [0, 25] V
  double offset_deg{45.0};          ///< [-220, 220] deg
  std::uint64_t seed{1};            ///< of the corruption
};

struct SimServoBusCounters {
  std::int64_t packets = 0;      ///< well-formed packets received
  std::int64_t replies = 0;      ///< status packets sent
  std::int64_t bad_packets = 0;  ///< checksum or length errors received
  std::int64_t corrupted_bytes = 0;
};

class SimServoBus {
 public:
  /// The servos (ids, calibration = where the simulated servo's raw 0 and 1023
  /// are) come from `servos`; ports and rates in it are not used.
  /// Starts serving at once.
  SimServoBus(World* world, const ScsArmsConfig& servos, const SimServoBusConfig& config);
  ~SimServoBus();
  SimServoBus(const SimServoBus&) = delete;
  SimServoBus& operator=(const SimServoBus&) = delete;

  /// The pty the driver opens.
  const std::string& port_path() const { return pty_.slave_path(); }
  /// Owner's thread, between world steps: goals to the arms and grippers,
  /// positions, load, moving back into the registers; the faults switch on at
  /// faults_from_s of the world's clock.
  void SyncWithWorld();
  /// Replaces the faults (thread-safe).
  void SetFaults(const SimServoBusConfig& config);
  /// The simulated time at which configured faults switched on; < 0: not (yet).
  double faults_on_since_s() const;
  SimServoBusCounters counters() const;
  /// A copy of one servo's registers (tests).
  std::vector<std::uint8_t> Registers(int id) const;

 private:
  struct Servo {
    int id;
    Side side;
    int joint;  // -1 for the gripper
    ServoCalibration calibration;
    std::vector<std::uint8_t> regs;
  };
  void Serve();
  void Handle(const scs::Packet& packet, std::size_t wire_bytes);
  Servo* Find(int id);
  /// Sends `servo`'s status packet; the driver waits for one of `awaited_params`
  /// parameter bytes (Deliver).
  void Reply(const Servo& servo, std::uint8_t error, const std::vector<std::uint8_t>& params,
             std::size_t awaited_params);
  /// Writes what the driver hears while it waits for servo `id`'s reply of
  /// `params` parameter bytes (every reply due within its reply timeout, up to
  /// the one it accepts: hardware/scs/scs_bus.h skips the others as late) and
  /// moves the driver's time on. Called with mutex_ held; unlocks it while writing.
  void Deliver(int id, std::size_t params);

  World* world_;
  ScsArmsConfig servos_config_;
  SimServoBusConfig config_;
  PseudoTerminal pty_;
  mutable std::mutex mutex_;
  std::vector<Servo> servos_;
  FastRandom rng_;
  SimServoBusCounters counters_;
  /// A reply on the wire or on its way, due at due_s of the simulated clock.
  struct Pending {
    double due_s;
    int id;
    std::vector<std::uint8_t> bytes;
  };
  double driver_s_ = 0.0;         // when the driver sent its latest request (simulated s)
  double wire_free_s_ = 0.0;      // when the wire is free again (simulated s)
  std::vector<Pending> pending_;  // in the order they are due
  std::thread thread_;
  std::atomic<bool> running_{true};
  bool faults_on_ = false;  // the faults apply (world time >= faults_from_s)
  double faults_on_since_s_ = -1.0;
};

}  // namespace aerograsp
