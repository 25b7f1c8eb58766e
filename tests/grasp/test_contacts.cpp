#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/config.h"
#include "grasp/contacts.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

using test::BoxMesh;
using test::MergeMeshes;

std::string Object(const std::string& name) {
  return std::string(AEROGRASP_DATA_DIR) + "/objects/" + name + "/" + name + ".ply";
}

int CountAxis(const ContactSet& set, int axis) {
  int n = 0;
  for (const ContactPair& p : set.pairs) n += p.axis == axis;
  return n;
}

TEST(ContactsTest, BoxGivesOnePairPerRayWithFaceNormals) {
  // 0.08 x 0.06 x 0.04 m: every extent fits the default gripper (0.12 - 2 x 0.01).
  const TriangleMesh box = BoxMesh(Eigen::Vector3d(0.08, 0.06, 0.04));
  const ContactSet set = ComputeContactPairs(box, GripperConfig{}, ContactOptions{});
  // Grid cells of 0.015 m: x rays 4 x 2, y rays 2 x 5, z rays 5 x 4.
  EXPECT_EQ(set.rays, 8 + 10 + 20);
  EXPECT_EQ(set.rays_hit, set.rays);
  EXPECT_EQ(set.rays_skipped, 0);
  ASSERT_EQ(set.pairs.size(), 38u);
  EXPECT_EQ(CountAxis(set, 0), 8);
  EXPECT_EQ(CountAxis(set, 2), 20);
  const Eigen::Vector3d size(0.08, 0.06, 0.04);
  for (const ContactPair& p : set.pairs) {
    EXPECT_NEAR(p.width_m(), size[p.axis], 1e-6);
    EXPECT_NEAR(p.a.p_o[p.axis], -0.5 * size[p.axis], 1e-6);
    EXPECT_TRUE(p.a.n_o.isApprox(-Eigen::Vector3d::Unit(p.axis), 1e-9)) << p.a.n_o.transpose();
    EXPECT_TRUE(p.b.n_o.isApprox(Eigen::Vector3d::Unit(p.axis), 1e-9));
  }
}

TEST(ContactsTest, PairsWiderThanTheGripperAreDropped) {
  // 0.20 m along x does not fit 0.10 m; y and z do.
  const ContactSet set = ComputeContactPairs(BoxMesh(Eigen::Vector3d(0.20, 0.06, 0.04)),
                                             GripperConfig{}, ContactOptions{});
  EXPECT_EQ(CountAxis(set, 0), 0);
  EXPECT_EQ(set.pairs_too_wide, 8);
  EXPECT_GT(CountAxis(set, 1), 0);
  EXPECT_DOUBLE_EQ(set.max_width_m, 0.10);
}

TEST(ContactsTest, RayThroughThreeFoldsGivesSixPairs) {
  // Three slabs 0.01 m thick along x, 0.03 x 0.03 across: each x ray crosses 3
  // folds, so Eq. 4 gives 1 + 2 + 3 = 6 pairs per ray (the widest, 0.09 m, fits).
  const Eigen::Vector3d slab(0.01, 0.03, 0.03);
  const TriangleMesh mesh =
      MergeMeshes(MergeMeshes(BoxMesh(slab, Eigen::Vector3d(-0.04, 0, 0)), BoxMesh(slab)),
                  BoxMesh(slab, Eigen::Vector3d(0.04, 0, 0)));
  const ContactSet set = ComputeContactPairs(mesh, GripperConfig{}, ContactOptions{});
  // 2 x 2 rays along x.
  EXPECT_EQ(CountAxis(set, 0), 4 * 6);
  std::vector<double> widths;
  for (const ContactPair& p : set.pairs) {
    if (p.axis == 0 && p.a.p_o.y() == set.pairs[0].a.p_o.y() &&
        p.a.p_o.z() == set.pairs[0].a.p_o.z()) {
      widths.push_back(p.width_m());
    }
  }
  std::sort(widths.begin(), widths.end());
  ASSERT_EQ(widths.size(), 6u);
  const double expected[6] = {0.01, 0.01, 0.01, 0.05, 0.05, 0.09};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(widths[i], expected[i], 1e-6);
}

