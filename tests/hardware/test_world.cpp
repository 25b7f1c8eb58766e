#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/config.h"
#include "core/data_dir.h"
#include "core/transforms.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/world.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {

WorldConfig DefaultConfig() { return WorldConfig::Load(DataPath("config/world_default.yaml")); }

/// No disturbances: the vehicle moves only when commanded.
WorldConfig CalmConfig() {
  WorldConfig c = DefaultConfig();
  c.vehicle.sway_amplitude_m.setZero();
  c.vehicle.tilt_amplitude_rad = 0.0;
  c.vehicle.gust_rate_hz = 0.0;
  c.vehicle.drift_std_m = 0.0;
  return c;
}

TEST(WorldConfigTest, DefaultsAndTheShippedFileAreValid) {
  WorldConfig defaults;
  defaults.source = "defaults";
  defaults.platform = DataPath("config/platform_4dof.yaml");
  EXPECT_NO_THROW(defaults.Validate(defaults.source, ""));
  EXPECT_NO_THROW(DefaultConfig());
}

TEST(WorldConfigTest, BadValuesNameFileKeyAndBound) {
  WorldConfig c = DefaultConfig();
  c.vehicle.delay_s = -0.1;
  try {
    c.Validate(c.source, "");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("world_default.yaml: vehicle.delay_s"), std::string::npos)
        << e.what();
  }
  c = DefaultConfig();
  c.object.motion = "fly";
  EXPECT_THROW(c.Validate(c.source, ""), ConfigError);
  c = DefaultConfig();
  c.camera.d435.min_range_m = 1.0;
  c.camera.d435.max_range_m = 0.5;
  try {
    c.Validate(c.source, "");
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("camera.d435.max_range_m"), std::string::npos) << e.what();
  }
}

TEST(WorldConfigTest, UnknownKeysAreRejected) {
  const std::string path = ::testing::TempDir() + "/world_typo.yaml";
  {
    std::ofstream out(path);
    out << "platform: " << DataPath("config/platform_4dof.yaml")
        << "\nvehicle:\n  sway_amplitud_m: [0, 0, 0]\n";
  }
  try {
    WorldConfig::Load(path);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("vehicle.sway_amplitud_m: unknown key"), std::string::npos)
        << e.what();
  }
}

TEST(WorldTest, SameSeedSameRunDifferentSeedDifferentRun) {
  WorldConfig config = DefaultConfig();
  config.object.motion = "crawl";
  config.vehicle.gust_rate_hz = 2.0;  // make the random part matter
  World a(config, 5), b(config, 5), c(config, 6);
  for (World* w : {&a, &b, &c}) w->StepTo(3.0);
  EXPECT_TRUE(a.wMd().isApprox(b.wMd(), 0.0));
  EXPECT_TRUE(a.wMo().isApprox(b.wMo(), 0.0));
  EXPECT_FALSE(a.wMd().isApprox(c.wMd(), 1e-9));
}

TEST(WorldTest, HoverSwaysWithinTheConfiguredEnvelope) {
  WorldConfig config = DefaultConfig();
  config.vehicle.gust_rate_hz = 0.0;
  config.vehicle.drift_std_m = 0.0;
  World world(config, 1);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (int i = 0; i < 2000; ++i) {
    world.Step(0.01);
    lo = lo.cwiseMin(world.wMd().translation());
    hi = hi.cwiseMax(world.wMd().translation());
  }
  const Eigen::Vector3d span = hi - lo;
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(span[a], 2.0 * config.vehicle.sway_amplitude_m[a] + 1e-9) << a;
    EXPECT_GE(span[a], 1.5 * config.vehicle.sway_amplitude_m[a])
        << a;  // 20 s covers several periods
  }
  EXPECT_EQ(world.vehicle().State().mode, FlightMode::kHold);
}

