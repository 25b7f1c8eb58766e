#include "core/camera_model.h"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "core/config.h"
#include "core/stdout_capture.h"

namespace aerograsp {

double CameraIntrinsics::HorizontalFovDeg() const {
  return 2.0 * std::atan2(0.5 * width, fx) * 180.0 / M_PI;
}

double CameraIntrinsics::VerticalFovDeg() const {
  return 2.0 * std::atan2(0.5 * height, fy) * 180.0 / M_PI;
}

void CameraIntrinsics::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "width", width, 1, 100000, "px");
  CheckRange(source, prefix + "height", height, 1, 100000, "px");
  CheckPositive(source, prefix + "fx", fx, "px");
  CheckPositive(source, prefix + "fy", fy, "px");
  CheckRange(source, prefix + "cx", cx, 0.0, width, "px");
  CheckRange(source, prefix + "cy", cy, 0.0, height, "px");
}

CameraIntrinsics LoadCameraXml(const std::string& path, const std::string& camera_name) {
  if (!std::filesystem::is_regular_file(path)) throw ConfigError(path + ": cannot open file");
  vpXmlParserCamera parser;
  vpCameraParameters cam;
  int status = vpXmlParserCamera::SEQUENCE_ERROR;
  try {
    const StdoutCapture quiet;  // ViSP reports what it found on std::cout
    // With width and height 0, ViSP takes the first camera of that name.
    status = parser.parse(cam, path, camera_name,
                          vpCameraParameters::perspectiveProjWithoutDistortion, 0, 0);
  } catch (const std::exception& e) {
    throw ConfigError(path + ": not a ViSP camera XML: " + e.what());
  }
  if (status != vpXmlParserCamera::SEQUENCE_OK) {
    throw ConfigError(path + ": no camera" +
                      (camera_name.empty() ? std::string() : " named '" + camera_name + "'") +
                      " with a perspectiveProjWithoutDistortion model");
  }
  CameraIntrinsics K;
  K.width = static_cast<int>(parser.getWidth());
  K.height = static_cast<int>(parser.getHeight());
  K.fx = cam.get_px();
  K.fy = cam.get_py();
  K.cx = cam.get_u0();
  K.cy = cam.get_v0();
  K.Validate(path, "");
  return K;
}

void SaveCameraXml(const CameraIntrinsics& K, const std::string& camera_name,
                   const std::string& path) {
  vpCameraParameters cam(K.fx, K.fy, K.cx, K.cy);
  vpXmlParserCamera parser;
  if (std::filesystem::exists(path)) std::filesystem::remove(path);
  const int status = parser.save(cam, path, camera_name, static_cast<unsigned>(K.width),
                                 static_cast<unsigned>(K.height));
  if (status != vpXmlParserCamera::SEQUENCE_OK) throw ConfigError(path + ": cannot write file");
}

}  // namespace aerograsp
