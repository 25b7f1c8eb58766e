#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/calibration/tag_board_mesh.h"
#include "calib/tag_board.h"
#include "core/random.h"
#include "core/transforms.h"
#include "hardware/sim/d435_model.h"

namespace aerograsp {
namespace {

/// Renders the board at cMt with the D435 colour noise.
ColorImage RenderBoardAt(const TagBoardConfig& board, const Eigen::Isometry3d& cMt,
                         std::uint64_t seed) {
  RgbdRenderer renderer;
  const int id = renderer.AddMesh(MakeBoardRenderMesh(board));
  renderer.SetPose(id, cMt);  // world = camera frame here
  Lighting light;
  light.to_light_w = {0.2, -0.3, -1.0};
  light.background = {0.3f, 0.3f, 0.3f};
  RenderBuffers buffers;
  renderer.Render(Eigen::Isometry3d::Identity(), CameraIntrinsics{}, light, &buffers);
  FastRandom rng(seed);
  RgbdFrame frame;
  SimulateD435(D435Config{}, CameraIntrinsics{}, buffers, &rng, &frame);
  return frame.color;
}

TEST(TagBoardTest, LayoutAndSize) {
  TagBoardConfig board;  // 2 x 3 tags of 18 mm, 6 mm apart, 4 mm margin: fits between the fingers
  EXPECT_NEAR(board.Size().x(), 3 * 0.018 + 2 * 0.006 + 2 * 0.004, 1e-12);
  EXPECT_NEAR(board.Size().y(), 2 * 0.018 + 0.006 + 2 * 0.004, 1e-12);
  const auto tags = BoardTags(board);
  ASSERT_EQ(tags.size(), 6u);
  EXPECT_EQ(tags[4].id, 4);
  EXPECT_NEAR(tags[4].corners_t[0].y(), -0.5 * board.Size().y() + 0.004 + 0.024, 1e-12);
  EXPECT_NEAR(tags[0].corners_t[0].x(), -0.5 * board.Size().x() + 0.004, 1e-12);
  EXPECT_NEAR((tags[1].corners_t[2] - tags[1].corners_t[0]).norm(), 0.018 * std::sqrt(2.0), 1e-12);
}

TEST(TagBoardTest, BadConfigNamesTheKey) {
  TagBoardConfig board;
  board.first_id = 586;
  try {
    board.Validate("calib.yaml", "board.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("calib.yaml: board.first_id"), std::string::npos)
        << e.what();
  }
}

TEST(TagBoardTest, SvgIsAtTrueScale) {
  const std::string path = ::testing::TempDir() + "/board.svg";
  WriteBoardSvg(TagBoardConfig{}, path);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("width=\"74mm\" height=\"50mm\""), std::string::npos) << text.substr(0, 300);
}

TEST(TagBoardTest, RenderedBoardIsDetectedAndItsPoseRecovered) {
  TagBoardConfig board;
  TagDetector detector;
  FastRandom rng(5);
  for (int trial = 0; trial < 6; ++trial) {
    const Eigen::Isometry3d cMt = MakeTransform(
        Eigen::Vector3d(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), rng.Uniform(0.25, 0.4)),
        Eigen::Vector3d(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), rng.Uniform(-M_PI, M_PI)));
    const ColorImage image = RenderBoardAt(board, cMt, 100 + trial);
    const std::vector<TagDetection> detections = detector.Detect(image);
    ASSERT_EQ(detections.size(), 6u) << "trial " << trial;
    const BoardPose pose = EstimateBoardPose(detections, board, CameraIntrinsics{});
    ASSERT_TRUE(pose.valid);
    EXPECT_EQ(pose.tags_used, 6);
    EXPECT_LT(pose.reprojection_rms_px, 0.5);
    const PoseError error = ComparePoses(pose.cMt, cMt);
    EXPECT_LT(error.translation_m, 0.003) << "trial " << trial;
    EXPECT_LT(error.rotation_rad * 180.0 / M_PI, 1.0) << "trial " << trial;
    std::printf("trial %d: %.2f mm, %.2f deg, %.2f px\n", trial, 1e3 * error.translation_m,
                error.rotation_rad * 180.0 / M_PI, pose.reprojection_rms_px);
  }
}

TEST(TagBoardTest, NoBoardNoPose) {
  const std::vector<TagDetection> none;
  EXPECT_FALSE(EstimateBoardPose(none, TagBoardConfig{}, CameraIntrinsics{}).valid);
  TagDetection foreign;
  foreign.id = 77;
  for (auto& c : foreign.corners_px) c.setZero();
  EXPECT_FALSE(EstimateBoardPose({foreign}, TagBoardConfig{}, CameraIntrinsics{}).valid);
}

}  // namespace
}  // namespace aerograsp
