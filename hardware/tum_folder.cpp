#include "hardware/tum_folder.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>

#include "core/config.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

[[noreturn]] void Fail(const std::string& what, const std::string& message) {
  throw HardwareError(what + ": " + message);
}

struct Row {
  double stamp_s = 0.0;
  std::vector<std::string> fields;  // after the timestamp
};

/// A TUM list: '#' comments, whitespace-separated fields, the first a timestamp.
/// Rows sorted by time.
std::vector<Row> ReadList(const std::string& path, std::size_t fields) {
  std::ifstream in(path);
  if (!in) Fail(path, "cannot be opened");
  std::vector<Row> rows;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream ss(line);
    std::string stamp;
    if (!(ss >> stamp)) continue;
    Row row;
    char* end = nullptr;
    row.stamp_s = std::strtod(stamp.c_str(), &end);
    if (end != stamp.c_str() + stamp.size() || !std::isfinite(row.stamp_s))
      Fail(path, "line " + std::to_string(number) + ": '" + stamp + "' is not a timestamp");
    std::string field;
    while (ss >> field) row.fields.push_back(field);
    if (row.fields.size() != fields) {
      Fail(path, "line " + std::to_string(number) + ": " + std::to_string(row.fields.size() + 1) +
                     " fields, expected " + std::to_string(fields + 1));
    }
    rows.push_back(std::move(row));
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const Row& a, const Row& b) { return a.stamp_s < b.stamp_s; });
  return rows;
}

std::vector<double> Stamps(const std::vector<Row>& rows) {
  std::vector<double> s;
  for (const Row& r : rows) s.push_back(r.stamp_s);
  return s;
}

/// wMc at time t from groundtruth rows (tx ty tz qx qy qz qw): linear in
/// translation, spherical in rotation between the two rows around t; none
/// outside the rows' span.
std::optional<Eigen::Isometry3d> Interpolate(const std::vector<Row>& truth,
                                             const std::vector<Eigen::Isometry3d>& poses,
                                             double t) {
  if (truth.empty() || t < truth.front().stamp_s || t > truth.back().stamp_s) return std::nullopt;
  const auto it = std::lower_bound(truth.begin(), truth.end(), t,
                                   [](const Row& r, double s) { return r.stamp_s < s; });
  const std::size_t j = static_cast<std::size_t>(it - truth.begin());
  if (truth[j].stamp_s == t || j == 0) return poses[j];
  const double t0 = truth[j - 1].stamp_s, t1 = truth[j].stamp_s;
  const double a = (t - t0) / (t1 - t0);
  const Eigen::Quaterniond q0(poses[j - 1].linear()), q1(poses[j].linear());
  Eigen::Isometry3d wMc = Eigen::Isometry3d::Identity();
  wMc.linear() = q0.slerp(a, q1).toRotationMatrix();
  wMc.translation() = (1.0 - a) * poses[j - 1].translation() + a * poses[j].translation();
  return wMc;
}

}  // namespace

CameraIntrinsics LoadIntrinsicsFile(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".xml") {
    // ViSP finds a camera by name: the file's first one.
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    std::smatch name;
    std::regex_search(text, name, std::regex(R"(<name>\s*([^<]*?)\s*</name>)"));
    return LoadCameraXml(path, name.empty() ? "" : name[1].str());
  }
  if (ext != ".yaml" && ext != ".yml") {
    throw ConfigError(path +
                      ": intrinsics are read from a ViSP camera XML (.xml) or a YAML file "
                      "(.yaml, .yml)");
  }
  if (!fs::exists(path)) throw ConfigError(path + ": no such file");
  const ConfigNode root = ConfigNode::LoadFile(path);
  const ConfigNode k = root.Has("intrinsics") ? root.Child("intrinsics") : root;
  CameraIntrinsics K;
  K.width = k.GetInt("width");
  K.height = k.GetInt("height");
  K.fx = k.GetDouble("fx");
  K.fy = k.GetDouble("fy");
  K.cx = k.GetDouble("cx");
  K.cy = k.GetDouble("cy");
  K.Validate(path, k.KeyPath(""));
  return K;
}

bool IsTumFolder(const std::string& folder) {
  return fs::is_directory(folder) && fs::exists(fs::path(folder) / "rgb.txt") &&
         fs::exists(fs::path(folder) / "depth.txt");
}

