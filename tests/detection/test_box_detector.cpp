#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "detection/box_detector.h"

namespace aerograsp {
namespace {

CenterNetMaps EmptyMaps(int w = 40, int h = 30) {
  CenterNetMaps m;
  m.width = w;
  m.height = h;
  const std::size_t n = std::size_t(w) * h;
  m.heat_logit.assign(n, -8.0f);
  m.offset_x.assign(n, 0.0f);
  m.offset_y.assign(n, 0.0f);
  m.log_width.assign(n, 0.0f);
  m.log_height.assign(n, 0.0f);
  return m;
}

void SetPeak(CenterNetMaps* m, int x, int y, float logit, float ox, float oy, float w_cells,
             float h_cells) {
  const std::size_t i = std::size_t(y) * m->width + x;
  m->heat_logit[i] = logit;
  m->offset_x[i] = ox;
  m->offset_y[i] = oy;
  m->log_width[i] = std::log(w_cells);
  m->log_height[i] = std::log(h_cells);
}

TEST(BoxDecodingTest, OnePeakGivesItsBoxInImagePixels) {
  CenterNetMaps m = EmptyMaps();
  SetPeak(&m, 10, 7, 2.0f, 0.5f, 0.25f, 3.0f, 2.0f);
  // Lower neighbours are not peaks of their own.
  m.heat_logit[7 * 40 + 11] = 1.5f;
  m.heat_logit[8 * 40 + 10] = 1.0f;
  const std::vector<Detection> d = DecodeCenterNet(m, 640, 480, 0.3f);
  ASSERT_EQ(d.size(), 1u);
  // One cell = 16 px: centre (10.5, 7.25) cells = (168, 116) px, size 48 x 32 px.
  EXPECT_EQ(d[0].box.x0, 144);
  EXPECT_EQ(d[0].box.x1, 192);
  EXPECT_EQ(d[0].box.y0, 100);
  EXPECT_EQ(d[0].box.y1, 132);
  EXPECT_NEAR(d[0].score, 1.0 / (1.0 + std::exp(-2.0)), 1e-6);
}

TEST(BoxDecodingTest, PeaksBestFirstThresholdAndLimit) {
  CenterNetMaps m = EmptyMaps();
  SetPeak(&m, 5, 5, 0.5f, 0, 0, 2, 2);     // 0.62
  SetPeak(&m, 20, 20, 3.0f, 0, 0, 2, 2);   // 0.95
  SetPeak(&m, 30, 10, -1.0f, 0, 0, 2, 2);  // 0.27: below 0.3
  std::vector<Detection> d = DecodeCenterNet(m, 640, 480, 0.3f);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_GT(d[0].score, d[1].score);
  EXPECT_EQ(d[0].box.x0, 20 * 16 - 16);
  d = DecodeCenterNet(m, 640, 480, 0.3f, 1);
  EXPECT_EQ(d.size(), 1u);
  EXPECT_TRUE(DecodeCenterNet(m, 640, 480, 0.99f).empty());
}

TEST(BoxDecodingTest, BoxesAreClippedToTheImage) {
  CenterNetMaps m = EmptyMaps();
  SetPeak(&m, 0, 0, 2.0f, 0.0f, 0.0f, 4.0f, 4.0f);
  const std::vector<Detection> d = DecodeCenterNet(m, 640, 480, 0.3f);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].box.x0, 0);
  EXPECT_EQ(d[0].box.y0, 0);
  EXPECT_EQ(d[0].box.x1, 32);
}

TEST(BoxDecodingTest, BadMapsGiveNothing) {
  CenterNetMaps m = EmptyMaps();
  SetPeak(&m, 10, 10, 2.0f, 0, 0, 2, 2);
  CenterNetMaps short_maps = m;
  short_maps.log_height.pop_back();
  EXPECT_TRUE(DecodeCenterNet(short_maps, 640, 480, 0.3f).empty());
  CenterNetMaps nan_maps = m;
  nan_maps.log_width[10 * 40 + 10] = std::nanf("");
  EXPECT_TRUE(DecodeCenterNet(nan_maps, 640, 480, 0.3f).empty());
  EXPECT_TRUE(DecodeCenterNet(CenterNetMaps{}, 640, 480, 0.3f).empty());
  EXPECT_TRUE(DecodeCenterNet(m, 0, 480, 0.3f).empty());
}

TEST(BoxDetectorTest, MissingOrCorruptModelIsAClearError) {
  EXPECT_THAT(
      [] { BoxDetector d("/nonexistent/detector.onnx"); },
      ::testing::ThrowsMessage<std::runtime_error>(::testing::HasSubstr("no such detector model")));
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("aerograsp_corrupt_" + std::to_string(getpid()) + ".onnx"))
                               .string();
  std::ofstream(path) << "not an onnx file";
  EXPECT_THAT([&] { BoxDetector d(path); },
              ::testing::ThrowsMessage<std::runtime_error>(
                  ::testing::HasSubstr("cannot load the detector model")));
  std::filesystem::remove(path);
}

TEST(BoxDetectorTest, ShippedModelsLoadAndFindNothingInABlankImage) {
  for (const char* name : {"crawler", "u_shape", "pipe"}) {
    const std::string path =
        std::string(AEROGRASP_DATA_DIR) + "/objects/" + name + "/detector.onnx";
    if (!std::filesystem::exists(path)) continue;
    BoxDetector detector(path);
    EXPECT_TRUE(detector.Detect(ColorImage(640, 480, 0), 0.5f).empty()) << name;
    EXPECT_TRUE(detector.Detect(ColorImage{}).empty());
  }
}

}  // namespace
}  // namespace aerograsp
