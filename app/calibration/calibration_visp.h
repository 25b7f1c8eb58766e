// Hand-eye data sets in ViSP's convention, as its calibration apps
// (visp-acquire-*-calib-data, visp-compute-apriltag-poses /
// visp-compute-chessboard-poses, visp-compute-eye-to-hand-calibration /
// visp-compute-eye-in-hand-calibration) write and read them:
//
//   pose_rPe_N.yaml  the end-effector e in the robot base r (forward kinematics)
//   pose_cPo_N.yaml  the calibration object o (tag or board) in the camera c
//   <anything>-N.png the image of sample N (optional)
//   camera.xml       the intrinsics (vpXmlParserCamera, with or without distortion)
//
// A pose file is a vpPoseVector saved by vpArray2D::saveYAML: `rows: 6`,
// `cols: 1`, `data:` then six rows `- [tx]`, `- [ty]`, `- [tz]` (metres) and
// `- [tux]`, `- [tuy]`, `- [tuz]` (theta-u, radians). N pairs the files; older
// ViSP apps name the robot poses pose_fPe_N.yaml, and a prefix before `pose_`
// (e.g. franka_pose_rPe_1.yaml) is allowed.
//
// Both setups are the same problem for the solvers of calib/hand_eye.h, whose
// model is cMt_i = cMb * bMe_i * eMt (eye-to-hand: camera fixed, object on the
// gripper):
//   eye-to-hand  bMe_i = rMe_i,      cMt_i = cMo_i; result cMb = cMr, eMt = eMo
//   eye-in-hand  bMe_i = rMe_i^-1,   cMt_i = cMo_i; result cMb = cMe, eMt = rMo
// (eye-in-hand: cMo_i = cMe * eMr_i * rMo, the camera on the gripper and the
// object fixed in the robot's base).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "calib/hand_eye.h"
#include "core/camera_model.h"

namespace aerograsp {

enum class HandEyeSetup { kEyeToHand, kEyeInHand };

/// "eye-to-hand" | "eye-in-hand". @throws ConfigError naming `what` otherwise.
HandEyeSetup ParseHandEyeSetup(const std::string& name, const std::string& what);
const char* HandEyeSetupName(HandEyeSetup setup);

/// Reads one vpPoseVector YAML file (see above).
/// @throws ConfigError "<file>: ..." when it is missing, malformed (line named),
/// holds a NaN or infinity, a translation beyond kMaxPlausibleTranslation_m
/// (millimetres instead of metres?) or a theta-u angle beyond pi (degrees?).
Eigen::Isometry3d ReadVispPose(const std::string& path);

/// Writes aMb as vpPoseVector YAML that ViSP's loadYAML reads, with every digit
/// a double needs (ViSP's own saveYAML keeps 6).
/// @throws std::runtime_error naming the file when it cannot be written.
void WriteVispPose(const std::string& path, const Eigen::Isometry3d& aMb);

/// The largest translation a pose file may hold, m: a hand-eye rig spans
/// metres; a larger number is a file in millimetres.
constexpr double kMaxPlausibleTranslation_m = 10.0;

/// Intrinsics from a ViSP camera XML, with or without distortion.
struct VispCamera {
  std::string source;
  CameraIntrinsics K;       ///< pinhole part (px, py, u0, v0)
  bool distortion = false;  ///< the file's model is perspectiveProjWithDistortion
  double kud = 0.0;         ///< undistorted-to-distorted coefficient
  double kdu = 0.0;         ///< distorted-to-undistorted coefficient
};
/// The first camera of the file (perspectiveProjWithDistortion if present,
/// else perspectiveProjWithoutDistortion).
/// @throws ConfigError naming the file when it is missing or holds no camera.
VispCamera LoadVispCameraXml(const std::string& path);

struct VispSample {
  int index = 0;         ///< N of the file names
  std::string rPe_file;  ///< paths
  std::string cPo_file;
  std::string image;  ///< empty when the data set has no images
  Eigen::Isometry3d rMe = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
};

struct VispDataset {
  std::string folder;
  std::vector<VispSample> samples;  ///< by increasing N
  bool has_camera = false;
  VispCamera camera;  ///< camera.xml, or the folder's only .xml file
};

/// True when `folder` holds at least one pose_rPe_N / pose_fPe_N / pose_cPo_N file.
bool IsVispDataset(const std::string& folder);

/// Reads every sample of a ViSP data set. A sample with its image and robot
/// pose but no pose_cPo_N.yaml (a data set before visp-compute-apriltag-poses
/// ran) gets cMo from the one tag36h11 tag detected in its image, of edge
/// `tag_size_m` (its black square; 0: not done), through the camera XML (pixels
/// undistorted with its kdu); the tag frame is the board frame of
/// calib/tag_board.h (origin at the tag's centre, z into the tag).
/// @throws ConfigError naming the file: a robot pose without its object pose
/// (or the reverse), an image missing for one N while others have theirs, an
/// image without pose files, an image in which no single tag is found, any
/// ReadVispPose error, a bad camera XML.
VispDataset ReadVispDataset(const std::string& folder, double tag_size_m = 0.0);

/// The samples in the model of calib/hand_eye.h for `setup` (table above).
std::vector<HandEyeSample> ToHandEyeSamples(const VispDataset& data, HandEyeSetup setup);

/// Writes sample N (eye-to-hand: rMe = bMe, cMo = cMt) as pose_rPe_N.yaml and
/// pose_cPo_N.yaml in `folder`, and the image as image-N.png (a hard link to
/// `image_path` when possible, else a copy) when `image_path` is not empty.
void WriteVispSample(const std::string& folder, int index, const Eigen::Isometry3d& rMe,
                     const Eigen::Isometry3d& cMo, const std::string& image_path);

}  // namespace aerograsp
