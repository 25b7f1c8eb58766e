#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/config.h"
#include "core/data_dir.h"
#include "detection/perception_config.h"
#include "tests/common/output_folder_test.h"

namespace aerograsp {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

/// Field-by-field equality of two PerceptionOptions (exact: the file's values
/// must be the code's, not close to them); each difference is reported by name.
void ExpectSameOptions(const PerceptionOptions& a, const PerceptionOptions& b) {
#define EXPECT_SAME_FIELD(field) EXPECT_EQ(a.field, b.field) << #field
  EXPECT_SAME_FIELD(model.spacing_m);
  EXPECT_SAME_FIELD(model.cell_m);
  EXPECT_SAME_FIELD(model.margin_m);
  EXPECT_SAME_FIELD(model.seed);
  EXPECT_SAME_FIELD(cloud.target_points);
  EXPECT_SAME_FIELD(cloud.min_depth_m);
  EXPECT_SAME_FIELD(cloud.max_depth_m);
  EXPECT_SAME_FIELD(cloud.normal_radius_m);
  EXPECT_SAME_FIELD(cloud.max_normal_jump_m);
  EXPECT_SAME_FIELD(icp.max_iterations);
  EXPECT_SAME_FIELD(icp.start_distance_m);
  EXPECT_SAME_FIELD(icp.end_distance_m);
  EXPECT_SAME_FIELD(icp.depth_noise_per_m2);
  EXPECT_SAME_FIELD(icp.min_normal_cos);
  EXPECT_SAME_FIELD(icp.min_normal_cos_without_color);
  EXPECT_SAME_FIELD(icp.max_color_distance);
  EXPECT_SAME_FIELD(icp.point_to_point_weight);
  EXPECT_SAME_FIELD(icp.damping);
  EXPECT_SAME_FIELD(icp.converged_step_m);
  EXPECT_SAME_FIELD(icp.min_inliers);
  EXPECT_SAME_FIELD(global.voxel_m);
  EXPECT_SAME_FIELD(global.feature_radius_m);
  EXPECT_SAME_FIELD(global.max_iterations);
  EXPECT_SAME_FIELD(global.attempts);
  EXPECT_SAME_FIELD(global.whole_frame_features);
  EXPECT_SAME_FIELD(global.orientations);
  EXPECT_SAME_FIELD(global.refined_orientations);
  EXPECT_SAME_FIELD(global.inlier_fraction);
  EXPECT_SAME_FIELD(global.seed);
  EXPECT_SAME_FIELD(global.work_per_frame);
  EXPECT_SAME_FIELD(segment.max_surfaces);
  EXPECT_SAME_FIELD(segment.surface_iterations);
  EXPECT_SAME_FIELD(segment.surface_tolerance_m);
  EXPECT_SAME_FIELD(segment.surface_extent);
  EXPECT_SAME_FIELD(segment.cluster_gap_m);
  EXPECT_SAME_FIELD(segment.max_candidates);
  EXPECT_SAME_FIELD(segment.seed);
  EXPECT_SAME_FIELD(ekf.accel_noise_mps2);
  EXPECT_SAME_FIELD(ekf.angular_accel_noise_radps2);
  EXPECT_SAME_FIELD(ekf.init_position_std_m);
  EXPECT_SAME_FIELD(ekf.init_rotation_std_rad);
  EXPECT_SAME_FIELD(ekf.init_velocity_std_mps);
  EXPECT_SAME_FIELD(ekf.init_angular_velocity_std_radps);
  EXPECT_SAME_FIELD(ekf.gate_nis);
  EXPECT_SAME_FIELD(ekf.max_predict_dt_s);
  EXPECT_SAME_FIELD(track.find_confidence);
  EXPECT_SAME_FIELD(track.keep_confidence);
  EXPECT_SAME_FIELD(track.frames_to_find);
  EXPECT_SAME_FIELD(track.frames_to_refind);
  EXPECT_SAME_FIELD(track.frames_to_lose);
  EXPECT_SAME_FIELD(min_detection_score);
  EXPECT_SAME_FIELD(box_margin);
  EXPECT_SAME_FIELD(near_centre_quantile);
  EXPECT_SAME_FIELD(min_support_ratio);
  EXPECT_SAME_FIELD(min_coverage);
  EXPECT_SAME_FIELD(min_box_overlap);
  EXPECT_SAME_FIELD(min_box_cover);
  EXPECT_SAME_FIELD(min_cloud_points);
  EXPECT_SAME_FIELD(whole_frame_points);
  EXPECT_SAME_FIELD(detect_every_frames);
  EXPECT_SAME_FIELD(frames_without_box_to_search_frame);
  EXPECT_SAME_FIELD(lost_search_every_frames);
  EXPECT_SAME_FIELD(min_global_range_m);
  EXPECT_SAME_FIELD(max_global_range_m);
  EXPECT_SAME_FIELD(reacquire_radius_m);
  EXPECT_SAME_FIELD(reacquire_speed_mps);
  EXPECT_SAME_FIELD(measurement_position_std_m);
  EXPECT_SAME_FIELD(measurement_rotation_std_rad);
  EXPECT_SAME_FIELD(gated_frames_to_reset);
  EXPECT_SAME_FIELD(weak_direction_ratio);
  EXPECT_SAME_FIELD(weak_direction_std_m);
  EXPECT_SAME_FIELD(self_filter.enabled);
  EXPECT_SAME_FIELD(self_filter.drop_from_depth);
  EXPECT_SAME_FIELD(self_filter.drop_from_cloud);
  EXPECT_SAME_FIELD(self_filter.in_support);
  EXPECT_SAME_FIELD(self_filter.in_slide);
  EXPECT_SAME_FIELD(self_filter.margin_m);
#undef EXPECT_SAME_FIELD
}

class PerceptionConfigTest : public testing::OutputFolderTest {
 protected:
  PerceptionConfigTest() : OutputFolderTest("aerograsp_perception_config_") {}
  /// Writes `text` to FOLDER/perception.yaml and returns its path.
  std::string Write(const std::string& text) {
    std::filesystem::create_directories(folder_);
    const std::string path = (std::filesystem::path(folder_) / "perception.yaml").string();
    std::ofstream(path) << text;
    return path;
  }
  /// The ConfigError message of loading `text` ("" when it loads).
  std::string ErrorOf(const std::string& text) {
    try {
      LoadPerceptionOptions(Write(text));
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(PerceptionConfigTest, TheShippedDefaultFileIsTheCodeDefaults) {
  ExpectSameOptions(LoadPerceptionOptions(DataPath("config/perception_default.yaml")),
                    PerceptionOptions{});
}

TEST_F(PerceptionConfigTest, AnEmptyMapKeepsTheDefaults) {
  ExpectSameOptions(LoadPerceptionOptions(Write("{}\n")), PerceptionOptions{});
}

TEST_F(PerceptionConfigTest, SetValuesChangeExactlyThoseFields) {
  const PerceptionOptions loaded = LoadPerceptionOptions(
      Write("min_coverage: 0.5\nicp:\n  max_iterations: 20\ntrack:\n  frames_to_lose: 5\n"));
  PerceptionOptions expected;
  expected.min_coverage = 0.5;
  expected.icp.max_iterations = 20;
  expected.track.frames_to_lose = 5;
  ExpectSameOptions(loaded, expected);
}

TEST_F(PerceptionConfigTest, AbsentKeysKeepTheGivenDefaults) {
  PerceptionOptions defaults;
  defaults.weak_direction_std_m = 0.02;
  EXPECT_EQ(LoadPerceptionOptions(Write("box_margin: 0.2\n"), defaults).weak_direction_std_m, 0.02);
  EXPECT_EQ(
      LoadPerceptionOptions(Write("weak_direction_std_m: 0.0\n"), defaults).weak_direction_std_m,
      0.0);
}

TEST_F(PerceptionConfigTest, AMissingFileIsNamed) {
  const std::string path = folder_ + "/absent.yaml";
  EXPECT_THAT(
      [&] { LoadPerceptionOptions(path); },
      ::testing::ThrowsMessage<ConfigError>(AllOf(HasSubstr(path), HasSubstr("cannot open file"))));
}

TEST_F(PerceptionConfigTest, MalformedYamlNamesTheFileAndLine) {
  EXPECT_THAT(ErrorOf("icp:\n  max_iterations: [1, 2\n"),
              AllOf(HasSubstr("perception.yaml"), HasSubstr("not valid YAML at line")));
}

TEST_F(PerceptionConfigTest, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_THAT(
      ErrorOf("box_margins: 0.2\n"),
      AllOf(HasSubstr("perception.yaml: box_margins: unknown key"), HasSubstr("box_margin")));
  EXPECT_THAT(ErrorOf("icp:\n  max_iteration: 20\n"),
              AllOf(HasSubstr("perception.yaml: icp.max_iteration: unknown key"),
                    HasSubstr("max_iterations")));
  EXPECT_THAT(ErrorOf("ekf:\n  gate: 10\n"), HasSubstr("perception.yaml: ekf.gate: unknown key"));
  EXPECT_THAT(ErrorOf("self_filter:\n  margin: 0.01\n"),
              HasSubstr("perception.yaml: self_filter.margin: unknown key"));
}

TEST_F(PerceptionConfigTest, WrongTypesAreNamedWithTheirPath) {
  EXPECT_THAT(ErrorOf("icp:\n  max_iterations: 12.5\n"),
              HasSubstr("perception.yaml: icp.max_iterations: expected an integer, got '12.5'"));
  EXPECT_THAT(ErrorOf("box_margin: wide\n"),
              HasSubstr("perception.yaml: box_margin: expected a number, got 'wide'"));
  EXPECT_THAT(ErrorOf("track: 3\n"),
              HasSubstr("perception.yaml: track: expected a map, got a scalar"));
}

TEST_F(PerceptionConfigTest, ValuesOutOfRangeAreNamedWithTheirPathAndBound) {
  EXPECT_THAT(ErrorOf("icp:\n  max_iterations: 0\n"),
              HasSubstr("perception.yaml: icp.max_iterations: must be in [1, 100]"));
  EXPECT_THAT(ErrorOf("frames_without_box_to_search_frame: -1\n"),
              HasSubstr("perception.yaml: frames_without_box_to_search_frame: must be in [0, 1000] "
                        "frames (0: never)"));
  EXPECT_THAT(ErrorOf("lost_search_every_frames: 0\n"),
              HasSubstr("perception.yaml: lost_search_every_frames: must be in [1, 30] frames"));
  EXPECT_THAT(ErrorOf("near_centre_quantile: 0.7\n"),
              HasSubstr("perception.yaml: near_centre_quantile: must be in [0, 0.5]"));
  EXPECT_THAT(ErrorOf("min_support_ratio: 1.5\n"),
              HasSubstr("perception.yaml: min_support_ratio: must be in (0, 1]"));
  EXPECT_THAT(ErrorOf("min_box_overlap: -0.1\n"),
              HasSubstr("perception.yaml: min_box_overlap: must be in [0, 1]"));
  EXPECT_THAT(ErrorOf("min_box_cover: 1.5\n"),
              HasSubstr("perception.yaml: min_box_cover: must be in [0, 1]"));
  EXPECT_THAT(ErrorOf("model:\n  spacing_m: 0.5\n"),
              HasSubstr("perception.yaml: model.spacing_m: must be in [0.001, 0.05] m"));
  EXPECT_THAT(ErrorOf("ekf:\n  accel_noise_mps2: 0\n"),
              HasSubstr("perception.yaml: ekf.accel_noise_mps2: must be > 0 m/s^2"));
  EXPECT_THAT(ErrorOf("track:\n  frames_to_lose: 0\n"),
              HasSubstr("perception.yaml: track.frames_to_lose: must be >= 1"));
  EXPECT_THAT(ErrorOf("global:\n  seed: -1\n"),
              HasSubstr("perception.yaml: global.seed: -1 is below the lower bound 0"));
  EXPECT_THAT(ErrorOf("icp:\n  min_normal_cos_without_color: 1.5\n"),
              HasSubstr("perception.yaml: icp.min_normal_cos_without_color: must be in [-1, 1]"));
  EXPECT_THAT(ErrorOf("global:\n  work_per_frame: -5\n"),
              HasSubstr("perception.yaml: global.work_per_frame: must be in [0, 1e9] pairings"));
  EXPECT_THAT(ErrorOf("global:\n  work_per_frame: 2000000000\n"),
              HasSubstr("perception.yaml: global.work_per_frame: must be in [0, 1e9] pairings"));
  EXPECT_THAT(
      ErrorOf("self_filter:\n  margin_m: 0.15\n"),
      HasSubstr("perception.yaml: self_filter.margin_m: 0.15 m is above the upper bound 0.1 m"));
  EXPECT_THAT(ErrorOf("global:\n  work_per_frame: many\n"),
              HasSubstr("perception.yaml: global.work_per_frame: expected an integer, got 'many'"));
  // A bound that depends on another field, possibly in another section.
  EXPECT_THAT(ErrorOf("model:\n  margin_m: 0.02\n"),
              HasSubstr("perception.yaml: icp.start_distance_m: must be below model.margin_m"));
  EXPECT_THAT(ErrorOf("global:\n  attempts: 2\n  work_per_frame: 100000\n"),
              HasSubstr("perception.yaml: global.attempts: must be 0 when global.work_per_frame "
                        "bounds the search"));
  EXPECT_EQ(ErrorOf("global:\n  attempts: 2\n  work_per_frame: 0\n"), "");
}

TEST_F(PerceptionConfigTest, TheMissionFileSearchesWithoutABound) {
  const PerceptionOptions mission =
      LoadPerceptionOptions(DataPath("config/perception_mission.yaml"));
  EXPECT_EQ(mission.global.work_per_frame, 0);
  EXPECT_EQ(mission.global.attempts, 2);
  EXPECT_FALSE(mission.global.whole_frame_features);
}

}  // namespace
TEST_F(PerceptionConfigTest, TheMissionSearchesADetectorBoxFromOneCentre) {
  EXPECT_FALSE(TwoCentresInBox(LoadPerceptionOptions(DataPath("config/perception_mission.yaml"))));
  EXPECT_TRUE(TwoCentresInBox(LoadPerceptionOptions(DataPath("config/perception_default.yaml"))));
}

TEST_F(PerceptionConfigTest, CountsThatDriveLoopsAreBoundedAbove) {
  EXPECT_THAT(ErrorOf("global:\n  max_iterations: 2147483647\n"),
              HasSubstr("perception.yaml: global.max_iterations: must be in [1, 100000]"));
  EXPECT_THAT(ErrorOf("global:\n  attempts: 1000000\n"),
              HasSubstr("perception.yaml: global.attempts: must be in [0, 20]"));
  EXPECT_THAT(ErrorOf("global:\n  orientations: 1000000\n"),
              HasSubstr("perception.yaml: global.orientations: must be in [0, 1000]"));
  EXPECT_THAT(ErrorOf("global:\n  refined_orientations: 1000000\n"),
              HasSubstr("perception.yaml: global.refined_orientations: must be in [0, 100]"));
}

}  // namespace aerograsp
