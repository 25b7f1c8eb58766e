#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/mesh_repair.h"
#include "core/shape_mesh.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {
using ::testing::HasSubstr;

/// The mesh as a triangle soup: every triangle with its own three vertices (as STL stores it).
TriangleMesh Soup(const TriangleMesh& mesh) {
  TriangleMesh soup;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k)
      soup.vertices.push_back(mesh.vertices[static_cast<std::size_t>(t[k])]);
    const int n = static_cast<int>(soup.vertices.size());
    soup.triangles.emplace_back(n - 3, n - 2, n - 1);
  }
  return soup;
}

std::string RepairError(TriangleMesh mesh) {
  try {
    RepairMesh(&mesh, 1e-9, "part.stl", "mm");
  } catch (const MeshError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshRepairTest, MergesDuplicateVertices) {
  TriangleMesh mesh = Soup(MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3)));
  ASSERT_EQ(mesh.vertices.size(), 36u);
  ASSERT_FALSE(CheckMesh(mesh).IsClosed());
  const MeshRepairReport report = RepairMesh(&mesh, 1e-9, "part.stl", "m");
  EXPECT_EQ(report.merged_vertices, 28u);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_TRUE(CheckMesh(mesh).IsClosed());
  EXPECT_THAT(report.Lines(), ::testing::ElementsAre("duplicate vertices merged: 28"));
}

TEST(MeshRepairTest, MergesVerticesWithinTheDistanceOnly) {
  TriangleMesh mesh = Soup(MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3)));
  mesh.vertices[0] += Eigen::Vector3d(1e-7, 0, 0);  // text rounding in an exporter
  EXPECT_EQ(RepairMesh(&mesh, 1e-6, "part.obj", "m").merged_vertices, 28u);
  TriangleMesh apart = Soup(MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3)));
  apart.vertices[0] += Eigen::Vector3d(1e-4, 0, 0);
  EXPECT_THAT(RepairError(apart), HasSubstr("open"));  // not merged: a crack
}

TEST(MeshRepairTest, TurnsInconsistentTrianglesToAgreeAndFaceOut) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3));
  for (std::size_t t : {0, 3, 7}) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  ASSERT_GT(CheckMesh(mesh).inconsistent_edges, 0u);
  const MeshRepairReport report = RepairMesh(&mesh, 1e-9, "part.ply", "m");
  EXPECT_EQ(report.flipped_triangles, 3u);
  const MeshCheck check = CheckMesh(mesh);
  EXPECT_TRUE(check.IsClosed()) << check.Describe();
  EXPECT_NEAR(check.signed_volume_m3, 0.1 * 0.2 * 0.3, 1e-12);
}

TEST(MeshRepairTest, TurnsAnInsideOutMeshOutwards) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3));
  for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
  EXPECT_EQ(RepairMesh(&mesh, 1e-9, "part.ply", "m").flipped_triangles, 12u);
  EXPECT_GT(CheckMesh(mesh).signed_volume_m3, 0.0);
}

TEST(MeshRepairTest, ACavityFacesInwards) {
  // A hollow box: the outer shell faces out, the inner one (read facing out too) faces in.
  TriangleMesh mesh = test::MergeMeshes(MakeBoxMesh(Eigen::Vector3d::Constant(0.1)),
                                        MakeBoxMesh(Eigen::Vector3d::Constant(0.08)));
  const MeshRepairReport report = RepairMesh(&mesh, 1e-9, "hollow.stl", "m");
  EXPECT_EQ(report.shells, 2u);
  EXPECT_EQ(report.flipped_triangles, 12u);
  EXPECT_NEAR(CheckMesh(mesh).signed_volume_m3, 0.1 * 0.1 * 0.1 - 0.08 * 0.08 * 0.08, 1e-12);
}

TEST(MeshRepairTest, DropsRepeatedTriangles) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(0.1, 0.2, 0.3));
  mesh.triangles.push_back(mesh.triangles[4]);
  EXPECT_EQ(RepairMesh(&mesh, 1e-9, "part.ply", "m").dropped_duplicates, 1u);
  EXPECT_TRUE(CheckMesh(mesh).IsClosed());
}

TEST(MeshRepairTest, RefusesAnOpenMeshNamingItsOpenEdges) {
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d(100, 100, 100));  // millimetres
  mesh.triangles.erase(mesh.triangles.begin());
  mesh.triangles.erase(mesh.triangles.begin());  // one whole face missing: a square hole
  const std::string error = RepairError(mesh);
  EXPECT_THAT(error, HasSubstr("part.stl: the mesh is open: 4 open edges"));
  EXPECT_THAT(error, HasSubstr("in 1 hole (4 edges around ("));
  EXPECT_THAT(error, HasSubstr(") mm"));  // where, in the file's units
  EXPECT_THAT(error, HasSubstr("close it in the CAD tool"));
}

TEST(MeshRepairTest, RefusesEdgesSharedByMoreThanTwoTriangles) {
  // Two cubes sharing one edge.
  const TriangleMesh mesh =
      test::MergeMeshes(MakeBoxMesh(Eigen::Vector3d::Ones()),
                        test::BoxMesh(Eigen::Vector3d::Ones(), Eigen::Vector3d(1, 1, 0)));
  EXPECT_THAT(RepairError(mesh), HasSubstr("1 edge is shared by more than two triangles"));
}

TEST(MeshRepairTest, RefusesAFlatClosedSurface) {
  TriangleMesh sheet;
  sheet.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 1}};
  // Both sides of one triangle: repeated, dropped, then open.
  EXPECT_THAT(RepairError(sheet), HasSubstr("open"));
}

}  // namespace
}  // namespace aerograsp
