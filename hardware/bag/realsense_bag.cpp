#include "hardware/bag/realsense_bag.h"

#include <diagnostic_msgs/KeyValue.h>
#include <geometry_msgs/Transform.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Float32.h>
#include <std_msgs/UInt32.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

/// Record times of static messages (options, calibration): the earliest a bag accepts.
const ros::Time kStaticTime = ros::TIME_MIN;

struct StreamTopic {
  std::string prefix;  // /device_D/sensor_S/Kind_N
  std::string sensor;  // /device_D/sensor_S
};

Eigen::Isometry3d FromTransform(const geometry_msgs::Transform& m) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(m.rotation.w, m.rotation.x, m.rotation.y, m.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(m.translation.x, m.translation.y, m.translation.z);
  return T;
}

geometry_msgs::Transform ToTransform(const Eigen::Isometry3d& T) {
  geometry_msgs::Transform m;
  const Eigen::Quaterniond q(T.linear());
  m.rotation.w = q.w(), m.rotation.x = q.x(), m.rotation.y = q.y(), m.rotation.z = q.z();
  m.translation.x = T.translation().x();
  m.translation.y = T.translation().y();
  m.translation.z = T.translation().z();
  return m;
}

std::string Size(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

constexpr std::uint32_t kMaxRecordHeaderBytes = 1u << 20;  // real ones are well under 1 KB

std::uint64_t LittleEndian(const std::string& bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = bytes.size(); i-- > 0;) v = (v << 8) | static_cast<std::uint8_t>(bytes[i]);
  return v;
}

/// One record's header and data length, read from `in` at `pos` and checked
/// against `end` (the file's size, or the end of the chunk holding it).
struct RecordHead {
  std::map<std::string, std::string> fields;
  std::uint32_t header_len = 0, data_len = 0;
  std::uint64_t data_pos = 0;
  std::string op() const { return fields.count("op") ? fields.at("op") : ""; }
};

/// Reads the record at `pos` of `in`; returns what is wrong, or "". `at`
/// names the record, `container` what it must fit in ("file", "chunk").
std::string ReadRecordHead(std::istream& in, std::uint64_t pos, std::uint64_t end,
                           const std::string& at, const std::string& container, RecordHead* head) {
  const auto u32 = [&in](std::uint32_t* v) {
    char b[4];
    if (!in.read(b, 4)) return false;
    *v = static_cast<std::uint32_t>(LittleEndian(std::string(b, 4)));
    return true;
  };
  in.clear();
  in.seekg(static_cast<std::streamoff>(pos));
  if (end - pos < 4 || !u32(&head->header_len)) return at + ": truncated";
  const std::uint32_t header_len = head->header_len;
  if (header_len > kMaxRecordHeaderBytes || header_len > end - pos - 4)
    return at + ": a header of " + std::to_string(header_len) + " bytes";
  std::string header(header_len, '\0');
  if (!in.read(header.data(), header_len)) return at + ": truncated";
  for (std::size_t off = 0; off < header.size();) {
    if (header.size() - off < 4) return at + ": a header field runs past the header";
    const std::uint64_t len = LittleEndian(header.substr(off, 4));
    off += 4;
    if (len > header.size() - off) return at + ": a header field runs past the header";
    const std::string field = header.substr(off, len);
    off += len;
    const std::size_t eq = field.find('=');
    if (eq != std::string::npos) head->fields[field.substr(0, eq)] = field.substr(eq + 1);
  }
  if (end - pos - 4 - header_len < 4 || !u32(&head->data_len)) return at + ": truncated";
  if (head->data_len > end - pos - 8 - header_len) {
    return at + ": " + std::to_string(head->data_len) + " bytes of data past the end of the " +
           container;
  }
  head->data_pos = pos + 8 + header_len;
  return "";
}

