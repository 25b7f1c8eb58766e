#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/collision.h"
#include "core/config.h"
#include "core/transforms.h"
#include "grasp/planner.h"
#include "mission/grasp_policy.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

/// The grasp policy's switching rule over the planner's rankings, at its default margin.
const double kSwitchMargin = GraspPolicyConfig{}.switch_margin;

Platform LoadPlatform() {
  return Platform::Load(std::string(AEROGRASP_DATA_DIR) + "/config/platform_4dof.yaml");
}

GraspObject Box(const Eigen::Vector3d& size) {
  GraspObject o;
  o.name = "box";
  o.mesh_o = test::BoxMesh(size);
  o.mass_kg = 0.3;
  return o;
}

/// The object placed so that the left arm at q_left holds it: the box's x axis
/// along the tool's closing axis, its centre `depth` behind the tool point.
Eigen::Isometry3d PlaceAtTool(const Platform& p, const Eigen::VectorXd& q_left, double depth) {
  const Eigen::Isometry3d dMe = p.dMb(Side::kLeft) * p.arm(Side::kLeft).ForwardKinematics(q_left);
  Eigen::Isometry3d dMo = dMe;
  dMo.translation() = dMe.translation() - depth * dMe.linear().col(2);
  return dMo;
}

TEST(GraspPlannerTest, ArmReachesABoxPlacedAtItsOwnTool) {
  const Platform platform = LoadPlatform();
  const GraspObject box = Box(Eigen::Vector3d(0.05, 0.05, 0.05));
  ContactSet contacts =
      ComputeContactPairs(box.mesh_o, platform.config().gripper, ContactOptions{});
  const GraspPlanner planner(platform, box, contacts, GraspPlannerConfig{});
  Eigen::VectorXd q(4);
  q << 0.3, -0.9, 0.6, 0.2;
  const Eigen::Isometry3d dMo = PlaceAtTool(platform, q, 0.04);
  int feasible = 0, unreachable = 0;
  for (int i = 0; i < static_cast<int>(planner.contacts().pairs.size()); ++i) {
    ArmGrasp g;
    Infeasibility why;
    if (planner.EvaluateArm(Side::kLeft, i, dMo, q, &g, &why)) {
      ++feasible;
      // The grasp frame closes along the pair's axis through its centre.
      const ContactPair& pair = planner.contacts().pairs[i];
      const Eigen::Vector3d x_d = dMo.linear() * pair.closing_axis_o();
      EXPECT_NEAR(std::abs(g.dMg.linear().col(0).dot(x_d)), 1.0, 1e-6);
      const Eigen::Vector3d c_d = dMo * pair.center_o();
      EXPECT_LT((g.dMg.translation() - (c_d + g.depth_m * g.dMg.linear().col(2))).norm(), 1e-5);
    } else {
      unreachable += why == Infeasibility::kUnreachable;
    }
  }
  // The closing axes along x and y of the box are perpendicular to the
  // approach and reachable; along z (the approach itself) they never are.
  EXPECT_EQ(feasible, 18);
  EXPECT_EQ(unreachable, 9);
}

/// The u_shape at the plan command's default placement.
class ShippedPlanTest : public ::testing::Test {
 protected:
  ShippedPlanTest()
      : platform_(LoadPlatform()),
        object_(UShape()),
        planner_(platform_, object_,
                 ComputeContactPairs(object_.mesh_o, platform_.config().gripper, ContactOptions{}),
                 GraspPlannerConfig{}) {
    query_.dMo =
        MakeTransform(Eigen::Vector3d(0.10, 0.0, 0.46), Eigen::Vector3d(M_PI, 0.0, M_PI / 2));
    query_.q_left = platform_.home(Side::kLeft);
    query_.q_right = platform_.home(Side::kRight);
  }
  static GraspObject UShape() {
    GraspObject o;
    o.name = "u_shape";
    o.mesh_o = LoadClosedMesh(std::string(AEROGRASP_DATA_DIR) + "/objects/u_shape/u_shape.ply");
    o.mass_kg = 0.3;
    o.com_o = ComputeMassProperties(o.mesh_o).center_of_mass;
    return o;
  }
  Platform platform_;
  GraspObject object_;
  GraspPlanner planner_;
  PlanQuery query_;
};