TEST(WorldTest, SetpointResponseHasTheDelayThenFirstOrder) {
  WorldConfig config = CalmConfig();
  World world(config, 1);
  SimAutopilot autopilot(&world);
  const Eigen::Vector3d start = world.wMd().translation();
  const Eigen::Vector3d goal = start + Eigen::Vector3d(0.2, 0.0, 0.0);  // 0.2 / 0.6 s < max speed
  const double dt = 0.01;
  double moved_at = -1.0, reached_63_at = -1.0;
  for (int i = 0; i < 400; ++i) {
    ASSERT_TRUE(autopilot.SetPositionTarget(goal, 0.0).accepted);
    world.Step(dt);
    const double progress = (world.wMd().translation().x() - start.x()) / 0.2;
    if (moved_at < 0 && progress > 1e-6) moved_at = world.now_s();
    if (reached_63_at < 0 && progress >= 1.0 - std::exp(-1.0)) reached_63_at = world.now_s();
  }
  EXPECT_EQ(autopilot.State().mode, FlightMode::kOffboard);
  EXPECT_NEAR(moved_at, config.vehicle.delay_s, 0.02);
  EXPECT_NEAR(reached_63_at, config.vehicle.delay_s + config.vehicle.response_time_s, 0.03);
  EXPECT_NEAR(world.wMd().translation().x(), goal.x(), 1e-3);
}

TEST(WorldTest, OffboardWithoutSetpointsFallsBackToHold) {
  World world(CalmConfig(), 1);
  SimAutopilot autopilot(&world);
  ASSERT_TRUE(autopilot.SetPositionTarget(world.wMd().translation(), 0.0).accepted);
  world.Step(0.4);
  EXPECT_EQ(autopilot.State().mode, FlightMode::kOffboard);
  world.Step(0.2);  // past offboard_timeout_s = 0.5 s
  EXPECT_EQ(autopilot.State().mode, FlightMode::kHold);
}

TEST(WorldTest, TakeOffAndLandFromTheGround) {
  WorldConfig config = CalmConfig();
  config.vehicle.start = "ground";
  World world(config, 1);
  SimAutopilot autopilot(&world);
  EXPECT_EQ(autopilot.State().mode, FlightMode::kDisarmed);
  const CommandAck refused = autopilot.Takeoff(2.0);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.reason.find("not armed"), std::string::npos);
  EXPECT_TRUE(autopilot.Arm().accepted);
  EXPECT_TRUE(autopilot.Takeoff(2.0).accepted);
  world.Step(8.0);
  EXPECT_EQ(autopilot.State().mode, FlightMode::kHold);
  EXPECT_NEAR(world.wMd().translation().z(), -2.0, 0.06);
  EXPECT_FALSE(autopilot.Disarm().accepted);  // flying
  EXPECT_TRUE(autopilot.Land().accepted);
  world.Step(10.0);
  EXPECT_EQ(autopilot.State().mode, FlightMode::kLanded);
  EXPECT_NEAR(world.wMd().translation().z(), -config.vehicle.landed_height_m, 1e-9);
  EXPECT_TRUE(autopilot.Disarm().accepted);
}

TEST(WorldTest, ServoPositionsAreQuantisedAndSpeedLimited) {
  World world(CalmConfig(), 1);
  SimArmsDriver arms(&world);
  const ArmModel& model = world.platform().arm(Side::kLeft);
  Eigen::VectorXd target = world.platform().home(Side::kLeft);
  target[0] += 1.0;
  arms.SetJointTargets(Side::kLeft, target);
  world.Step(0.1);
  const Eigen::VectorXd q = world.arm(Side::kLeft).q_true_rad();
  const double max_step = model.velocity_limits()[0] * 0.1;
  EXPECT_LE(q[0] - world.platform().home(Side::kLeft)[0], max_step + 1e-9);
  world.Step(3.0);
  const Eigen::VectorXd measured = arms.JointPositions(Side::kLeft);
  const double quantum = world.arm(Side::kLeft).quantum_rad();
  EXPECT_NEAR(quantum, 220.0 / 1023.0 * M_PI / 180.0, 1e-12);  // ~0.21 deg (docs/hardware.md)
  for (int i = 0; i < measured.size(); ++i) {
    const double counts = (measured[i] - model.lower_limits()[i]) / quantum;
    EXPECT_NEAR(counts, std::round(counts), 1e-6) << "joint " << i;
    EXPECT_NEAR(measured[i], target[i], quantum) << "joint " << i;
  }
}

TEST(WorldTest, NaNJointTargetsAreIgnored) {
  World world(CalmConfig(), 1);
  SimArmsDriver arms(&world);
  Eigen::VectorXd bad = world.platform().home(Side::kRight);
  bad[1] = std::nan("");
  arms.SetJointTargets(Side::kRight, bad);
  world.Step(0.5);
  EXPECT_TRUE(world.arm(Side::kRight).q_true_rad().allFinite());
  EXPECT_TRUE(
      world.arm(Side::kRight).q_true_rad().isApprox(world.platform().home(Side::kRight), 1e-9));
}

