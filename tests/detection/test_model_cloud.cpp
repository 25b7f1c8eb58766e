#include <gtest/gtest.h>

#include "core/object_model.h"
#include "core/shape_mesh.h"
#include "detection/model_cloud.h"
#include "test_helpers.h"

namespace aerograsp {
namespace {

TEST(ModelCloudTest, SamplesTheSurfaceWithOutwardNormalsAndColours) {
  const ModelCloud& model = testing::CrawlerModel();
  ASSERT_GT(model.points_o.size(), 3000u);
  EXPECT_NEAR(model.diameter_m, std::sqrt(0.22 * 0.22 + 0.09 * 0.09 + 0.08 * 0.08), 0.01);
  int yellow = 0;
  for (std::size_t i = 0; i < model.points_o.size(); ++i) {
    EXPECT_NEAR(model.normals_o[i].norm(), 1.0f, 1e-4f);
    yellow += model.colors[i].x() > 200 ? 1 : 0;
  }
  EXPECT_GT(yellow, 100);
  // The grid finds a point itself (or one within a cell).
  for (std::size_t i = 0; i < model.points_o.size(); i += 97) {
    const int j = model.Nearest(model.points_o[i]);
    ASSERT_GE(j, 0);
    EXPECT_LT((model.points_o[j] - model.points_o[i]).norm(), 0.004f);
  }
  EXPECT_EQ(model.Nearest(Eigen::Vector3f(1, 1, 1)), -1);
}

TEST(ModelCloudTest, FindsTheCrawlersHalfTurnsAndThePipesAxis) {
  const ObjectSymmetry& crawler = testing::CrawlerModel().symmetry;
  EXPECT_EQ(crawler.rotations.size(), 4u);  // identity and half turns about x, y, z
  EXPECT_FALSE(crawler.continuous_axis_o.has_value());
  const ModelCloud pipe = BuildModelCloud(ObjectModel::Load("pipe").mesh_o);
  ASSERT_TRUE(pipe.symmetry.continuous_axis_o.has_value());
  EXPECT_GT(std::abs(pipe.symmetry.continuous_axis_o->x()), 0.99);
  const ModelCloud u = BuildModelCloud(ObjectModel::Load("u_shape").mesh_o);
  EXPECT_EQ(u.symmetry.rotations.size(),
            2u);  // identity and the half turn about z (open at the top)
  EXPECT_FALSE(u.symmetry.continuous_axis_o.has_value());
}

TEST(ModelCloudTest, SymmetricRotationErrorIgnoresSymmetriesOnly) {
  const ObjectSymmetry& crawler = testing::CrawlerModel().symmetry;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d half_z =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(SymmetricRotationError(R * half_z, R, crawler), 0.0, 1e-9);
  const Eigen::Matrix3d small =
      Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_NEAR(SymmetricRotationError(R * half_z * small, R, crawler), 0.05, 1e-9);
  const Eigen::Matrix3d quarter_z =
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(SymmetricRotationError(R * quarter_z, R, crawler), M_PI / 2, 1e-9);

  ObjectSymmetry axis;
  axis.rotations = {Eigen::Matrix3d::Identity()};
  axis.continuous_axis_o = Eigen::Vector3d::UnitX();
  const Eigen::Matrix3d spin = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(SymmetricRotationError(R * spin, R, axis), 0.0, 1e-9);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_NEAR(SymmetricRotationError(R * spin * tilt, R, axis), 0.1, 1e-9);
}

TEST(ModelCloudTest, ClosestSymmetricRotationUndoesAFlipAndASpin) {
  const ObjectSymmetry& crawler = testing::CrawlerModel().symmetry;
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d half_x =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_TRUE(ClosestSymmetricRotation(R * half_x, R, crawler).isApprox(R, 1e-9));
  ObjectSymmetry axis;
  axis.rotations = {Eigen::Matrix3d::Identity()};
  axis.continuous_axis_o = Eigen::Vector3d::UnitX();
  const Eigen::Matrix3d spin = Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_TRUE(ClosestSymmetricRotation(R * spin, R, axis).isApprox(R, 1e-9));
}

TEST(ModelCloudTest, RejectsADegenerateMesh) {
  TriangleMesh flat;
  flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(BuildModelCloud(flat), std::invalid_argument);
}

}  // namespace
}  // namespace aerograsp