TEST_F(ShippedPlanTest, RankedPairsAreFeasibleForBothArmsTogether) {
  const PlanResult plan = planner_.Plan(query_);
  ASSERT_FALSE(plan.ranked.empty());
  EXPECT_EQ(plan.left_stats.candidates, static_cast<int>(planner_.contacts().pairs.size()));
  EXPECT_EQ(plan.pair_stats.valid, static_cast<long long>(plan.ranked.size()));
  const PlatformCollision collision(platform_);
  for (std::size_t i = 0; i < plan.ranked.size(); ++i) {
    const DualGrasp& d = plan.ranked[i];
    if (i > 0 && d.epsilon_exact == plan.ranked[i - 1].epsilon_exact) {
      EXPECT_LE(d.score, plan.ranked[i - 1].score);
    }
    EXPECT_GT(d.epsilon, 0.0);
    for (const ArmGrasp* g : {&d.left, &d.right}) {
      const ArmModel& arm = platform_.arm(g->side);
      EXPECT_TRUE(arm.WithinLimits(g->q_grasp));
      EXPECT_TRUE(arm.WithinLimits(g->q_precatch));
      EXPECT_FALSE(collision.ArmInSafeVolume(g->side, g->q_grasp));
      const Eigen::Isometry3d dMe = platform_.dMb(g->side) * arm.ForwardKinematics(g->q_grasp);
      EXPECT_LT(ComparePoses(dMe, g->dMg).translation_m, 1e-9);
      // The pre-catch tool point is back along the approach.
      const Eigen::Vector3d back = g->dMg.translation() - 0.08 * g->dMg.linear().col(2);
      EXPECT_LT((g->dMp.translation() - back).norm(), 1e-5);
    }
    EXPECT_FALSE(collision.ArmsCollide(d.left.q_grasp, d.right.q_grasp));
  }
  // The exact epsilon of the best pair is what Qhull gives for both grippers' contacts.
  const DualGrasp& best = plan.ranked.front();
  ASSERT_TRUE(best.epsilon_exact);
  EXPECT_DOUBLE_EQ(best.epsilon, planner_.ExactQuality(best.left.pair, best.right.pair).epsilon);
}

TEST_F(ShippedPlanTest, PlanIsDeterministic) {
  const PlanResult a = planner_.Plan(query_), b = planner_.Plan(query_);
  ASSERT_EQ(a.ranked.size(), b.ranked.size());
  for (std::size_t i = 0; i < a.ranked.size(); ++i) {
    EXPECT_EQ(a.ranked[i].left.pair, b.ranked[i].left.pair);
    EXPECT_EQ(a.ranked[i].right.pair, b.ranked[i].right.pair);
    EXPECT_EQ(a.ranked[i].score, b.ranked[i].score);
  }
}

TEST_F(ShippedPlanTest, ObjectOutOfReachHasNoGraspAndSaysWhy) {
  PlanQuery far = query_;
  far.dMo.translation() = Eigen::Vector3d(1.5, 0.0, 0.5);
  const PlanResult plan = planner_.Plan(far);
  EXPECT_TRUE(plan.ranked.empty());
  EXPECT_EQ(plan.left_stats.by_reason[static_cast<int>(Infeasibility::kUnreachable)],
            plan.left_stats.candidates);
  EXPECT_EQ(DescribeReasons(plan.left_stats),
            std::to_string(plan.left_stats.candidates) + " unreachable");
  EXPECT_EQ(DescribeReasons(ArmStats{}), "");
  const SwitchDecision d = DecideSwitch(plan, SwitchState{}, kSwitchMargin);
  EXPECT_EQ(d.status, SwitchDecision::Status::kNoGrasp);
  EXPECT_THAT(d.reason, HasSubstr("no feasible dual grasp"));
}