/// The crawler placed so that the left tool point is in the middle of one of
/// its tracks (0.03 to 0.045 m from the centre in y), closing along the
/// object's z (the track's 0.08 m height fits the 0.12 m opening;
/// tools/make_objects.py draws the crawler).
constexpr double kTrackCentre_m = 0.0375;
/// The object placed at offset_e from the left tool point: tool x (closing)
/// along object z, tool z (approach) along object x.
void PlaceAtLeftTool(World* world, const Eigen::Vector3d& offset_e) {
  Eigen::Matrix3d eRo;
  eRo.col(0) = Eigen::Vector3d(0, 0, 1);   // o x in e = e z
  eRo.col(1) = Eigen::Vector3d(0, 1, 0);   // o y in e
  eRo.col(2) = Eigen::Vector3d(-1, 0, 0);  // o z in e = -e x
  Eigen::Isometry3d eMo = Eigen::Isometry3d::Identity();
  eMo.linear() = eRo;
  eMo.translation() = offset_e;
  world->PlaceObject(world->wMe(Side::kLeft) * eMo);
}
class GripperTest : public ::testing::Test {
 protected:
  GripperTest() : world_(CalmConfig(), 1), arms_(&world_) {}
  void PlaceAtTool(const Eigen::Vector3d& offset_e) { PlaceAtLeftTool(&world_, offset_e); }
  World world_;
  SimArmsDriver arms_;
};

TEST_F(GripperTest, ClosingOnTheObjectHoldsItAtItsWidth) {
  PlaceAtTool(Eigen::Vector3d(0.0, kTrackCentre_m, 0.0));
  arms_.SetGripper(Side::kLeft, GripperCommand::kClose);
  world_.Step(1.0);
  const GripperState g = arms_.Gripper(Side::kLeft);
  EXPECT_TRUE(g.holding);
  EXPECT_NEAR(g.aperture_m, world_.object().dimensions_m.z(), 1e-6);
  EXPECT_TRUE(world_.held_by(Side::kLeft));
  // The object now moves with the gripper.
  const Eigen::Isometry3d eMo = world_.wMe(Side::kLeft).inverse() * world_.wMo();
  Eigen::VectorXd q = world_.platform().home(Side::kLeft);
  q[0] += 0.3;
  arms_.SetJointTargets(Side::kLeft, q);
  world_.Step(1.0);
  EXPECT_TRUE((world_.wMe(Side::kLeft).inverse() * world_.wMo()).isApprox(eMo, 1e-9));
  // Opening releases it: it falls to the ground.
  arms_.SetGripper(Side::kLeft, GripperCommand::kOpen);
  world_.Step(1.0);
  EXPECT_FALSE(arms_.Gripper(Side::kLeft).holding);
  EXPECT_NEAR(world_.wMo().translation().z(), -0.5 * world_.object().dimensions_m.z(), 1e-9);
}