/// The bag's records (ROS bag 2.0: header length, header fields, data length,
/// data) against the file's size, before rosbag_storage reads them: it
/// allocates a record's declared length before reading it, so a corrupt length
/// becomes an allocation of gigabytes. The records inside an uncompressed chunk
/// (connections and messages) are checked against the chunk's end the same
/// way, and the index records after a chunk must point at records in it
/// (`count` entries of 12 bytes, each offset the start of one); the index and
/// the chunks the bag header and chunk infos name must start at a record.
/// Returns what is wrong, or "" (also for a file that is not a 2.0 bag:
/// rosbag_storage says what it is).
std::string CheckBagRecords(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uint64_t size = fs::file_size(path, ec);
  std::string magic(13, '\0');
  if (ec || !in.read(magic.data(), 13) || magic != "#ROSBAG V2.0\n") return "";
  std::set<std::uint64_t> starts;
  std::vector<std::pair<std::string, std::uint64_t>> pointers;  // (field, position)
  // The last uncompressed chunk: where it is, and its records' offsets in its data.
  std::optional<std::uint64_t> chunk;
  std::set<std::uint64_t> chunk_records;
  for (std::uint64_t pos = 13; pos < size;) {
    const std::string at = "record at byte " + std::to_string(pos);
    starts.insert(pos);
    RecordHead head;
    if (std::string wrong = ReadRecordHead(in, pos, size, at, "file", &head); !wrong.empty())
      return wrong;
    std::map<std::string, std::string>& fields = head.fields;
    const std::string op = head.op();
    if (op == "\x03" && fields["index_pos"].size() == 8)
      pointers.push_back({"index_pos", LittleEndian(fields["index_pos"])});
    if (op == "\x06" && fields["chunk_pos"].size() == 8)
      pointers.push_back({"chunk_pos", LittleEndian(fields["chunk_pos"])});
    if (op == "\x05") {
      chunk.reset();
      chunk_records.clear();
      if (fields["compression"] == "none") {
        if (fields["size"].size() == 4 && LittleEndian(fields["size"]) != head.data_len) {
          return at + ": an uncompressed chunk of " + std::to_string(head.data_len) +
                 " bytes says " + std::to_string(LittleEndian(fields["size"]));
        }
        chunk = pos;
        const std::uint64_t chunk_end = head.data_pos + head.data_len;
        for (std::uint64_t inner = head.data_pos; inner < chunk_end;) {
          const std::string inner_at = "record at byte " + std::to_string(inner) +
                                       " in the chunk at byte " + std::to_string(pos);
          RecordHead record;
          if (std::string wrong = ReadRecordHead(in, inner, chunk_end, inner_at, "chunk", &record);
              !wrong.empty())
            return wrong;
          if (record.op() != "\x02" && record.op() != "\x07")
            return inner_at + ": neither a message nor a connection record";
          chunk_records.insert(inner - head.data_pos);
          inner = record.data_pos + record.data_len;
        }
      }
    }
    if (op == "\x04" && fields["ver"].size() == 4 && LittleEndian(fields["ver"]) == 1 &&
        fields["count"].size() == 4) {
      const std::string index_at = "index record at byte " + std::to_string(pos);
      const std::uint64_t count = LittleEndian(fields["count"]);
      if (12 * count != head.data_len) {
        return index_at + ": " + std::to_string(head.data_len) + " bytes of data for " +
               std::to_string(count) + " entries";
      }
      if (chunk) {  // each entry: time (8 bytes), offset in the chunk's data (4)
        std::string entries(head.data_len, '\0');
        in.clear();
        in.seekg(static_cast<std::streamoff>(head.data_pos));
        if (!in.read(entries.data(), head.data_len)) return index_at + ": truncated";
        for (std::uint64_t i = 0; i < count; ++i) {
          const std::uint64_t offset = LittleEndian(entries.substr(12 * i + 8, 4));
          if (!chunk_records.count(offset)) {
            return index_at + ": offset " + std::to_string(offset) +
                   " is not the start of a record in the chunk at byte " + std::to_string(*chunk);
          }
        }
      }
    }
    pos = head.data_pos + head.data_len;
  }
  for (const auto& [field, position] : pointers) {
    if (!starts.count(position) && !(field == "index_pos" && position == size))
      return field + " " + std::to_string(position) + " is not the start of a record";
  }
  return "";
}

}  // namespace

