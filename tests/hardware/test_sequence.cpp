#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/config.h"
#include "core/transforms.h"
#include "hardware/sequence.h"
#include "tests/common/simulated_recording.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;

/// A small synthetic sequence: 4 frames of 32 x 24 with ramps, a pose, the
/// vehicle and joints, written into a fresh temporary folder.
class SequenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = (fs::temp_directory_path() / (std::string("aerograsp_seq_") + info->name())).string();
    fs::remove_all(folder_);
    info_.intrinsics = {32, 24, 30.0, 31.0, 15.5, 11.5};
    info_.depth_scale_m = 0.001;
    info_.object = "crawler";
    info_.frame_rate_hz = 30.0;
    info_.description = "test";
  }
  void TearDown() override { fs::remove_all(folder_); }

  RgbdFrame MakeFrame(int i) const {
    RgbdFrame f;
    f.stamp_s = 0.1 * i + 1.0 / 3.0;
    f.color = ColorImage(32, 24);
    f.depth = DepthImage(32, 24);
    for (std::size_t k = 0; k < f.color.data.size(); ++k)
      f.color.data[k] = static_cast<std::uint8_t>(k * 7 + i);
    for (std::size_t k = 0; k < f.depth.data.size(); ++k)
      f.depth.data[k] = static_cast<std::uint16_t>(k * 97 + i);
    return f;
  }
  SequenceExtras MakeExtras(int i) const {
    SequenceExtras e;
    e.cMo = MakeTransform(Eigen::Vector3d(0.1 * i, -0.2, 0.7 + 1e-7 * i),
                          Eigen::Vector3d(0.1, 0.2 * i, -0.3));
    VehicleState v;
    v.wMd = MakeTransform(Eigen::Vector3d(1, 2, -3), Eigen::Vector3d(0.01, -0.02, 0.5 + i));
    v.v_w = Eigen::Vector3d(0.1, 0.2, 1.0 / 3.0);
    e.vehicle = v;
    e.q_left_rad = Eigen::Vector4d(0.1, 0.2, 0.3, i);
    e.q_right_rad = Eigen::Vector4d(-0.1, -0.2, -0.3, -i);
    return e;
  }
  void WriteSequence(int frames) {
    SequenceWriter writer(folder_, info_);
    for (int i = 0; i < frames; ++i) writer.Write(MakeFrame(i), MakeExtras(i));
  }
  static void ExpectThrowsWith(const std::function<void()>& f, const std::string& text) {
    try {
      f();
      ADD_FAILURE() << "expected an error containing '" << text << "'";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  }
  std::string folder_;
  SequenceInfo info_;
};

TEST_F(SequenceTest, ReplayReadsBackExactlyWhatWasWritten) {
  WriteSequence(4);
  ReplayCamera replay(folder_);
  EXPECT_EQ(replay.info().frame_count, 4);
  EXPECT_EQ(replay.info().object, "crawler");
  EXPECT_EQ(replay.intrinsics().fx, 30.0);
  EXPECT_EQ(replay.intrinsics().cy, 11.5);
  EXPECT_TRUE(replay.has_groundtruth());
  RgbdFrame frame;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(replay.Grab(&frame));
    const RgbdFrame expected = MakeFrame(i);
    EXPECT_EQ(frame.index, i);
    EXPECT_EQ(frame.stamp_s, expected.stamp_s);  // bit for bit
    EXPECT_TRUE(frame.color == expected.color);
    EXPECT_TRUE(frame.depth == expected.depth);
    const SequenceExtras want = MakeExtras(i);
    const SequenceExtras& got = replay.extras(i);
    EXPECT_EQ(got.cMo->translation(), want.cMo->translation());
    // The pose is rebuilt from the written t and q: t is exact, the rotation
    // equal up to rounding.
    EXPECT_TRUE(QuaternionWxyz(*got.cMo).isApprox(QuaternionWxyz(*want.cMo), 1e-15));
    EXPECT_LT(ComparePoses(*got.cMo, *want.cMo).rotation_rad, 1e-15);
    EXPECT_EQ(got.vehicle->wMd.translation(), want.vehicle->wMd.translation());
    EXPECT_EQ(got.vehicle->v_w, want.vehicle->v_w);
    EXPECT_EQ(*got.q_left_rad, *want.q_left_rad);
    EXPECT_EQ(*got.q_right_rad, *want.q_right_rad);
  }
  EXPECT_FALSE(replay.Grab(&frame));
  replay.Rewind();
  ASSERT_TRUE(replay.Grab(&frame));
  EXPECT_EQ(frame.index, 0);
}

