#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "hardware/bag/realsense_bag.h"
#include "hardware/bag/recording.h"
#include "tests/common/simulated_recording.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

class RealsenseBagTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    recording_ = new testing::SimulatedRecording(testing::SimulateRecording(3));
  }
  static void TearDownTestSuite() { delete recording_; }
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = (fs::temp_directory_path() /
             (std::string("aerograsp_bag_") + test->name() + std::to_string(getpid()) + ".bag"))
                .string();
    fs::remove(path_);
  }
  void TearDown() override { fs::remove(path_); }

  RealsenseBagWriter::Streams Streams() const {
    RealsenseBagWriter::Streams s;
    s.color = recording_->color;
    s.depth = recording_->depth;
    s.colorMdepth = recording_->colorMdepth;
    s.depth_scale_m = recording_->depth_scale_m;
    return s;
  }
  /// Colour at 30 Hz; depth 4 ms later, as a D435 delivers them.
  void WriteBag(const RealsenseBagWriter::Streams& streams, bool color = true, bool depth = true) {
    RealsenseBagWriter writer(path_, streams);
    for (std::size_t i = 0; i < recording_->frames.size(); ++i) {
      const double t = 1.0 + i / 30.0;
      if (color) writer.WriteColor(t, recording_->frames[i].color);
      if (depth) writer.WriteDepth(t + 0.004, recording_->frames[i].depth);
    }
  }
  template <typename F>
  static void ExpectError(const F& f, const std::string& text) {
    EXPECT_THAT(f, ::testing::ThrowsMessage<HardwareError>(HasSubstr(text)));
  }

  static testing::SimulatedRecording* recording_;
  std::string path_;
};
testing::SimulatedRecording* RealsenseBagTest::recording_ = nullptr;

TEST_F(RealsenseBagTest, ReadsStreamsCalibrationAndAlignedFrames) {
  WriteBag(Streams());
  RealsenseBagCamera bag(path_);
  EXPECT_EQ(bag.file_version(), 4);
  EXPECT_EQ(bag.info().frame_count, 3);
  EXPECT_NEAR(bag.info().frame_rate_hz, 30.0, 1e-3);
  EXPECT_DOUBLE_EQ(bag.info().depth_scale_m, 0.001);
  EXPECT_EQ(bag.intrinsics().fx, recording_->color.intrinsics.fx);
  EXPECT_EQ(bag.depth_stream().intrinsics.cx, recording_->depth.intrinsics.cx);
  EXPECT_EQ(bag.color_stream().model, DistortionModel::kBrownConrady);
  EXPECT_TRUE(bag.colorMdepth().isApprox(recording_->colorMdepth, 1e-9));
  EXPECT_EQ(bag.unpaired_frames(), 0);
  EXPECT_NEAR(bag.max_pair_offset_s(), 0.004, 1e-6);
  RgbdFrame frame;
  for (const testing::SimulatedFrame& f : recording_->frames) {
    ASSERT_TRUE(bag.Grab(&frame));
    EXPECT_EQ(frame.color, f.color);
    EXPECT_EQ(bag.last_raw_depth(), f.depth);
    EXPECT_EQ(frame.depth, AlignDepthToColor(f.depth, recording_->depth, recording_->color,
                                             recording_->colorMdepth, 0.001));
  }
  EXPECT_FALSE(bag.Grab(&frame));
}

TEST_F(RealsenseBagTest, OpenRecordingTellsBagsSequencesAndTumFoldersApart) {
  WriteBag(Streams());
  EXPECT_NE(dynamic_cast<RealsenseBagCamera*>(OpenRecording(path_).get()), nullptr);
  RecordingOptions tum_only;
  tum_only.intrinsics_file = "camera.xml";
  ExpectError([&] { OpenRecording(path_, tum_only); }, "apply to TUM RGB-D folders only");
  const fs::path folder = fs::path(path_).replace_extension("");
  fs::create_directories(folder);
  ExpectError([&] { OpenRecording(folder.string()); }, "not a recording");
  fs::remove_all(folder);
}

TEST_F(RealsenseBagTest, ABagWithoutColourOrDepthIsNamed) {
  WriteBag(Streams(), /*color=*/false, /*depth=*/true);
  ExpectError([&] { RealsenseBagCamera bag(path_); }, path_ + ": no colour stream");
  fs::remove(path_);
  WriteBag(Streams(), /*color=*/true, /*depth=*/false);
  ExpectError([&] { RealsenseBagCamera bag(path_); }, path_ + ": no depth stream");
}

