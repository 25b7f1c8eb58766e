#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/commands/object_command.h"
#include "core/config.h"
#include "core/mesh.h"
#include "core/object_model.h"
#include "core/shape_mesh.h"
#include "tests/common/output_folder_test.h"
#include "tests/common/test_meshes.h"
#include "tests/common/validation_message.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// A binary STL as CAD tools write it: an 80-byte header, a count, then per
/// triangle a normal, three corners and a 2-byte attribute (little endian).
void WriteBinaryStl(const TriangleMesh& mesh, const std::string& path) {
  std::string bytes(80, ' ');
  const auto append = [&bytes](const auto& value) {
    char raw[sizeof(value)];
    std::memcpy(raw, &value, sizeof(value));
    bytes.append(raw, sizeof(value));
  };
  append(static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3f n = mesh.TriangleNormal(t).cast<float>();
    for (int a = 0; a < 3; ++a) append(n[a]);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f v =
          mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])].cast<float>();
      for (int a = 0; a < 3; ++a) append(v[a]);
    }
    append(std::uint16_t{0});
  }
  std::ofstream(path, std::ios::binary) << bytes;
}

/// An OBJ of an axis-aligned box with quad faces, its origin at a corner.
/// `reversed`: one face written clockwise (as some exporters mix them).
void WriteBoxObj(const Eigen::Vector3d& size, const std::string& path, bool reversed = false) {
  std::ofstream out(path);
  out << "# box\no box\n";
  for (int i = 0; i < 8; ++i) {
    out << "v " << ((i & 1) ? size.x() : 0.0) << " " << ((i & 2) ? size.y() : 0.0) << " "
        << ((i & 4) ? size.z() : 0.0) << "\n";
  }
  out << "vn 0 0 1\n";
  out << (reversed ? "f 1 2 4 3\n" : "f 1//1 3//1 4//1 2//1\n");  // bottom (z = 0)
  out << "f 5 6 8 7\nf 1 2 6 5\nf 2 4 8 6\nf 4 3 7 8\nf 3 1 5 7\n";
}

