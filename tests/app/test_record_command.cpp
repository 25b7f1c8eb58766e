#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "app/commands/record_command.h"
#include "app/commands/replay_command.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/shape_mesh.h"
#include "hardware/sequence.h"
#include "hardware/sim/sim_devices.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RecordCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = (fs::temp_directory_path() /
               (std::string("aerograsp_record_") +
                ::testing::UnitTest::GetInstance()->current_test_info()->name()))
                  .string();  // one folder per test: ctest runs them in parallel
    fs::remove_all(folder_);
    options_.out_dir = folder_;
    options_.frames = 4;
    options_.seed = 11;
    options_.motion = "crawl";
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string Run() {
    std::ostringstream out, progress;
    RunRecordCommand(options_, out, progress);
    EXPECT_THAT(progress.str(), HasSubstr("record: done"));
    return out.str();
  }
  std::string folder_;
  RecordCommandOptions options_;
};

TEST_F(RecordCommandTest, ReplayMatchesTheSimulatorFrameForFrame) {
  const std::string out = Run();
  EXPECT_THAT(out, HasSubstr("4 frames at 30 Hz"));
  EXPECT_THAT(out, HasSubstr("object crawler (crawl), seed 11"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "preview_color.png"));
  EXPECT_TRUE(fs::exists(fs::path(folder_) / "preview_depth.png"));

  // The same world and seed, run again here, gives the frames the replay reads.
  WorldConfig config = WorldConfig::Load(DataPath("config/world_default.yaml"));
  config.object.motion = "crawl";
  World world(config, 11);
  SimCamera camera(&world);
  ReplayCamera replay(folder_);
  ASSERT_TRUE(replay.has_groundtruth());
  EXPECT_EQ(replay.info().frame_rate_hz, 30.0);
  RgbdFrame simulated, replayed;
  for (int i = 0; i < 4; ++i) {
    world.StepTo(i / 30.0);
    camera.Grab(&simulated);
    ASSERT_TRUE(replay.Grab(&replayed));
    EXPECT_TRUE(simulated.color == replayed.color) << "frame " << i;
    EXPECT_TRUE(simulated.depth == replayed.depth) << "frame " << i;
    EXPECT_EQ(simulated.stamp_s, replayed.stamp_s);
    const Eigen::Isometry3d cMo = world.wMc().inverse() * world.wMo();
    EXPECT_EQ(replay.extras(i).cMo->translation(), cMo.translation());
  }
  EXPECT_FALSE(replay.Grab(&replayed));
  // The object crawls: its pose changes from frame to frame.
  EXPECT_GT((replay.extras(3).cMo->translation() - replay.extras(0).cMo->translation()).norm(),
            1e-3);
}

TEST_F(RecordCommandTest, RefusesToOverwriteUnlessAsked) {
  Run();
  try {
    Run();
    FAIL() << "expected an error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr(": holds an earlier report; --overwrite replaces it"));
  }
  options_.overwrite = true;
  options_.frames = 2;
  Run();
  EXPECT_EQ(ReplayCamera(folder_).info().frame_count, 2);
  EXPECT_FALSE(
      fs::exists(fs::path(folder_) / "color" / "000003.png"));  // nothing left of the old one
}

TEST_F(RecordCommandTest, UnknownObjectListsTheShippedOnes) {
  options_.object = "teapot";
  try {
    Run();
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("teapot: no such file and no object of that name"));
    EXPECT_THAT(e.what(), HasSubstr("crawler, pipe, u_shape"));
  }
}

TEST_F(RecordCommandTest, ASequenceOfAMeshFileReplaysWithoutNamingTheObjectAgain) {
  // A user's mesh given by a relative path, its origin at a corner of its box.
  const fs::path mesh_dir = fs::path(folder_ + "_mesh");
  fs::create_directories(mesh_dir);
  TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(0.2, 0.08, 0.06));
  for (Eigen::Vector3d& v : box.vertices) v += Eigen::Vector3d(0.1, 0.04, 0.03);
  SaveMeshPly(box, (mesh_dir / "corner_box.ply").string());
  const fs::path cwd = fs::current_path();
  fs::current_path(mesh_dir);
  options_.object = "corner_box.ply";
  options_.motion = "static";
  options_.frames = 3;
  Run();
  fs::current_path(cwd);

  const SequenceInfo info = ReplayCamera(folder_).info();
  EXPECT_EQ(info.object, fs::absolute(mesh_dir / "corner_box.ply").lexically_normal().string());
  ReplayCommandOptions replay;
  replay.sequence = folder_;
  replay.out_dir = folder_ + "_replay";
  replay.use_detector = false;
  replay.run_peer = false;
  replay.init_from_truth = true;
  std::ostringstream out, progress;
  RunReplayCommand(replay, out, progress);  // no --object
  EXPECT_THAT(out.str(), HasSubstr("object corner_box"));
  fs::remove_all(mesh_dir);
  fs::remove_all(replay.out_dir);
}

}  // namespace
}  // namespace aerograsp