TEST_F(RealsenseBagTest, AStreamOfAnotherSizeIsNamed) {
  RealsenseBagWriter::Streams streams = Streams();
  streams.depth.intrinsics = streams.depth.intrinsics.Scaled(0.5);  // camera_info 320x240
  WriteBag(streams);
  ExpectError([&] { RealsenseBagCamera bag(path_); },
              "/device_0/sensor_0/Depth_0/image/data message 0: the depth image is 640x480, its "
              "camera_info says 320x240");
}

TEST_F(RealsenseBagTest, AnUnknownDistortionModelIsNamed) {
  RealsenseBagWriter::Streams streams = Streams();
  streams.color_model_name = "Kannala Brandt4";
  WriteBag(streams);
  ExpectError([&] { RealsenseBagCamera bag(path_); },
              path_ +
                  ": /device_0/sensor_1/Color_0/info/camera_info: distortion model "
                  "'Kannala Brandt4' is not supported");
}

TEST_F(RealsenseBagTest, ATruncatedBagIsNamed) {
  WriteBag(Streams());
  fs::resize_file(path_, fs::file_size(path_) / 2);
  ExpectError([&] { RealsenseBagCamera bag(path_); }, path_ + ": cannot be read as a ROS bag");
  std::ofstream(path_, std::ios::trunc) << "not a bag at all\n";
  ExpectError([&] { RealsenseBagCamera bag(path_); }, path_ + ": cannot be read as a ROS bag");
  fs::remove(path_);
  ExpectError([&] { RealsenseBagCamera bag(path_); }, path_ + ": no such file");
}

TEST_F(RealsenseBagTest, ARecordLengthPastTheEndIsNamedBeforeTheBagLibraryReadsIt) {
  // The bag library allocates a record's declared length before reading it:
  // a corrupt length would be gigabytes of memory.
  WriteBag(Streams());
  std::fstream file(path_, std::ios::in | std::ios::out | std::ios::binary);
  char length[4];
  file.seekg(13);  // the first record, after "#ROSBAG V2.0\n"
  file.read(length, 4);
  const std::uint32_t header_len = std::uint8_t(length[0]) | std::uint8_t(length[1]) << 8 |
                                   std::uint8_t(length[2]) << 16 | std::uint32_t(length[3]) << 24;
  file.seekp(13 + 4 + header_len);
  file.write("\xf0\xff\xff\xff", 4);  // its data length: 4294967280 bytes
  file.close();
  ExpectError([&] { RealsenseBagCamera bag(path_); },
              path_ +
                  ": cannot be read as a ROS bag (truncated or corrupt): record at byte 13: "
                  "4294967280 bytes of data past the end of the file");
}