class ObjectCommandTest : public testing::OutputFolderTest {
 protected:
  ObjectCommandTest() : OutputFolderTest("aerograsp_object_") {}
  void SetUp() override {
    OutputFolderTest::SetUp();
    fs::create_directories(folder_);
    options_.objects_dir = (fs::path(folder_) / "objects").string();
  }
  std::string Run() {
    std::ostringstream out;
    RunObjectImport(options_, out);
    return out.str();
  }
  std::string Error() {
    try {
      Run();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "no error";
  }
  std::string Path(const std::string& name) const { return (fs::path(folder_) / name).string(); }
  ObjectImportOptions options_;
};

TEST_F(ObjectCommandTest, ACubeFromABinaryStlInMillimetresGetsItsGroupAndKeepsItsFrame) {
  // 85 mm, origin at a corner, each triangle with its own corners (STL).
  WriteBinaryStl(test::BoxMesh(Eigen::Vector3d::Constant(85), Eigen::Vector3d::Constant(42.5)),
                 Path("cube.stl"));
  options_.mesh_path = Path("cube.stl");
  options_.name = "cube";
  options_.units = "mm";
  const std::string out = Run();
  EXPECT_THAT(out, HasSubstr("read: 8 vertices, 12 triangles, in millimetres"));  // STL: merged
  EXPECT_THAT(out, HasSubstr("repairs: none needed"));
  EXPECT_THAT(out, HasSubstr("size: 0.0850 x 0.0850 x 0.0850 m"));
  EXPECT_THAT(out, HasSubstr("estimated at 300 kg/m^3"));
  EXPECT_THAT(out, HasSubstr("symmetry: 24 rotations (a cube's group)"));

  const ObjectModel model = ObjectModel::Load(fs::path(options_.objects_dir) / "cube");
  EXPECT_EQ(model.name, "cube");
  EXPECT_EQ(model.symmetry.rotations.size(), 24u);
  EXPECT_TRUE(model.mesh_o.BoundsMin().isZero(1e-7));  // not re-centred
  EXPECT_NEAR(model.mass_kg, 300.0 * 0.085 * 0.085 * 0.085, 1e-6);
  EXPECT_NEAR(model.inertia_kg_m2(0, 0), model.mass_kg * 2 * 0.085 * 0.085 / 12, 1e-8);
  EXPECT_TRUE(model.center_of_mass_o.isApprox(Eigen::Vector3d::Constant(0.0425), 1e-6));
}

TEST_F(ObjectCommandTest, ShowSaysWhereAnObjectIsAndWhatItIs) {
  WriteBoxObj(Eigen::Vector3d(0.2, 0.1, 0.05), Path("box.obj"));
  options_.mesh_path = Path("box.obj");
  options_.name = "shown";
  const std::string folder = RunObjectImport(options_, std::cout);
  std::ostringstream out, path;
  RunObjectShow(folder, false, out);
  EXPECT_THAT(out.str(), HasSubstr("object shown: " + folder + "/object.yaml"));
  EXPECT_THAT(out.str(), HasSubstr("bounding-box centre [0.1000, 0.0500, 0.0250] m in o"));
  EXPECT_THAT(out.str(), HasSubstr("symmetry: 4 rotations"));
  EXPECT_THAT(out.str(), HasSubstr("detector: none (train one: scripts/train_detectors.sh "));
  RunObjectShow(folder, true, path);
  EXPECT_EQ(path.str(), folder + "\n");
  std::ostringstream ignored;
  EXPECT_THROW(RunObjectShow(Path("box.obj"), true, ignored), ConfigError);
}

TEST_F(ObjectCommandTest, DuplicateVerticesOfATriangleSoupAreMerged) {
  // Each triangle with its own corners, written to text with rounding noise.
  const TriangleMesh box = test::BoxMesh(Eigen::Vector3d(0.2, 0.1, 0.05));
  std::ofstream obj(Path("soup.obj"));
  obj.precision(12);
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = box.vertices[static_cast<std::size_t>(box.triangles[t][k])] +
                                Eigen::Vector3d::Constant(1e-11 * static_cast<double>(t));
      obj << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    obj << "f -3 -2 -1\n";
  }
  obj.close();
  options_.mesh_path = Path("soup.obj");
  options_.name = "soup";
  EXPECT_THAT(Run(), HasSubstr("repaired: duplicate vertices merged: 28"));
}

TEST_F(ObjectCommandTest, EveryCommandFindsAnImportedObjectByName) {
  WriteBoxObj(Eigen::Vector3d(0.2, 0.1, 0.05), Path("box.obj"));
  options_.mesh_path = Path("box.obj");
  options_.name = "my_box";
  options_.mass_kg = 0.35;
  ASSERT_EQ(setenv("AEROGRASP_OBJECTS_DIR", options_.objects_dir.c_str(), 1), 0);
  options_.objects_dir.clear();  // the default: the folder of $AEROGRASP_OBJECTS_DIR
  EXPECT_THAT(Run(), HasSubstr("use it as: --object my_box"));
  const ObjectModel model = ObjectModel::Load("my_box");
  unsetenv("AEROGRASP_OBJECTS_DIR");
  EXPECT_EQ(model.reference, "my_box");
  EXPECT_DOUBLE_EQ(model.mass_kg, 0.35);
  EXPECT_FALSE(model.mass_estimated);
  EXPECT_EQ(model.symmetry.rotations.size(), 4u);          // read back from object.yaml
  EXPECT_THROW(ObjectModel::Load("my_box"), ConfigError);  // not searched without the variable
}

TEST_F(ObjectCommandTest, InconsistentQuadFacesAreTurnedOutwards) {
  WriteBoxObj(Eigen::Vector3d(0.2, 0.1, 0.05), Path("mixed.obj"), /*reversed=*/true);
  options_.mesh_path = Path("mixed.obj");
  options_.name = "mixed";
  EXPECT_THAT(Run(), HasSubstr("repaired: triangles turned to face out, consistently with their "
                               "neighbours: 2"));
  const MeshCheck check =
      CheckMesh(ObjectModel::Load(fs::path(options_.objects_dir) / "mixed").mesh_o);
  EXPECT_TRUE(check.IsClosed()) << check.Describe();
}

