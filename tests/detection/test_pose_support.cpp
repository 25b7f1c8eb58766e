#include <gtest/gtest.h>

#include <cmath>

#include "core/data_dir.h"
#include "detection/object_tracker.h"
#include "detection/pose_support.h"
#include "hardware/sim/sim_devices.h"
#include "hardware/sim/world.h"
#include "test_helpers.h"

namespace aerograsp {
namespace {

/// The colour image moved right by `shift_px` (the left columns repeat).
ColorImage Shifted(const ColorImage& color, int shift_px) {
  ColorImage out = color;
  for (int y = 0; y < color.height; ++y) {
    for (int x = 0; x < color.width; ++x) {
      const int from = std::max(0, x - shift_px);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = color.at(from, y, c);
    }
  }
  return out;
}

// The crawler 1.5 m away, where a pixel is 2.4 mm and the depth tolerance
// 32 mm. Neither of two things contradicts the true pose: a model point next to
// the border between the yellow body and a dark track landing a pixel over it,
// and a strip of the body hidden behind the taller track, whose depth agrees
// within the tolerance but whose colour is the track's. Counted against it, they
// would make the true pose 3.5 % contradicted. A wrong colour still contradicts.
TEST(PoseSupportTest, TheTruePoseAt1_5mIsNotContradictedByItsOwnEdges) {
  WorldConfig config = WorldConfig::Load(DataPath("config/world_distance_1.5m.yaml"));
  config.camera.d435.subpixel = 0.0;
  config.camera.d435.color_noise_levels = 0.0;
  World world(config, 7);
  SimCamera camera(&world);
  RgbdFrame frame;
  ASSERT_TRUE(camera.Grab(&frame));
  const Eigen::Isometry3d truth = world.wMc().inverse() * world.wMo();
  auto score = [&](const ColorImage& color) {
    return ScorePoseSupport(testing::CrawlerModel(), truth, color, frame.depth,
                            camera.depth_scale_m(), camera.intrinsics());
  };
  const PoseSupport aligned = score(frame.color);
  ASSERT_GT(aligned.projected, 200);
  EXPECT_GT(aligned.ratio(), 0.99);
  EXPECT_GT(score(Shifted(frame.color, 1)).ratio(), 0.98);
  ColorImage green = frame.color;
  for (int y = 0; y < green.height; ++y) {
    for (int x = 0; x < green.width; ++x) {
      green.at(x, y, 0) = 40;
      green.at(x, y, 1) = 160;
      green.at(x, y, 2) = 40;
    }
  }
  EXPECT_LT(score(green).ratio(), 0.2);
}

// A white label over the crawler's whole top (a tag board, printed, fixed on it): its depth
// agrees with the true pose, its colour does not, so a third of the visible points contradict
// the pose. With the model's colours under the label forgotten, they agree on shape alone; a
// wrong colour elsewhere still contradicts.
TEST(PoseSupportTest, ColoursForgottenUnderALabelNoLongerContradictTheTruePose) {
  WorldConfig config = WorldConfig::Load(DataPath("config/world_distance_0.45m.yaml"));
  World world(config, 7);
  SimCamera camera(&world);
  RgbdFrame frame;
  ASSERT_TRUE(camera.Grab(&frame));
  const Eigen::Isometry3d cMo = world.wMc().inverse() * world.wMo();
  // The label: white wherever the crawler's top faces (o's z above 0.02 m) show.
  ColorImage labelled = frame.color;
  const CameraIntrinsics& K = camera.intrinsics();
  for (int v = 0; v < labelled.height; ++v) {
    for (int u = 0; u < labelled.width; ++u) {
      const std::uint16_t d = frame.depth.at(u, v);
      if (d == 0) continue;
      const Eigen::Vector3d p_o = cMo.inverse() * K.Unproject(u, v, d * camera.depth_scale_m());
      if (p_o.z() > 0.02 && p_o.z() < 0.045 && std::abs(p_o.x()) < 0.11 &&
          std::abs(p_o.y()) < 0.045) {
        for (int c = 0; c < 3; ++c) labelled.at(u, v, c) = 250;
      }
    }
  }
  ModelCloud model = testing::CrawlerModel();
  auto score = [&](const ColorImage& color) {
    return ScorePoseSupport(model, cMo, color, frame.depth, camera.depth_scale_m(), K);
  };
  ASSERT_GT(score(frame.color).ratio(), 0.98);
  EXPECT_LT(score(labelled).ratio(), 0.8);

  const Eigen::Isometry3d oMb(Eigen::Translation3d(0.0, 0.0, 0.0325));
  ForgetColorsInBox(&model, oMb, Eigen::Vector3d(0.11, 0.045, 0.0125));
  std::size_t forgotten = 0;
  for (std::size_t i = 0; i < model.points_o.size(); ++i) {
    const bool inside = model.points_o[i].z() > 0.0205 && model.points_o[i].z() < 0.0445;
    if (inside || model.points_o[i].z() < 0.019) {
      EXPECT_EQ(model.color_known(i), !inside) << i;
    }
    forgotten += !model.color_known(i);
  }
  EXPECT_GT(forgotten, 100u);
  EXPECT_GT(score(labelled).ratio(), 0.98);
  ColorImage green = labelled;
  for (int y = 0; y < green.height; ++y) {
    for (int x = 0; x < green.width; ++x) {
      if (green.at(x, y, 0) == 250) continue;
      green.at(x, y, 0) = 40;
      green.at(x, y, 1) = 160;
      green.at(x, y, 2) = 40;
    }
  }
  EXPECT_LT(score(green).ratio(), 0.8);
}

// The pipe 0.45 m away, as the arms see it while they grasp, and the same
// depth with a strip 3 cm nearer across the pipe's middle (a finger over it:
// the pixels within 2 cm of the pipe's centre along its axis).
struct PipeUnderAFinger {
  PipeUnderAFinger() {
    WorldConfig config = WorldConfig::Load(DataPath("config/world_distance_0.45m.yaml"));
    config.object.name = "pipe";
    World world(config, 7);
    SimCamera camera(&world);
    if (!camera.Grab(&frame)) return;
    cMo = world.wMc().inverse() * world.wMo();
    K = camera.intrinsics();
    scale_m = camera.depth_scale_m();
    covered = frame.depth;
    finger_dropped = frame.depth;
    for (int v = 0; v < covered.height; ++v) {
      for (int u = 0; u < covered.width; ++u) {
        const std::uint16_t d = covered.at(u, v);
        if (d == 0) continue;
        const Eigen::Vector3d p_o = cMo.inverse() * K.Unproject(u, v, d * scale_m);
        if (std::abs(p_o.x()) < 0.02 && p_o.norm() < 0.06) {
          covered.at(u, v) =
              static_cast<std::uint16_t>(std::lround((d * scale_m - 0.03) / scale_m));
          finger_dropped.at(u, v) = 0;
        }
      }
    }
  }
  PoseSupport Score(const DepthImage& depth, const DepthImage* arms_dropped = nullptr) const {
    return ScorePoseSupport(model, cMo, frame.color, depth, scale_m, K, {}, arms_dropped);
  }
  ModelCloud model = BuildModelCloud(ObjectModel::Load("pipe").mesh_o);
  RgbdFrame frame;
  Eigen::Isometry3d cMo = Eigen::Isometry3d::Identity();
  CameraIntrinsics K;
  double scale_m = 0.001;
  DepthImage covered;         ///< the strip 3 cm nearer
  DepthImage finger_dropped;  ///< the camera's depth without the strip (the self filter's)
};

// About half of the pipe's front-facing model points are on the far inner
// wall, behind the near wall. The near wall hides them, at the depth the
// model puts it: they are not part of the visible model, and the true pose
// explains nearly all of what is left. Something else in front of the pipe
// still hides part of it.
TEST(PoseSupportTest, APipesInnerWallHiddenByItsNearWallIsNotCountedAsVisible) {
  const PipeUnderAFinger pipe;
  ASSERT_FALSE(pipe.frame.depth.empty());
  const PoseSupport seen = pipe.Score(pipe.frame.depth);
  ASSERT_GT(seen.projected, 100);
  EXPECT_GT(seen.ratio(), 0.98);
  EXPECT_GT(seen.coverage(), 0.85);
  EXPECT_LT(seen.occluded, seen.projected / 10);

  const PoseSupport hidden = pipe.Score(pipe.covered);
  EXPECT_GT(hidden.occluded, seen.occluded + seen.projected / 10);
  EXPECT_LT(hidden.coverage(), seen.coverage() - 0.1);
  EXPECT_GT(hidden.ratio(), 0.98);
}

// Where the self filter says the nearer surface is the robot's own arm, the
// model behind it is hidden, not occluded: the pose explains as much of the
// visible model as with nothing in front of it, and the depth scored is the
// camera's (the finger is still in it).
TEST(PoseSupportTest, TheModelBehindTheRobotsArmIsHiddenNotOccluded) {
  const PipeUnderAFinger pipe;
  ASSERT_FALSE(pipe.frame.depth.empty());
  const PoseSupport seen = pipe.Score(pipe.frame.depth);
  const PoseSupport behind_arm = pipe.Score(pipe.covered, &pipe.finger_dropped);
  EXPECT_LT(behind_arm.occluded, seen.occluded + 5);
  EXPECT_LT(behind_arm.projected, seen.projected - seen.projected / 10);
  EXPECT_GT(behind_arm.coverage(), seen.coverage() - 0.02);
  EXPECT_GT(behind_arm.ratio(), 0.98);
  // A self filter's image of another size is no information.
  const DepthImage other(pipe.covered.width / 2, pipe.covered.height / 2);
  EXPECT_EQ(pipe.Score(pipe.covered, &other).occluded, pipe.Score(pipe.covered).occluded);
}

// A finger over one end of the pipe (the pixels of the pipe's half at x > 0
// of o, 3 cm nearer): the outline of what the true pose explains leaves it
// out, the outline of the whole projected model does not.
TEST(PoseSupportTest, TheExplainedOutlineLeavesOutWhatAFingerHides) {
  const PipeUnderAFinger pipe;
  ASSERT_FALSE(pipe.frame.depth.empty());
  DepthImage end_covered = pipe.frame.depth;
  for (int v = 0; v < end_covered.height; ++v) {
    for (int u = 0; u < end_covered.width; ++u) {
      const std::uint16_t d = end_covered.at(u, v);
      if (d == 0) continue;
      const Eigen::Vector3d p_o = pipe.cMo.inverse() * pipe.K.Unproject(u, v, d * pipe.scale_m);
      if (p_o.x() > 0.0 && p_o.norm() < 0.12)
        end_covered.at(u, v) =
            static_cast<std::uint16_t>(std::lround((d * pipe.scale_m - 0.03) / pipe.scale_m));
    }
  }
  const PoseSupport seen = pipe.Score(pipe.frame.depth);
  const PoseSupport hidden = pipe.Score(end_covered);
  ASSERT_FALSE(seen.agree_box.empty());
  ASSERT_FALSE(hidden.agree_box.empty());
  EXPECT_GT(seen.agree_box.width() * seen.agree_box.height(),
            0.9 * seen.box.width() * seen.box.height());
  EXPECT_EQ(hidden.box.width(), seen.box.width());
  EXPECT_LT(hidden.agree_box.width() * hidden.agree_box.height(),
            0.7 * hidden.box.width() * hidden.box.height());
}

// The crawler 1 m away, its pose slid 30 mm along its length (the direction
// ICP's point-to-plane pairs leave free when the ends are not seen).
class SlideTest : public ::testing::Test {
 protected:
  void SetUp() override {
    WorldConfig config = WorldConfig::Load(DataPath("config/world_distance_1.0m.yaml"));
    World world(config, 7);
    SimCamera camera(&world);
    ASSERT_TRUE(camera.Grab(&frame_));
    K_ = camera.intrinsics();
    scale_m_ = camera.depth_scale_m();
    truth_ = world.wMc().inverse() * world.wMo();
    const testing::ModelLength length = testing::CrawlerLength();
    length_o_ = length.axis_o;
    half_length_m_ = length.half_m;
    centre_along_m_ = length.middle_m;
    slid_ = truth_;
    slid_.translation() += truth_.linear() * (0.03 * length_o_);
  }
  SlideFit Slide(const DepthImage& depth, double range_m) const {
    return SlideToBestSupport(testing::CrawlerModel(), slid_, length_o_, frame_.color, depth,
                              scale_m_, K_, {}, range_m);
  }
  double ErrorAlongM(const Eigen::Isometry3d& cMo) const {
    return length_o_.dot(truth_.linear().transpose() * (cMo.translation() - truth_.translation()));
  }
  /// Something 0.2 m nearer (fingers) in front of the object's far end along
  /// its length, or of both ends: every pixel of the object beyond 60 mm from
  /// its middle on that side. Returns the depth with it, and (in
  /// *arms_dropped, if given) that depth with its pixels set to no data, as
  /// the self filter leaves it.
  DepthImage EndsBoxed(bool both_ends, DepthImage* arms_dropped = nullptr) const {
    DepthImage depth = frame_.depth;
    if (arms_dropped) *arms_dropped = frame_.depth;
    for (int v = 0; v < depth.height; ++v) {
      for (int u = 0; u < depth.width; ++u) {
        const std::uint16_t d = depth.at(u, v);
        if (d == 0) continue;
        const Eigen::Vector3d p_o = truth_.inverse() * K_.Unproject(u, v, d * scale_m_);
        const double along_m = length_o_.dot(p_o) - centre_along_m_;
        const double beyond_m = both_ends ? std::abs(along_m) : along_m;
        if (beyond_m > 0.06 && beyond_m < half_length_m_ + 0.02 && p_o.norm() < 0.3) {
          depth.at(u, v) = static_cast<std::uint16_t>(d - 0.2 / scale_m_);
          if (arms_dropped) arms_dropped->at(u, v) = 0;
        }
      }
    }
    return depth;
  }
  RgbdFrame frame_;
  CameraIntrinsics K_;
  double scale_m_ = 0.001;
  Eigen::Isometry3d truth_, slid_;
  Eigen::Vector3d length_o_;
  double half_length_m_ = 0.0, centre_along_m_ = 0.0;
};

TEST_F(SlideTest, TheOutlineLocatesTheObjectAndSaysWhenItLiesBeyondTheRange) {
  const SlideFit full = Slide(frame_.depth, 0.04);
  EXPECT_LT(std::abs(ErrorAlongM(full.cMo)), 0.003);
  EXPECT_GT(full.drop, 40);  // both ends in view: 10 mm either way loses many points
  // A 4 mm search from 30 mm off: a probe 10 mm farther on is better supported.
  const SlideFit short_range = Slide(frame_.depth, 0.004);
  EXPECT_GT(ErrorAlongM(short_range.cMo), 0.02);
  EXPECT_LT(short_range.drop, 0);
}

TEST_F(SlideTest, WithBothEndsHiddenTheSlideIsAGuess) {
  // Fingers in front of both ends, as grippers closing on it would be.
  const DepthImage depth = EndsBoxed(true);
  const SlideFit hidden = Slide(depth, 0.04);
  // Too small a drop for the tracker to place the object along its length by it.
  EXPECT_LT(std::abs(hidden.drop), PerceptionOptions{}.weak_direction_min_drop)
      << "error along " << ErrorAlongM(hidden.cMo);
}

TEST_F(SlideTest, AnEndAtTheArmsPixelsDoesNotFixTheSlide) {
  DepthImage arms_dropped;
  const DepthImage depth = EndsBoxed(false, &arms_dropped);
  // Without the arms' pixels known, the box's edge passes for the object's end.
  const SlideFit blind = SlideToBestSupport(testing::CrawlerModel(), slid_, length_o_, frame_.color,
                                            depth, scale_m_, K_, {}, 0.04);
  // The drop the tracker takes for an object placed along its length.
  const int fixing_drop = PerceptionOptions().weak_direction_min_drop;
  EXPECT_GE(blind.drop, fixing_drop);
  const SlideFit aware =
      SlideToBestSupport(testing::CrawlerModel(), slid_, length_o_, frame_.color, depth, scale_m_,
                         K_, {}, 0.04, 0.001, 0.01, &arms_dropped);
  EXPECT_LT(aware.drop, fixing_drop) << "error along " << ErrorAlongM(aware.cMo);
}

TEST_F(SlideTest, AnEndInViewFixesTheSlideWithTheArmsKnown) {
  // Arms' pixels known at the image's left edge, away from the object: both
  // ends in view.
  DepthImage no_arm_on_the_object = frame_.depth;
  for (int v = 0; v < no_arm_on_the_object.height; ++v) {
    for (int u = 0; u < no_arm_on_the_object.width / 8; ++u) no_arm_on_the_object.at(u, v) = 0;
  }
  const SlideFit fit =
      SlideToBestSupport(testing::CrawlerModel(), slid_, length_o_, frame_.color, frame_.depth,
                         scale_m_, K_, {}, 0.04, 0.001, 0.01, &no_arm_on_the_object);
  EXPECT_LT(std::abs(ErrorAlongM(fit.cMo)), 0.003);
  EXPECT_GE(fit.drop, PerceptionOptions().weak_direction_min_drop);
}

}  // namespace
}  // namespace aerograsp