/// The bag's bytes, to corrupt in place.
class BagBytes {
 public:
  explicit BagBytes(const std::string& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::uint32_t U32(std::size_t at) const {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | std::uint8_t(bytes_.at(at + i));
    return v;
  }
  void SetU32(std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.at(at + i) = char(v >> (8 * i));
  }
  /// The record after the one at `at` (header length, header, data length, data).
  std::size_t Next(std::size_t at) const {
    const std::uint32_t header_len = U32(at);
    return at + 8 + header_len + U32(at + 4 + header_len);
  }
  /// The first top-level record whose header holds `field` (e.g. "op=\x05", a chunk).
  std::size_t Find(const std::string& field) const {
    for (std::size_t at = 13; at < bytes_.size(); at = Next(at)) {
      if (std::string(bytes_.data() + at + 4, U32(at)).find(field) != std::string::npos) return at;
    }
    ADD_FAILURE() << "no record with " << field;
    return 13;
  }
  /// Where the value of the header field `name` ("count=") of the record at `at` starts.
  std::size_t FieldValue(std::size_t at, const std::string& name) const {
    const std::size_t field = std::string(bytes_.data() + at + 4, U32(at)).find(name);
    EXPECT_NE(field, std::string::npos) << name;
    return at + 4 + field + name.size();
  }
  /// Where the data of the record at `at` starts.
  std::size_t Data(std::size_t at) const { return at + 8 + U32(at); }
  void Write() const { std::ofstream(path_, std::ios::binary | std::ios::trunc) << bytes_; }

 private:
  std::string path_, bytes_;
};

// The records inside a chunk are checked as the top-level ones are: a nested
// record's lengths running past its chunk are named before the library reads them.
TEST_F(RealsenseBagTest, ANestedRecordRunningPastItsChunkIsNamed) {
  WriteBag(Streams());
  const BagBytes written(path_);
  const std::size_t chunk = written.Find(std::string("op=\x05", 4));
  const std::size_t first = written.Data(chunk);  // the chunk's first record
  const std::size_t second = written.Next(first);

  BagBytes bag = written;
  bag.SetU32(second, 0xfffffff0u);  // its header length
  bag.Write();
  ExpectError([&] { RealsenseBagCamera b(path_); },
              fmt::format("{}: cannot be read as a ROS bag (truncated or corrupt): record at byte "
                          "{} in the chunk at byte {}: a header of 4294967280 bytes",
                          path_, second, chunk));

  bag = written;
  bag.SetU32(second + 4 + bag.U32(second), 0x7ffffff0u);  // its data length
  bag.Write();
  ExpectError([&] { RealsenseBagCamera b(path_); },
              fmt::format("record at byte {} in the chunk at byte {}: 2147483632 bytes of data "
                          "past the end of the chunk",
                          second, chunk));
}

// An index record points at records inside the chunk before it: an offset
// that is not the start of one (or a count its data does not hold) is named.
TEST_F(RealsenseBagTest, AnIndexOffsetThatIsNotARecordInItsChunkIsNamed) {
  WriteBag(Streams());
  const BagBytes written(path_);
  const std::size_t chunk = written.Find(std::string("op=\x05", 4));
  const std::size_t index = written.Next(chunk);  // the chunk's first index record

  BagBytes bag = written;
  const std::size_t offset_at = bag.Data(index) + 8;  // its first entry: time, then offset
  bag.SetU32(offset_at, bag.U32(offset_at) + 3);
  bag.Write();
  ExpectError([&] { RealsenseBagCamera b(path_); },
              fmt::format("index record at byte {}: offset {} is not the start of a record in "
                          "the chunk at byte {}",
                          index, written.U32(offset_at) + 3, chunk));

  bag = written;
  bag.SetU32(bag.FieldValue(index, "count="), 100);  // its data holds one entry
  bag.Write();
  ExpectError([&] { RealsenseBagCamera b(path_); },
              fmt::format("index record at byte {}: 12 bytes of data for 100 entries", index));
}

/// The real D435 recording, where it exists (AEROGRASP_REALSENSE_SAMPLES names its folder).
TEST(RealRealsenseBagTest, ReadsTheD435Recording) {
  const char* dir = std::getenv("AEROGRASP_REALSENSE_SAMPLES");
  const std::string folder = dir ? dir : AEROGRASP_REALSENSE_SAMPLES;
  const fs::path path = fs::path(folder) / "single_depth_color_640x480.bag";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is not here";
  RealsenseBagCamera bag(path.string());
  EXPECT_EQ(bag.file_version(), 3);
  EXPECT_DOUBLE_EQ(bag.info().depth_scale_m, 0.001);
  EXPECT_NEAR(bag.depth_stream().intrinsics.fx, 390.43, 0.01);
  EXPECT_NEAR(bag.depth_stream().intrinsics.cx, 331.39, 0.01);
  EXPECT_NEAR(bag.color_stream().intrinsics.fx, 613.20, 0.01);
  EXPECT_NEAR(bag.color_stream().intrinsics.cy, 239.18, 0.01);
  EXPECT_EQ(bag.color_stream().model, DistortionModel::kBrownConrady);
  // The depth origin lies 14 mm along the colour camera's +x.
  EXPECT_NEAR(bag.colorMdepth().translation().x(), 0.0143, 0.0002);
  EXPECT_EQ(bag.info().frame_count, 1);
  RgbdFrame frame;
  ASSERT_TRUE(bag.Grab(&frame));
  EXPECT_EQ(frame.color.width, 640);
  EXPECT_EQ(frame.depth.width, 640);
  const auto valid = std::count_if(frame.depth.data.begin(), frame.depth.data.end(),
                                   [](std::uint16_t d) { return d != 0; });
  EXPECT_GT(valid, 640 * 480 / 4);
  EXPECT_FALSE(bag.Grab(&frame));
}

}  // namespace
}  // namespace aerograsp