struct RealsenseBagCamera::Impl {
  std::string path;
  rosbag::Bag bag;
  std::string color_topic, depth_topic;
  StreamCalibration color, depth;
  Eigen::Isometry3d colorMdepth = Eigen::Isometry3d::Identity();
  int file_version = 0;
  std::vector<rosbag::MessageInstance> color_msgs, depth_msgs;  // paired frames
  std::vector<int> color_numbers;  // message number of each paired colour frame in its topic
  SequenceInfo info;
  SequenceExtras no_extras;
  DepthImage raw_depth;
  std::unique_ptr<DepthAligner> aligner;  // made at the first frame
  int unpaired = 0;
  double gap_s = 0.0, max_offset_s = 0.0;
  std::int64_t next = 0;

  [[noreturn]] void Fail(const std::string& message) const {
    throw HardwareError(path + ": " + message);
  }

  template <typename M>
  std::optional<M> ReadFirst(const std::string& topic) {
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    for (const rosbag::MessageInstance& m : view) {
      if (!m.isType<M>()) {
        Fail(topic + " holds " + m.getDataType() + ", expected " +
             ros::message_traits::DataType<M>::value());
      }
      return *m.instantiate<M>();
    }
    return std::nullopt;
  }

  StreamCalibration ReadCalibration(const std::string& prefix) {
    const std::string topic = prefix + "/info/camera_info";
    const std::optional<sensor_msgs::CameraInfo> ci = ReadFirst<sensor_msgs::CameraInfo>(topic);
    if (!ci) Fail("no " + topic + " (the stream's intrinsics)");
    StreamCalibration s;
    s.intrinsics.width = static_cast<int>(ci->width);
    s.intrinsics.height = static_cast<int>(ci->height);
    s.intrinsics.fx = ci->K[0];
    s.intrinsics.fy = ci->K[4];
    s.intrinsics.cx = ci->K[2];
    s.intrinsics.cy = ci->K[5];
    try {
      s.intrinsics.Validate(path, topic + ".");
    } catch (const std::exception& e) {
      throw HardwareError(e.what());
    }
    s.model = ParseDistortionModel(ci->distortion_model, path + ": " + topic);
    if (ci->D.size() > s.coeffs.size())
      Fail(topic + ": " + std::to_string(ci->D.size()) + " distortion coefficients, at most 5");
    for (std::size_t i = 0; i < ci->D.size(); ++i) s.coeffs[i] = ci->D[i];
    return s;
  }

  /// The stream's extrinsic from the reference stream (identity when not recorded for it).
  std::optional<Eigen::Isometry3d> ReadExtrinsic(const std::string& prefix) {
    const auto m = ReadFirst<geometry_msgs::Transform>(prefix + "/tf/0");
    if (!m) return std::nullopt;
    const Eigen::Isometry3d T = FromTransform(*m);
    if (!T.matrix().allFinite()) Fail(prefix + "/tf/0: not a finite transform");
    return T;
  }

