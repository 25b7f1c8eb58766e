#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/plan_command.h"
#include "core/mesh.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class PlanCommandTest : public ::testing::Test {
 protected:
  PlanCommandTest() {
    dir_ = fs::temp_directory_path() / ("aerograsp_plan_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    options_.config_path = std::string(AEROGRASP_DATA_DIR) + "/config/platform_4dof.yaml";
    options_.out_dir = (dir_ / "out").string();
    options_.cache_dir = (dir_ / "cache").string();
    options_.repeats = 1;
  }
  ~PlanCommandTest() override { fs::remove_all(dir_); }
  std::string Run() {
    std::ostringstream out;
    RunPlanCommand(options_, out);
    return out.str();
  }
  nlohmann::json Summary() {
    std::ifstream in(fs::path(options_.out_dir) / "summary.json");
    return nlohmann::json::parse(in);
  }
  fs::path dir_;
  PlanCommandOptions options_;
};

TEST_F(PlanCommandTest, ShippedObjectGivesTableSummaryPngAndCache) {
  options_.object = "u_shape";
  const std::string first = Run();
  EXPECT_THAT(first, HasSubstr("rank"));
  EXPECT_THAT(first, HasSubstr("cache missing"));
  const nlohmann::json j = Summary();
  for (const char* key : {"contacts_ms", "candidates", "feasible_left", "feasible_right",
                          "dual_pairs", "feasibility_us_per_grasp", "quality_us_per_grasp"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_GT(j["dual_pairs"].get<int>(), 0);
  EXPECT_TRUE(j["feasible"].get<bool>());
  EXPECT_TRUE(fs::exists(fs::path(options_.out_dir) / "grasps.png"));
  // Second run reads the cache.
  EXPECT_THAT(Run(), HasSubstr("cache ok"));
  EXPECT_EQ(Summary()["dual_pairs"], j["dual_pairs"]);
  // A damaged cache is detected and rebuilt.
  for (const auto& entry : fs::directory_iterator(options_.cache_dir)) {
    std::fstream f(entry.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put(static_cast<char>(0x5a));
  }
  const std::string third = Run();
  EXPECT_THAT(third, HasSubstr("checksum mismatch (corrupt); regenerating"));
  EXPECT_EQ(Summary()["dual_pairs"], j["dual_pairs"]);
}

TEST_F(PlanCommandTest, ObjectTooBigForTheGripperSaysSo) {
  const std::string path = (dir_ / "big_box.ply").string();
  SaveMeshPly(test::BoxMesh(Eigen::Vector3d(0.3, 0.3, 0.3)), path);
  options_.object = path;
  EXPECT_THAT(Run(), HasSubstr("No feasible dual grasp: the object is too big for the gripper"));
  EXPECT_FALSE(Summary()["feasible"].get<bool>());
}

TEST_F(PlanCommandTest, ObjectOutOfReachSaysWhichArmAndWhy) {
  options_.object = "pipe";
  options_.object_xyz_m = Eigen::Vector3d(1.0, 0.0, 0.5);
  const std::string out = Run();
  EXPECT_THAT(out, HasSubstr("left arm: none of"));
  EXPECT_THAT(out, HasSubstr("unreachable"));
  EXPECT_THAT(out, HasSubstr("reach 0.443 m"));
}

TEST_F(PlanCommandTest, MissingOpenOrUnknownMeshNamesTheFile) {
  options_.object = (dir_ / "nothing.ply").string();
  try {
    Run();
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nothing.ply"));
  }
  TriangleMesh open = test::BoxMesh(Eigen::Vector3d::Constant(0.05));
  open.triangles.pop_back();
  const std::string path = (dir_ / "open.ply").string();
  SaveMeshPly(open, path);
  options_.object = path;
  try {
    Run();
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("open.ply"));
    EXPECT_THAT(e.what(), HasSubstr("boundary edges"));
  }
  options_.object = "teapot";
  try {
    Run();
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("teapot: not a shipped object (crawler"));
  }
}

}  // namespace
}  // namespace aerograsp
