#include "hardware/sequence.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "core/config.h"
#include "core/transforms.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr const char* kFormat = "aerograsp-sequence";
constexpr int kVersion = 1;

std::string FrameName(std::int64_t i) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06lld.png", static_cast<long long>(i));
  return name;
}

std::string ColorPath(const std::string& folder, std::int64_t i) {
  return (fs::path(folder) / "color" / FrameName(i)).string();
}
std::string DepthPath(const std::string& folder, std::int64_t i) {
  return (fs::path(folder) / "depth" / FrameName(i)).string();
}

[[noreturn]] void Fail(const std::string& what, const std::string& message) {
  throw HardwareError(what + ": " + message);
}

/// Writes doubles so that they read back to the same value.
void WriteRow(std::ofstream& out, std::int64_t frame, const std::vector<double>& values) {
  out << frame;
  char buffer[40];
  for (double v : values) {
    std::snprintf(buffer, sizeof(buffer), ",%.17g", v);
    out << buffer;
  }
  out << '\n';
}

std::vector<double> PoseValues(const Eigen::Isometry3d& aMb) {
  const Eigen::Vector3d t = aMb.translation();
  const Eigen::Vector4d q = QuaternionWxyz(aMb);
  return {t.x(), t.y(), t.z(), q[0], q[1], q[2], q[3]};
}

/// A pose from t and q (w, x, y, z) of frame `frame` of the CSV `path`. A unit
/// quaternion is kept as it is (what was written reads back bit for bit), one
/// a little off is normalised, one far off (a zero quaternion) refused.
Eigen::Isometry3d PoseFromValues(const double* v, const std::string& path, std::int64_t frame) {
  Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= 0.1)) {
    Fail(path, "frame " + std::to_string(frame) + ": the quaternion (w, x, y, z) has norm " +
                   std::to_string(norm) + ", not a rotation");
  }
  if (std::abs(norm - 1.0) > 1e-9) q.normalize();
  Eigen::Isometry3d aMb = Eigen::Isometry3d::Identity();
  aMb.linear() = q.toRotationMatrix();
  aMb.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return aMb;
}

constexpr double kMaxStampS = 1e10;  // stamps beyond this many seconds are corrupt

/// A CSV with a header line and one row per frame, each starting with the
/// frame number and its stamp (s, strictly increasing), then `columns - 2`
/// more finite numbers.
std::vector<std::vector<double>> ReadCsv(const std::string& path, std::int64_t frames,
                                         std::size_t columns) {
  std::ifstream in(path);
  if (!in) Fail(path, "cannot be opened");
  std::string line;
  if (!std::getline(in, line)) Fail(path, "is empty (expected a header line)");
  std::vector<std::vector<double>> rows;
  std::int64_t line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) {
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v)) {
        Fail(path,
             "line " + std::to_string(line_number) + ": '" + cell + "' is not a finite number");
      }
      row.push_back(v);
    }
    if (row.size() != columns) {
      Fail(path, "line " + std::to_string(line_number) + ": " + std::to_string(row.size()) +
                     " columns, expected " + std::to_string(columns));
    }
    if (row[0] != static_cast<double>(rows.size())) {
      Fail(path, "line " + std::to_string(line_number) + ": frame " +
                     std::to_string(static_cast<long long>(row[0])) + ", expected " +
                     std::to_string(rows.size()));
    }
    const std::string where = "line " + std::to_string(line_number) + ": stamp_s ";
    if (!(std::abs(row[1]) <= kMaxStampS))
      Fail(path, where + std::to_string(row[1]) + " s is beyond 1e10 s (year 2286)");
    if (!rows.empty() && !(row[1] > rows.back()[1])) {
      Fail(path, where + std::to_string(row[1]) + " s does not follow the previous frame's " +
                     std::to_string(rows.back()[1]) + " s (stamps must increase)");
    }
    rows.push_back(std::move(row));
  }
  if (static_cast<std::int64_t>(rows.size()) != frames) {
    Fail(path, std::to_string(rows.size()) + " rows but sequence.yaml says " +
                   std::to_string(frames) + " frames (truncated recording?)");
  }
  return rows;
}

/// width, height, fx, fy, cx, cy of a map (which may also hold `extra_keys`), validated.
CameraIntrinsics ReadIntrinsics(const ConfigNode& k, std::vector<std::string> extra_keys) {
  for (const char* key : {"width", "height", "fx", "fy", "cx", "cy"}) extra_keys.push_back(key);
  k.RequireOnlyKeys(extra_keys);
  CameraIntrinsics K;
  K.width = k.GetInt("width");
  K.height = k.GetInt("height");
  K.fx = k.GetDouble("fx");
  K.fy = k.GetDouble("fy");
  K.cx = k.GetDouble("cx");
  K.cy = k.GetDouble("cy");
  K.Validate(k.source(), k.KeyPath(""));
  return K;
}