TumCamera::TumCamera(const std::string& folder, const TumOptions& options) : folder_(folder) {
  if (!IsTumFolder(folder)) Fail(folder, "not a TUM RGB-D folder (needs rgb.txt and depth.txt)");
  if (!options.intrinsics) {
    Fail(folder,
         "a TUM RGB-D folder carries no camera intrinsics; give them with --intrinsics FILE "
         "(a ViSP camera XML or a YAML file with width, height, fx, fy, cx, cy)");
  }
  const fs::path root(folder);
  const std::vector<Row> rgb = ReadList((root / "rgb.txt").string(), 1);
  const std::vector<Row> depth = ReadList((root / "depth.txt").string(), 1);
  if (rgb.empty()) Fail((root / "rgb.txt").string(), "lists no image");
  if (depth.empty()) Fail((root / "depth.txt").string(), "lists no image");
  const std::vector<double> depth_stamps = Stamps(depth);
  const double gap_s =
      options.max_pair_gap_s > 0.0 ? options.max_pair_gap_s : MedianInterval(depth_stamps);
  const std::vector<int> pairs = PairByStamp(Stamps(rgb), depth_stamps, gap_s);

  std::vector<Row> truth;
  std::vector<Eigen::Isometry3d> wMc;
  const fs::path truth_path = root / "groundtruth.txt";
  if (fs::exists(truth_path)) {
    truth = ReadList(truth_path.string(), 7);
    for (const Row& r : truth) {
      double v[7];
      for (int i = 0; i < 7; ++i) {
        char* end = nullptr;
        v[i] = std::strtod(r.fields[i].c_str(), &end);
        if (end != r.fields[i].c_str() + r.fields[i].size() || !std::isfinite(v[i]))
          Fail(truth_path.string(), "'" + r.fields[i] + "' is not a number");
      }
      const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
      if (q.norm() < 1e-9) Fail(truth_path.string(), "a zero quaternion");
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = q.normalized().toRotationMatrix();
      pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
      wMc.push_back(pose);
    }
  }

  has_groundtruth_ = options.wMo.has_value() && !truth.empty();
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    if (pairs[i] < 0) {
      ++unpaired_;
      continue;
    }
    const std::string color = (root / rgb[i].fields[0]).string();
    const std::string d = (root / depth[static_cast<std::size_t>(pairs[i])].fields[0]).string();
    for (const std::string& p : {color, d}) {
      if (!fs::exists(p)) Fail(p, "missing (listed in " + folder + ")");
    }
    color_files_.push_back(color);
    depth_files_.push_back(d);
    stamps_s_.push_back(rgb[i].stamp_s);
    SequenceExtras extras;
    if (options.wMo) {
      if (const auto pose = Interpolate(truth, wMc, rgb[i].stamp_s))
        extras.cMo = pose->inverse() * *options.wMo;
    }
    has_groundtruth_ = has_groundtruth_ && extras.cMo.has_value();
    extras_.push_back(extras);
  }
  if (color_files_.empty()) {
    Fail(folder, "no colour frame has a depth frame within " + std::to_string(gap_s) + " s");
  }
  info_.intrinsics = *options.intrinsics;
  info_.depth_scale_m = kTumDepthScaleM;
  info_.object = options.object;
  info_.frame_count = static_cast<std::int64_t>(color_files_.size());
  const double period_s = MedianInterval(stamps_s_);
  info_.frame_rate_hz = std::isfinite(period_s) && period_s > 0.0 ? 1.0 / period_s : 30.0;
  info_.description = "TUM RGB-D folder " + folder;
}

bool TumCamera::Grab(RgbdFrame* frame) {
  if (next_ >= info_.frame_count) return false;
  const std::size_t i = static_cast<std::size_t>(next_);
  const CameraIntrinsics& K = info_.intrinsics;
  const cv::Mat bgr = cv::imread(color_files_[i], cv::IMREAD_COLOR);
  if (bgr.empty()) Fail(color_files_[i], "cannot be read as an image");
  const cv::Mat depth = cv::imread(depth_files_[i], cv::IMREAD_UNCHANGED);
  if (depth.empty()) Fail(depth_files_[i], "cannot be read as an image");
  if (depth.type() != CV_16UC1) Fail(depth_files_[i], "is not a 16-bit single-channel depth image");
  for (const auto& [path, image] : {std::pair{color_files_[i], bgr}, {depth_files_[i], depth}}) {
    if (image.cols != K.width || image.rows != K.height) {
      Fail(path, "is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     ", the intrinsics say " + std::to_string(K.width) + "x" +
                     std::to_string(K.height));
    }
  }
  frame->color = ColorImage(K.width, K.height);
  cv::Mat rgb(K.height, K.width, CV_8UC3, frame->color.data.data());
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  frame->depth = DepthImage(K.width, K.height);
  cv::Mat out(K.height, K.width, CV_16UC1, frame->depth.data.data());
  depth.copyTo(out);
  frame->index = next_;
  frame->stamp_s = stamps_s_[i];
  ++next_;
  return true;
}

}  // namespace aerograsp