TEST_F(SequenceTest, ExtrasAreOptional) {
  {
    SequenceWriter writer(folder_, info_);
    writer.Write(MakeFrame(0));
  }
  ReplayCamera replay(folder_);
  EXPECT_FALSE(replay.has_groundtruth());
  EXPECT_FALSE(replay.extras(0).cMo.has_value());
  EXPECT_FALSE(replay.extras(0).q_left_rad.has_value());
  RgbdFrame frame;
  ASSERT_TRUE(replay.Grab(&frame));
  EXPECT_EQ(frame.stamp_s, MakeFrame(0).stamp_s);  // from stamps.csv
}

TEST_F(SequenceTest, WriterRefusesToOverwriteAndInconsistentExtras) {
  WriteSequence(1);
  ExpectThrowsWith([&] { SequenceWriter again(folder_, info_); }, "already holds a sequence");
  SequenceWriter writer(folder_, info_, /*overwrite=*/true);
  writer.Write(MakeFrame(0), MakeExtras(0));
  ExpectThrowsWith([&] { writer.Write(MakeFrame(1)); },
                   "lacks this kind of data but frame 0 had it");
  RgbdFrame wrong = MakeFrame(1);
  wrong.depth = DepthImage(16, 24);
  ExpectThrowsWith([&] { writer.Write(wrong, MakeExtras(1)); }, "the intrinsics say 32x24");
}

TEST_F(SequenceTest, AFolderWithoutSequenceYamlIsNotASequence) {
  ExpectThrowsWith([&] { ReplayCamera r(folder_); }, "no such folder");
  fs::create_directories(folder_);
  ExpectThrowsWith([&] { ReplayCamera r(folder_); }, "not a sequence: no sequence.yaml");
}

TEST_F(SequenceTest, MissingFrameIsNamed) {
  WriteSequence(4);
  fs::remove(fs::path(folder_) / "depth" / "000002.png");
  ExpectThrowsWith([&] { ReplayCamera r(folder_); },
                   "depth/000002.png: missing (sequence.yaml says 4 frames)");
}

TEST_F(SequenceTest, ImageOfTheWrongSizeIsNamedWhenRead) {
  WriteSequence(2);
  fs::copy_file(fs::path(folder_) / "color" / "000000.png", fs::path(folder_) / "big.png");
  {
    SequenceInfo other = info_;
    other.intrinsics = {64, 24, 30.0, 31.0, 15.5, 11.5};
    const std::string elsewhere = folder_ + "_other";
    fs::remove_all(elsewhere);
    {
      SequenceWriter w(elsewhere, other);
      RgbdFrame f;
      f.color = ColorImage(64, 24);
      f.depth = DepthImage(64, 24);
      w.Write(f);
    }
    fs::copy_file(fs::path(elsewhere) / "color" / "000000.png",
                  fs::path(folder_) / "color" / "000001.png", fs::copy_options::overwrite_existing);
    fs::remove_all(elsewhere);
  }
  ReplayCamera replay(folder_);
  RgbdFrame frame;
  ASSERT_TRUE(replay.Grab(&frame));
  ExpectThrowsWith([&] { replay.Grab(&frame); },
                   "color/000001.png: is 64x24, sequence.yaml says 32x24");
}

TEST_F(SequenceTest, CorruptImageIsNamed) {
  WriteSequence(1);
  std::ofstream(fs::path(folder_) / "depth" / "000000.png", std::ios::trunc) << "not a png";
  ReplayCamera replay(folder_);
  RgbdFrame frame;
  ExpectThrowsWith([&] { replay.Grab(&frame); }, "depth/000000.png: cannot be read as an image");
}