/// distortion_model (a name, rgbd_alignment.h) and distortion_coeffs (k1 k2 p1 p2 k3).
void ReadLens(const ConfigNode& lens, DistortionModel* model, std::array<double, 5>* coeffs) {
  try {
    *model = ParseDistortionModel(lens.GetString("distortion_model"), lens.source());
  } catch (const HardwareError&) {
    lens.Fail("distortion_model", "'" + lens.GetString("distortion_model") +
                                      "' is not one of none, Brown Conrady, Modified Brown "
                                      "Conrady, Inverse Brown Conrady");
  }
  const std::vector<double> c = lens.GetDoubles("distortion_coeffs", 5);
  std::copy(c.begin(), c.end(), coeffs->begin());
}

}  // namespace

// ---------------------------------------------------------------------------
// SequenceWriter

SequenceWriter::SequenceWriter(const std::string& folder, const SequenceInfo& info, bool overwrite)
    : folder_(folder), info_(info) {
  info_.intrinsics.Validate(folder, "intrinsics.");
  if (info_.depth_camera) info_.depth_camera->intrinsics.Validate(folder, "depth_camera.");
  const fs::path root(folder);
  if (fs::exists(root / "sequence.yaml") && !overwrite) {
    Fail(folder, "already holds a sequence (sequence.yaml); choose another folder or overwrite it");
  }
  std::error_code ec;
  // An overwritten recording must keep nothing of the old one.
  for (const char* old : {"sequence.yaml", "color", "depth", "stamps.csv", "groundtruth.csv",
                          "vehicle.csv", "joints.csv"}) {
    fs::remove_all(root / old, ec);
  }
  for (const char* sub : {"color", "depth"}) {
    fs::create_directories(root / sub, ec);
    if (ec) Fail((root / sub).string(), "cannot be created: " + ec.message());
  }
}

SequenceWriter::~SequenceWriter() {
  try {
    Close();
  } catch (const std::exception&) {
    // Close() reports errors to callers that call it; a destructor cannot.
  }
}