TEST_F(ShippedPlanTest, KeepsTheCurrentPairUntilItBecomesUnreachable) {
  SwitchDecision first = DecideSwitch(planner_.Plan(query_), SwitchState{}, kSwitchMargin);
  ASSERT_EQ(first.status, SwitchDecision::Status::kSwitch);
  EXPECT_THAT(first.reason, HasSubstr("first choice"));
  // Same pose: keep.
  SwitchDecision again = DecideSwitch(planner_.Plan(query_), first.next, kSwitchMargin);
  EXPECT_EQ(again.status, SwitchDecision::Status::kKeep);
  EXPECT_TRUE(again.current_feasible);
  // Move the object to where the current pair is out of reach but others are
  // not: the planner switches, says why, and picks the best pair there.
  bool switched = false;
  for (int i = 0; i < 27 * 3 && !switched; ++i) {
    const int step = 1 + i / 27, cell = i % 27;
    const Eigen::Vector3d offset(0.01 * step * (cell % 3 - 1), 0.01 * step * (cell / 3 % 3 - 1),
                                 0.01 * step * (cell / 9 - 1));
    PlanQuery moved = query_;
    moved.dMo.translation() += offset;
    const PlanResult plan = planner_.Plan(moved);
    if (plan.ranked.empty()) continue;
    bool current_valid = false;
    for (const DualGrasp& d : plan.ranked) {
      current_valid |= d.left.pair == first.next.left_pair && d.right.pair == first.next.right_pair;
    }
    if (current_valid) continue;
    const SwitchDecision d = DecideSwitch(plan, first.next, kSwitchMargin);
    switched = true;
    EXPECT_EQ(d.status, SwitchDecision::Status::kSwitch);
    EXPECT_FALSE(d.current_feasible);
    EXPECT_THAT(d.reason, HasSubstr("became unreachable"));
    EXPECT_EQ(d.next.left_pair, plan.ranked.front().left.pair);
    EXPECT_EQ(d.next.right_pair, plan.ranked.front().right.pair);
  }
  EXPECT_TRUE(switched);
}

TEST_F(ShippedPlanTest, HysteresisStopsFlappingUnderSway) {
  // The object sways +-1 cm and +-1 deg about its placement; with the switch
  // margin the choice changes far less often than the best pair does.
  SwitchState state = DecideSwitch(planner_.Plan(query_), SwitchState{}, kSwitchMargin).next;
  int switches = 0, best_changes = 0;
  int previous_best_left = state.left_pair, previous_best_right = state.right_pair;
  for (int k = 0; k < 16; ++k) {
    PlanQuery q = query_;
    const double s = std::sin(0.7 * k);
    q.dMo.translation() += Eigen::Vector3d(0.01 * s, 0.01 * std::cos(1.3 * k), 0.0);
    q.dMo = q.dMo * Eigen::AngleAxisd(0.017 * s, Eigen::Vector3d::UnitX());
    const PlanResult plan = planner_.Plan(q);
    const SwitchDecision d = DecideSwitch(plan, state, kSwitchMargin);
    if (!plan.ranked.empty()) {
      const DualGrasp& b = plan.ranked.front();
      best_changes += b.left.pair != previous_best_left || b.right.pair != previous_best_right;
      previous_best_left = b.left.pair;
      previous_best_right = b.right.pair;
    }
    switches += d.status == SwitchDecision::Status::kSwitch;
    if (d.status != SwitchDecision::Status::kNoGrasp) state = d.next;
  }
  EXPECT_LE(switches, best_changes);
  EXPECT_LT(switches, 8);
}

