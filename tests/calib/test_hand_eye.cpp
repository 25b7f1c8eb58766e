#include <gtest/gtest.h>

#include <cmath>

#include "calib/hand_eye.h"
#include "calib/tag_board.h"
#include "core/random.h"
#include "core/transforms.h"

namespace aerograsp {
namespace {

/// A camera 0.4 m from the arm base, a board 5 cm off the tool point, and
/// random gripper poses in view of the camera.
class HandEyeTest : public ::testing::Test {
 protected:
  HandEyeTest()
      : cMb_(MakeTransform(Eigen::Vector3d(0.12, 0.25, 0.08), Eigen::Vector3d(-2.3, 0.1, 1.4))),
        eMt_(MakeTransform(Eigen::Vector3d(0.0, 0.0205, -0.16),
                           Eigen::Vector3d(-M_PI / 2, 0.0, 0.0))) {}

  std::vector<HandEyeSample> Samples(int n, double corner_noise_px, std::uint64_t seed,
                                     bool one_axis = false) {
    FastRandom rng(seed);
    std::vector<HandEyeSample> samples;
    const std::vector<BoardTag> tags = BoardTags(TagBoardConfig{});
    while (static_cast<int>(samples.size()) < n) {
      HandEyeSample s;
      const Eigen::Vector3d rpy =
          one_axis ? Eigen::Vector3d(0, 0, rng.Uniform(-1.0, 1.0))
                   : Eigen::Vector3d(rng.Uniform(-0.6, 0.6), rng.Uniform(-0.6, 0.6),
                                     rng.Uniform(-1.0, 1.0));
      // Board 0.35-0.5 m in front of the camera, tool placed to match.
      const Eigen::Isometry3d cMt_wanted =
          MakeTransform(Eigen::Vector3d(rng.Uniform(-0.08, 0.08), rng.Uniform(-0.06, 0.06),
                                        rng.Uniform(0.35, 0.5)),
                        Eigen::Vector3d(M_PI, 0, 0) + rpy);
      s.bMe = cMb_.inverse() * cMt_wanted * eMt_.inverse();
      s.cMt = cMb_ * s.bMe * eMt_;
      for (const BoardTag& tag : tags) {
        for (const Eigen::Vector3d& p_t : tag.corners_t) {
          const Eigen::Vector2d px = K_.Project(s.cMt * p_t);
          s.corners.emplace_back(
              p_t, px + corner_noise_px * Eigen::Vector2d(rng.Normal(), rng.Normal()));
        }
      }
      // The measured board pose: a pose fit to the noisy corners.
      if (corner_noise_px > 0.0) {
        std::vector<TagDetection> detections;
        std::size_t k = 0;
        for (const BoardTag& tag : tags) {
          TagDetection d;
          d.id = tag.id;
          for (int c = 0; c < 4; ++c) d.corners_px[c] = s.corners[k++].second;
          detections.push_back(d);
        }
        const BoardPose pose = EstimateBoardPose(detections, TagBoardConfig{}, K_);
        if (!pose.valid) continue;
        s.cMt = pose.cMt;
      }
      samples.push_back(s);
    }
    return samples;
  }
  Eigen::Isometry3d cMb_, eMt_;
  CameraIntrinsics K_;
};

TEST_F(HandEyeTest, ExactSamplesGiveTheTruthWithEveryMethod) {
  const auto samples = Samples(12, 0.0, 1);
  std::vector<HandEyeResult> results = SolveEyeToHandOpenCv(samples, K_);
  results.push_back(SolveEyeToHandVisp(samples, K_));
  results.push_back(RefineEyeToHand(samples, K_, results.back()));
  ASSERT_EQ(results.size(), 7u);
  for (const HandEyeResult& r : results) {
    ASSERT_TRUE(r.ok) << r.method << ": " << r.message;
    const PoseError e = ComparePoses(r.cMb, cMb_);
    EXPECT_LT(e.translation_m, 1e-6) << r.method;
    EXPECT_LT(e.rotation_rad, 1e-6) << r.method;
    EXPECT_LT(ComparePoses(r.eMt, eMt_).translation_m, 1e-6) << r.method;
    EXPECT_LT(r.residual_mm_rms, 1e-3) << r.method;
  }
}

TEST_F(HandEyeTest, RefinementOnCornersBeatsEveryOpenCvMethodUnderNoise) {
  const auto samples = Samples(20, 0.3, 2);
  const HandEyeResult visp = SolveEyeToHandVisp(samples, K_);
  ASSERT_TRUE(visp.ok) << visp.message;
  const HandEyeResult refined = RefineEyeToHand(samples, K_, visp);
  ASSERT_TRUE(refined.ok) << refined.message;
  const PoseError refined_error = ComparePoses(refined.cMb, cMb_);
  EXPECT_LT(refined_error.translation_m, 1e-3);
  EXPECT_LT(refined_error.rotation_rad * 180 / M_PI, 0.1);
  EXPECT_LE(refined.reprojection_rms_px, visp.reprojection_rms_px);
  for (const HandEyeResult& r : SolveEyeToHandOpenCv(samples, K_)) {
    ASSERT_TRUE(r.ok) << r.method;
    const PoseError e = ComparePoses(r.cMb, cMb_);
    EXPECT_LT(refined_error.translation_m, e.translation_m) << r.method;
  }
}

TEST_F(HandEyeTest, DiversityFlagsRotationsAboutOneAxis) {
  EXPECT_TRUE(MeasureDiversity(Samples(10, 0.0, 3)).Sufficient());
  const PoseSetDiversity one_axis = MeasureDiversity(Samples(10, 0.0, 3, /*one_axis=*/true));
  EXPECT_EQ(one_axis.axis_rank, 1);
  EXPECT_FALSE(one_axis.Sufficient());
}

TEST(PoseSetDiversityTest, AdviceNamesTheToolAxisTheSamplesDoNotTurnAbout) {
  // Gripper turned by 10 deg about its x and y axes only.
  std::vector<HandEyeSample> samples(5);
  const double a = 10.0 * M_PI / 180.0;
  const Eigen::Vector3d rpy[5] = {{0, 0, 0}, {a, 0, 0}, {-a, 0, 0}, {0, a, 0}, {0, -a, 0}};
  for (int i = 0; i < 5; ++i) samples[i].bMe = MakeTransform(Eigen::Vector3d::Zero(), rpy[i]);
  const PoseSetDiversity d = MeasureDiversity(samples);
  EXPECT_EQ(d.axis_rank, 2);
  EXPECT_EQ(DiversityAdvice(d, samples.size()),
            "rotate the gripper more about its approach axis (z)");
  samples.resize(2);
  EXPECT_EQ(DiversityAdvice(MeasureDiversity(samples), 2),
            "turn the gripper further between samples (at most 10 deg apart so far; 20 or more "
            "wanted)");
  samples.push_back({});
  samples.back().bMe = MakeTransform(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.4, -0.3, 0.5));
  samples.push_back({});
  samples.back().bMe = MakeTransform(Eigen::Vector3d::Zero(), Eigen::Vector3d(-0.3, 0.5, -0.6));
  EXPECT_EQ(DiversityAdvice(MeasureDiversity(samples), samples.size()), "");
}

TEST_F(HandEyeTest, TooFewSamplesIsAClearFailure) {
  const auto samples = Samples(2, 0.0, 4);
  const HandEyeResult visp = SolveEyeToHandVisp(samples, K_);
  EXPECT_FALSE(visp.ok);
  EXPECT_EQ(visp.message, "needs at least 3 samples");
  EXPECT_FALSE(RefineEyeToHand(samples, K_, visp).ok);
}

}  // namespace
}  // namespace aerograsp
