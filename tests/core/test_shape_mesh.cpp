#include <gtest/gtest.h>

#include <cmath>

#include "core/object_model.h"
#include "core/random.h"
#include "core/shape_mesh.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

TEST(ShapeMeshTest, PrimitivesAreClosedWithTheirVolumes) {
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(0.2, 0.3, 0.4));
  EXPECT_TRUE(CheckMesh(box).IsClosed()) << CheckMesh(box).Describe();
  EXPECT_NEAR(ComputeMassProperties(box).volume_m3, 0.024, 1e-12);
  const TriangleMesh cylinder = MakeCylinderMesh(0.1, 0.5, 64);
  EXPECT_TRUE(CheckMesh(cylinder).IsClosed()) << CheckMesh(cylinder).Describe();
  // An inscribed 64-gon prism: (64 / 2) r^2 sin(2 pi / 64) h.
  EXPECT_NEAR(ComputeMassProperties(cylinder).volume_m3, 32 * 0.01 * std::sin(2 * M_PI / 64) * 0.5,
              1e-12);
  const TriangleMesh sphere = MakeSphereMesh(0.1, 16, 32);
  EXPECT_TRUE(CheckMesh(sphere).IsClosed()) << CheckMesh(sphere).Describe();
  EXPECT_NEAR(ComputeMassProperties(sphere).volume_m3, 4.0 / 3.0 * M_PI * 1e-3,
              0.03 * 4.0 / 3.0 * M_PI * 1e-3);
}

TEST(ShapeMeshTest, MeshFromShapeAppliesTheShapeFrame) {
  CollisionShape shape;
  shape.type = CollisionShape::Type::kCylinder;
  shape.size = Eigen::Vector3d(0.05, 0.2, 0.0);
  shape.segMs = MakeTransform(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(M_PI / 2, 0, 0));
  const TriangleMesh mesh = MeshFromShape(shape);
  // The cylinder's axis (z) turned onto -y: 0.2 m long along y around (1, 2, 3).
  EXPECT_NEAR(mesh.BoundsMax().y() - mesh.BoundsMin().y(), 0.2, 1e-9);
  EXPECT_TRUE(
      (0.5 * (mesh.BoundsMax() + mesh.BoundsMin())).isApprox(Eigen::Vector3d(1, 2, 3), 1e-9));
}

TEST(IntersectRayTest, ABoxIsEnteredAndLeft) {
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d(2, 2, 2));
  const std::vector<double> hits =
      IntersectRay(box, Eigen::Vector3d(-5, 0.3, 0.2), Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[0], 4.0, 1e-12);
  EXPECT_NEAR(hits[1], 6.0, 1e-12);
  EXPECT_TRUE(IntersectRay(box, Eigen::Vector3d(-5, 3, 0), Eigen::Vector3d(1, 0, 0)).empty());
  EXPECT_EQ(IntersectRay(box, Eigen::Vector3d(0, 0.3, 0.2), Eigen::Vector3d(0, 0, 1)).size(),
            1u);  // from inside
  // Through the diagonal each x face is split along, and through a corner: one
  // crossing each, not one per triangle.
  const std::vector<double> diagonal =
      IntersectRay(box, Eigen::Vector3d(-5, 0.3, 0.3), Eigen::Vector3d(1, 0, 0));
  ASSERT_EQ(diagonal.size(), 2u);
  EXPECT_NEAR(diagonal[0], 4.0, 1e-12);
  EXPECT_NEAR(diagonal[1], 6.0, 1e-12);
  EXPECT_EQ(IntersectRay(box, Eigen::Vector3d(-2, -2, -2), Eigen::Vector3d(1, 1, 1)).size(), 2u);
}

TEST(ObjectModelTest, ShippedNamesAndErrors) {
  const ObjectModel crawler = ObjectModel::Load("crawler");
  EXPECT_EQ(crawler.name, "crawler");
  EXPECT_DOUBLE_EQ(crawler.mass_kg, 0.4);
  EXPECT_FALSE(crawler.mass_estimated);
  EXPECT_NEAR(crawler.dimensions_m.x(), 0.22, 1e-6);
  EXPECT_EQ(ShippedObjectNames(), (std::vector<std::string>{"crawler", "pipe", "u_shape"}));
  try {
    ObjectModel::Load("teapot");
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("shipped: crawler, pipe, u_shape"), std::string::npos)
        << e.what();
  }
}

TEST(ObjectModelTest, ABareMeshGetsAnEstimatedMass) {
  const std::string path = ::testing::TempDir() + "/cube_for_object_model.ply";
  SaveMeshPly(MakeBoxMesh(Eigen::Vector3d(0.1, 0.1, 0.1)), path);
  const ObjectModel model = ObjectModel::Load(path);
  EXPECT_TRUE(model.mass_estimated);
  EXPECT_NEAR(model.mass_kg, 1e-3 * ObjectModel::kDefaultDensity, 1e-9);
}

TEST(FastRandomTest, SameSeedSameSequenceAndSaneMoments) {
  FastRandom a(9), b(9), c(10);
  EXPECT_EQ(a.Next(), b.Next());
  EXPECT_NE(a.Next(), c.Next());
  FastRandom r(1);
  double sum = 0, sq = 0, fsum = 0, fsq = 0, usum = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double x = r.Normal(), y = r.FastNormal(), u = r.Uniform();
    sum += x;
    sq += x * x;
    fsum += y;
    fsq += y * y;
    usum += u;
    ASSERT_TRUE(u >= 0.0 && u < 1.0);
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sq / n, 1.0, 0.01);
  EXPECT_NEAR(fsum / n, 0.0, 0.01);
  EXPECT_NEAR(fsq / n, 1.0, 0.01);
  EXPECT_NEAR(usum / n, 0.5, 0.005);
}

}  // namespace
}  // namespace aerograsp