TEST_F(ShippedPlanTest, RobustGraspsStayFeasibleWhenTheObjectMovesAndRankFirst) {
  GraspPlannerConfig config;
  config.reach_margin_m = 0.01;
  const GraspPlanner robust_planner(
      platform_, object_,
      ComputeContactPairs(object_.mesh_o, platform_.config().gripper, ContactOptions{}), config);
  const PlanResult plan = robust_planner.Plan(query_);
  const PlanResult plain = planner_.Plan(query_);
  // Robustness only orders and marks: the same pairs are feasible either way.
  EXPECT_EQ(plan.ranked.size(), plain.ranked.size());
  EXPECT_EQ(plan.left.size(), plain.left.size());
  for (const ArmGrasp& g : plain.left) EXPECT_TRUE(g.robust);  // margin 0: every feasible pair
  int robust = 0, fragile = 0;
  for (const std::vector<ArmGrasp>* grasps : {&plan.left, &plan.right}) {
    for (const ArmGrasp& g : *grasps) {
      // A robust pair is feasible with the object moved 1 cm along each axis;
      // a fragile one fails at one of those places at least.
      bool all = true;
      for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
          Eigen::Isometry3d moved = query_.dMo;
          moved.translation()[axis] += sign * 0.01;
          ArmGrasp unused;
          Infeasibility why;
          const Eigen::VectorXd& q = g.side == Side::kLeft ? query_.q_left : query_.q_right;
          all = all && robust_planner.EvaluateArm(g.side, g.pair, moved, q, &unused, &why);
        }
      }
      EXPECT_EQ(g.robust, all) << "pair " << g.pair;
      (g.robust ? robust : fragile)++;
    }
  }
  EXPECT_GT(robust, 0);
  EXPECT_GT(fragile, 0);  // the placement is near the edge of the 4-DoF arms' reach
  bool seen_fragile = false;
  for (const DualGrasp& d : plan.ranked) {
    EXPECT_EQ(d.robust, d.left.robust && d.right.robust);
    if (!d.robust) seen_fragile = true;
    if (seen_fragile) {
      EXPECT_FALSE(d.robust) << "a robust dual grasp ranks after a fragile one";
    }
  }
}

TEST_F(ShippedPlanTest, RobustOnTheBranchMeansTheNearestMovedSolutionStaysNear) {
  GraspPlannerConfig any_branch;
  any_branch.reach_margin_m = 0.01;
  GraspPlannerConfig one_branch = any_branch;
  one_branch.robust_branch_rad = 0.2;
  const ContactSet contacts =
      ComputeContactPairs(object_.mesh_o, platform_.config().gripper, ContactOptions{});
  const GraspPlanner any_planner(platform_, object_, contacts, any_branch);
  const GraspPlanner branch_planner(platform_, object_, contacts, one_branch);
  const PlanResult any = any_planner.Plan(query_);
  const PlanResult plan = branch_planner.Plan(query_);
  ASSERT_EQ(plan.left.size(), any.left.size());
  int robust = 0, fragile = 0;
  for (std::size_t i = 0; i < plan.left.size(); ++i) {
    const ArmGrasp& g = plan.left[i];
    // Robust on the branch: at each moved place the solution nearest g's
    // joints is feasible and within 0.2 rad of them in every joint.
    bool all = true;
    for (int axis = 0; axis < 3; ++axis) {
      for (double sign : {-1.0, 1.0}) {
        Eigen::Isometry3d moved = query_.dMo;
        moved.translation()[axis] += sign * 0.01;
        ArmGrasp near;
        Infeasibility why;
        all = all && branch_planner.EvaluateArm(g.side, g.pair, moved, g.q_grasp, &near, &why) &&
              (near.q_grasp - g.q_grasp).cwiseAbs().maxCoeff() <= 0.2;
      }
    }
    EXPECT_EQ(g.robust, all) << "pair " << g.pair;
    if (g.robust) {
      EXPECT_TRUE(any.left[i].robust) << "pair " << g.pair;
    }
    (g.robust ? robust : fragile)++;
  }
  EXPECT_GT(robust, 0);
  EXPECT_GT(fragile, 0);
}

