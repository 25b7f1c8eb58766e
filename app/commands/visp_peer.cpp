#include "app/commands/visp_peer.h"

#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpColVector.h>
#include <visp3/core/vpException.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpImage.h>
#include <visp3/mbt/vpMbGenericTracker.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include "core/conversions.h"
#include "core/stdout_capture.h"
#include "core/thread_clock.h"

namespace aerograsp {

void WriteCaoModel(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out << "V1\n# 3D Points\n" << mesh.vertices.size() << "\n";
  for (const Eigen::Vector3d& v : mesh.vertices)
    out << v.x() << " " << v.y() << " " << v.z() << "\n";
  out << "# 3D Lines\n0\n# Faces from 3D lines\n0\n# Faces from 3D points\n"
      << mesh.triangles.size() << "\n";
  for (const Eigen::Vector3i& t : mesh.triangles)
    out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  out << "# 3D cylinders\n0\n# 3D circles\n0\n";
  if (!out) throw std::runtime_error(path + ": cannot be written");
}

struct VispPeerTracker::Impl {
  // (1 camera, dense depth): the one-argument constructor would take the enum as a camera count.
  vpMbGenericTracker tracker{1, vpMbGenericTracker::DEPTH_DENSE_TRACKER};
  vpImage<unsigned char> gray;
  std::vector<vpColVector> cloud;
  CameraIntrinsics K;
};

VispPeerTracker::VispPeerTracker(const ObjectModel& object, const CameraIntrinsics& K,
                                 const std::string& work_dir)
    : impl_(new Impl) {
  std::filesystem::create_directories(work_dir);
  const std::string cao = (std::filesystem::path(work_dir) / "peer_model.cao").string();
  WriteCaoModel(object.mesh_o, cao);
  impl_->K = K;
  try {
    {
      const StdoutCapture quiet;  // ViSP lists what it parsed on stdout
      impl_->tracker.loadModel(cao);
    }
    impl_->tracker.setCameraParameters(vpCameraParameters(K.fx, K.fy, K.cx, K.cy));
    impl_->tracker.setDepthDenseSamplingStep(4, 4);
    impl_->tracker.setNearClippingDistance(0.1);
    impl_->tracker.setFarClippingDistance(4.0);
    impl_->tracker.setAngleAppear(vpMath::rad(85));
    impl_->tracker.setAngleDisappear(vpMath::rad(89));
  } catch (const vpException& e) {
    throw std::runtime_error(cao + ": ViSP cannot use the model: " + e.getStringMessage());
  }
  impl_->gray.resize(K.height, K.width, 0);
  impl_->cloud.assign(std::size_t(K.width) * K.height, vpColVector(3, 0.0));
}

VispPeerTracker::~VispPeerTracker() = default;

void VispPeerTracker::Initialize(const Eigen::Isometry3d& cMo) {
  try {
    impl_->tracker.initFromPose(impl_->gray, ToVisp(cMo));
    initialized_ = true;
  } catch (const vpException&) {
    initialized_ = false;
  }
}

PeerResult VispPeerTracker::Track(const ColorImage& color, const DepthImage& depth,
                                  double depth_scale_m) {
  PeerResult result;
  const CameraIntrinsics& K = impl_->K;
  if (!initialized_ || depth.width != K.width || depth.height != K.height) return result;
  for (int v = 0; v < depth.height; ++v) {
    for (int u = 0; u < depth.width; ++u) {
      vpColVector& p = impl_->cloud[std::size_t(v) * depth.width + u];
      const double z = depth.at(u, v) * depth_scale_m;
      p[0] = z > 0 ? (u - K.cx) * z / K.fx : 0.0;
      p[1] = z > 0 ? (v - K.cy) * z / K.fy : 0.0;
      p[2] = z;
    }
  }
  if (color.width == K.width && color.height == K.height) {
    for (int v = 0; v < K.height; ++v) {
      for (int u = 0; u < K.width; ++u) {
        impl_->gray[v][u] = static_cast<unsigned char>(
            (77 * color.at(u, v, 0) + 150 * color.at(u, v, 1) + 29 * color.at(u, v, 2)) >> 8);
      }
    }
  }
  std::map<std::string, const vpImage<unsigned char>*> images;
  std::map<std::string, const std::vector<vpColVector>*> clouds;
  std::map<std::string, unsigned int> widths, heights;
  for (const std::string& name : impl_->tracker.getCameraNames()) {
    images[name] = &impl_->gray;
    clouds[name] = &impl_->cloud;
    widths[name] = unsigned(K.width);
    heights[name] = unsigned(K.height);
  }
  const double t0 = ThreadCpuMs();
  try {
    impl_->tracker.track(images, clouds, widths, heights);
    vpHomogeneousMatrix cMo;
    impl_->tracker.getPose(cMo);
    result.cMo = FromVisp(cMo);
    result.ok = result.cMo.matrix().allFinite();
  } catch (const vpException& e) {
    result.error = e.getStringMessage();
  } catch (const std::exception& e) {  // e.g. std::length_error from a track with no features left
    result.error = e.what();
  }
  result.ms = ThreadCpuMs() - t0;
  if (!result.ok) initialized_ = false;
  return result;
}

}  // namespace aerograsp
