#include "detection/pose_support.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/object_model.h"
#include "test_helpers.h"

namespace aerograsp {
namespace {
using testing::CrawlerModel;
using testing::Perturbed;
using testing::TypicalCMo;

constexpr double kDepthScaleM = 0.001;

struct Drawn {
  DepthImage depth;
  ColorImage color;
};

/// The crawler at cMo in front of a grey wall 2 m away, drawn by splatting a
/// dense sample of its surface (z-buffer, 3x3 pixels a point, so the object
/// is a pixel fatter than its points), then moved `shift_px` pixels right: with
/// 2, the one-pixel misregistration of a real image (rounding, mixed pixels at
/// silhouettes and colour seams).
Drawn Draw(const Eigen::Isometry3d& cMo, const CameraIntrinsics& K, int shift_px) {
  ModelCloudOptions dense_options;
  dense_options.spacing_m = 0.001;
  static const ModelCloud dense = BuildModelCloud(ObjectModel::Load("crawler").mesh_o, dense_options);
  Drawn d{DepthImage(K.width, K.height, 2000), ColorImage(K.width, K.height, 128)};
  std::vector<float> z_buffer(std::size_t(K.width) * K.height, std::numeric_limits<float>::infinity());
  const Eigen::Isometry3f T = cMo.cast<float>();
  for (std::size_t i = 0; i < dense.points_o.size(); ++i) {
    const Eigen::Vector3f p = T * dense.points_o[i];
    if ((T.linear() * dense.normals_o[i]).dot(p) >= 0.0f) continue;
    const Eigen::Vector2d uv = K.Project(p.cast<double>());
    const int u0 = static_cast<int>(std::lround(uv.x())) + shift_px, v0 = static_cast<int>(std::lround(uv.y()));
    for (int v = v0 - 1; v <= v0 + 1; ++v) {
      for (int u = u0 - 1; u <= u0 + 1; ++u) {
        if (u < 0 || v < 0 || u >= K.width || v >= K.height) continue;
        float& z = z_buffer[std::size_t(v) * K.width + u];
        if (p.z() >= z) continue;
        z = p.z();
        d.depth.at(u, v) = static_cast<std::uint16_t>(std::lround(p.z() / kDepthScaleM));
        for (int c = 0; c < 3; ++c) d.color.at(u, v, c) = static_cast<std::uint8_t>(dense.colors[i][c]);
      }
    }
  }
  return d;
}

TEST(PoseSupportTest, APixelOfMisregistrationContradictsNoPoseWithTheNeighbourSlack) {
  const ModelCloud& model = CrawlerModel();
  const CameraIntrinsics K;
  const Eigen::Isometry3d truth = TypicalCMo();
  const Drawn exact = Draw(truth, K, 0), shifted = Draw(truth, K, 2);
  PoseSupportOptions own_pixel;
  own_pixel.neighbour_px = 0;
  const PoseSupportOptions slack;  // the default: one pixel
  ASSERT_EQ(slack.neighbour_px, 1);

  const PoseSupport exact_own = ScorePoseSupport(model, truth, exact.color, exact.depth, kDepthScaleM, K, own_pixel);
  ASSERT_GT(exact_own.projected, 300);
  EXPECT_GT(exact_own.ratio(), 0.97);
  // Shifted a pixel, the points at the silhouette and the colour seams land on
  // the wall or on the other colour ...
  const PoseSupport shifted_own =
      ScorePoseSupport(model, truth, shifted.color, shifted.depth, kDepthScaleM, K, own_pixel);
  const PoseSupport shifted_slack = ScorePoseSupport(model, truth, shifted.color, shifted.depth, kDepthScaleM, K, slack);
  EXPECT_GT(shifted_own.see_through, shifted_slack.see_through + 5);
  // ... but a pixel away they agree.
  EXPECT_GT(shifted_slack.ratio(), 0.98);
  EXPECT_GE(shifted_slack.ratio(), exact_own.ratio());
}

TEST(PoseSupportTest, AWrongPoseStillContradictsTheDepthWithTheNeighbourSlack) {
  const ModelCloud& model = CrawlerModel();
  const CameraIntrinsics K;
  const Eigen::Isometry3d truth = TypicalCMo();
  const Drawn exact = Draw(truth, K, 0);
  PoseSupportOptions own_pixel;
  own_pixel.neighbour_px = 0;
  const PoseSupportOptions slack;
  // Off by 2 cm across the image or in depth, or turned 0.3 rad: below the
  // tracker's acceptance (min_support_ratio 0.9) with or without the slack.
  for (const Eigen::Isometry3d& wrong : {Perturbed(truth, {0.0, 0.02, 0.0}, Eigen::Vector3d::Zero()),
                                         Perturbed(truth, {0.0, 0.0, 0.02}, Eigen::Vector3d::Zero()),
                                         Perturbed(truth, Eigen::Vector3d::Zero(), {0.0, 0.0, 0.3})}) {
    const PoseSupport with = ScorePoseSupport(model, wrong, exact.color, exact.depth, kDepthScaleM, K, slack);
    const PoseSupport without = ScorePoseSupport(model, wrong, exact.color, exact.depth, kDepthScaleM, K, own_pixel);
    EXPECT_LT(with.ratio(), 0.8);
    EXPECT_LE(without.ratio(), with.ratio());
  }
}

}  // namespace
}  // namespace aerograsp
