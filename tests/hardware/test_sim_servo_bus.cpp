// The simulated SCS bus answers over its pseudo-terminal what a servo answers
// (docs/hardware.md, Servo bus): the registers a READ names, a WRITE's
// acknowledgement, an error status for an instruction it does not know or a
// range past its register map, and nothing for a malformed packet or a
// broadcast. Requests go through the real bus (hardware/scs/scs_bus.h) or as
// raw bytes through a serial port on the pty.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "core/data_dir.h"
#include "hardware/scs/scs_arms_driver.h"
#include "hardware/scs/scs_bus.h"
#include "hardware/scs/scs_protocol.h"
#include "hardware/serial_port.h"
#include "hardware/sim/sim_servo_bus.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

constexpr std::uint8_t kServo = 12;  // left arm, joint 2

class SimServoBusTest : public ::testing::Test {
 protected:
  SimServoBusTest() : world_(WorldConfig::Load(DataPath("config/world_default.yaml")), 1) {
    servos_ = ScsArmsConfig::Default(world_.platform());
    servos_.reply_timeout_s = 0.2;  // the bus answers from its own thread: generous
    SimServoBusConfig config;
    config.byte_time_s = 0.0;  // no wire timing: the tests are about what is answered
    config.return_delay_s = 0.0;
    sim_ = std::make_unique<SimServoBus>(&world_, servos_, config);
    bus_ = std::make_unique<ScsBus>(
        std::make_unique<SerialPort>(sim_->port_path(), servos_.baud, "servo bus"),
        servos_.reply_timeout_s);
  }

  /// Writes `bytes` as they are on the pty and returns what comes back within the timeout.
  std::vector<std::uint8_t> Raw(const std::vector<std::uint8_t>& bytes) {
    SerialPort port(sim_->port_path(), servos_.baud, "servo bus");
    EXPECT_TRUE(port.Write(bytes.data(), bytes.size()));
    std::vector<std::uint8_t> heard(64);
    heard.resize(port.ReadSome(heard.data(), heard.size(), servos_.reply_timeout_s));
    return heard;
  }

  World world_;
  ScsArmsConfig servos_;
  std::unique_ptr<SimServoBus> sim_;
  std::unique_ptr<ScsBus> bus_;
};

TEST_F(SimServoBusTest, AReadOfThePositionRegistersGetsThePresentPosition) {
  std::vector<std::uint8_t> data;
  std::uint8_t error = 0xFF;
  ASSERT_EQ(bus_->Read(kServo, scs::reg::kPresentPosition, 2, &data, &error), BusStatus::kOk);
  EXPECT_EQ(error, 0);
  const std::vector<std::uint8_t> regs = sim_->Registers(kServo);
  ASSERT_EQ(data.size(), 2u);
  EXPECT_EQ(scs::GetU16(data.data()), scs::GetU16(&regs[scs::reg::kPresentPosition]));
  // Where the simulated joint is, through its calibration.
  const ServoCalibration& calibration = servos_.joints[0][1];
  EXPECT_EQ(scs::GetU16(data.data()),
            calibration.RawFromAngle(world_.arm(Side::kLeft).q_true_rad()[1]));
}

TEST_F(SimServoBusTest, AReadGetsTheRegistersItNamesAndNoMore) {
  std::vector<std::uint8_t> data;
  ASSERT_EQ(bus_->Read(kServo, scs::reg::kVoltage, 2, &data), BusStatus::kOk);
  const std::vector<std::uint8_t> regs = sim_->Registers(kServo);
  EXPECT_EQ(data, std::vector<std::uint8_t>(regs.begin() + scs::reg::kVoltage,
                                            regs.begin() + scs::reg::kVoltage + 2));
  ASSERT_EQ(bus_->Read(kServo, scs::reg::kId, 1, &data), BusStatus::kOk);
  EXPECT_EQ(data, std::vector<std::uint8_t>{kServo});
}

TEST_F(SimServoBusTest, AWriteIsAcknowledgedAndLandsInItsRegisters) {
  std::uint8_t error = 0xFF;
  ASSERT_EQ(bus_->Write(kServo, scs::reg::kGoalTime, {0x01, 0x2C}, &error), BusStatus::kOk);
  EXPECT_EQ(error, 0);
  const std::vector<std::uint8_t> regs = sim_->Registers(kServo);
  EXPECT_EQ(scs::GetU16(&regs[scs::reg::kGoalTime]), 300);
  EXPECT_EQ(bus_->counters().late_replies, 0);
}

