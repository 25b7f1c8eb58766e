#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "core/shape_mesh.h"
#include "core/transforms.h"
#include "hardware/sim/d435_model.h"
#include "hardware/sim/rgbd_renderer.h"

namespace aerograsp {
namespace {

CameraIntrinsics D435Color() { return CameraIntrinsics{}; }  // 640x480, f 615, c (320, 240)

/// A 0.2 x 0.1 x 0.05 m box at 1 m straight ahead of a camera at the world
/// origin looking along world x (optical z = world x).
class BoxSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    RenderMesh box;
    box.mesh = MakeBoxMesh(Eigen::Vector3d(0.2, 0.1, 0.05));
    box.material.albedo = {0.9f, 0.2f, 0.1f};
    box_ = renderer_.AddMesh(box);
    // Box frame: its x along camera x (world -y), y along camera y (world z), z towards the camera.
    wMc_.linear() << 0, 0, 1,  //
        -1, 0, 0,              //
        0, -1, 0;
    wMc_.translation().setZero();
    cMbox_ = MakeTransform(Eigen::Vector3d(0.1, -0.05, 1.0), Eigen::Vector3d::Zero());
    renderer_.SetPose(box_, wMc_ * cMbox_);
    renderer_.Render(wMc_, D435Color(), Lighting{}, &buffers_);
  }
  RgbdRenderer renderer_;
  int box_ = -1;
  Eigen::Isometry3d wMc_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d cMbox_;
  RenderBuffers buffers_;
};

TEST_F(BoxSceneTest, BoxFrontFaceLandsOnTheProjectedPixelsAtItsDepth) {
  const CameraIntrinsics K = D435Color();
  // The front face is at z = 1 - 0.025 m; its corners project to these pixels.
  const double z_front = 1.0 - 0.025;
  const Eigen::Vector2d lo = K.Project({0.0, -0.1, z_front});
  const Eigen::Vector2d hi = K.Project({0.2, 0.0, z_front});
  int inside = 0, outside_hits = 0;
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const bool in = u > lo.x() + 0.5 && u < hi.x() - 0.5 && v > lo.y() + 0.5 && v < hi.y() - 0.5;
      const bool out = u < lo.x() - 0.5 || u > hi.x() + 0.5 || v < lo.y() - 0.5 || v > hi.y() + 0.5;
      const float z = buffers_.depth_m.at(u, v);
      if (in) {
        ++inside;
        ASSERT_NEAR(z, z_front, 1e-5) << "pixel " << u << "," << v;
        ASSERT_EQ(buffers_.object_id.at(u, v), box_);
        ASSERT_NEAR(buffers_.cos_incidence.at(u, v),
                    1.0 / Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).norm(), 1e-4);
      } else if (out && z > 0.0f) {
        ++outside_hits;
      }
    }
  }
  // 0.2 m x 0.1 m at 0.975 m with f = 615: about 126 x 63 pixels.
  EXPECT_GT(inside, 120 * 60);
  EXPECT_EQ(outside_hits, 0);
  EXPECT_EQ(buffers_.object_id.at(0, 0), -1);
  EXPECT_EQ(buffers_.depth_m.at(0, 0), 0.0f);
}

TEST_F(BoxSceneTest, ColourIsAlbedoTimesLightingAndBackgroundElsewhere) {
  const Eigen::Vector2d centre = D435Color().Project({0.1, -0.05, 0.975});
  const std::uint8_t* rgb = &buffers_.color.at(int(centre.x()), int(centre.y()));
  EXPECT_GT(rgb[0], 2 * rgb[1]);  // red box
  const Lighting lighting;
  const std::uint8_t* sky = &buffers_.color.at(0, 0);
  EXPECT_EQ(sky[2], static_cast<std::uint8_t>(lighting.background.z() * 255.0f + 0.5f));
}

TEST_F(BoxSceneTest, HidingTheBoxLeavesNothing) {
  renderer_.SetVisible(box_, false);
  renderer_.Render(wMc_, D435Color(), Lighting{}, &buffers_);
  for (float z : buffers_.depth_m.data) ASSERT_EQ(z, 0.0f);
  renderer_.SetVisible(box_, true);
  renderer_.Render(wMc_, D435Color(), Lighting{}, &buffers_);
  EXPECT_GT(buffers_.depth_m.at(int(D435Color().Project({0.1, -0.05, 0.975}).x()), 230), 0.0f);
}