  /// Checks an image message against its stream and returns it.
  sensor_msgs::ImageConstPtr ReadImage(const rosbag::MessageInstance& m, const std::string& kind,
                                       const StreamCalibration& stream, int number) {
    sensor_msgs::ImageConstPtr image;
    try {
      image = m.instantiate<sensor_msgs::Image>();
    } catch (const std::exception& e) {
      Fail(m.getTopic() + " message " + std::to_string(number) +
           " cannot be read (truncated bag?): " + e.what());
    }
    if (!image) Fail(m.getTopic() + " holds " + m.getDataType() + ", expected sensor_msgs/Image");
    const std::string where = m.getTopic() + " message " + std::to_string(number);
    const CameraIntrinsics& K = stream.intrinsics;
    if (static_cast<int>(image->width) != K.width || static_cast<int>(image->height) != K.height) {
      Fail(where + ": the " + kind + " image is " + Size(image->width, image->height) +
           ", its camera_info says " + Size(K.width, K.height));
    }
    int bytes = 0;
    if (kind == "depth") {
      if (image->encoding == "mono16" || image->encoding == "16UC1") bytes = 2;
    } else if (image->encoding == "rgb8" || image->encoding == "bgr8") {
      bytes = 3;
    } else if (image->encoding == "rgba8" || image->encoding == "bgra8") {
      bytes = 4;
    }
    if (bytes == 0) {
      Fail(where + ": encoding '" + image->encoding + "' is not supported for " + kind +
           (kind == "depth" ? " (mono16, 16UC1)" : " (rgb8, bgr8, rgba8, bgra8)"));
    }
    if (image->step < image->width * bytes ||
        image->data.size() < std::size_t(image->step) * image->height) {
      Fail(where + ": " + std::to_string(image->data.size()) + " bytes of data for " +
           Size(image->width, image->height) + " " + image->encoding + " (truncated?)");
    }
    return image;
  }

