// The PX4 client against the simulated PX4 over MAVLink 2 on UDP loopback,
// pumped on the world's simulated clock.
#include <gtest/gtest.h>

#include <memory>

#include "core/data_dir.h"
#include "hardware/mavlink/px4_autopilot.h"
#include "hardware/rgbd_camera.h"
#include "hardware/sim/sim_px4.h"
#include "hardware/sim/world.h"

namespace aerograsp {
namespace {

constexpr double kStep_s = 0.01;
const std::string kKeyHex = "5a17f00d5a17f00d5a17f00d5a17f00d5a17f00d5a17f00d5a17f00d5a17f00d";

WorldConfig OnTheGround() {
  WorldConfig c = WorldConfig::Load(DataPath("config/world_default.yaml"));
  c.vehicle.start = "ground";
  c.vehicle.sway_amplitude_m.setZero();
  c.vehicle.tilt_amplitude_rad = 0.0;
  c.vehicle.gust_rate_hz = 0.0;
  c.vehicle.drift_std_m = 0.0;
  return c;
}

class Px4AutopilotTest : public ::testing::Test {
 protected:
  Px4AutopilotTest() : world_(OnTheGround(), 1) {
    config_.udp_local_host = "127.0.0.1";
    config_.udp_local_port = 0;
    // Generous: the peer answers at once from its own thread, which a loaded
    // machine may hold back; an ACK that is late, not lost, must not be sent again.
    config_.command_timeout_s = 1.0;
  }

  void Start(const SimPx4Config& peer_config = {}) {
    peer_ = std::make_unique<SimPx4>(&world_, peer_config);
    config_.udp_remote_port = peer_->port();
    client_ = std::make_unique<Px4Autopilot>(
        std::make_unique<UdpLink>("127.0.0.1", 0, "127.0.0.1", peer_->port(), "autopilot"), config_,
        [this] { return world_.now_s(); });
  }

  /// The owner's loop: the world (through the peer), then the client.
  void Run(double seconds, const Eigen::Vector3d* stream_p_w = nullptr) {
    const int steps = static_cast<int>(seconds / kStep_s + 0.5);
    for (int i = 0; i < steps; ++i) {
      peer_->StepWorld(kStep_s);
      if (stream_p_w) client_->SetPositionTarget(*stream_p_w, 0.0);
      client_->Spin();
      peer_->WaitForSetpoints(client_->setpoints_sent(), 0.2);
    }
  }