void SequenceWriter::Write(const RgbdFrame& frame, const SequenceExtras& extras) {
  if (closed_) Fail(folder_, "the sequence is closed");
  if (!(std::abs(frame.stamp_s) <= kMaxStampS) ||
      (count_ > 0 && !(frame.stamp_s > last_stamp_s_))) {
    Fail(folder_, "frame " + std::to_string(count_) + ": stamp " + std::to_string(frame.stamp_s) +
                      " s does not follow the previous frame's (stamps must increase)");
  }
  const CameraIntrinsics& K = info_.intrinsics;
  const CameraIntrinsics& Kd = info_.depth_camera ? info_.depth_camera->intrinsics : K;
  if (frame.color.width != K.width || frame.color.height != K.height ||
      frame.depth.width != Kd.width || frame.depth.height != Kd.height) {
    Fail(folder_, "frame " + std::to_string(count_) + " is " + std::to_string(frame.color.width) +
                      "x" + std::to_string(frame.color.height) + " colour, " +
                      std::to_string(frame.depth.width) + "x" + std::to_string(frame.depth.height) +
                      " depth; the intrinsics say " + std::to_string(K.width) + "x" +
                      std::to_string(K.height) + " colour, " + std::to_string(Kd.width) + "x" +
                      std::to_string(Kd.height) + " depth");
  }
  const cv::Mat rgb(K.height, K.width, CV_8UC3, const_cast<std::uint8_t*>(frame.color.data.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::string color_path = ColorPath(folder_, count_);
  if (!cv::imwrite(color_path, bgr, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    Fail(color_path, "cannot be written");
  const cv::Mat depth(Kd.height, Kd.width, CV_16UC1,
                      const_cast<std::uint16_t*>(frame.depth.data.data()));
  const std::string depth_path = DepthPath(folder_, count_);
  if (!cv::imwrite(depth_path, depth, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    Fail(depth_path, "cannot be written");

  auto open_once = [this](std::ofstream& out, const char* name, const std::string& header,
                          bool present) {
    const std::string path = (fs::path(folder_) / name).string();
    if (count_ == 0 && present) {
      out.open(path);
      if (!out) Fail(path, "cannot be written");
      out << header << '\n';
    }
    if (present != out.is_open()) {
      Fail(path, std::string("frame ") + std::to_string(count_) +
                     (present ? " has this kind of data but frame 0 had none"
                              : " lacks this kind of data but frame 0 had it"));
    }
  };
  open_once(stamps_, "stamps.csv", "frame,stamp_s", true);
  WriteRow(stamps_, count_, {frame.stamp_s});
  open_once(groundtruth_, "groundtruth.csv", "frame,stamp_s,tx,ty,tz,qw,qx,qy,qz",
            extras.cMo.has_value());
  if (extras.cMo) {
    std::vector<double> row = {frame.stamp_s};
    for (double v : PoseValues(*extras.cMo)) row.push_back(v);
    WriteRow(groundtruth_, count_, row);
  }
  open_once(vehicle_, "vehicle.csv", "frame,stamp_s,x,y,z,qw,qx,qy,qz,vx,vy,vz",
            extras.vehicle.has_value());
  if (extras.vehicle) {
    std::vector<double> row = {frame.stamp_s};
    for (double v : PoseValues(extras.vehicle->wMd)) row.push_back(v);
    for (int i = 0; i < 3; ++i) row.push_back(extras.vehicle->v_w[i]);
    WriteRow(vehicle_, count_, row);
  }
  const bool has_joints = extras.q_left_rad.has_value() && extras.q_right_rad.has_value();
  if (has_joints && count_ == 0) {
    std::string header = "frame,stamp_s";
    for (long i = 0; i < extras.q_left_rad->size(); ++i) header += ",left_q" + std::to_string(i);
    for (long i = 0; i < extras.q_right_rad->size(); ++i) header += ",right_q" + std::to_string(i);
    open_once(joints_, "joints.csv", header, true);
  } else {
    open_once(joints_, "joints.csv", "", has_joints);
  }
  if (has_joints) {
    std::vector<double> row = {frame.stamp_s};
    for (long i = 0; i < extras.q_left_rad->size(); ++i) row.push_back((*extras.q_left_rad)[i]);
    for (long i = 0; i < extras.q_right_rad->size(); ++i) row.push_back((*extras.q_right_rad)[i]);
    WriteRow(joints_, count_, row);
  }
  last_stamp_s_ = frame.stamp_s;
  ++count_;
}

void SequenceWriter::Close() {
  if (closed_) return;
  closed_ = true;
  for (std::ofstream* out : {&stamps_, &groundtruth_, &vehicle_, &joints_}) {
    if (out->is_open()) out->close();
  }
  info_.frame_count = count_;
  const SequenceInfo& i = info_;
  YAML::Emitter y;
  y.SetDoublePrecision(17);
  y << YAML::BeginMap;
  y << YAML::Key << "format" << YAML::Value << kFormat;
  y << YAML::Key << "version" << YAML::Value << kVersion;
  y << YAML::Key << "description" << YAML::Value << i.description;
  y << YAML::Key << "object" << YAML::Value << i.object;
  y << YAML::Key << "frame_count" << YAML::Value << i.frame_count;
  y << YAML::Key << "frame_rate_hz" << YAML::Value << i.frame_rate_hz;
  y << YAML::Key << "depth_scale_m" << YAML::Value << i.depth_scale_m;
  y << YAML::Key << "intrinsics" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "width" << YAML::Value << i.intrinsics.width;
  y << YAML::Key << "height" << YAML::Value << i.intrinsics.height;
  y << YAML::Key << "fx" << YAML::Value << i.intrinsics.fx;
  y << YAML::Key << "fy" << YAML::Value << i.intrinsics.fy;
  y << YAML::Key << "cx" << YAML::Value << i.intrinsics.cx;
  y << YAML::Key << "cy" << YAML::Value << i.intrinsics.cy;
  y << YAML::EndMap;
  auto lens = [&y](DistortionModel model, const std::array<double, 5>& coeffs) {
    y << YAML::Key << "distortion_model" << YAML::Value << ToString(model);
    y << YAML::Key << "distortion_coeffs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (double c : coeffs) y << c;
    y << YAML::EndSeq;
  };
  if (i.color_model != DistortionModel::kNone) {
    y << YAML::Key << "color_lens" << YAML::Value << YAML::BeginMap;
    lens(i.color_model, i.color_coeffs);
    y << YAML::EndMap;
  }
  if (i.depth_camera) {
    const CameraIntrinsics& Kd = i.depth_camera->intrinsics;
    y << YAML::Key << "depth_camera" << YAML::Value << YAML::BeginMap;
    y << YAML::Key << "width" << YAML::Value << Kd.width;
    y << YAML::Key << "height" << YAML::Value << Kd.height;
    y << YAML::Key << "fx" << YAML::Value << Kd.fx;
    y << YAML::Key << "fy" << YAML::Value << Kd.fy;
    y << YAML::Key << "cx" << YAML::Value << Kd.cx;
    y << YAML::Key << "cy" << YAML::Value << Kd.cy;
    lens(i.depth_camera->model, i.depth_camera->coeffs);
    y << YAML::EndMap;
  }
  y << YAML::Key << "depth_to_color" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) y << i.colorMdepth.matrix()(r, c);
  }
  y << YAML::EndSeq << YAML::EndMap;
  const std::string path = (fs::path(folder_) / "sequence.yaml").string();
  std::ofstream out(path);
  out << "# An aerograsp RGB-D sequence (hardware/sequence.h describes the folder).\n"
      << y.c_str() << "\n";
  if (!out) Fail(path, "cannot be written");
}

// ---------------------------------------------------------------------------
// Reading

SequenceInfo ReadSequenceInfo(const std::string& folder) {
  const fs::path path = fs::path(folder) / "sequence.yaml";
  if (!fs::is_directory(folder)) Fail(folder, "no such folder");
  if (!fs::exists(path))
    Fail(folder, "not a sequence: no sequence.yaml (an unfinished recording?)");
  const ConfigNode node = ConfigNode::LoadFile(path.string());
  node.RequireOnlyKeys({"format", "version", "description", "object", "frame_count",
                        "frame_rate_hz", "depth_scale_m", "intrinsics", "color_lens",
                        "depth_camera", "depth_to_color"});
  if (node.GetString("format") != kFormat)
    node.Fail("format", std::string("expected '") + kFormat + "'");
  if (node.GetInt("version") != kVersion) {
    node.Fail("version", "version " + std::to_string(node.GetInt("version")) +
                             " is not supported (this build reads " + std::to_string(kVersion) +
                             ")");
  }
  SequenceInfo info;
  info.description = node.GetString("description", "");
  info.object = node.GetString("object", "");
  info.frame_count = node.GetInt("frame_count");
  CheckRange(path.string(), "frame_count", static_cast<double>(info.frame_count), 0, 1e8, "");
  info.frame_rate_hz = node.GetDouble("frame_rate_hz");
  CheckRange(path.string(), "frame_rate_hz", info.frame_rate_hz, 0.01, 1000.0, "Hz");
  info.depth_scale_m = node.GetDouble("depth_scale_m");
  CheckRange(path.string(), "depth_scale_m", info.depth_scale_m, 1e-6, 1.0, "m");
  info.intrinsics = ReadIntrinsics(node.Child("intrinsics"), {});
  if (node.Has("color_lens")) {
    const ConfigNode lens = node.Child("color_lens");
    lens.RequireOnlyKeys({"distortion_model", "distortion_coeffs"});
    ReadLens(lens, &info.color_model, &info.color_coeffs);
  }
  if (node.Has("depth_camera")) {
    const ConfigNode d = node.Child("depth_camera");
    StreamCalibration depth;
    depth.intrinsics = ReadIntrinsics(d, {"distortion_model", "distortion_coeffs"});
    ReadLens(d, &depth.model, &depth.coeffs);
    info.depth_camera = depth;
  }
  const std::vector<double> m = node.GetDoubles("depth_to_color", 16);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) info.colorMdepth.matrix()(r, c) = m[4 * r + c];
  }
  if (!IsValidTransform(info.colorMdepth)) node.Fail("depth_to_color", "not a rigid transform");
  return info;
}

ReplayCamera::ReplayCamera(const std::string& folder)
    : folder_(folder), info_(ReadSequenceInfo(folder)), frame_info_(info_) {
  frame_info_.depth_camera.reset();
  const std::int64_t n = info_.frame_count;
  for (std::int64_t i = 0; i < n; ++i) {
    for (const std::string& p : {ColorPath(folder, i), DepthPath(folder, i)}) {
      if (!fs::exists(p)) Fail(p, "missing (sequence.yaml says " + std::to_string(n) + " frames)");
    }
  }
  extras_.resize(static_cast<std::size_t>(n));
  stamps_s_.resize(static_cast<std::size_t>(n));
  for (std::int64_t i = 0; i < n; ++i) stamps_s_[i] = static_cast<double>(i) / info_.frame_rate_hz;
  const fs::path root(folder);
  if (fs::exists(root / "groundtruth.csv")) {
    const auto rows = ReadCsv((root / "groundtruth.csv").string(), n, 9);
    for (std::int64_t i = 0; i < n; ++i) {
      stamps_s_[i] = rows[i][1];
      extras_[i].cMo = PoseFromValues(&rows[i][2], (root / "groundtruth.csv").string(), i);
    }
    has_groundtruth_ = true;
  }
  if (fs::exists(root / "stamps.csv")) {
    const auto rows = ReadCsv((root / "stamps.csv").string(), n, 2);
    for (std::int64_t i = 0; i < n; ++i) stamps_s_[i] = rows[i][1];
  }
  if (fs::exists(root / "vehicle.csv")) {
    const auto rows = ReadCsv((root / "vehicle.csv").string(), n, 12);
    for (std::int64_t i = 0; i < n; ++i) {
      VehicleState v;
      v.stamp_s = rows[i][1];
      v.wMd = PoseFromValues(&rows[i][2], (root / "vehicle.csv").string(), i);
      v.v_w = Eigen::Vector3d(rows[i][9], rows[i][10], rows[i][11]);
      v.mode = FlightMode::kOffboard;  // not recorded
      extras_[i].vehicle = v;
    }
  }
  const fs::path joints = root / "joints.csv";
  if (fs::exists(joints)) {
    std::ifstream in(joints);
    std::string header;
    std::getline(in, header);
    std::size_t n_left = 0, n_right = 0;
    std::stringstream ss(header);
    std::string name;
    while (std::getline(ss, name, ',')) {
      n_left += name.rfind("left_q", 0) == 0;
      n_right += name.rfind("right_q", 0) == 0;
    }
    const auto rows = ReadCsv(joints.string(), n, 2 + n_left + n_right);
    for (std::int64_t i = 0; i < n; ++i) {
      extras_[i].q_left_rad =
          Eigen::Map<const Eigen::VectorXd>(&rows[i][2], static_cast<long>(n_left));
      extras_[i].q_right_rad =
          Eigen::Map<const Eigen::VectorXd>(&rows[i][2 + n_left], static_cast<long>(n_right));
    }
  }
}

bool ReplayCamera::Grab(RgbdFrame* frame) {
  if (next_ >= info_.frame_count) return false;
  const CameraIntrinsics& K = info_.intrinsics;
  const std::string color_path = ColorPath(folder_, next_);
  const cv::Mat bgr = cv::imread(color_path, cv::IMREAD_UNCHANGED);
  if (bgr.empty()) Fail(color_path, "cannot be read as an image (corrupt or truncated PNG?)");
  if (bgr.type() != CV_8UC3) Fail(color_path, "is not 8-bit 3-channel colour");
  if (bgr.cols != K.width || bgr.rows != K.height) {
    Fail(color_path, "is " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                         ", sequence.yaml says " + std::to_string(K.width) + "x" +
                         std::to_string(K.height));
  }
  const std::string depth_path = DepthPath(folder_, next_);
  const cv::Mat depth = cv::imread(depth_path, cv::IMREAD_UNCHANGED);
  if (depth.empty()) Fail(depth_path, "cannot be read as an image (corrupt or truncated PNG?)");
  if (depth.type() != CV_16UC1) Fail(depth_path, "is not a 16-bit single-channel depth image");
  const CameraIntrinsics& Kd = info_.depth_camera ? info_.depth_camera->intrinsics : K;
  if (depth.cols != Kd.width || depth.rows != Kd.height) {
    Fail(depth_path, "is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
                         ", sequence.yaml says " + std::to_string(Kd.width) + "x" +
                         std::to_string(Kd.height) + (info_.depth_camera ? " (depth_camera)" : ""));
  }
  frame->color = ColorImage(K.width, K.height);
  cv::Mat rgb(K.height, K.width, CV_8UC3, frame->color.data.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  frame->depth = DepthImage(Kd.width, Kd.height);
  cv::Mat out(Kd.height, Kd.width, CV_16UC1, frame->depth.data.data());
  depth.copyTo(out);
  if (info_.depth_camera) {
    if (!aligner_) {
      aligner_ = std::make_shared<const DepthAligner>(*info_.depth_camera, info_.color_stream(),
                                                      info_.colorMdepth, info_.depth_scale_m);
    }
    frame->depth = aligner_->Align(frame->depth);
  }
  frame->index = next_;
  frame->stamp_s = stamps_s_[static_cast<std::size_t>(next_)];
  ++next_;
  return true;
}

}  // namespace aerograsp