TEST(ContactsTest, UShapeOffersItsInnerNooks) {
  // u_shape: 0.20 m wide along x, walls 0.03 m thick, opening at the top. An x
  // ray through both walls offers each wall alone (0.03 m, the nooks) and the
  // whole (0.20 m, too wide for the gripper).
  const ContactSet set =
      ComputeContactPairs(LoadClosedMesh(Object("u_shape")), GripperConfig{}, ContactOptions{});
  int left_wall = 0, right_wall = 0;
  for (const ContactPair& p : set.pairs) {
    if (p.axis != 0 || p.a.p_o.z() < 0.0) continue;  // upper half: through both walls
    EXPECT_NEAR(p.width_m(), 0.03, 1e-6);
    left_wall += std::abs(p.a.p_o.x() + 0.10) < 1e-6;
    right_wall += std::abs(p.b.p_o.x() - 0.10) < 1e-6;
  }
  EXPECT_GT(left_wall, 0);
  EXPECT_EQ(left_wall, right_wall);
  EXPECT_GT(set.pairs_too_wide, 0);
}

TEST(ContactsTest, DeterministicAcrossRuns) {
  const TriangleMesh mesh = LoadClosedMesh(Object("crawler"));
  const ContactSet a = ComputeContactPairs(mesh, GripperConfig{}, ContactOptions{});
  const ContactSet b = ComputeContactPairs(mesh, GripperConfig{}, ContactOptions{});
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) {
    EXPECT_EQ(a.pairs[i].a.p_o, b.pairs[i].a.p_o);
    EXPECT_EQ(a.pairs[i].b.n_o, b.pairs[i].b.n_o);
  }
}

TEST(ContactsTest, BadResolutionIsRejectedWithItsKey) {
  ContactOptions options;
  options.resolution_m = 0.5;
  try {
    options.Validate("plan.yaml", "contacts.");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("plan.yaml: contacts.resolution_m"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("above the upper bound"));
  }
  EXPECT_THROW(
      ComputeContactPairs(BoxMesh(Eigen::Vector3d::Constant(0.05)), GripperConfig{}, options),
      std::invalid_argument);
}

TEST(ContactsTest, PairsNearAFacesEdgeAreNotClearOfEdges) {
  // A 0.09 x 0.06 x 0.09 m box: the y rays run on a 6 x 6 grid (x, z) at
  // +-0.0075, +-0.0225, +-0.0375 m. Shifted 0.01 m, a ray at 0.0375 (7.5 mm
  // from an edge) leaves the face; one at 0.0225 stays on it.
  const TriangleMesh box = BoxMesh(Eigen::Vector3d(0.09, 0.06, 0.09));
  const ContactSet set = ComputeContactPairs(box, GripperConfig{}, ContactOptions{});
  int y_pairs = 0, clear = 0;
  for (const ContactPair& p : set.pairs) {
    if (p.axis != 1) continue;
    ++y_pairs;
    const bool inner = std::abs(p.center_o().x()) < 0.03 && std::abs(p.center_o().z()) < 0.03;
    EXPECT_EQ(ContactsClearOfEdges(box, p, 0.01), inner) << p.center_o().transpose();
    clear += ContactsClearOfEdges(box, p, 0.01);
    EXPECT_TRUE(ContactsClearOfEdges(box, p, 0.0));  // no margin: every pair
  }
  EXPECT_EQ(y_pairs, 36);
  EXPECT_EQ(clear, 16);
}

TEST(ContactsTest, CrawlerPairsAcrossTheTracksNearItsEndsAreNotClearOfEdges) {
  // The crawler's x rays are too long for the gripper; across its tracks (y)
  // the grid runs along x at +-0.0975, +-0.0825, ...: the outermost column is
  // 12.5 mm from an end.
  const TriangleMesh crawler = LoadClosedMesh(Object("crawler"));
  const ContactSet set = ComputeContactPairs(crawler, GripperConfig{}, ContactOptions{});
  int outer = 0;
  for (const ContactPair& p : set.pairs) {
    if (p.axis != 1 || std::abs(p.width_m() - 0.09) > 1e-3) continue;  // across both tracks
    if (std::abs(std::abs(p.center_o().x()) - 0.0975) < 1e-6) {
      ++outer;
      EXPECT_FALSE(ContactsClearOfEdges(crawler, p, 0.015)) << p.center_o().transpose();
    }
  }
  EXPECT_GT(outer, 0);
}

}  // namespace
}  // namespace aerograsp
