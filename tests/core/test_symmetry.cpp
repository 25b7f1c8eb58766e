#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>

#include "core/config.h"
#include "core/object_model.h"
#include "core/shape_mesh.h"
#include "core/symmetry.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {
using ::testing::HasSubstr;

/// Every rotation of the group maps the group onto itself (a group: closed).
void ExpectClosed(const ObjectSymmetry& s) {
  for (const Eigen::Matrix3d& a : s.rotations) {
    for (const Eigen::Matrix3d& b : s.rotations) {
      bool found = false;
      for (const Eigen::Matrix3d& c : s.rotations) found = found || (a * b).isApprox(c, 1e-6);
      EXPECT_TRUE(found);
    }
  }
}

TEST(SymmetryTest, ACubeHasTwentyFourRotationsWhereverItsOriginIs) {
  // A plain cube mesh whose origin is a corner (as CAD tools often write it).
  const TriangleMesh cube =
      test::BoxMesh(Eigen::Vector3d(0.085, 0.085, 0.085), Eigen::Vector3d(0.0425, 0.0425, 0.0425));
  const ObjectSymmetry s = FindMeshSymmetries(cube);
  EXPECT_EQ(s.rotations.size(), 24u);
  EXPECT_FALSE(s.continuous_axis_o.has_value());
  EXPECT_TRUE(s.rotations.front().isIdentity());
  EXPECT_TRUE(s.center_o.isApprox(Eigen::Vector3d::Constant(0.0425), 1e-9));
  ExpectClosed(s);
  EXPECT_THAT(DescribeSymmetry(s), HasSubstr("24 rotations (a cube's group)"));
  EXPECT_THAT(DescribeSymmetry(s), HasSubstr("3 4-fold axes, 4 3-fold axes, 6 2-fold axes"));
}

TEST(SymmetryTest, ASymmetricPoseOfACornerOriginCubeShowsTheSameCube) {
  const TriangleMesh cube =
      test::BoxMesh(Eigen::Vector3d::Constant(0.1), Eigen::Vector3d::Constant(0.05));
  const ObjectSymmetry s = FindMeshSymmetries(cube);
  const Eigen::Isometry3d cMo = Eigen::Translation3d(0.1, 0.2, 0.8) *
                                Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -1, 2).normalized());
  for (const Eigen::Matrix3d& S : s.rotations) {
    const Eigen::Isometry3d turned = WithSymmetricRotation(cMo, cMo.linear() * S, s);
    // Every corner lands on a corner of the cube where cMo shows it.
    for (const Eigen::Vector3d& v : cube.vertices) {
      double nearest = 1.0;
      for (const Eigen::Vector3d& w : cube.vertices) {
        nearest = std::min(nearest, (turned * v - cMo * w).norm());
      }
      EXPECT_LT(nearest, 1e-9);
    }
  }
}

TEST(SymmetryTest, ACubeTurnedOffItsAxesStillHasTwentyFour) {
  TriangleMesh cube;
  const Eigen::Isometry3d turned = Eigen::Translation3d(0.01, -0.02, 0.03) *
                                   Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized());
  AppendMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.1)), turned, &cube);
  EXPECT_EQ(FindMeshSymmetries(cube).rotations.size(), 24u);
}

TEST(SymmetryTest, ACubeTessellatedUnevenlyIsStillACube) {
  // One face split into a 3 x 3 grid of quads, the others two triangles each:
  // symmetry is a property of the surface, not of its triangles.
  TriangleMesh cube = MakeBoxMesh(Eigen::Vector3d::Constant(0.1));
  TriangleMesh top;
  for (std::size_t t = 0; t < cube.triangles.size(); ++t) {
    if (cube.TriangleNormal(t).z() > 0.5) continue;
    top.triangles.push_back(cube.triangles[t]);
  }
  top.vertices = cube.vertices;
  const int base = static_cast<int>(top.vertices.size());
  for (int j = 0; j <= 3; ++j) {
    for (int i = 0; i <= 3; ++i)
      top.vertices.emplace_back(-0.05 + 0.1 * i / 3.0, -0.05 + 0.1 * j / 3.0, 0.05);
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const int a = base + j * 4 + i;
      top.triangles.emplace_back(a, a + 1, a + 5);
      top.triangles.emplace_back(a, a + 5, a + 4);
    }
  }
  EXPECT_EQ(FindMeshSymmetries(top).rotations.size(), 24u);
}

TEST(SymmetryTest, ABoxWithThreeDifferentSidesHasFour) {
  const ObjectSymmetry s = FindMeshSymmetries(test::BoxMesh(Eigen::Vector3d(0.2, 0.1, 0.05)));
  ASSERT_EQ(s.rotations.size(), 4u);
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_NEAR(Eigen::AngleAxisd(s.rotations[i]).angle(), M_PI, 1e-9);  // three half turns
  }
  ExpectClosed(s);
}

TEST(SymmetryTest, ASquarePrismHasEightAndAHexagonalPrismTwelve) {
  EXPECT_EQ(FindMeshSymmetries(test::BoxMesh(Eigen::Vector3d(0.2, 0.1, 0.1))).rotations.size(), 8u);
  const ObjectSymmetry hex = FindMeshSymmetries(MakeCylinderMesh(0.05, 0.2, 6));
  EXPECT_EQ(hex.rotations.size(), 12u);  // six turns about z, six half turns across
  EXPECT_FALSE(hex.continuous_axis_o.has_value());
  ExpectClosed(hex);
}