// One gripper held the object where it sat on its pipe, then let go: it falls
// back onto the pipe, not through it to the ground (GripperTest above: away from
// the pipe it falls to the ground).
TEST(GripperReleaseTest, AnObjectReleasedAboveItsPipeLandsOnThePipe) {
  WorldConfig config = CalmConfig();
  config.object.motion = "static";
  Eigen::Isometry3d eMo = Eigen::Isometry3d::Identity();  // tool x along o z, tool z along o x
  eMo.linear().col(0) = Eigen::Vector3d(0, 0, 1);
  eMo.linear().col(1) = Eigen::Vector3d(0, 1, 0);
  eMo.linear().col(2) = Eigen::Vector3d(-1, 0, 0);
  eMo.translation() = Eigen::Vector3d(0.0, kTrackCentre_m, 0.0);
  const Eigen::Vector3d held_w = (World(config, 1).wMe(Side::kLeft) * eMo).translation();
  // The pipe moved under the held object: its resting place on the pipe 2 cm
  // below and 1 cm aside of where the gripper holds it.
  const double half_height_m = -ObjectModel::Load(config.object.name).mesh_o.BoundsMin().z();
  const Eigen::Vector3d aside_w(-std::sin(config.scene.pipe_yaw_rad),
                                std::cos(config.scene.pipe_yaw_rad), 0.0);
  config.scene.pipe_center_w_m =
      held_w + 0.01 * aside_w +
      Eigen::Vector3d(0.0, 0.0, 0.02 + config.scene.pipe_radius_m + half_height_m);
  World world(config, 1);
  SimArmsDriver arms(&world);
  world.PlaceObject(world.wMe(Side::kLeft) * eMo);
  arms.SetGripper(Side::kLeft, GripperCommand::kClose);
  world.Step(1.0);
  ASSERT_TRUE(world.held_by(Side::kLeft));
  ASSERT_LT((world.wMo().translation() - held_w).norm(), 1e-9);
  arms.SetGripper(Side::kLeft, GripperCommand::kOpen);
  world.Step(0.1);
  const Eigen::Vector3d landed_w = world.wMo().translation();
  EXPECT_NEAR(landed_w.z(), held_w.z() + 0.02, 1e-9) << "on the pipe's top";
  EXPECT_NEAR((landed_w - held_w).head<2>().norm(), 0.01, 1e-9) << "onto the pipe's axis";
  // Upright and along the pipe, as it sat before it was taken.
  EXPECT_NEAR(world.wMo().linear().col(2).dot(Eigen::Vector3d(0, 0, -1)), 1.0, 1e-9);
}

TEST_F(GripperTest, OffCentreWithinTheOpeningStillHolds) {
  PlaceAtTool(Eigen::Vector3d(0.005, kTrackCentre_m, 0.0));  // 5 mm towards one finger
  arms_.SetGripper(Side::kLeft, GripperCommand::kClose);
  world_.Step(1.0);
  EXPECT_TRUE(arms_.Gripper(Side::kLeft).holding);
  EXPECT_NEAR(arms_.Gripper(Side::kLeft).aperture_m, world_.object().dimensions_m.z() + 0.01, 1e-6);
}

// The object slides toward one pad while the pads close (a swaying vehicle
// moves the tool against the object at up to about 0.1 m/s): the width
// between the pads then grows as the gap narrows and the two meet between
// two physics steps; the pads hold it where they meet, not pass through it.
TEST(GripperSlidingTest, PadsMeetAnObjectSlidingTowardOneOfThemAndHoldIt) {
  constexpr double kStep_s = 0.002;
  for (double speed_mps = 0.02; speed_mps <= 0.12 + 1e-9; speed_mps += 0.01) {
    World world(CalmConfig(), 1);
    SimArmsDriver arms(&world);
    arms.SetGripper(Side::kLeft, GripperCommand::kClose);
    for (double t = 0.0; t < 0.3 && !arms.Gripper(Side::kLeft).holding; t += kStep_s) {
      PlaceAtLeftTool(&world, Eigen::Vector3d(speed_mps * t, kTrackCentre_m, 0.0));
      world.Step(kStep_s);
    }
    const GripperState g = arms.Gripper(Side::kLeft);
    EXPECT_TRUE(g.holding) << speed_mps << " m/s";
    // They meet where the 0.08 m track, off centre by d = v t, spans 0.08 + 2 d
    // of the gap 0.12 - 0.15 t.
    const double meet_s = 0.04 / (0.15 + 2.0 * speed_mps);
    EXPECT_NEAR(g.aperture_m, 0.12 - 0.15 * meet_s, 0.002) << speed_mps << " m/s";
  }
}

TEST_F(GripperTest, ClosingOnNothingClosesFully) {
  PlaceAtTool(Eigen::Vector3d(0.0, 0.0, 0.3));  // 0.3 m ahead of the fingers
  arms_.SetGripper(Side::kLeft, GripperCommand::kClose);
  world_.Step(0.4);
  EXPECT_TRUE(arms_.Gripper(Side::kLeft).moving);
  world_.Step(0.6);
  const GripperState g = arms_.Gripper(Side::kLeft);
  EXPECT_FALSE(g.holding);
  EXPECT_TRUE(g.closed);
  EXPECT_EQ(g.aperture_m, 0.0);
}

TEST_F(GripperTest, AnObjectWiderThanTheOpeningIsNotHeld) {
  // Closing along the crawler's 0.22 m length.
  Eigen::Isometry3d eMo = Eigen::Isometry3d::Identity();
  world_.PlaceObject(world_.wMe(Side::kLeft) * eMo);
  arms_.SetGripper(Side::kLeft, GripperCommand::kClose);
  world_.Step(1.0);
  EXPECT_FALSE(arms_.Gripper(Side::kLeft).holding);
}