TEST(RendererTest, TextureNeedsUv) {
  RgbdRenderer renderer;
  RenderMesh mesh;
  mesh.mesh = MakeBoxMesh(Eigen::Vector3d::Ones());
  mesh.material.texture = std::make_shared<ColorImage>(4, 4);
  EXPECT_THROW(renderer.AddMesh(mesh), std::invalid_argument);
  mesh.uv.assign(3, Eigen::Vector2f::Zero());
  EXPECT_THROW(renderer.AddMesh(mesh), std::invalid_argument);
}

TEST(RendererTest, TextureIsSampledByUv) {
  // A quad facing the camera with a 2x1 texture: left half black, right half white.
  RgbdRenderer renderer;
  RenderMesh quad;
  quad.mesh.vertices = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
  quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  quad.uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  auto texture = std::make_shared<ColorImage>(2, 1, 0);
  for (int c = 0; c < 3; ++c) texture->at(1, 0, c) = 255;
  quad.material.texture = texture;
  const int id = renderer.AddMesh(quad);
  // Camera at z = -1 looking along +z at the quad (optical frame = world frame).
  const Eigen::Isometry3d wMc = MakeTransform(Eigen::Vector3d(0, 0, -1), Eigen::Vector3d::Zero());
  renderer.SetPose(id, Eigen::Isometry3d::Identity());
  RenderBuffers out;
  Lighting light;
  light.to_light_w = {0, 0, -1};
  light.intensity = 0.5;
  light.ambient = 0.3;
  renderer.Render(wMc, D435Color(), light, &out);
  EXPECT_EQ(out.color.at(200, 240, 0), 0);
  EXPECT_NEAR(out.color.at(440, 240, 0), 255 * 0.8, 1.0);
}

/// A white wall facing the camera at distance z fills the image.
RenderBuffers WallAt(double z, int width = 640, int height = 480) {
  RgbdRenderer renderer;
  RenderMesh wall;
  wall.mesh = MakeBoxMesh(Eigen::Vector3d(40.0, 40.0, 0.01));
  renderer.SetPose(renderer.AddMesh(wall),
                   MakeTransform(Eigen::Vector3d(0, 0, z + 0.005), Eigen::Vector3d::Zero()));
  CameraIntrinsics K;
  K.width = width;
  K.height = height;
  RenderBuffers out;
  renderer.Render(Eigen::Isometry3d::Identity(), K, Lighting{}, &out);
  return out;
}

TEST(D435ModelTest, DepthNoiseOnAFlatWallMatchesTheModelWithin20Percent) {
  D435Config config;
  const CameraIntrinsics K;
  FastRandom rng(7);
  for (double z : {0.5, 1.0, 1.5, 2.0, 3.0}) {
    const RenderBuffers wall = WallAt(z);
    RgbdFrame frame;
    SimulateD435(config, K, wall, &rng, &frame);
    // The central part of the image sees the wall head-on; away from edges.
    double sum = 0.0, sq = 0.0;
    int n = 0, holes = 0;
    for (int v = 140; v < 340; ++v) {
      for (int u = 220; u < 420; ++u) {
        const std::uint16_t d = frame.depth.at(u, v);
        if (d == 0) {
          ++holes;
          continue;
        }
        const double err = d * config.depth_scale_m - z;
        sum += err;
        sq += err * err;
        ++n;
      }
    }
    const double mean = sum / n, rms = std::sqrt(sq / n - mean * mean);
    const double sigma = config.DepthNoiseStdM(z, K.width);
    const double expected = std::sqrt(sigma * sigma + std::pow(config.depth_scale_m, 2) / 12.0);
    EXPECT_NEAR(rms, expected, 0.2 * expected) << "wall at " << z << " m";
    EXPECT_NEAR(mean, 0.0, 0.1 * expected + 1e-4) << "wall at " << z << " m";
    EXPECT_EQ(holes, 0) << "wall at " << z << " m";
    std::printf("wall at %.1f m: measured noise %.2f mm, model %.2f mm\n", z, 1e3 * rms,
                1e3 * expected);
  }
}

TEST(D435ModelTest, NothingCloserThanMinRangeOrBeyondMaxRange) {
  D435Config config;
  FastRandom rng(1);
  RgbdFrame frame;
  SimulateD435(config, CameraIntrinsics{}, WallAt(0.15), &rng, &frame);
  for (auto d : frame.depth.data) ASSERT_EQ(d, 0);
  SimulateD435(config, CameraIntrinsics{}, WallAt(7.0), &rng, &frame);
  for (auto d : frame.depth.data) ASSERT_EQ(d, 0);
}