TEST_F(SequenceTest, TruncatedAndGarbledCsvAreNamedWithTheLine) {
  WriteSequence(3);
  const fs::path gt = fs::path(folder_) / "groundtruth.csv";
  std::string text;
  {
    std::ifstream in(gt);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  // Drop the last row: a truncated recording.
  const std::string truncated = text.substr(0, text.rfind('\n', text.size() - 2) + 1);
  std::ofstream(gt, std::ios::trunc) << truncated;
  ExpectThrowsWith([&] { ReplayCamera r(folder_); },
                   "groundtruth.csv: 2 rows but sequence.yaml says 3 frames");
  // A garbage number on line 3.
  std::string garbled = text;
  garbled.replace(garbled.find(",", garbled.find('\n', garbled.find('\n') + 1)) + 1, 1, "x");
  std::ofstream(gt, std::ios::trunc) << garbled;
  ExpectThrowsWith([&] { ReplayCamera r(folder_); }, "groundtruth.csv: line 3:");
}

TEST_F(SequenceTest, AZeroQuaternionInTheGroundTruthIsRefusedWithItsFrame) {
  WriteSequence(3);
  std::ofstream(fs::path(folder_) / "groundtruth.csv", std::ios::trunc)
      << "frame,stamp_s,tx,ty,tz,qw,qx,qy,qz\n0,0.0,0,0,0.7,1,0,0,0\n1,0.1,0,0,0.7,0,0,0,0\n"
      << "2,0.2,0,0,0.7,1,0,0,0\n";
  ExpectThrowsWith([&] { ReplayCamera r(folder_); },
                   "groundtruth.csv: frame 1: the quaternion (w, x, y, z) has norm 0.000000, not "
                   "a rotation");
}

TEST_F(SequenceTest, AQuaternionALittleOffUnitIsNormalised) {
  WriteSequence(3);
  std::ofstream(fs::path(folder_) / "groundtruth.csv", std::ios::trunc)
      << "frame,stamp_s,tx,ty,tz,qw,qx,qy,qz\n0,0.0,0,0,0.7,0.7072,0.7072,0,0\n"
      << "1,0.1,0,0,0.7,1,0,0,0\n2,0.2,0,0,0.7,1,0,0,0\n";
  ReplayCamera replay(folder_);
  const Eigen::Matrix3d R = replay.extras(0).cMo->linear();
  EXPECT_NEAR((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(R(1, 2), -1.0, 1e-12);  // 90 degrees about x
}

TEST_F(SequenceTest, StampsThatGoBackOrJumpFarAreRefusedWithTheLine) {
  WriteSequence(3);
  const fs::path stamps = fs::path(folder_) / "stamps.csv";
  std::ofstream(stamps, std::ios::trunc) << "frame,stamp_s\n0,0.0\n1,0.1\n2,0.05\n";
  ExpectThrowsWith([&] { ReplayCamera r(folder_); },
                   "stamps.csv: line 4: stamp_s 0.050000 s does not follow the previous frame's "
                   "0.100000 s");
  std::ofstream(stamps, std::ios::trunc) << "frame,stamp_s\n0,0.0\n1,0.1\n2,1e308\n";
  ExpectThrowsWith([&] { ReplayCamera r(folder_); }, "stamps.csv: line 4: stamp_s");
  std::ofstream(stamps, std::ios::trunc) << "frame,stamp_s\n0,0.0\n1,0.1\n2,0.1\n";
  ExpectThrowsWith([&] { ReplayCamera r(folder_); }, "(stamps must increase)");
}

TEST_F(SequenceTest, BadYamlIsNamedWithTheField) {
  WriteSequence(1);
  const fs::path yaml = fs::path(folder_) / "sequence.yaml";
  std::string text;
  {
    std::ifstream in(yaml);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::string bad = text;
  bad.replace(bad.find("fx: "), 4, "fx: -");
  std::ofstream(yaml, std::ios::trunc) << bad;
  ExpectThrowsWith([&] { ReadSequenceInfo(folder_); }, "sequence.yaml: intrinsics");
  std::ofstream(yaml, std::ios::trunc) << "format: [unclosed\n";
  ExpectThrowsWith([&] { ReadSequenceInfo(folder_); }, "sequence.yaml");
  bad = text;
  bad.replace(bad.find("version: 1"), 10, "version: 9");
  std::ofstream(yaml, std::ios::trunc) << bad;
  ExpectThrowsWith([&] { ReadSequenceInfo(folder_); }, "version: version 9 is not supported");
}

/// A sequence with the depth camera's own images: stored as they are, aligned
/// on read by the alignment of every input, and the colour camera's render agrees.
TEST_F(SequenceTest, UnalignedDepthIsStoredAsItIsAndAlignedOnRead) {
  const testing::SimulatedRecording r = testing::SimulateRecording(2);
  SequenceInfo info;
  info.intrinsics = r.color.intrinsics;
  info.color_model = r.color.model;
  info.depth_camera = r.depth;
  info.colorMdepth = r.colorMdepth;
  info.depth_scale_m = r.depth_scale_m;
  {
    SequenceWriter writer(folder_, info);
    for (const testing::SimulatedFrame& f : r.frames) {
      RgbdFrame frame;
      frame.stamp_s = 0.1 * static_cast<double>(writer.frame_count());
      frame.color = f.color;
      frame.depth = f.depth;
      writer.Write(frame);
    }
  }
  const SequenceInfo stored = ReadSequenceInfo(folder_);
  ASSERT_TRUE(stored.depth_camera.has_value());
  EXPECT_EQ(stored.depth_camera->intrinsics.fx, r.depth.intrinsics.fx);
  EXPECT_EQ(stored.depth_camera->model, DistortionModel::kBrownConrady);
  EXPECT_EQ(stored.color_model, DistortionModel::kBrownConrady);
  EXPECT_TRUE(stored.colorMdepth.isApprox(r.colorMdepth, 1e-15));

  ReplayCamera replay(folder_);
  EXPECT_FALSE(replay.info().depth_camera.has_value());  // frames come aligned
  RgbdFrame frame;
  for (const testing::SimulatedFrame& f : r.frames) {
    ASSERT_TRUE(replay.Grab(&frame));
    EXPECT_EQ(frame.depth, AlignDepthToColor(f.depth, r.depth, r.color, r.colorMdepth, 0.001));
    int agree = 0, compared = 0;
    for (std::size_t i = 0; i < frame.depth.data.size(); ++i) {
      if (!frame.depth.data[i] || !f.color_depth.data[i]) continue;
      ++compared;
      agree += std::abs(frame.depth.data[i] - f.color_depth.data[i]) <= 2;
    }
    EXPECT_GT(agree, 0.97 * compared);
  }
}

TEST_F(SequenceTest, UnalignedDepthOfAnotherSizeAndAnUnknownLensAreNamed) {
  info_.depth_camera =
      StreamCalibration{{16, 12, 15.0, 15.0, 7.5, 5.5}, DistortionModel::kNone, {}};
  {
    SequenceWriter writer(folder_, info_);
    RgbdFrame frame = MakeFrame(0);
    ExpectThrowsWith([&] { writer.Write(frame); }, "the intrinsics say 32x24 colour, 16x12 depth");
    frame.depth = DepthImage(16, 12);
    writer.Write(frame);
  }
  const fs::path yaml = fs::path(folder_) / "sequence.yaml";
  std::string text;
  {
    std::ifstream in(yaml);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  ReplayCamera replay(folder_);
  RgbdFrame frame;
  EXPECT_TRUE(replay.Grab(&frame));
  EXPECT_EQ(frame.depth.width, 32);
  text.replace(text.find("distortion_model: none"), 22, "distortion_model: fisheye");
  std::ofstream(yaml, std::ios::trunc) << text;
  ExpectThrowsWith([&] { ReadSequenceInfo(folder_); },
                   "depth_camera.distortion_model: 'fisheye' is not one of");
}

}  // namespace
}  // namespace aerograsp