TEST_F(ShippedPlanTest, GraspsClearOfEdgesRankFirstAndGetTheExactEpsilon) {
  GraspPlannerConfig config;
  config.edge_margin_m = 0.015;
  const ContactSet contacts =
      ComputeContactPairs(object_.mesh_o, platform_.config().gripper, ContactOptions{});
  const GraspPlanner edge_planner(platform_, object_, contacts, config);
  const PlanResult plan = edge_planner.Plan(query_);
  const PlanResult plain = planner_.Plan(query_);
  // The margin only orders and marks: the same pairs are feasible either way.
  EXPECT_EQ(plan.ranked.size(), plain.ranked.size());
  for (const DualGrasp& d : plain.ranked) EXPECT_TRUE(d.clear_of_edges);  // margin 0: every pair
  int clear = 0, near_edge = 0;
  bool seen_near_edge = false;
  for (const DualGrasp& d : plan.ranked) {
    // The flag is the contacts' own test, for both arms' pairs.
    EXPECT_EQ(d.left.clear_of_edges,
              ContactsClearOfEdges(object_.mesh_o, contacts.pairs[d.left.pair], 0.015));
    EXPECT_EQ(d.clear_of_edges, d.left.clear_of_edges && d.right.clear_of_edges);
    (d.clear_of_edges ? clear : near_edge)++;
    if (!d.clear_of_edges) seen_near_edge = true;
    if (seen_near_edge) {
      EXPECT_FALSE(d.clear_of_edges) << "a dual grasp clear of edges ranks after one near an edge";
    }
  }
  ASSERT_GT(clear, 0);
  EXPECT_GT(near_edge, 0);
  // The exact epsilon goes to the first ones, which are clear of edges.
  EXPECT_TRUE(plan.ranked.front().epsilon_exact);
}

/// Two rankings' entries the same, field by field.
void ExpectSameEntry(const DualGrasp& a, const DualGrasp& b) {
  EXPECT_EQ(a.left.pair, b.left.pair);
  EXPECT_EQ(a.right.pair, b.right.pair);
  EXPECT_EQ(a.score, b.score);
  EXPECT_EQ(a.epsilon, b.epsilon);
  EXPECT_EQ(a.epsilon_exact, b.epsilon_exact);
  EXPECT_EQ(a.task, b.task);
  EXPECT_EQ(a.robust, b.robust);
  EXPECT_EQ(a.clear_of_edges, b.clear_of_edges);
  EXPECT_EQ(a.left.robust, b.left.robust);
  EXPECT_EQ(a.right.robust, b.right.robust);
  EXPECT_EQ(a.left.q_grasp, b.left.q_grasp);
  EXPECT_EQ(a.right.q_precatch, b.right.q_precatch);
}

