#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpPoseVector.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "app/calibration/calibration_visp.h"
#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/config.h"
#include "core/conversions.h"
#include "core/random.h"
#include "core/transforms.h"
#include "tests/common/output_folder_test.h"

namespace aerograsp {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kRadToDeg = 180.0 / M_PI;

/// A robot 0.7 m in front of a camera (eye-to-hand) with a tag 5 cm off its
/// flange, or the camera 8 cm off the flange (eye-in-hand), and diverse
/// robot poses; every file written by ViSP's own vpPoseVector::saveYAML.
class VispDatasetTest : public testing::OutputFolderTest {
 protected:
  VispDatasetTest()
      : OutputFolderTest("aerograsp_visp_dataset_"),
        rMc_(MakeTransform(Eigen::Vector3d(0.9, 0.1, 0.5), Eigen::Vector3d(-1.9, 0.05, 1.7))),
        eMo_(MakeTransform(Eigen::Vector3d(0.01, -0.02, 0.05), Eigen::Vector3d(0.0, M_PI, 0.3))),
        eMc_(MakeTransform(Eigen::Vector3d(0.03, 0.0, 0.08), Eigen::Vector3d(0.02, -0.01, 1.57))),
        rMo_(MakeTransform(Eigen::Vector3d(0.5, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 0.4))) {}

  void SaveVisp(const std::string& name, const Eigen::Isometry3d& aMb) {
    vpPoseVector p(ToVisp(aMb));
    ASSERT_TRUE(vpPoseVector::saveYAML((fs::path(folder_) / name).string(), p));
  }

  /// n samples; eye-to-hand: cMo = rMc^-1 rMe eMo; eye-in-hand: cMo = eMc^-1 rMe^-1 rMo.
  void WriteDataset(int n, HandEyeSetup setup, bool images) {
    fs::create_directories(folder_);
    FastRandom rng(7);
    for (int i = 1; i <= n; ++i) {
      const Eigen::Isometry3d rMe = MakeTransform(
          Eigen::Vector3d(rng.Uniform(0.3, 0.5), rng.Uniform(-0.2, 0.2), rng.Uniform(0.2, 0.4)),
          Eigen::Vector3d(M_PI + rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5),
                          rng.Uniform(-1.0, 1.0)));
      const Eigen::Isometry3d cMo = setup == HandEyeSetup::kEyeToHand
                                        ? rMc_.inverse() * rMe * eMo_
                                        : eMc_.inverse() * rMe.inverse() * rMo_;
      SaveVisp("pose_rPe_" + std::to_string(i) + ".yaml", rMe);
      SaveVisp("pose_cPo_" + std::to_string(i) + ".yaml", cMo);
      if (images) std::ofstream(fs::path(folder_) / ("image-" + std::to_string(i) + ".png")) << "x";
    }
  }

  std::string ErrorOf(const std::function<void()>& read) {
    try {
      read();
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "no error";
  }

  Eigen::Isometry3d rMc_, eMo_, eMc_, rMo_;
};

TEST_F(VispDatasetTest, EyeToHandDataSetResolvesToTheTransformItWasMadeFrom) {
  WriteDataset(10, HandEyeSetup::kEyeToHand, true);
  const VispDataset data = ReadVispDataset(folder_);
  ASSERT_EQ(data.samples.size(), 10u);
  const HandEyeResult r =
      SolveEyeToHandVisp(ToHandEyeSamples(data, HandEyeSetup::kEyeToHand), CameraIntrinsics{});
  ASSERT_TRUE(r.ok) << r.message;
  const PoseError e = ComparePoses(r.cMb.inverse(), rMc_);
  EXPECT_LT(1e3 * e.translation_m, 0.1);
  EXPECT_LT(kRadToDeg * e.rotation_rad, 0.01);
  const PoseError o = ComparePoses(r.eMt, eMo_);
  EXPECT_LT(1e3 * o.translation_m, 0.1);
  EXPECT_LT(kRadToDeg * o.rotation_rad, 0.01);
}

TEST_F(VispDatasetTest, EyeInHandDataSetResolvesToTheTransformItWasMadeFrom) {
  WriteDataset(10, HandEyeSetup::kEyeInHand, false);
  const HandEyeResult r = SolveEyeToHandVisp(
      ToHandEyeSamples(ReadVispDataset(folder_), HandEyeSetup::kEyeInHand), CameraIntrinsics{});
  ASSERT_TRUE(r.ok) << r.message;
  const PoseError e = ComparePoses(r.cMb.inverse(), eMc_);
  EXPECT_LT(1e3 * e.translation_m, 0.1);
  EXPECT_LT(kRadToDeg * e.rotation_rad, 0.01);
  const PoseError o = ComparePoses(r.eMt, rMo_);
  EXPECT_LT(1e3 * o.translation_m, 0.1);
  EXPECT_LT(kRadToDeg * o.rotation_rad, 0.01);
}

TEST_F(VispDatasetTest, OurPoseFilesReadBackExactlyAndViSPReadsThem) {
  fs::create_directories(folder_);
  FastRandom rng(3);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Isometry3d aMb = MakeTransform(
        Eigen::Vector3d(rng.Uniform(-1, 1), rng.Uniform(-1, 1), rng.Uniform(-1, 1)),
        Eigen::Vector3d(rng.Uniform(-3, 3), rng.Uniform(-1.5, 1.5), rng.Uniform(-3, 3)));
    const std::string path = (fs::path(folder_) / "pose.yaml").string();
    WriteVispPose(path, aMb);
    EXPECT_TRUE(ReadVispPose(path).isApprox(aMb, 1e-14)) << i;
    vpPoseVector p;
    ASSERT_TRUE(vpPoseVector::loadYAML(path, p));
    EXPECT_TRUE(FromVisp(vpHomogeneousMatrix(p)).isApprox(aMb, 1e-12)) << i;
  }
}