TEST_F(SimServoBusTest, AnUnknownInstructionGetsAnInstructionErrorStatus) {
  const std::vector<std::uint8_t> heard = Raw(scs::Encode({kServo, 0x30, {}}));
  scs::PacketParser parser;
  bool replied = false;
  for (std::uint8_t b : heard) replied |= parser.Push(b) == scs::PacketParser::Result::kPacket;
  ASSERT_TRUE(replied) << heard.size() << " bytes heard";
  EXPECT_EQ(parser.packet().id, kServo);
  EXPECT_EQ(parser.packet().code, scs::kErrorInstruction);
  EXPECT_TRUE(parser.packet().params.empty());
}

TEST_F(SimServoBusTest, AReadPastTheRegisterMapGetsARangeErrorStatus) {
  const std::vector<std::uint8_t> heard =
      Raw(scs::EncodeRead(kServo, static_cast<std::uint8_t>(scs::reg::kCount - 1), 2));
  scs::PacketParser parser;
  bool replied = false;
  for (std::uint8_t b : heard) replied |= parser.Push(b) == scs::PacketParser::Result::kPacket;
  ASSERT_TRUE(replied) << heard.size() << " bytes heard";
  EXPECT_EQ(parser.packet().code, scs::kErrorRange);
  EXPECT_TRUE(parser.packet().params.empty());
  // The driver waits for the two bytes it asked for: a status without them is not its answer.
  std::vector<std::uint8_t> data;
  EXPECT_EQ(bus_->Read(kServo, static_cast<std::uint8_t>(scs::reg::kCount - 1), 2, &data),
            BusStatus::kTimeout);
}

TEST_F(SimServoBusTest, AMalformedPacketGetsNoReply) {
  std::vector<std::uint8_t> bad_checksum = scs::EncodeRead(kServo, scs::reg::kPresentPosition, 2);
  bad_checksum.back() ^= 0x01;
  const std::int64_t bad_before = sim_->counters().bad_packets;
  EXPECT_TRUE(Raw(bad_checksum).empty());
  EXPECT_EQ(sim_->counters().bad_packets, bad_before + 1);
  // The bus still answers the next well-formed request.
  std::vector<std::uint8_t> data;
  EXPECT_EQ(bus_->Read(kServo, scs::reg::kPresentPosition, 2, &data), BusStatus::kOk);
}

TEST_F(SimServoBusTest, ABroadcastWriteReachesEveryServoUnanswered) {
  EXPECT_TRUE(Raw(scs::EncodeWrite(scs::kBroadcastId, scs::reg::kTorqueEnable, {0})).empty());
  for (int id : {11, 12, 17, 21, 27}) EXPECT_EQ(sim_->Registers(id)[scs::reg::kTorqueEnable], 0);
}

TEST_F(SimServoBusTest, AnAbsentServoDoesNotAnswer) {
  EXPECT_EQ(bus_->Ping(99), BusStatus::kTimeout);
}

// A slow servo's reply to a READ comes during the next request to the same
// servo: the driver skips it (it carries data a PING's reply does not) and
// the bus still delivers the PING's reply within that exchange.
TEST_F(SimServoBusTest, AServosLateReplyDoesNotStandForItsNextAnswer) {
  SimServoBusConfig slow;
  slow.byte_time_s = 0.0;
  slow.return_delay_s = 0.0;
  slow.slow_ids = {kServo};
  slow.slow_extra_s = 0.3;  // past the 0.2 s timeout, within the next exchange
  sim_->SetFaults(slow);
  std::vector<std::uint8_t> data;
  ASSERT_EQ(bus_->Read(kServo, scs::reg::kPresentPosition, 2, &data), BusStatus::kTimeout);
  SimServoBusConfig healthy = slow;
  healthy.slow_ids.clear();
  sim_->SetFaults(healthy);
  EXPECT_EQ(bus_->Ping(kServo), BusStatus::kOk);
  EXPECT_EQ(bus_->counters().late_replies, 1);
}

}  // namespace
}  // namespace aerograsp