TEST_F(ShippedPlanTest, PlanFrontGivesPlansFirstEntryAndTheKeptPairsEntry) {
  // The mission's ranking classes (robust, clear of edges), with every
  // number of exact epsilons: all of them, a few, none.
  for (const int exact_top_k : {20, 3, 0}) {
    GraspPlannerConfig config;
    config.reach_margin_m = 0.01;
    config.robust_branch_rad = 0.5;
    config.edge_margin_m = 0.005;
    config.exact_top_k = exact_top_k;
    const GraspPlanner planner(
        platform_, object_,
        ComputeContactPairs(object_.mesh_o, platform_.config().gripper, ContactOptions{}), config);
    int poses = 0, kept_elsewhere = 0, kept_unranked = 0, robust_classes_seen = 0;
    for (int k = 0; k < 6; ++k) {
      PlanQuery q = query_;
      q.dMo.translation() += Eigen::Vector3d(0.01 * std::sin(1.3 * k), 0.01 * std::cos(0.9 * k),
                                             0.01 * std::sin(0.4 * k));
      q.dMo = q.dMo * Eigen::AngleAxisd(0.05 * std::sin(0.7 * k), Eigen::Vector3d::UnitZ());
      const PlanResult plan = planner.Plan(q);
      if (plan.ranked.empty()) continue;
      ++poses;
      robust_classes_seen += plan.ranked.front().robust != plan.ranked.back().robust;
      // Kept pairs from every part of the ranking, one no arm takes and none.
      std::vector<std::pair<int, int>> kept = {{-1, -1}, {0, 1}};
      const std::size_t last = plan.ranked.size() - 1;
      for (const std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{2},
                                  static_cast<std::size_t>(exact_top_k), last / 2, last}) {
        const DualGrasp& d = plan.ranked[std::min(i, last)];
        kept.emplace_back(d.left.pair, d.right.pair);
      }
      for (const auto& [left, right] : kept) {
        const PlanResult front = planner.PlanFront(q, left, right);
        EXPECT_EQ(front.left_stats.feasible, plan.left_stats.feasible);
        EXPECT_EQ(front.right_stats.feasible, plan.right_stats.feasible);
        ASSERT_FALSE(front.ranked.empty());
        ExpectSameEntry(front.ranked.front(), plan.ranked.front());
        const DualGrasp* in_plan = nullptr;
        for (const DualGrasp& d : plan.ranked) {
          if (d.left.pair == left && d.right.pair == right) in_plan = &d;
        }
        const bool is_front = in_plan == &plan.ranked.front();
        ASSERT_EQ(front.ranked.size(), in_plan && !is_front ? 2u : 1u) << left << ", " << right;
        if (in_plan && !is_front) {
          ExpectSameEntry(front.ranked[1], *in_plan);
          ++kept_elsewhere;
        }
        kept_unranked += !in_plan;
        // The policy's decision from either is the same.
        const SwitchState followed{left, right};
        const SwitchDecision a = DecideSwitch(plan, followed, kSwitchMargin);
        const SwitchDecision b = DecideSwitch(front, followed, kSwitchMargin);
        EXPECT_EQ(a.status, b.status);
        EXPECT_EQ(a.reason, b.reason);
      }
    }
    EXPECT_GE(poses, 4);
    EXPECT_GT(kept_elsewhere, 0);
    EXPECT_GT(kept_unranked, 0);
    EXPECT_GT(robust_classes_seen, 0) << "no plan ranked both robust and other grasps";
  }
}