TEST(D435ModelTest, DepthIsQuantisedToTheDepthUnit) {
  D435Config config;
  config.subpixel = 0.0;
  config.depth_scale_m = 0.004;
  FastRandom rng(1);
  RgbdFrame frame;
  SimulateD435(config, CameraIntrinsics{}, WallAt(1.001), &rng, &frame);
  EXPECT_EQ(frame.depth.at(320, 240), 250);  // 1.001 / 0.004 = 250.25
}

TEST(D435ModelTest, GrazingAnglesLoseDepth) {
  // A floor seen at grazing incidence: far rows (near the horizon) lose depth.
  RgbdRenderer renderer;
  RenderMesh floor;
  floor.mesh = MakeBoxMesh(Eigen::Vector3d(20.0, 0.01, 20.0));
  // Camera y (down) towards the floor 0.3 m below.
  renderer.SetPose(renderer.AddMesh(floor),
                   MakeTransform(Eigen::Vector3d(0, 0.305, 0), Eigen::Vector3d::Zero()));
  RenderBuffers out;
  renderer.Render(Eigen::Isometry3d::Identity(), CameraIntrinsics{}, Lighting{}, &out);
  D435Config config;
  config.max_range_m = 20.0;
  FastRandom rng(3);
  RgbdFrame frame;
  SimulateD435(config, CameraIntrinsics{}, out, &rng, &frame);
  // Row 250: ray at atan(10/615) below the axis: incidence ~89 deg -> hole.
  // Row 470: atan(230/615) = 20.5 deg below: incidence 69.5 deg -> kept.
  int holes_far = 0, holes_near = 0;
  for (int u = 200; u < 440; ++u) {
    holes_far += frame.depth.at(u, 250) == 0;
    holes_near += frame.depth.at(u, 470) == 0;
  }
  EXPECT_EQ(holes_far, 240);
  EXPECT_EQ(holes_near, 0);
}

TEST(D435ModelTest, StereoShadowLeftOfANearObject) {
  // A post 0.5 m away in front of a wall at 2 m: a band of width
  // f b (1/0.5 - 1/2) = 615 * 0.05 * 1.5 = 46 px left of the post has no depth.
  RgbdRenderer renderer;
  RenderMesh wall, post;
  wall.mesh = MakeBoxMesh(Eigen::Vector3d(40.0, 40.0, 0.01));
  post.mesh = MakeBoxMesh(Eigen::Vector3d(0.05, 2.0, 0.05));
  renderer.SetPose(renderer.AddMesh(wall),
                   MakeTransform(Eigen::Vector3d(0, 0, 2.005), Eigen::Vector3d::Zero()));
  renderer.SetPose(renderer.AddMesh(post),
                   MakeTransform(Eigen::Vector3d(0, 0, 0.525), Eigen::Vector3d::Zero()));
  RenderBuffers out;
  renderer.Render(Eigen::Isometry3d::Identity(), CameraIntrinsics{}, Lighting{}, &out);
  D435Config config;
  config.edge_hole_probability = 0.0;
  FastRandom rng(3);
  RgbdFrame frame;
  SimulateD435(config, CameraIntrinsics{}, out, &rng, &frame);
  const int left_edge = static_cast<int>(std::ceil(320 - 615 * 0.025 / 0.5));  // first post pixel
  const int band = static_cast<int>(std::ceil(615 * 0.05 * (1 / 0.5 - 1 / 2.0)));
  for (int u = left_edge - band; u < left_edge; ++u) EXPECT_EQ(frame.depth.at(u, 240), 0) << u;
  EXPECT_GT(frame.depth.at(left_edge - band - 2, 240), 0);
  EXPECT_GT(frame.depth.at(left_edge + 2, 240), 0);  // the post itself
  // The right side of the post has no shadow.
  const int right_edge = static_cast<int>(std::floor(320 + 615 * 0.025 / 0.5));
  EXPECT_GT(frame.depth.at(right_edge + 3, 240), 0);
}

TEST(D435ModelTest, SameSeedSameFrame) {
  const RenderBuffers wall = WallAt(1.0);
  FastRandom a(42), b(42), c(43);
  RgbdFrame fa, fb, fc;
  SimulateD435(D435Config{}, CameraIntrinsics{}, wall, &a, &fa);
  SimulateD435(D435Config{}, CameraIntrinsics{}, wall, &b, &fb);
  SimulateD435(D435Config{}, CameraIntrinsics{}, wall, &c, &fc);
  EXPECT_TRUE(fa.depth == fb.depth && fa.color == fb.color);
  EXPECT_FALSE(fa.depth == fc.depth);
}

}  // namespace
}  // namespace aerograsp