TEST_F(VispDatasetTest, ARobotPoseWithoutItsObjectPoseIsNamed) {
  WriteDataset(5, HandEyeSetup::kEyeToHand, false);
  fs::remove(fs::path(folder_) / "pose_cPo_3.yaml");
  EXPECT_THAT(ErrorOf([&] { ReadVispDataset(folder_); }),
              HasSubstr("pose_cPo_3.yaml: missing (the object pose of pose_rPe_3.yaml)"));
}

TEST_F(VispDatasetTest, AMissingImageIsNamed) {
  WriteDataset(5, HandEyeSetup::kEyeToHand, true);
  fs::remove(fs::path(folder_) / "image-4.png");
  EXPECT_THAT(ErrorOf([&] { ReadVispDataset(folder_); }),
              HasSubstr("image-4.png: missing: the image of sample 4"));
}

TEST_F(VispDatasetTest, PosesInMillimetresAreNamed) {
  WriteDataset(4, HandEyeSetup::kEyeToHand, false);
  SaveVisp("pose_rPe_2.yaml",
           MakeTransform(Eigen::Vector3d(412.0, -33.0, 719.0), Eigen::Vector3d(3.0, 0.0, 0.1)));
  EXPECT_THAT(ErrorOf([&] { ReadVispDataset(folder_); }),
              HasSubstr("pose_rPe_2.yaml: translation of 829.3 m"));
  EXPECT_THAT(ErrorOf([&] { ReadVispDataset(folder_); }), HasSubstr("millimetres"));
}

TEST_F(VispDatasetTest, RotationsInDegreesAreNamed) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "pose_cPo_1.yaml").string();
  std::ofstream(path) << "rows: 6\ncols: 1\ndata:\n  - [0.1]\n  - [0]\n  - [0.4]\n  - [175.3]\n"
                         "  - [0.2]\n  - [6.0]\n";
  EXPECT_THAT(ErrorOf([&] { ReadVispPose(path); }),
              HasSubstr("pose_cPo_1.yaml: theta-u angle of 175.4 rad is beyond pi"));
}

TEST_F(VispDatasetTest, ANaNIsNamedByFileLineAndRow) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "pose_cPo_1.yaml").string();
  std::ofstream(path) << "rows: 6\ncols: 1\ndata:\n  - [0.1]\n  - [0]\n  - [nan]\n  - [0]\n"
                         "  - [0]\n  - [0]\n";
  EXPECT_THAT(ErrorOf([&] { ReadVispPose(path); }),
              HasSubstr("pose_cPo_1.yaml: line 6: tz is nan"));
}

TEST_F(VispDatasetTest, ATruncatedPoseFileIsNamed) {
  fs::create_directories(folder_);
  const std::string path = (fs::path(folder_) / "pose_rPe_1.yaml").string();
  std::ofstream(path) << "rows: 6\ncols: 1\ndata:\n  - [0.1]\n  - [0]\n";
  EXPECT_THAT(ErrorOf([&] { ReadVispPose(path); }),
              HasSubstr("pose_rPe_1.yaml: expected a 6x1 pose vector"));
  EXPECT_THAT(ErrorOf([&] { ReadVispPose(path + ".absent"); }),
              HasSubstr("pose_rPe_1.yaml.absent: cannot open file"));
}

