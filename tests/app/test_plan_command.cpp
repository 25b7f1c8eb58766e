#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/commands/object_command.h"
#include "app/commands/plan_command.h"
#include "core/config.h"
#include "core/mesh.h"
#include "tests/common/earlier_report.h"
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
  options_.overwrite = true;
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

TEST_F(PlanCommandTest, AnEarlierReportIsRefusedAndReplacedWithOverwrite) {
  options_.object = "u_shape";
  testing::ExpectRefusesAnEarlierReport([&] { Run(); }, options_.out_dir);
  options_.overwrite = true;
  EXPECT_THAT(Run(), HasSubstr("Wrote " + options_.out_dir + "/summary.json"));
  testing::ExpectReplacedTheEarlierReport(options_.out_dir);
  EXPECT_TRUE(fs::exists(fs::path(options_.out_dir) / "grasps.png"));
}

TEST_F(PlanCommandTest, PlaceSearchesWhereTheMissionHoldsTheObjectAndPlansThere) {
  options_.object = "crawler";
  options_.object_xyz_m = Eigen::Vector3d(0.075, 0.0, 0.47);  // the mission's grasp_dto_m
  options_.place = true;
  const std::string out = Run();
  EXPECT_THAT(out, HasSubstr("Placement (the mission's): the object's origin at ["));
  const nlohmann::json j = Summary();
  ASSERT_TRUE(j.contains("placement"));
  EXPECT_GT(j["placement"]["dual_grasps"].get<int>(), 0);
  // The plan is made where the placement put the object.
  const std::vector<double> placed = j["placement"]["dMo_xyz_m"];
  const std::vector<double> planned = j["dMo_xyz_m"];
  EXPECT_EQ(placed, planned);
  EXPECT_TRUE(j["feasible"].get<bool>());
}

TEST_F(PlanCommandTest, ObjectTooBigForTheGripperSaysSo) {
  const std::string path = (dir_ / "big_box.ply").string();
  SaveMeshPly(test::BoxMesh(Eigen::Vector3d(0.3, 0.3, 0.3)), path);
  options_.object = path;
  EXPECT_THAT(Run(), HasSubstr("No feasible dual grasp: the object is too big for the gripper"));
  EXPECT_FALSE(Summary()["feasible"].get<bool>());
}

// A mesh far smaller than the rays' spacing (0.8 um: in the wrong units) meets
// no ray; it is not "too big for the gripper".
TEST_F(PlanCommandTest, ObjectSmallerThanTheRaysSpacingSaysSo) {
  const std::string path = (dir_ / "tiny_box.ply").string();
  SaveMeshPly(test::BoxMesh(Eigen::Vector3d(8e-7, 8e-7, 8e-7)), path);
  options_.object = path;
  const std::string out = Run();
  EXPECT_THAT(out, HasSubstr("No feasible dual grasp: no contact pair on the object: "));
  EXPECT_THAT(out, HasSubstr("smaller than the rays' spacing: is the mesh in metres?"));
  EXPECT_THAT(out, ::testing::Not(HasSubstr("too big")));
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
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nothing.ply: no such file"));
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
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("teapot: no such file and no object of that name (shipped: "
                                    "crawler, pipe, u_shape"));
  }
}

TEST_F(PlanCommandTest, AnImportedBoxWhoseOriginIsACornerIsPlacedByItsCentre) {
  // A plain box mesh as CAD tools write it: origin at a corner, quads, no colours.
  const std::string obj = (dir_ / "corner_box.obj").string();
  {
    std::ofstream out(obj);
    for (int i = 0; i < 8; ++i) {
      out << "v " << ((i & 1) ? 0.2 : 0.0) << " " << ((i & 2) ? 0.08 : 0.0) << " "
          << ((i & 4) ? 0.06 : 0.0) << "\n";
    }
    out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\n";
  }
  ObjectImportOptions import;
  import.mesh_path = obj;
  import.name = "corner_box";
  import.objects_dir = (dir_ / "objects").string();
  std::ostringstream import_out;
  RunObjectImport(import, import_out);
  ASSERT_EQ(setenv("AEROGRASP_OBJECTS_DIR", import.objects_dir.c_str(), 1), 0);
  options_.object = "corner_box";
  const std::string out = Run();
  unsetenv("AEROGRASP_OBJECTS_DIR");
  EXPECT_THAT(out,
              HasSubstr("Placed with its bounding-box centre ([0.1000 0.0400 0.0300] m in o)"));
  const nlohmann::json j = Summary();
  EXPECT_TRUE(j["feasible"].get<bool>()) << out;
  EXPECT_GT(j["dual_pairs"].get<int>(), 0);
  // dMo puts o's origin (the corner) off the requested centre by the rotated half extents.
  EXPECT_NEAR(j["dMo_xyz_m"][2].get<double>(), 0.46 + 0.03, 1e-9);
}

}  // namespace
}  // namespace aerograsp
