#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/config.h"
#include "core/mesh.h"
#include "core/object_model.h"
#include "grasp/placement.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

Platform LoadPlatform() {
  return Platform::Load(std::string(AEROGRASP_DATA_DIR) + "/config/platform_4dof.yaml");
}

/// The shipped crawler and the mission's planner settings (contacts 2.5 to 10
/// cm behind the tool point, 1.5 cm clear of edges and robust to 2 cm ranked first).
class PlacementTest : public ::testing::Test {
 protected:
  PlacementTest()
      : platform_(LoadPlatform()), planner_(platform_, Crawler(), Contacts(), Config()) {}
  static GraspObject Crawler() {
    const ObjectModel model = ObjectModel::Load("crawler");
    return {model.name, model.mesh_o, model.mass_kg, model.center_of_mass_o};
  }
  ContactSet Contacts() const {
    return ComputeContactPairs(Crawler().mesh_o, platform_.config().gripper, Config().contacts);
  }
  static GraspPlannerConfig Config() {
    GraspPlannerConfig c;
    c.depth_min_m = 0.025;
    c.depth_max_m = 0.10;
    c.edge_margin_m = 0.015;
    c.reach_margin_m = 0.02;
    return c;
  }
  Placement Choose(const PlacementConfig& config) const {
    return ChoosePlacement(planner_, kNominal, config, platform_.home(Side::kLeft),
                           platform_.home(Side::kRight));
  }
  const Eigen::Vector3d kNominal{0.075, 0.0, 0.47};
  Platform platform_;
  GraspPlanner planner_;
};

TEST_F(PlacementTest, PairsClearOfEndsKeepTheirContactsAwayFromTheEnds) {
  const ContactSet& contacts = planner_.contacts();
  const std::vector<bool> clear = PairsClearOfEnds(Crawler().mesh_o, contacts, 0.025);
  ASSERT_EQ(clear.size(), contacts.pairs.size());
  int kept = 0;
  for (std::size_t i = 0; i < clear.size(); ++i) {
    const double x =
        std::max(std::abs(contacts.pairs[i].a.p_o.x()), std::abs(contacts.pairs[i].b.p_o.x()));
    // The crawler's ends are at x = +-0.11 m.
    EXPECT_EQ(clear[i], x <= 0.085 + 1e-9) << "pair " << i << " at |x| " << x;
    kept += clear[i];
  }
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, static_cast<int>(clear.size()));
}

TEST_F(PlacementTest, WithoutSearchTheNominalPointIsThePlacement) {
  PlacementConfig config;
  config.search_x_m = config.search_y_m = config.search_z_m = 0.0;
  EXPECT_FALSE(config.Searches());
  const Placement placement = Choose(config);
  EXPECT_LT((placement.dMo.translation() - kNominal).norm(), 1e-12);
  EXPECT_EQ(placement.points, 1);
  // Upright, its long x axis across the vehicle (along y of d).
  EXPECT_NEAR(placement.dMo.linear().col(0).dot(Eigen::Vector3d::UnitY()), 1.0, 1e-12);
  EXPECT_NEAR(placement.dMo.linear().col(2).dot(Eigen::Vector3d::UnitZ()), -1.0, 1e-12);
}

TEST_F(PlacementTest, ChosenPointHasMoreGraspsClearOfTheEndsThanTheNominal) {
  const PlacementConfig config;
  const Placement placement = Choose(config);
  const Eigen::Vector3d off = placement.dMo.translation() - kNominal;
  EXPECT_LE(std::abs(off.x()), config.search_x_m + 1e-9);
  EXPECT_LE(std::abs(off.y()), config.search_y_m + 1e-9);
  EXPECT_LE(std::abs(off.z()), config.search_z_m + 1e-9);
  EXPECT_EQ(placement.level, 0);
  EXPECT_GT(placement.dual_grasps, 0);
  EXPECT_GT(std::min(placement.robust_pairs[0], placement.robust_pairs[1]),
            std::min(placement.nominal_robust_pairs[0], placement.nominal_robust_pairs[1]));
}

TEST_F(PlacementTest, CountedGraspsStayFeasibleThroughTheSway) {
  const PlacementConfig config;
  const Placement placement = Choose(config);
  const std::vector<bool> clear =
      PairsClearOfEnds(Crawler().mesh_o, planner_.contacts(), config.end_margin_m);
  // Recount the left arm's grasps at the placement from the planner directly.
  int counted = 0;
  const Eigen::VectorXd& q = platform_.home(Side::kLeft);
  for (int p = 0; p < static_cast<int>(clear.size()); ++p) {
    ArmGrasp g;
    Infeasibility why;
    if (!clear[p] || !planner_.EvaluateArm(Side::kLeft, p, placement.dMo, q, &g, &why) ||
        !g.clear_of_edges) {
      continue;
    }
    bool robust = true;
    for (int axis = 0; axis < 3; ++axis) {
      for (double sign : {-1.0, 1.0}) {
        Eigen::Isometry3d moved = placement.dMo;
        moved.translation()[axis] += sign * planner_.config().reach_margin_m;
        ArmGrasp unused;
        robust = robust && planner_.EvaluateArm(Side::kLeft, p, moved, q, &unused, &why);
      }
    }
    counted += robust;
  }
  EXPECT_EQ(counted, placement.robust_pairs[0]);
}

TEST(PlacementConfigTest, BadValueNamesItsKey) {
  PlacementConfig config;
  config.step_m = 0.0;
  try {
    config.Validate("mission.yaml", "placement.");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mission.yaml: placement.step_m"));
  }
}

}  // namespace
}  // namespace aerograsp