// A data set as ViSP's acquisition apps leave it before
// visp-compute-apriltag-poses: images of one 48 mm tag on the flange, robot
// poses, a camera XML (model with distortion, coefficients 0); the tag's pose
// is detected in each image.
TEST_F(VispDatasetTest, WithoutObjectPosesTheTagIsDetectedInTheImages) {
  fs::create_directories(folder_);
  CameraIntrinsics K;
  vpCameraParameters cam;
  cam.initPersProjWithDistortion(K.fx, K.fy, K.cx, K.cy, 0.0, 0.0);
  vpXmlParserCamera parser;
  ASSERT_EQ(parser.save(cam, (fs::path(folder_) / "camera.xml").string(), "Camera", 640, 480),
            vpXmlParserCamera::SEQUENCE_OK);
  TagBoardConfig tag;
  tag.rows = tag.cols = 1;
  tag.tag_size_m = 0.048;
  tag.spacing_m = 0.0;
  tag.margin_m = 0.012;
  const double px_per_m = 5000.0;
  const ColorImage printed = RenderBoardImage(tag, px_per_m);
  const cv::Mat printed_rgb(printed.height, printed.width, CV_8UC3,
                            const_cast<std::uint8_t*>(printed.data.data()));
  // Pixel (u, v) of the printed tag is t = (u / px_per_m - w / 2, v / px_per_m - h / 2, 0).
  Eigen::Matrix3d A;
  A << 1.0 / px_per_m, 0, -0.5 * printed.width / px_per_m, 0, 1.0 / px_per_m,
      -0.5 * printed.height / px_per_m, 0, 0, 1;
  Eigen::Matrix3d Kmat;
  Kmat << K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1;
  FastRandom rng(9);
  for (int i = 1; i <= 10; ++i) {
    const Eigen::Isometry3d cMo = MakeTransform(
        Eigen::Vector3d(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.07, 0.07), rng.Uniform(0.35, 0.5)),
        Eigen::Vector3d(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5), rng.Uniform(-1.5, 1.5)));
    WriteVispPose((fs::path(folder_) / ("pose_rPe_" + std::to_string(i) + ".yaml")).string(),
                  rMc_ * cMo * eMo_.inverse());
    Eigen::Matrix3d Rt;
    Rt << cMo.linear().col(0), cMo.linear().col(1), cMo.translation();
    const Eigen::Matrix3d H = Kmat * Rt * A;
    cv::Mat Hcv(3, 3, CV_64F);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) Hcv.at<double>(r, c) = H(r, c);
    }
    cv::Mat image;
    cv::warpPerspective(printed_rgb, image, Hcv, cv::Size(K.width, K.height), cv::INTER_LINEAR,
                        cv::BORDER_CONSTANT, cv::Scalar(90, 90, 90));
    cv::cvtColor(image, image, cv::COLOR_RGB2BGR);
    cv::imwrite((fs::path(folder_) / ("franka_image-" + std::to_string(i) + ".png")).string(),
                image);
  }
  EXPECT_THAT(ErrorOf([&] { ReadVispDataset(folder_); }),
              HasSubstr("pose_cPo_1.yaml: missing (the object pose of pose_rPe_1.yaml); or pass "
                        "--tag-size"));
  const VispDataset data = ReadVispDataset(folder_, 0.048);
  ASSERT_EQ(data.samples.size(), 10u);
  const HandEyeResult r =
      SolveEyeToHandVisp(ToHandEyeSamples(data, HandEyeSetup::kEyeToHand), data.camera.K);
  ASSERT_TRUE(r.ok) << r.message;
  const PoseError e = ComparePoses(r.cMb.inverse(), rMc_);
  // Measured: 1.92 mm, 0.18 deg (one 48 mm tag 0.35-0.5 m away, ViSP's pose-level solve).
  EXPECT_LT(1e3 * e.translation_m, 3.0);
  EXPECT_LT(kRadToDeg * e.rotation_rad, 0.3);
}

TEST_F(VispDatasetTest, CameraXmlWithAndWithoutDistortionIsRead) {
  fs::create_directories(folder_);
  const std::string with = (fs::path(folder_) / "with.xml").string();
  const std::string without = (fs::path(folder_) / "without.xml").string();
  vpXmlParserCamera parser;
  vpCameraParameters cam;
  cam.initPersProjWithDistortion(607.6, 607.5, 323.5, 243.3, -0.05, 0.06);
  ASSERT_EQ(parser.save(cam, with, "Camera", 640, 480), vpXmlParserCamera::SEQUENCE_OK);
  cam.initPersProjWithoutDistortion(600.0, 601.0, 320.0, 240.0);
  ASSERT_EQ(parser.save(cam, without, "Camera", 640, 480), vpXmlParserCamera::SEQUENCE_OK);

  const VispCamera a = LoadVispCameraXml(with);
  EXPECT_TRUE(a.distortion);
  EXPECT_DOUBLE_EQ(a.K.fx, 607.6);
  EXPECT_DOUBLE_EQ(a.K.cy, 243.3);
  EXPECT_DOUBLE_EQ(a.kud, -0.05);
  EXPECT_DOUBLE_EQ(a.kdu, 0.06);
  const VispCamera b = LoadVispCameraXml(without);
  EXPECT_FALSE(b.distortion);
  EXPECT_DOUBLE_EQ(b.K.fy, 601.0);
  EXPECT_EQ(b.K.width, 640);
}

}  // namespace
}  // namespace aerograsp
