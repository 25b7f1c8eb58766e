// The peer in the replay benchmark: ViSP's model-based tracker
// (vpMbGenericTracker) with dense depth features only, fed the same aligned
// depth as ours and initialised with the same first pose. It writes the
// object's mesh as a ViSP .cao model file into the replay's output folder
// (ViSP loads models from files only). ViSP stays in the .cpp.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/object_model.h"

namespace aerograsp {

struct PeerResult {
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  bool ok = false;    ///< tracking did not throw and the pose is finite
  double ms = 0.0;    ///< thread CPU time of track()
  std::string error;  ///< ViSP's message when tracking failed
};

class VispPeerTracker {
 public:
  /// @throws std::runtime_error when the model file cannot be written or ViSP rejects it.
  VispPeerTracker(const ObjectModel& object, const CameraIntrinsics& K,
                  const std::string& work_dir);
  ~VispPeerTracker();
  VispPeerTracker(const VispPeerTracker&) = delete;
  VispPeerTracker& operator=(const VispPeerTracker&) = delete;

  void Initialize(const Eigen::Isometry3d& cMo);
  bool initialized() const { return initialized_; }
  /// Tracks one frame; a ViSP exception makes ok false and the tracker must be
  /// initialised again.
  PeerResult Track(const ColorImage& color, const DepthImage& depth, double depth_scale_m);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool initialized_ = false;
};

/// Writes a triangle mesh as a ViSP .cao model (faces from 3D points).
/// @throws std::runtime_error when the file cannot be written.
void WriteCaoModel(const TriangleMesh& mesh, const std::string& path);

}  // namespace aerograsp