  void Open(const BagOptions& options) {
    if (!fs::is_regular_file(path)) Fail("no such file");
    if (const std::string wrong = CheckBagRecords(path); !wrong.empty())
      Fail("cannot be read as a ROS bag (truncated or corrupt): " + wrong);
    try {
      bag.open(path, rosbag::bagmode::Read);
    } catch (const std::exception& e) {
      Fail(std::string("cannot be read as a ROS bag (truncated, or not a bag?): ") + e.what());
    }
    // Streams by topic name.
    const std::regex image_topic(R"((/device_\d+/sensor_\d+)/(Depth|Color)_\d+/image/data)");
    std::string topics;
    {
      rosbag::View all(bag);
      for (const rosbag::ConnectionInfo* c : all.getConnections()) {
        std::smatch match;
        if (!std::regex_match(c->topic, match, image_topic)) continue;
        std::string& chosen = match[2] == "Depth" ? depth_topic : color_topic;
        if (chosen.empty() || c->topic < chosen) chosen = c->topic;
        topics += (topics.empty() ? "" : ", ") + c->topic;
      }
    }
    const std::string found = topics.empty() ? "none" : topics;
    if (color_topic.empty())
      Fail("no colour stream (no /device_*/sensor_*/Color_*/image/data; image topics: " + found +
           ")");
    if (depth_topic.empty())
      Fail("no depth stream (no /device_*/sensor_*/Depth_*/image/data; image topics: " + found +
           ")");
    const std::string color_prefix = color_topic.substr(0, color_topic.size() - 11);
    const std::string depth_prefix = depth_topic.substr(0, depth_topic.size() - 11);
    const std::string depth_sensor = depth_prefix.substr(0, depth_prefix.rfind('/'));

    if (const auto v = ReadFirst<std_msgs::UInt32>("/file_version")) {
      file_version = static_cast<int>(v->data);
      if (file_version < 2)
        Fail("/file_version " + std::to_string(file_version) + " is not supported (2 and up)");
    }
    color = ReadCalibration(color_prefix);
    depth = ReadCalibration(depth_prefix);
    const auto color_ext = ReadExtrinsic(color_prefix);
    const auto depth_ext = ReadExtrinsic(depth_prefix);
    if (!color_ext && !depth_ext)
      Fail("no extrinsic (" + color_prefix + "/tf/0) between the depth and colour streams");
    const Eigen::Isometry3d colorMref = color_ext.value_or(Eigen::Isometry3d::Identity());
    const Eigen::Isometry3d depthMref = depth_ext.value_or(Eigen::Isometry3d::Identity());
    colorMdepth = colorMref * depthMref.inverse();

    info.depth_scale_m = 0.001;
    std::string units_note = "depth units recorded";
    if (const auto units =
            ReadFirst<std_msgs::Float32>(depth_sensor + "/option/Depth Units/value")) {
      // Float32 in the bag: keep the 7 significant digits it holds.
      char text[32];
      std::snprintf(text, sizeof(text), "%.7g", static_cast<double>(units->data));
      info.depth_scale_m = std::strtod(text, nullptr);
      if (!(info.depth_scale_m > 0.0 && info.depth_scale_m < 1.0))
        Fail(depth_sensor + "/option/Depth Units/value: " + text + " m is not a depth unit");
    } else {
      units_note = "no Depth Units option recorded, 0.001 m assumed";
    }

    // Index both streams by record time and pair them.
    std::vector<rosbag::MessageInstance> colors, depths;
    std::vector<double> color_t, depth_t;
    try {
      rosbag::View cv(bag, rosbag::TopicQuery(color_topic));
      for (const rosbag::MessageInstance& m : cv)
        colors.push_back(m), color_t.push_back(m.getTime().toSec());
      rosbag::View dv(bag, rosbag::TopicQuery(depth_topic));
      for (const rosbag::MessageInstance& m : dv)
        depths.push_back(m), depth_t.push_back(m.getTime().toSec());
    } catch (const std::exception& e) {
      Fail(std::string("cannot be indexed (truncated bag?): ") + e.what());
    }
    if (colors.empty()) Fail(color_topic + " holds no image");
    if (depths.empty()) Fail(depth_topic + " holds no image");
    ReadImage(colors.front(), "colour", color, 0);
    ReadImage(depths.front(), "depth", depth, 0);
    gap_s = options.max_pair_gap_s > 0.0 ? options.max_pair_gap_s : MedianInterval(depth_t);
    const std::vector<int> pairs = PairByStamp(color_t, depth_t, gap_s);
    std::vector<double> paired_t;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i] < 0) {
        ++unpaired;
        continue;
      }
      color_msgs.push_back(colors[i]);
      depth_msgs.push_back(depths[static_cast<std::size_t>(pairs[i])]);
      color_numbers.push_back(static_cast<int>(i));
      paired_t.push_back(color_t[i]);
      max_offset_s = std::max(max_offset_s, std::abs(color_t[i] - depth_t[pairs[i]]));
    }
    if (color_msgs.empty()) {
      Fail("no colour frame has a depth frame within " + std::to_string(gap_s) +
           " s of record time");
    }
    info.intrinsics = color.intrinsics;
    info.color_model = color.model;
    info.color_coeffs = color.coeffs;
    info.colorMdepth = colorMdepth;
    info.object = options.object;
    info.frame_count = static_cast<std::int64_t>(color_msgs.size());
    const double period_s = MedianInterval(paired_t);
    info.frame_rate_hz = std::isfinite(period_s) && period_s > 0.0 ? 1.0 / period_s : 30.0;
    info.description = "RealSense bag " + path + " (file version " + std::to_string(file_version) +
                       ", " + units_note + ")";
  }
};

RealsenseBagCamera::RealsenseBagCamera(const std::string& path, const BagOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  try {
    impl_->Open(options);
  } catch (const HardwareError&) {
    throw;
  } catch (const std::exception& e) {  // the bag library's, on a corrupt record
    throw HardwareError(path + ": cannot be read as a ROS bag (corrupt): " + e.what());
  }
}

RealsenseBagCamera::~RealsenseBagCamera() = default;