TEST_F(ObjectCommandTest, MillimetresReadAsMetresAreRefusedWithTheSizeAndAHint) {
  WriteBoxObj(Eigen::Vector3d(85, 85, 85), Path("mm.obj"));
  options_.mesh_path = Path("mm.obj");
  options_.name = "mm";
  const std::string error = Error();
  EXPECT_THAT(error, HasSubstr("mm.obj: the mesh is 85 x 85 x 85 in the file's units, 85 m across "
                               "read as metres (--units m)"));
  EXPECT_THAT(error, HasSubstr("; if the file is in millimetres, give --units mm (0.085 m); if in "
                               "centimetres, give --units cm (0.85 m)"));
  EXPECT_FALSE(fs::exists(options_.objects_dir));  // nothing written
}

TEST_F(ObjectCommandTest, AnOpenMeshIsRefusedNamingItsHoleAndNothingIsLeft) {
  TriangleMesh open = test::BoxMesh(Eigen::Vector3d(0.1, 0.1, 0.1));
  open.triangles.pop_back();
  SaveMeshPly(open, Path("open.ply"));
  options_.mesh_path = Path("open.ply");
  options_.name = "open";
  EXPECT_THAT(Error(), HasSubstr("open.ply: the mesh is open: 3 open edges (used by one triangle "
                                 "only) in 1 hole (3 edges around ("));
  EXPECT_TRUE(!fs::exists(options_.objects_dir) || fs::is_empty(options_.objects_dir));
}

TEST_F(ObjectCommandTest, ACaoWithACylinderIsRefusedByLine) {
  std::ofstream(Path("can.cao")) << "V1\n# 3D Points\n2\n0 0 0\n0 0 0.1\n# 3D Lines\n0\n"
                                    "# Faces from 3D lines\n0\n# Faces from 3D points\n0\n"
                                    "# 3D cylinders\n1\n0 1 0.03\n# 3D circles\n0\n";
  options_.mesh_path = Path("can.cao");
  options_.name = "can";
  EXPECT_THAT(Error(), HasSubstr("can.cao: line 14: a 3D cylinder"));
}

TEST_F(ObjectCommandTest, NamesAreUniqueAndValid) {
  WriteBoxObj(Eigen::Vector3d(0.2, 0.1, 0.05), Path("box.obj"));
  options_.mesh_path = Path("box.obj");
  options_.name = "pipe";  // shipped
  EXPECT_THAT(Error(), HasSubstr("--name: 'pipe' is already an object in"));
  options_.name = "../escape";
  EXPECT_THAT(Error(), HasSubstr("is not a usable object name"));
  options_.name = "box";
  Run();
  EXPECT_THAT(Error(), HasSubstr("already exists; --overwrite replaces it"));
  options_.overwrite = true;
  EXPECT_THAT(Run(), HasSubstr("object import"));
}

TEST_F(ObjectCommandTest, AFlatMeshIsRefusedAsASheet) {
  WriteBoxObj(Eigen::Vector3d(0.2, 0.1, 0.0002), Path("sheet.obj"));
  options_.mesh_path = Path("sheet.obj");
  options_.name = "sheet";
  EXPECT_THAT(Error(), HasSubstr("m thin along its thinnest side"));
}

TEST(ObjectImportConfigTest, ValidateNamesTheFileAndTheFullKeyPath) {
  ObjectImportConfig c;
  c.max_extent_m = 200.0;
  EXPECT_THAT(testing::ValidationMessage(c, "import.yaml", ""),
              HasSubstr("import.yaml: max_extent_m: 200 m is above the upper bound 100 m"));
  c = ObjectImportConfig{};
  c.symmetry.max_axis_order = 1;
  EXPECT_THAT(
      testing::ValidationMessage(c, "import.yaml", "import."),
      HasSubstr("import.yaml: import.symmetry.max_axis_order: 1 is below the lower bound 2"));
}

}  // namespace
}  // namespace aerograsp