TEST(SimCameraTest, TheObjectIsWhereTheGroundTruthSaysItIs) {
  WorldConfig config = DefaultConfig();
  World world(config, 3);
  SimCamera camera(&world);
  RgbdFrame frame;
  for (int i = 0; i < 3; ++i) {
    world.Step(0.5);
    ASSERT_TRUE(camera.Grab(&frame));
    EXPECT_EQ(frame.index, i);
    EXPECT_DOUBLE_EQ(frame.stamp_s, world.now_s());
    const Eigen::Isometry3d cMo = world.wMc().inverse() * world.wMo();
    // The top of the crawler's track (o z up) is on the object in the image.
    const Eigen::Vector3d top_c =
        cMo * Eigen::Vector3d(0, kTrackCentre_m, 0.5 * world.object().dimensions_m.z());
    const Eigen::Vector2d uv = camera.intrinsics().Project(top_c);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    ASSERT_TRUE(u >= 0 && u < 640 && v >= 0 && v < 480) << uv.transpose();
    EXPECT_EQ(camera.last_truth().object_id.at(u, v), camera.object_render_id());
    EXPECT_NEAR(camera.last_truth().depth_m.at(u, v), top_c.z(), 2e-3);
    // The measured depth there agrees within 4 sigma of the noise model, or is a hole.
    const std::uint16_t d = frame.depth.at(u, v);
    if (d != 0) {
      EXPECT_NEAR(d * 0.001, top_c.z(),
                  4.0 * config.camera.d435.DepthNoiseStdM(top_c.z(), 640) + 1e-3);
    }
  }
}

TEST(SimCameraTest, AMeshOnTheObjectMovesWithItAndIsRendered) {
  World world(CalmConfig(), 3);
  SimCamera camera(&world);
  // A 4 cm white square 1 mm above the middle of the crawler's top, facing up (+z_o).
  RenderMesh square;
  square.mesh.vertices = {
      {-0.02, -0.02, 0.0}, {0.02, -0.02, 0.0}, {0.02, 0.02, 0.0}, {-0.02, 0.02, 0.0}};
  square.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  square.material.albedo = {1.0f, 1.0f, 1.0f};
  const Eigen::Isometry3d oMm =
      MakeTransform(Eigen::Vector3d(0, 0, 0.5 * world.object().dimensions_m.z() + 0.001),
                    Eigen::Vector3d::Zero());
  world.AttachToObject(square, oMm);
  const Eigen::Isometry3d wMo =
      world.wMo() * MakeTransform(Eigen::Vector3d(0.05, 0.02, 0), Eigen::Vector3d(0, 0, 0.3));
  world.PlaceObject(wMo);
  ASSERT_EQ(world.attachments().size(), 1u);
  EXPECT_TRUE(world.wMattachment(world.attachments()[0]).isApprox(wMo * oMm, 1e-12));
  RgbdFrame frame;
  ASSERT_TRUE(camera.Grab(&frame));
  const Eigen::Vector3d centre_c = world.wMc().inverse() * wMo * oMm.translation();
  const Eigen::Vector2d uv = camera.intrinsics().Project(centre_c);
  const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
  ASSERT_TRUE(u >= 0 && u < 640 && v >= 0 && v < 480) << uv.transpose();
  EXPECT_NE(camera.last_truth().object_id.at(u, v),
            camera.object_render_id());  // the square hides the object
  EXPECT_NEAR(camera.last_truth().depth_m.at(u, v), centre_c.z(), 2e-3);
}