bool RealsenseBagCamera::Grab(RgbdFrame* frame) {
  Impl& m = *impl_;
  if (m.next >= m.info.frame_count) return false;
  const std::size_t i = static_cast<std::size_t>(m.next);
  const sensor_msgs::ImageConstPtr color =
      m.ReadImage(m.color_msgs[i], "colour", m.color, m.color_numbers[i]);
  const sensor_msgs::ImageConstPtr depth =
      m.ReadImage(m.depth_msgs[i], "depth", m.depth, static_cast<int>(i));
  const CameraIntrinsics& Kc = m.color.intrinsics;
  frame->color = ColorImage(Kc.width, Kc.height);
  const int channels = color->encoding.size() == 5 ? 4 : 3;  // rgba8, bgra8
  const bool bgr = color->encoding[0] == 'b';
  for (int y = 0; y < Kc.height; ++y) {
    const std::uint8_t* src = color->data.data() + std::size_t(y) * color->step;
    std::uint8_t* dst = frame->color.Row(y);
    for (int x = 0; x < Kc.width; ++x, src += channels, dst += 3) {
      dst[0] = src[bgr ? 2 : 0], dst[1] = src[1], dst[2] = src[bgr ? 0 : 2];
    }
  }
  const CameraIntrinsics& Kd = m.depth.intrinsics;
  m.raw_depth = DepthImage(Kd.width, Kd.height);
  const bool swap = depth->is_bigendian != 0;
  for (int y = 0; y < Kd.height; ++y) {
    const std::uint8_t* src = depth->data.data() + std::size_t(y) * depth->step;
    std::uint16_t* dst = m.raw_depth.Row(y);
    for (int x = 0; x < Kd.width; ++x, src += 2) {
      dst[x] = swap ? static_cast<std::uint16_t>(src[0] << 8 | src[1])
                    : static_cast<std::uint16_t>(src[1] << 8 | src[0]);
    }
  }
  if (!m.aligner) {
    m.aligner =
        std::make_unique<DepthAligner>(m.depth, m.color, m.colorMdepth, m.info.depth_scale_m);
  }
  frame->depth = m.aligner->Align(m.raw_depth);
  frame->index = m.next;
  frame->stamp_s = color->header.stamp.toSec();
  ++m.next;
  return true;
}

const SequenceInfo& RealsenseBagCamera::info() const { return impl_->info; }
const SequenceExtras& RealsenseBagCamera::extras(std::int64_t) const { return impl_->no_extras; }
const StreamCalibration& RealsenseBagCamera::color_stream() const { return impl_->color; }
const StreamCalibration& RealsenseBagCamera::depth_stream() const { return impl_->depth; }
const Eigen::Isometry3d& RealsenseBagCamera::colorMdepth() const { return impl_->colorMdepth; }
const DepthImage& RealsenseBagCamera::last_raw_depth() const { return impl_->raw_depth; }
int RealsenseBagCamera::file_version() const { return impl_->file_version; }
int RealsenseBagCamera::unpaired_frames() const { return impl_->unpaired; }
double RealsenseBagCamera::pairing_gap_s() const { return impl_->gap_s; }
double RealsenseBagCamera::max_pair_offset_s() const { return impl_->max_offset_s; }

// ---------------------------------------------------------------------------
// Writer

struct RealsenseBagWriter::Impl {
  std::string path;
  rosbag::Bag bag;
  Streams streams;
  std::uint32_t color_seq = 0, depth_seq = 0;
  bool closed = false;

  static constexpr const char* kDepth = "/device_0/sensor_0/Depth_0";
  static constexpr const char* kColor = "/device_0/sensor_1/Color_0";

  void WriteInfo(const std::string& prefix, const StreamCalibration& s, const std::string& name) {
    sensor_msgs::CameraInfo ci;
    ci.header.frame_id = "0";
    ci.width = static_cast<std::uint32_t>(s.intrinsics.width);
    ci.height = static_cast<std::uint32_t>(s.intrinsics.height);
    ci.K = {s.intrinsics.fx,
            0.0,
            s.intrinsics.cx,
            0.0,
            s.intrinsics.fy,
            s.intrinsics.cy,
            0.0,
            0.0,
            1.0};
    ci.distortion_model = name.empty() ? ToString(s.model) : name;
    if (ci.distortion_model == "none") ci.distortion_model = "None";
    ci.D.assign(s.coeffs.begin(), s.coeffs.end());
    bag.write(prefix + "/info/camera_info", kStaticTime, ci);
  }