  World world_;
  Px4Config config_;
  std::unique_ptr<SimPx4> peer_;
  std::unique_ptr<Px4Autopilot> client_;
};

TEST_F(Px4AutopilotTest, ConnectsAndSeesTheVehicleOnTheGround) {
  Start();
  client_->Connect();
  Run(0.2);
  const VehicleState state = client_->State();
  EXPECT_TRUE(state.link_ok);
  EXPECT_EQ(state.mode, FlightMode::kDisarmed);
  EXPECT_NEAR(state.wMd.translation().z(), -world_.config().vehicle.landed_height_m, 1e-6);
}

TEST_F(Px4AutopilotTest, FliesArmTakeoffOffboardLandDisarm) {
  Start();
  client_->Connect();
  Run(0.1);
  ASSERT_TRUE(client_->Arm().accepted);
  Run(0.6);  // heartbeats come at 2 Hz
  EXPECT_EQ(client_->State().mode, FlightMode::kLanded);

  const CommandAck takeoff = client_->Takeoff(2.0);
  ASSERT_TRUE(takeoff.accepted) << takeoff.reason;
  Run(0.6);
  EXPECT_EQ(client_->State().mode, FlightMode::kTakingOff);
  Run(8.0);
  EXPECT_EQ(client_->State().mode, FlightMode::kHold);
  EXPECT_NEAR(client_->State().wMd.translation().z(), -2.0, 0.06);

  const Eigen::Vector3d target(1.0, 0.5, -2.0);
  const std::int64_t setpoints_before = peer_->setpoints_received();
  const CommandAck offboard = client_->SetPositionTarget(target, 0.0);
  ASSERT_TRUE(offboard.accepted) << offboard.reason;
  EXPECT_GE(peer_->setpoints_received() - setpoints_before, 3);  // streamed before the switch
  Run(6.0, &target);
  EXPECT_EQ(client_->State().mode, FlightMode::kOffboard);
  EXPECT_LT((client_->State().wMd.translation() - target).norm(), 0.05);

  ASSERT_TRUE(client_->Land().accepted);
  Run(0.6);
  EXPECT_EQ(client_->State().mode, FlightMode::kLanding);
  Run(8.0);
  EXPECT_EQ(client_->State().mode, FlightMode::kLanded);
  EXPECT_TRUE(client_->Disarm().accepted);
  Run(0.6);
  EXPECT_EQ(client_->State().mode, FlightMode::kDisarmed);
}

TEST_F(Px4AutopilotTest, TheSetpointStreamRunsAtTheConfiguredRate) {
  Start();
  client_->Connect();
  ASSERT_TRUE(client_->Arm().accepted);
  ASSERT_TRUE(client_->Takeoff(1.5).accepted);
  Run(6.0);
  const Eigen::Vector3d target(0.0, 0.0, -1.5);
  ASSERT_TRUE(client_->SetPositionTarget(target, 0.0).accepted);
  const std::int64_t before = peer_->setpoints_received();
  Run(2.0);  // Spin alone keeps the stream going
  const std::int64_t per_second = (peer_->setpoints_received() - before) / 2;
  EXPECT_GE(per_second, 10);
  EXPECT_NEAR(per_second, config_.setpoint_hz, 2);
  EXPECT_EQ(client_->State().mode, FlightMode::kOffboard);  // no offboard-loss failsafe
}

TEST_F(Px4AutopilotTest, ARefusalCarriesPx4sReason) {
  Start();
  client_->Connect();
  const CommandAck ack = client_->Takeoff(2.0);
  EXPECT_FALSE(ack.accepted);
  EXPECT_EQ(ack.reason, "take-off temporarily rejected: take-off refused: not armed");
}

TEST_F(Px4AutopilotTest, ALostCommandIsSentAgain) {
  Start();
  client_->Connect();
  peer_->DropNextCommands(1);
  const CommandAck ack = client_->Arm();
  EXPECT_TRUE(ack.accepted) << ack.reason;
  EXPECT_EQ(client_->commands_sent(), 2);
  EXPECT_EQ(peer_->commands_received(), 2);
}

TEST_F(Px4AutopilotTest, NoAckAtAllGivesUpAfterTheAttempts) {
  Start();
  client_->Connect();
  peer_->DropNextCommands(100);
  const CommandAck ack = client_->Arm();
  EXPECT_FALSE(ack.accepted);
  EXPECT_NE(ack.reason.find("arm: no COMMAND_ACK after 3 attempts (udp 127.0.0.1:"),
            std::string::npos)
      << ack.reason;
  EXPECT_EQ(peer_->commands_received(), 3);
}

TEST_F(Px4AutopilotTest, LinkLossIsDetectedAndRecovered) {
  Start();
  client_->Connect();
  Run(0.5);
  EXPECT_TRUE(client_->State().link_ok);
  peer_->SetSilent(true);
  Run(config_.link_timeout_s + 0.1);
  EXPECT_FALSE(client_->State().link_ok);
  peer_->SetSilent(false);
  Run(0.6);
  EXPECT_TRUE(client_->State().link_ok);
}

TEST_F(Px4AutopilotTest, SignedLinkWorksAndUnsignedPeersAreIgnored) {
  config_.signing_key_hex = kKeyHex;
  SimPx4Config peer_config;
  peer_config.signing_key_hex = kKeyHex;
  Start(peer_config);
  client_->Connect();
  EXPECT_TRUE(client_->Arm().accepted);

  // The same client against a peer that does not sign: nothing it says counts.
  world_.vehicle().Disarm();
  config_.connect_timeout_s = 0.2;
  Start();
  try {
    client_->Connect();
    FAIL() << "expected a HardwareError";
  } catch (const HardwareError& e) {
    EXPECT_NE(std::string(e.what()).find("no heartbeat from system 1 component 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_GT(client_->parser_counters().bad_signature, 0);
}

TEST_F(Px4AutopilotTest, NobodyThereNamesTheLink) {
  config_.connect_timeout_s = 0.2;
  UdpLink silent("127.0.0.1", 0, "", 0, "nobody");
  Px4Autopilot client(
      std::make_unique<UdpLink>("127.0.0.1", 0, "127.0.0.1", silent.local_port(), "autopilot"),
      config_, [] { return 0.0; });
  try {
    client.Connect();
    FAIL() << "expected a HardwareError";
  } catch (const HardwareError& e) {
    EXPECT_NE(std::string(e.what()).find("autopilot (udp 127.0.0.1:"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("-> 127.0.0.1:" + std::to_string(silent.local_port())),
              std::string::npos)
        << e.what();
  }
}

TEST_F(Px4AutopilotTest, TheClientsThreadReceivesOnItsOwn) {
  Start();
  client_->Connect();
  client_->StartThread();
  const CommandAck ack = client_->Arm();  // the thread receives the ACK
  EXPECT_TRUE(ack.accepted) << ack.reason;
  client_->StopThread();
}

}  // namespace
}  // namespace aerograsp