TEST(SimCameraTest, AMeshHeldInFrontOfTheCameraStaysInPlaceInTheImageAndMoves) {
  World world(DefaultConfig(), 3);  // the vehicle sways: the mesh follows the camera
  SimCamera camera(&world);
  RenderMesh square;  // 4 cm, facing the camera (-z_m towards it)
  square.mesh.vertices = {
      {-0.02, -0.02, 0.0}, {0.02, -0.02, 0.0}, {0.02, 0.02, 0.0}, {-0.02, 0.02, 0.0}};
  square.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  square.material.albedo = {1.0f, 1.0f, 1.0f};
  const Eigen::Isometry3d cMm =
      MakeTransform(Eigen::Vector3d(0.1, -0.05, 0.3), Eigen::Vector3d::Zero());
  const std::size_t index = world.AttachToCamera(square, cMm);
  RgbdFrame frame;
  for (double t_s : {0.0, 0.7}) {
    world.StepTo(t_s);
    EXPECT_TRUE(world.wMattachment(world.attachments()[index]).isApprox(world.wMc() * cMm, 1e-12));
    ASSERT_TRUE(camera.Grab(&frame));
    const Eigen::Vector2d uv = camera.intrinsics().Project(cMm.translation());
    EXPECT_NEAR(camera.last_truth().depth_m.at(static_cast<int>(uv.x()), static_cast<int>(uv.y())),
                0.3, 1e-3);
  }
  const Eigen::Isometry3d moved =
      MakeTransform(Eigen::Vector3d(-0.1, 0.05, 0.4), Eigen::Vector3d::Zero());
  world.MoveAttachment(index, moved);
  ASSERT_TRUE(camera.Grab(&frame));
  const Eigen::Vector2d uv = camera.intrinsics().Project(moved.translation());
  EXPECT_NEAR(camera.last_truth().depth_m.at(static_cast<int>(uv.x()), static_cast<int>(uv.y())),
              0.4, 1e-3);
  EXPECT_THROW(world.MoveAttachment(index + 1, moved), std::out_of_range);
}

TEST(SimCameraTest, TheOccluderHidesTheObjectFullyOnlyInItsWindows) {
  WorldConfig config = DefaultConfig();
  config.occluder.enabled = true;
  config.occluder.start_s = 0.5;
  config.occluder.duration_s = 0.3;
  config.occluder.period_s = 1.0;
  config.Validate(config.source, "");
  World world(config, 3);
  SimCamera camera(&world);
  RgbdFrame frame;
  auto object_pixels = [&] {
    const auto& ids = camera.last_truth().object_id.data;
    return std::count(ids.begin(), ids.end(), camera.object_render_id());
  };
  // Before, between and after its windows [0.5, 0.8) and [1.5, 1.8) s.
  for (double t_s : {0.4, 0.6, 0.79, 1.2, 1.6, 1.9}) {
    world.StepTo(t_s);
    ASSERT_TRUE(camera.Grab(&frame));
    const bool hidden = (t_s >= 0.5 && t_s < 0.8) || (t_s >= 1.5 && t_s < 1.8);
    EXPECT_EQ(world.occluder_active(), hidden) << t_s;
    if (hidden) {
      EXPECT_EQ(object_pixels(), 0) << t_s;
      // The panel is at its distance on the line of sight: the image centre sees it.
      const int u = camera.intrinsics().width / 2, v = camera.intrinsics().height / 2;
      EXPECT_NEAR(camera.last_truth().depth_m.at(u, v), config.occluder.distance_m, 0.05) << t_s;
    } else {
      EXPECT_GT(object_pixels(), 1000) << t_s;
    }
  }
  config.occluder.period_s = 0.2;  // shorter than the hide: it would never end
  EXPECT_THROW(config.Validate(config.source, ""), ConfigError);
}

TEST(WorldConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  WorldConfig c = DefaultConfig();
  c.vehicle.delay_s = 3.0;
  EXPECT_NE(testing::ValidationMessage(c, "w.yaml", "")
                .find("w.yaml: vehicle.delay_s: 3 s is above the upper bound 2 s"),
            std::string::npos);
  EXPECT_NE(testing::ValidationMessage(c, "w.yaml", "world.")
                .find("w.yaml: world.vehicle.delay_s: 3 s is above the upper bound 2 s"),
            std::string::npos);
  c = DefaultConfig();
  c.camera.image_scale = 0.7;
  EXPECT_NE(
      testing::ValidationMessage(c, "w.yaml", "world.").find("w.yaml: world.camera.image_scale: "),
      std::string::npos);
  c = DefaultConfig();
  c.camera.d435.baseline_m = 0.5;
  EXPECT_NE(testing::ValidationMessage(c, "w.yaml", "world.")
                .find("w.yaml: world.camera.d435.baseline_m: 0.5 m is above the upper bound 0.2 m"),
            std::string::npos);
}

}  // namespace
}  // namespace aerograsp