  template <typename M>
  void Write(const std::string& topic, double stamp_s, const M& m) {
    try {
      bag.write(topic, ros::Time(stamp_s), m);
    } catch (const std::exception& e) {
      throw HardwareError(path + ": " + topic + " cannot be written: " + e.what());
    }
  }
};

RealsenseBagWriter::RealsenseBagWriter(const std::string& path, const Streams& streams)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.streams = streams;
  try {
    m.bag.open(path, rosbag::bagmode::Write);
    std_msgs::UInt32 version;
    version.data = 4;
    m.bag.write("/file_version", kStaticTime, version);
    diagnostic_msgs::KeyValue name;
    name.key = "Name";
    name.value = "aerograsp simulated D435";
    m.bag.write("/device_0/info", kStaticTime, name);
    std_msgs::Float32 units;
    units.data = static_cast<float>(streams.depth_scale_m);
    m.bag.write("/device_0/sensor_0/option/Depth Units/value", kStaticTime, units);
    m.WriteInfo(Impl::kDepth, streams.depth, streams.depth_model_name);
    m.WriteInfo(Impl::kColor, streams.color, streams.color_model_name);
    // Extrinsics from the reference stream (depth) to each stream.
    m.bag.write(std::string(Impl::kDepth) + "/tf/0", kStaticTime,
                ToTransform(Eigen::Isometry3d::Identity()));
    m.bag.write(std::string(Impl::kColor) + "/tf/0", kStaticTime, ToTransform(streams.colorMdepth));
  } catch (const std::exception& e) {
    throw HardwareError(path + ": cannot be written as a bag: " + e.what());
  }
}

RealsenseBagWriter::~RealsenseBagWriter() {
  try {
    Close();
  } catch (const std::exception&) {
    // Close() reports errors to callers that call it; a destructor cannot.
  }
}

void RealsenseBagWriter::WriteColor(double stamp_s, const ColorImage& color) {
  sensor_msgs::Image m;
  m.header.seq = impl_->color_seq++;
  m.header.stamp = ros::Time(stamp_s);
  m.header.frame_id = "0";
  m.width = static_cast<std::uint32_t>(color.width);
  m.height = static_cast<std::uint32_t>(color.height);
  m.encoding = "rgb8";
  m.step = m.width * 3;
  m.data = color.data;
  impl_->Write(std::string(Impl::kColor) + "/image/data", stamp_s, m);
}

void RealsenseBagWriter::WriteDepth(double stamp_s, const DepthImage& depth) {
  sensor_msgs::Image m;
  m.header.seq = impl_->depth_seq++;
  m.header.stamp = ros::Time(stamp_s);
  m.header.frame_id = "0";
  m.width = static_cast<std::uint32_t>(depth.width);
  m.height = static_cast<std::uint32_t>(depth.height);
  m.encoding = "mono16";
  m.is_bigendian = 0;
  m.step = m.width * 2;
  m.data.resize(depth.data.size() * 2);
  for (std::size_t i = 0; i < depth.data.size(); ++i) {
    m.data[2 * i] = static_cast<std::uint8_t>(depth.data[i] & 0xff);
    m.data[2 * i + 1] = static_cast<std::uint8_t>(depth.data[i] >> 8);
  }
  impl_->Write(std::string(Impl::kDepth) + "/image/data", stamp_s, m);
}

void RealsenseBagWriter::Close() {
  if (impl_->closed) return;
  impl_->closed = true;
  try {
    impl_->bag.close();
  } catch (const std::exception& e) {
    throw HardwareError(impl_->path + ": cannot be closed: " + e.what());
  }
}

}  // namespace aerograsp
