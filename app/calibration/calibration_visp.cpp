#include "app/calibration/calibration_visp.h"

#include <fmt/format.h>
#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpPixelMeterConversion.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <regex>
#include <sstream>

#include "calib/tag_board.h"
#include "core/config.h"
#include "core/stdout_capture.h"
#include "core/transforms.h"

namespace aerograsp {
namespace fs = std::filesystem;
namespace {

constexpr const char* kRowNames[6] = {"tx", "ty", "tz", "tux", "tuy", "tuz"};

std::string Trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const std::size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

/// The integer after `key:` on a header line.
int HeaderInt(const std::string& path, int line_no, const std::string& line,
              const std::string& key) {
  const std::string value = Trim(line.substr(key.size() + 1));
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0')
    throw ConfigError(
        fmt::format("{}: line {}: {}: '{}' is not an integer", path, line_no, key, value));
  return static_cast<int>(v);
}

struct Files {
  std::string rPe, cPo, image;
};

/// cMo of the one tag36h11 tag in `image_path` (see ReadVispDataset).
Eigen::Isometry3d DetectTagPose(const std::string& image_path, double tag_size_m,
                                const VispCamera& camera, TagDetector* detector) {
  const cv::Mat bgr = cv::imread(image_path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw ConfigError(image_path + ": cannot read the image");
  ColorImage rgb(bgr.cols, bgr.rows);
  cv::Mat view(rgb.height, rgb.width, CV_8UC3, rgb.data.data());
  cv::cvtColor(bgr, view, cv::COLOR_BGR2RGB);
  std::vector<TagDetection> tags = detector->Detect(rgb);
  if (tags.size() != 1) {
    throw ConfigError(
        fmt::format("{}: {} tag36h11 tags found, one expected (no pose_cPo file: "
                    "the tag's pose comes from the image)",
                    image_path, tags.size()));
  }
  if (camera.distortion) {  // ViSP's model: the distorted pixel to the ideal one through kdu
    vpCameraParameters cam;
    cam.initPersProjWithDistortion(camera.K.fx, camera.K.fy, camera.K.cx, camera.K.cy, camera.kud,
                                   camera.kdu);
    for (Eigen::Vector2d& px : tags.front().corners_px) {
      double x = 0.0, y = 0.0;
      vpPixelMeterConversion::convertPoint(cam, px.x(), px.y(), x, y);
      px = Eigen::Vector2d(camera.K.fx * x + camera.K.cx, camera.K.fy * y + camera.K.cy);
    }
  }
  TagBoardConfig tag;
  tag.rows = tag.cols = 1;
  tag.tag_size_m = tag_size_m;
  tag.spacing_m = tag.margin_m = 0.0;
  tag.first_id = tags.front().id;
  const BoardPose pose = EstimateBoardPose(tags, tag, camera.K);
  if (!pose.valid) throw ConfigError(image_path + ": the tag's pose could not be estimated");
  return pose.cMt;
}

}  // namespace

HandEyeSetup ParseHandEyeSetup(const std::string& name, const std::string& what) {
  if (name == "eye-to-hand") return HandEyeSetup::kEyeToHand;
  if (name == "eye-in-hand") return HandEyeSetup::kEyeInHand;
  throw ConfigError(what + ": '" + name + "' is not eye-to-hand or eye-in-hand");
}

const char* HandEyeSetupName(HandEyeSetup setup) {
  return setup == HandEyeSetup::kEyeToHand ? "eye-to-hand" : "eye-in-hand";
}

Eigen::Isometry3d ReadVispPose(const std::string& path) {
  std::ifstream in(path);
  if (!fs::is_regular_file(path) || !in) throw ConfigError(path + ": cannot open file");
  // vpArray2D::loadYAML's layout: any header lines, `rows:`, `cols:`, `data:`,
  // then one `- [v, ...]` line per row.
  int rows = -1, cols = -1, line_no = 0;
  bool in_data = false;
  std::vector<double> values;
  std::string line;
  while (std::getline(in, line)) {
    ++line_no;
    if (!in_data) {
      if (line.rfind("rows:", 0) == 0) {
        rows = HeaderInt(path, line_no, line, "rows");
      } else if (line.rfind("cols:", 0) == 0) {
        cols = HeaderInt(path, line_no, line, "cols");
      } else if (line.rfind("data:", 0) == 0) {
        in_data = true;
      }
      continue;
    }
    const std::string row = Trim(line);
    if (row.empty() || row[0] == '#') continue;
    const std::size_t open = row.find('['), close = row.rfind(']');
    if (row[0] != '-' || open == std::string::npos || close == std::string::npos || close < open)
      throw ConfigError(
          fmt::format("{}: line {}: '{}' is not a data row '- [value]'", path, line_no, row));
    std::stringstream cells(row.substr(open + 1, close - open - 1));
    std::string cell;
    while (std::getline(cells, cell, ',')) {
      const std::string v = Trim(cell);
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0')
        throw ConfigError(fmt::format("{}: line {}: '{}' is not a number", path, line_no, v));
      if (!std::isfinite(x)) {
        const std::string name =
            values.size() < 6 ? kRowNames[values.size()] : std::to_string(values.size());
        throw ConfigError(fmt::format("{}: line {}: {} is {} (a pose needs finite numbers)", path,
                                      line_no, name, v));
      }
      values.push_back(x);
    }
  }
  if (!in_data)
    throw ConfigError(path + ": no 'data:' line: not a ViSP pose vector (vpPoseVector::saveYAML)");
  if (rows != 6 || cols != 1 || values.size() != 6) {
    throw ConfigError(fmt::format(
        "{}: expected a 6x1 pose vector (rows tx ty tz tux tuy tuz), got rows: {}, cols: {} and "
        "{} values",
        path, rows, cols, values.size()));
  }
  const Eigen::Vector3d t(values[0], values[1], values[2]);
  const Eigen::Vector3d tu(values[3], values[4], values[5]);
  if (t.norm() > kMaxPlausibleTranslation_m) {
    throw ConfigError(fmt::format(
        "{}: translation of {:.4g} m ({} {} {}): ViSP's pose files hold metres and a hand-eye "
        "rig spans less than {} m (is this file in millimetres?)",
        path, t.norm(), values[0], values[1], values[2], kMaxPlausibleTranslation_m));
  }
  if (tu.norm() > M_PI + 1e-6) {
    throw ConfigError(fmt::format(
        "{}: theta-u angle of {:.4g} rad is beyond pi: ViSP's pose files hold radians (is this "
        "rotation in degrees?)",
        path, tu.norm()));
  }
  Eigen::Isometry3d aMb = Eigen::Isometry3d::Identity();
  if (tu.norm() > 0.0)
    aMb.linear() = Eigen::AngleAxisd(tu.norm(), tu / tu.norm()).toRotationMatrix();
  aMb.translation() = t;
  return aMb;
}

void WriteVispPose(const std::string& path, const Eigen::Isometry3d& aMb) {
  const Eigen::Vector3d t = aMb.translation(), tu = ThetaU(aMb.linear());
  std::ofstream out(path);
  out.precision(std::numeric_limits<double>::max_digits10);
  out << "rows: 6\ncols: 1\ndata:\n";
  for (int i = 0; i < 3; ++i) out << "  - [" << t[i] << "]\n";
  for (int i = 0; i < 3; ++i) out << "  - [" << tu[i] << "]\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

VispCamera LoadVispCameraXml(const std::string& path) {
  if (!fs::is_regular_file(path)) throw ConfigError(path + ": cannot open file");
  VispCamera camera;
  camera.source = path;
  // ViSP 3.5's parser matches a camera by name (an empty name matches none):
  // take the first camera's.
  std::string name;
  {
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::smatch m;
    if (std::regex_search(text, m, std::regex(R"(<camera>[\s\S]*?<name>\s*([^<]*?)\s*</name>)")))
      name = m[1].str();
  }
  vpXmlParserCamera parser;
  vpCameraParameters cam;
  bool found = false;
  for (const auto model : {vpCameraParameters::perspectiveProjWithDistortion,
                           vpCameraParameters::perspectiveProjWithoutDistortion}) {
    int status = vpXmlParserCamera::SEQUENCE_ERROR;
    try {
      const StdoutCapture quiet;  // ViSP reports what it found on std::cout
      status = parser.parse(cam, path, name, model, 0, 0);
    } catch (const std::exception& e) {
      throw ConfigError(path + ": not a ViSP camera XML: " + e.what());
    }
    if (status == vpXmlParserCamera::SEQUENCE_OK) {
      found = true;
      camera.distortion = model == vpCameraParameters::perspectiveProjWithDistortion;
      break;
    }
  }
  if (!found)
    throw ConfigError(path +
                      ": no camera with a perspectiveProjWithDistortion or "
                      "perspectiveProjWithoutDistortion model");
  camera.K.width = static_cast<int>(parser.getWidth());
  camera.K.height = static_cast<int>(parser.getHeight());
  camera.K.fx = cam.get_px();
  camera.K.fy = cam.get_py();
  camera.K.cx = cam.get_u0();
  camera.K.cy = cam.get_v0();
  if (camera.distortion) {
    camera.kud = cam.get_kud();
    camera.kdu = cam.get_kdu();
  }
  camera.K.Validate(path, "");
  return camera;
}

bool IsVispDataset(const std::string& folder) {
  static const std::regex pose(R"(^(.*_)?pose_(rPe|fPe|cPo)_[0-9]+\.yaml$)");
  if (!fs::is_directory(folder)) return false;
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
    if (std::regex_match(e.path().filename().string(), pose)) return true;
  }
  return false;
}

VispDataset ReadVispDataset(const std::string& folder, double tag_size_m) {
  if (!fs::is_directory(folder)) throw ConfigError(folder + ": not a folder");
  static const std::regex pose(R"(^(.*_)?pose_(rPe|fPe|cPo)_([0-9]+)\.yaml$)");
  static const std::regex image(R"(^.*[-_]([0-9]+)\.(png|jpg|jpeg|pgm|ppm|bmp|PNG|JPG)$)");
  std::map<int, Files> files;
  std::vector<std::string> xmls;
  std::vector<fs::path> entries;
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) entries.push_back(e.path());
  std::sort(entries.begin(), entries.end());
  for (const fs::path& p : entries) {
    const std::string name = p.filename().string();
    std::smatch m;
    if (std::regex_match(name, m, pose)) {
      Files& f = files[std::stoi(m[3].str())];
      std::string& slot = m[2].str() == "cPo" ? f.cPo : f.rPe;
      if (!slot.empty())
        throw ConfigError(fmt::format("{}: {} and {} are two poses of the same kind for sample {}",
                                      folder, fs::path(slot).filename().string(), name,
                                      m[3].str()));
      slot = p.string();
    } else if (std::regex_match(name, m, image)) {
      Files& f = files[std::stoi(m[1].str())];
      if (!f.image.empty())
        throw ConfigError(fmt::format("{}: {} and {} are two images for sample {}", folder,
                                      fs::path(f.image).filename().string(), name, m[1].str()));
      f.image = p.string();
    } else if (p.extension() == ".xml") {
      xmls.push_back(p.string());
    }
  }
  VispDataset data;
  data.folder = folder;
  std::string camera_xml;
  for (const std::string& x : xmls) {
    if (fs::path(x).filename() == "camera.xml") camera_xml = x;
  }
  if (camera_xml.empty() && xmls.size() == 1) camera_xml = xmls.front();
  if (camera_xml.empty() && xmls.size() > 1)
    throw ConfigError(folder + ": several XML files and none is camera.xml: name the camera's " +
                      "intrinsics camera.xml");
  if (!camera_xml.empty()) {
    data.camera = LoadVispCameraXml(camera_xml);
    data.has_camera = true;
  }
  std::unique_ptr<TagDetector> detector;
  bool any_image = false;
  for (const auto& [n, f] : files) any_image = any_image || !f.image.empty();
  for (const auto& [n, f] : files) {
    const std::string where = fmt::format("{}/", folder);
    if (f.rPe.empty() && f.cPo.empty()) {
      throw ConfigError(
          fmt::format("{}pose_rPe_{}.yaml and {}pose_cPo_{}.yaml: missing (the image "
                      "{} has no poses)",
                      where, n, where, n, f.image));
    }
    if (f.rPe.empty())
      throw ConfigError(fmt::format("{}pose_rPe_{}.yaml: missing (the robot pose of {})", where, n,
                                    fs::path(f.cPo).filename().string()));
    const bool detect = f.cPo.empty() && !f.image.empty() && tag_size_m > 0.0;
    if (f.cPo.empty() && !detect) {
      throw ConfigError(fmt::format(
          "{}pose_cPo_{}.yaml: missing (the object pose of {}){}", where, n,
          fs::path(f.rPe).filename().string(),
          f.image.empty() ? ""
                          : "; or pass --tag-size (the tag's black square, m) to detect the tag "
                            "in " +
                                fs::path(f.image).filename().string()));
    }
    if (detect && !data.has_camera)
      throw ConfigError(folder + ": detecting the tags needs the camera's intrinsics (camera.xml)");
    if (any_image && f.image.empty()) {
      // Named as the other samples' images are, e.g. franka_image-1.png -> franka_image-3.png.
      std::string like;
      for (const auto& [k, g] : files) {
        if (like.empty() && !g.image.empty()) like = fs::path(g.image).filename().string();
      }
      std::smatch m;
      std::regex_match(like, m, image);
      const std::string expected = like.substr(0, static_cast<std::size_t>(m.position(1))) +
                                   std::to_string(n) + "." + m[2].str();
      throw ConfigError(fmt::format(
          "{}{}: missing: the image of sample {} ({} and {}); the other samples have theirs", where,
          expected, n, fs::path(f.rPe).filename().string(), fs::path(f.cPo).filename().string()));
    }
    VispSample s;
    s.index = n;
    s.rPe_file = f.rPe;
    s.cPo_file = f.cPo;
    s.image = f.image;
    s.rMe = ReadVispPose(f.rPe);
    if (detect) {
      if (!detector) detector = std::make_unique<TagDetector>("tag36h11");
      s.cMo = DetectTagPose(f.image, tag_size_m, data.camera, detector.get());
    } else {
      s.cMo = ReadVispPose(f.cPo);
    }
    data.samples.push_back(s);
  }
  return data;
}

std::vector<HandEyeSample> ToHandEyeSamples(const VispDataset& data, HandEyeSetup setup) {
  std::vector<HandEyeSample> samples;
  for (const VispSample& s : data.samples) {
    HandEyeSample h;
    h.bMe = setup == HandEyeSetup::kEyeToHand ? s.rMe : s.rMe.inverse();
    h.cMt = s.cMo;
    samples.push_back(h);
  }
  return samples;
}

void WriteVispSample(const std::string& folder, int index, const Eigen::Isometry3d& rMe,
                     const Eigen::Isometry3d& cMo, const std::string& image_path) {
  fs::create_directories(folder);
  WriteVispPose((fs::path(folder) / fmt::format("pose_rPe_{}.yaml", index)).string(), rMe);
  WriteVispPose((fs::path(folder) / fmt::format("pose_cPo_{}.yaml", index)).string(), cMo);
  if (image_path.empty()) return;
  const fs::path image = fs::path(folder) / fmt::format("image-{}.png", index);
  std::error_code ec;
  fs::remove(image, ec);
  fs::create_hard_link(image_path, image, ec);
  if (ec) fs::copy_file(image_path, image, fs::copy_options::overwrite_existing);
}

}  // namespace aerograsp