TEST(SymmetryTest, TheShippedPipeTurnsFreelyAboutItsAxisAndFlipsEndForEnd) {
  const ObjectSymmetry s = FindMeshSymmetries(ObjectModel::Load("pipe").mesh_o);
  ASSERT_TRUE(s.continuous_axis_o.has_value());
  EXPECT_TRUE(s.continuous_axis_o->isApprox(Eigen::Vector3d::UnitX(), 1e-6));
  ASSERT_EQ(s.rotations.size(), 2u);
  const Eigen::AngleAxisd half(s.rotations[1]);
  EXPECT_NEAR(half.angle(), M_PI, 1e-9);
  EXPECT_NEAR(half.axis().x(), 0.0, 1e-9);  // across the axis
  EXPECT_THAT(DescribeSymmetry(s), HasSubstr("continuous about the axis (1, 0, 0)"));
}

TEST(SymmetryTest, EveryShippedObjectStoresTheGroupFoundOnItsMesh) {
  for (const char* name : {"crawler", "pipe", "u_shape"}) {
    SCOPED_TRACE(name);
    const ObjectModel model = ObjectModel::Load(name);  // the group as object.yaml stores it
    ASSERT_TRUE(YAML::LoadFile(model.source)["symmetry"]) << model.source;
    const ObjectSymmetry found = FindMeshSymmetries(model.mesh_o);
    const ObjectSymmetry& stored = model.symmetry;
    EXPECT_LT((stored.center_o - found.center_o).norm(), 1e-6);
    ASSERT_EQ(stored.continuous_axis_o.has_value(), found.continuous_axis_o.has_value());
    if (stored.continuous_axis_o) {
      EXPECT_TRUE(stored.continuous_axis_o->isApprox(*found.continuous_axis_o, 1e-9));
    }
    ASSERT_EQ(stored.rotations.size(), found.rotations.size());
    ASSERT_GT(stored.rotations.size(), 1u);  // each shipped object has a symmetry
    for (const Eigen::Matrix3d& R : stored.rotations) {
      bool matched = false;
      for (const Eigen::Matrix3d& F : found.rotations) {
        const Eigen::Matrix3d between = R.transpose() * F;
        // Equal, or (about a continuous axis) equal up to a spin about it.
        matched =
            matched ||
            (stored.continuous_axis_o
                 ? (between * *stored.continuous_axis_o).isApprox(*stored.continuous_axis_o, 1e-6)
                 : between.isIdentity(1e-6));
      }
      EXPECT_TRUE(matched) << R;
    }
  }
}

TEST(SymmetryTest, AGenericObjectHasOnlyTheIdentity) {
  // Three boxes of different sizes at different places: no rotation maps it onto itself.
  TriangleMesh mesh = test::BoxMesh(Eigen::Vector3d(0.1, 0.06, 0.04));
  mesh = test::MergeMeshes(
      mesh, test::BoxMesh(Eigen::Vector3d(0.03, 0.03, 0.05), Eigen::Vector3d(0.03, 0.01, 0.045)));
  mesh = test::MergeMeshes(mesh, test::BoxMesh(Eigen::Vector3d(0.02, 0.04, 0.02),
                                               Eigen::Vector3d(-0.035, -0.02, -0.03)));
  const ObjectSymmetry s = FindMeshSymmetries(mesh);
  EXPECT_EQ(s.rotations.size(), 1u);
  EXPECT_FALSE(s.continuous_axis_o.has_value());
  EXPECT_EQ(DescribeSymmetry(s), "none (the identity only)");
}

TEST(SymmetryTest, AlmostACubeIsNotACube) {
  // 2 % longer along z: the quarter turns about x and y no longer fit.
  EXPECT_EQ(FindMeshSymmetries(test::BoxMesh(Eigen::Vector3d(0.1, 0.1, 0.102))).rotations.size(),
            8u);
}

TEST(SymmetryTest, ColoursBreakSymmetry) {
  // A cube with its +z face red: only the turns about z keep the colours.
  TriangleMesh cube;
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d::Constant(0.1));
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    const bool top = box.TriangleNormal(t).z() > 0.5;
    for (int k = 0; k < 3; ++k) {
      cube.vertices.push_back(box.vertices[static_cast<std::size_t>(box.triangles[t][k])]);
      cube.colors.push_back(top ? std::array<std::uint8_t, 3>{220, 30, 30}
                                : std::array<std::uint8_t, 3>{200, 200, 200});
    }
    const int n = static_cast<int>(cube.vertices.size());
    cube.triangles.emplace_back(n - 3, n - 2, n - 1);
  }
  EXPECT_EQ(FindMeshSymmetries(cube).rotations.size(), 4u);
}

TEST(SymmetryTest, BadOptionsAndEmptyMeshesAreRefused) {
  SymmetryOptions bad;
  bad.tolerance_ratio = 0.0;
  try {
    FindMeshSymmetries(MakeBoxMesh(Eigen::Vector3d::Ones()), bad);
    FAIL() << "accepted a zero tolerance";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("symmetry.tolerance_ratio: 0 is below the lower bound"));
  }
  TriangleMesh flat;
  flat.vertices = {Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), 2 * Eigen::Vector3d::UnitX()};
  flat.triangles = {Eigen::Vector3i(0, 1, 2)};
  EXPECT_THROW(FindMeshSymmetries(flat), std::invalid_argument);
}

}  // namespace
}  // namespace aerograsp
