// ViSP .cao reading and the mass properties of a mesh.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/mesh.h"
#include "core/shape_mesh.h"

namespace aerograsp {
namespace {
using ::testing::HasSubstr;

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A 2 x 4 x 6 cm box as ViSP's tutorials write one: quads from 3D points.
const char* kBoxPoints =
    "V1\n"
    "# 3D Points\n"
    "8                  # Number of points\n"
    "0 0 0\n0.02 0 0\n0.02 0.04 0\n0 0.04 0\n"
    "0 0 0.06\n0.02 0 0.06\n0.02 0.04 0.06\n0 0.04 0.06\n";

std::string BoxCao(const std::string& tail) {
  return std::string(kBoxPoints) +
         "# 3D Lines\n0\n# Faces from 3D lines\n0\n"
         "# Faces from 3D points\n6\n"
         "4 0 3 2 1 name=bottom\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n" +
         tail;
}

TEST(CaoMeshTest, ReadsQuadFacesAsTriangles) {
  const TriangleMesh mesh =
      LoadMesh(Write("box.cao", BoxCao("# 3D cylinders\n0\n# 3D circles\n0\n")));
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_TRUE(check.IsClosed()) << check.Describe();
  EXPECT_NEAR(check.signed_volume_m3, 0.02 * 0.04 * 0.06, 1e-15);
}

TEST(CaoMeshTest, ReadsFacesFromLines) {
  const std::string text = std::string(kBoxPoints) +
                           "# 3D Lines\n4\n0 1\n1 2\n2 3\n3 0\n"
                           "# Faces from 3D lines\n1\n4 0 1 3 2\n"  // sides in any order
                           "# Faces from 3D points\n5\n"
                           "4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  const TriangleMesh mesh = LoadMesh(Write("lines.cao", text));
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(CheckMesh(mesh).boundary_edges, 0u);
}

TEST(CaoMeshTest, RefusesCylindersAndCirclesNamingTheLine) {
  try {
    LoadMesh(Write("cylinder.cao", BoxCao("# 3D cylinders\n1\n0 4 0.01\n# 3D circles\n0\n")));
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cylinder.cao: line 26: a 3D cylinder (1 in the file)"));
    EXPECT_THAT(e.what(), HasSubstr("not polygon faces"));
  }
  try {
    LoadMesh(Write("circle.cao", BoxCao("0\n1\n0.01 0 1 3\n")));
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("circle.cao: line 26: a 3D circle"));
  }
}

TEST(CaoMeshTest, RefusesALineThatBoundsNoFace) {
  const std::string text = std::string(kBoxPoints) + "# 3D Lines\n1\n0 6\n0\n0\n";
  try {
    LoadMesh(Write("edge.cao", text));
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_THAT(e.what(), HasSubstr("edge.cao: line 14: 3D line 0 bounds no face"));
  }
}

TEST(CaoMeshTest, RefusesMalformedFiles) {
  const auto error = [](const std::string& name, const std::string& text) {
    try {
      LoadMesh(Write(name, text));
    } catch (const MeshError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error("v.cao", "V2\n0\n"), HasSubstr("v.cao: not a ViSP .cao file"));
  EXPECT_THAT(error("load.cao", "load(\"other.cao\")\nV1\n"), HasSubstr("line 1: load(...)"));
  EXPECT_THAT(error("short.cao", "V1\n8\n0 0 0\n"), HasSubstr("file is truncated"));
  EXPECT_THAT(error("index.cao", std::string(kBoxPoints) + "0\n0\n1\n3 0 1 9\n"),
              HasSubstr("line 15: expected a point index in [0, 7], found 9"));
}

TEST(MassPropertiesTest, ABoxHasTheTextbookInertia) {
  // Off its origin, so the parallel-axis step is exercised: I_xx = V (b^2 + c^2) / 12.
  TriangleMesh box;
  AppendMesh(MakeBoxMesh(Eigen::Vector3d(0.2, 0.1, 0.05)),
             Eigen::Isometry3d(Eigen::Translation3d(0.3, -0.1, 0.2)), &box);
  const MassProperties p = ComputeMassProperties(box);
  const double v = 0.2 * 0.1 * 0.05;
  EXPECT_NEAR(p.volume_m3, v, 1e-15);
  EXPECT_TRUE(p.center_of_mass.isApprox(Eigen::Vector3d(0.3, -0.1, 0.2), 1e-12));
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(v * (0.1 * 0.1 + 0.05 * 0.05) / 12, v * (0.2 * 0.2 + 0.05 * 0.05) / 12,
                      v * (0.2 * 0.2 + 0.1 * 0.1) / 12)
          .asDiagonal();
  EXPECT_LT((p.inertia_unit_density - expected).norm(), 1e-12 * expected.norm() + 1e-18);
}

}  // namespace
}  // namespace aerograsp