// The 6-DoF arms with the wrist margin: the same pairs stay feasible, more of
// their grasps keep the wrist off its singularity and limits, and a grasp
// without the margin is not robust.
TEST(GraspPlannerTest, WristMarginPicksGraspsAwayFromTheWristsSingularity) {
  const Platform platform =
      Platform::Load(std::string(AEROGRASP_DATA_DIR) + "/config/platform_6dof.yaml");
  GraspObject u_shape;
  u_shape.name = "u_shape";
  u_shape.mesh_o = LoadClosedMesh(std::string(AEROGRASP_DATA_DIR) + "/objects/u_shape/u_shape.ply");
  u_shape.mass_kg = 0.3;
  u_shape.com_o = ComputeMassProperties(u_shape.mesh_o).center_of_mass;
  const ContactSet contacts =
      ComputeContactPairs(u_shape.mesh_o, platform.config().gripper, ContactOptions{});
  GraspPlannerConfig nearest;
  nearest.reach_margin_m = 0.02;
  nearest.robust_branch_rad = 0.5;
  nearest.grasp_axis_approaches = 16;  // the mission's sampling
  nearest.grasp_axis_depths = 3;
  GraspPlannerConfig margin = nearest;
  margin.wrist_margin_rad = 0.3;
  const GraspPlanner nearest_planner(platform, u_shape, contacts, nearest);
  const GraspPlanner margin_planner(platform, u_shape, contacts, margin);
  PlanQuery query;
  query.dMo =
      MakeTransform(Eigen::Vector3d(0.035, 0.0, 0.48), Eigen::Vector3d(M_PI, 0.0, M_PI / 2));
  query.q_left = platform.home(Side::kLeft);
  query.q_right = platform.home(Side::kRight);
  const PlanResult before = nearest_planner.Plan(query);
  const PlanResult after = margin_planner.Plan(query);
  const ArmIk ik(platform.arm(Side::kLeft));
  ASSERT_EQ(after.left.size(), before.left.size());
  int kept_before = 0, kept_after = 0;
  for (std::size_t i = 0; i < after.left.size(); ++i) {
    EXPECT_EQ(after.left[i].pair, before.left[i].pair);
    const bool kept = ik.WristMargin(after.left[i].q_grasp) >= 0.3;
    kept_before += ik.WristMargin(before.left[i].q_grasp) >= 0.3;
    kept_after += kept;
    if (!kept) {
      EXPECT_FALSE(after.left[i].robust) << "pair " << after.left[i].pair;
    }
  }
  EXPECT_GT(kept_after, kept_before);
}

TEST(GraspPlannerConfigTest, DefaultsAreValidAndBadDepthNamesItsKey) {
  GraspPlannerConfig c;
  EXPECT_NO_THROW(c.Validate("plan.yaml", "planner."));
  EXPECT_NO_THROW(c.CheckFingers(GripperConfig{}, "plan.yaml", "planner."));
  c.depth_max_m = 0.2;  // longer than the 0.12 m fingers
  EXPECT_NO_THROW(c.Validate("plan.yaml", "planner."));
  try {
    c.CheckFingers(GripperConfig{}, "plan.yaml", "planner.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plan.yaml: planner.depth_max_m"));
    EXPECT_THAT(e.what(), HasSubstr("above the upper bound 0.12 m"));
  }
  // Validate refuses the config, naming the file, the key and the bound.
  const auto expect_refused = [](const GraspPlannerConfig& bad, const std::string& message) {
    try {
      bad.Validate("plan.yaml", "planner.");
      ADD_FAILURE() << "accepted; expected: " << message;
    } catch (const ConfigError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  };
  c.depth_max_m = 0.35;  // longer than any platform's fingers
  expect_refused(c, "plan.yaml: planner.depth_max_m: 0.35 m is above the upper bound 0.3 m");
  c = GraspPlannerConfig{};
  c.reach_margin_m = 0.5;
  expect_refused(c, "plan.yaml: planner.reach_margin_m: 0.5 m is above");
  c = GraspPlannerConfig{};
  c.robust_branch_rad = 7.0;
  expect_refused(c, "plan.yaml: planner.robust_branch_rad: 7 rad is above");
  c = GraspPlannerConfig{};
  c.wrist_margin_rad = 2.0;
  expect_refused(c, "plan.yaml: planner.wrist_margin_rad: 2 rad is above");
}

TEST(GraspPlannerConfigTest, BadGraspAxisSamplingNamesItsKey) {
  GraspPlannerConfig c;
  c.grasp_axis_approaches = 0;
  try {
    c.Validate("plan.yaml", "planner.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plan.yaml: planner.grasp_axis_approaches: 0"));
    EXPECT_THAT(e.what(), HasSubstr("below the lower bound 1"));
  }
  c = GraspPlannerConfig{};
  c.grasp_axis_depths = 17;
  try {
    c.Validate("plan.yaml", "planner.");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plan.yaml: planner.grasp_axis_depths: 17"));
    EXPECT_THAT(e.what(), HasSubstr("above the upper bound 16"));
  }
}

}  // namespace
}  // namespace aerograsp
