#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <regex>
#include <sstream>

#include "core/collision.h"
#include "core/shape_mesh.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

std::string Config(const std::string& name) {
  return std::string(AEROGRASP_DATA_DIR) + "/config/" + name;
}

/// Joint positions with the shoulder pitch q1 and elbow q2 set, the rest zero.
Eigen::VectorXd Pose(int dof, double q0, double q1, double q2) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(dof);
  q[0] = q0;
  q[1] = q1;
  q[2] = q2;
  return q;
}

/// dMe: the arm's tool point in the body frame at q.
Eigen::Isometry3d dMe(const Platform& p, Side side, const Eigen::VectorXd& q) {
  return p.dMb(side) * p.arm(side).ForwardKinematics(q);
}

/// The safe volume of the shipped vehicle: one axis-aligned box in d.
struct VolumeBox {
  Eigen::Vector3d lo, hi;
};
VolumeBox SafeBox(const Platform& p) {
  const CollisionShape& s = p.safe_volume_d().at(0);
  EXPECT_EQ(s.type, CollisionShape::Type::kBox);
  EXPECT_TRUE(s.segMs.linear().isIdentity(1e-12));
  return {s.segMs.translation() - 0.5 * s.size, s.segMs.translation() + 0.5 * s.size};
}

/// Independent of PlatformCollision: where the arm's segments from
/// `first_segment` on are with respect to the (axis-aligned) safe volume, from
/// the URDF primitives, the forward kinematics and their exact support extents.
struct ArmExtent {
  double min_z = std::numeric_limits<double>::infinity();  ///< highest point (FRD)
  bool under_footprint = true;  ///< every shape within the volume's x and y bounds
  double max_depth = 0.0;       ///< deepest overlap with the volume along x, y or z
};
ArmExtent Extent(const Platform& p, Side side, const Eigen::VectorXd& q, int first_segment) {
  const ArmModel& arm = p.arm(side);
  const VolumeBox v = SafeBox(p);
  std::vector<Eigen::Isometry3d> bMs;
  arm.SegmentPoses(q, &bMs);
  ArmExtent e;
  for (int seg = first_segment; seg < static_cast<int>(arm.segments().size()); ++seg) {
    for (const CollisionShape& c : arm.segments()[seg].collision) {
      const Eigen::Isometry3d dMs = p.dMb(side) * bMs[seg] * c.segMs;
      const Eigen::Matrix3d& R = dMs.linear();
      Eigen::Vector3d half = Eigen::Vector3d::Zero();  // exact half extent along x, y, z of d
      switch (c.type) {
        case CollisionShape::Type::kBox:
          half = R.cwiseAbs() * (0.5 * c.size);
          break;
        case CollisionShape::Type::kCylinder:
          for (int k = 0; k < 3; ++k) {
            const double a = R(k, 2);  // the axis' component along d's axis k
            half[k] = 0.5 * c.size.y() * std::abs(a) + c.size.x() * std::sqrt(1.0 - a * a);
          }
          break;
        case CollisionShape::Type::kSphere:
          half.setConstant(c.size.x());
          break;
        case CollisionShape::Type::kMesh:
          ADD_FAILURE() << "the shipped arms have no mesh shapes";
          continue;
      }
      const Eigen::Vector3d lo = dMs.translation() - half, hi = dMs.translation() + half;
      e.min_z = std::min(e.min_z, lo.z());
      e.under_footprint = e.under_footprint &&
                          (lo.head<2>().array() > v.lo.head<2>().array()).all() &&
                          (hi.head<2>().array() < v.hi.head<2>().array()).all();
      const Eigen::Vector3d overlap = (v.hi - lo).cwiseMin(hi - v.lo);
      if ((overlap.array() > 0.0).all()) e.max_depth = std::max(e.max_depth, overlap.minCoeff());
    }
  }
  return e;
}

class PlatformCollisionTest : public ::testing::TestWithParam<const char*> {
 protected:
  PlatformCollisionTest() : platform_(Platform::Load(Config(GetParam()))), collision_(platform_) {}
  int dof() const { return platform_.arm(Side::kLeft).dof(); }

  Platform platform_;
  PlatformCollision collision_;
};

INSTANTIATE_TEST_SUITE_P(ShippedConfigs, PlatformCollisionTest,
                         ::testing::Values("platform_4dof.yaml", "platform_6dof.yaml"));

TEST_P(PlatformCollisionTest, BasePlateAndYawingShoulderAreExempt) {
  // Segment 0 (base plate, shoulder top) and 1 (after the yaw j0) sit inside or
  // on the volume by design; segment 2 moves with the shoulder pitch j1.
  EXPECT_EQ(collision_.ExemptSegmentCount(Side::kLeft), 2);
  EXPECT_EQ(collision_.ExemptSegmentCount(Side::kRight), 2);
}

TEST_P(PlatformCollisionTest, ArmsAtHomeAreOutsideTheSafeVolume) {
  for (Side side : kSides) {
    EXPECT_FALSE(collision_.ArmInSafeVolume(side, platform_.home(side))) << SideName(side);
    EXPECT_GT(collision_.DistanceToSafeVolume(side, platform_.home(side)), 0.0) << SideName(side);
  }
}

TEST_P(PlatformCollisionTest, ArmRaisedAboveTheShoulderIsInTheSafeVolume) {
  // Shoulder pitch -100 deg, elbow -15 deg: the forearm rises forward and its
  // end (the wrist roll j3, segment 4's origin) is inside the volume.
  const Eigen::VectorXd q = Pose(dof(), 0.0, -1.745, -0.26);
  const VolumeBox v = SafeBox(platform_);
  for (Side side : kSides) {
    std::vector<Eigen::Isometry3d> bMs;
    platform_.arm(side).SegmentPoses(q, &bMs);
    const Eigen::Vector3d p_d = platform_.dMb(side) * bMs[4].translation();
    ASSERT_TRUE((p_d.array() > v.lo.array()).all() && (p_d.array() < v.hi.array()).all())
        << "the forearm's end " << p_d.transpose() << " should be inside the volume";
    EXPECT_TRUE(collision_.ArmInSafeVolume(side, q)) << SideName(side);
    EXPECT_LT(collision_.DistanceToSafeVolume(side, q), 0.0) << SideName(side);
  }
}

TEST_P(PlatformCollisionTest, StraightDownDistanceIsTheUpperArmsGapBelowTheVolume) {
  // vehicle.urdf: base at z = 0.04, volume bottom at -0.055 + 0.29 / 2 = 0.09.
  // arm URDF: shoulder pitch 0.02 + 0.03 + 0.03 below the base; the upper arm
  // box (0.178 long, centred 0.074 past the pitch axis) reaches 0.015 above it.
  const double pitch_z = 0.04 + 0.02 + 0.03 + 0.03;
  const double upper_arm_top = pitch_z - (0.178 / 2 - 0.074);
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(dof());
  EXPECT_NEAR(collision_.DistanceToSafeVolume(Side::kLeft, q), upper_arm_top - 0.09, 1e-6);
  EXPECT_NEAR(collision_.DistanceToSafeVolume(Side::kRight, q), 0.015, 1e-6);
}

TEST_P(PlatformCollisionTest, HorizontalArmDistanceIsHalfTheUpperArmsWidth) {
  // Pitched forward by 90 deg the upper arm's 0.04 m side is vertical (so is
  // the wrist cylinder's 0.02 m radius): its top is 0.02 above the pitch axis.
  const Eigen::VectorXd q = Pose(dof(), 0.0, -M_PI / 2, 0.0);
  EXPECT_NEAR(collision_.DistanceToSafeVolume(Side::kLeft, q), 0.12 - 0.02 - 0.09, 1e-6);
}

TEST_P(PlatformCollisionTest, DistanceMatchesTheVolumesBottomFaceForRandomConfigurations) {
  // While every moving shape is within the volume's x and y bounds, the only
  // face it can meet is the bottom one (z = 0.09): the distance is the height
  // of the shapes' highest point below that face, or minus the deepest
  // overlap (along an axis of d, exact for a box in a box) once they cross it.
  const VolumeBox v = SafeBox(platform_);
  std::mt19937 rng(42);
  int apart = 0, penetrating = 0;
  for (Side side : kSides) {
    const ArmModel& arm = platform_.arm(side);
    for (int n = 0; n < 1000; ++n) {
      Eigen::VectorXd q(arm.dof());
      for (int i = 0; i < arm.dof(); ++i) {
        q[i] = std::uniform_real_distribution<double>(arm.lower_limits()[i],
                                                      arm.upper_limits()[i])(rng);
      }
      const ArmExtent e = Extent(platform_, side, q, 2);
      if (!e.under_footprint) continue;
      const double d = collision_.DistanceToSafeVolume(side, q);
      if (e.max_depth > 0.0) {
        ++penetrating;
        EXPECT_NEAR(d, -e.max_depth, 1e-6) << SideName(side) << " q " << q.transpose();
        EXPECT_TRUE(collision_.ArmInSafeVolume(side, q))
            << SideName(side) << " q " << q.transpose();
      } else {
        ++apart;
        EXPECT_NEAR(d, e.min_z - v.hi.z(), 1e-6) << SideName(side) << " q " << q.transpose();
      }
    }
  }
  EXPECT_GT(apart, 100);
  EXPECT_GT(penetrating, 100);
}

TEST_P(PlatformCollisionTest, InSafeVolumeIsDistanceBelowTheMargin) {
  std::mt19937 rng(7);
  const ArmModel& arm = platform_.arm(Side::kRight);
  for (int n = 0; n < 500; ++n) {
    Eigen::VectorXd q(arm.dof());
    for (int i = 0; i < arm.dof(); ++i) {
      q[i] =
          std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(rng);
    }
    const double d = collision_.DistanceToSafeVolume(Side::kRight, q);
    EXPECT_EQ(collision_.ArmInSafeVolume(Side::kRight, q), d <= 0.0) << "q " << q.transpose();
    EXPECT_EQ(collision_.ArmInSafeVolume(Side::kRight, q, 0.03), d < 0.03) << "q " << q.transpose();
  }
}

TEST_P(PlatformCollisionTest, MarginMakesANearMissCount) {
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(dof());  // 0.015 m below the volume
  EXPECT_FALSE(collision_.ArmInSafeVolume(Side::kLeft, q, 0.0));
  EXPECT_FALSE(collision_.ArmInSafeVolume(Side::kLeft, q, 0.01));
  EXPECT_TRUE(collision_.ArmInSafeVolume(Side::kLeft, q, 0.02));
}

TEST_P(PlatformCollisionTest, ArmsAtHomeDoNotCollide) {
  EXPECT_FALSE(collision_.ArmsCollide(platform_.home(Side::kLeft), platform_.home(Side::kRight)));
}

TEST_P(PlatformCollisionTest, ArmsSwungInwardCollide) {
  // Horizontal (pitch -90 deg) and yawed 90 deg towards each other: each tool
  // point passes the other arm's base.
  const Eigen::VectorXd q_left = Pose(dof(), -M_PI / 2, -M_PI / 2, 0.0);
  const Eigen::VectorXd q_right = Pose(dof(), M_PI / 2, -M_PI / 2, 0.0);
  ASSERT_GT(dMe(platform_, Side::kLeft, q_left).translation().y(), 0.1525);
  ASSERT_LT(dMe(platform_, Side::kRight, q_right).translation().y(), -0.1525);
  EXPECT_TRUE(collision_.ArmsCollide(q_left, q_right));
}

TEST_P(PlatformCollisionTest, ArmReachingAcrossHitsTheOtherArmAtHome) {
  // Only the left arm swings inward; it passes through the right shoulder.
  const Eigen::VectorXd q_left = Pose(dof(), -M_PI / 2, -M_PI / 2, 0.0);
  EXPECT_TRUE(collision_.ArmsCollide(q_left, platform_.home(Side::kRight)));
}

TEST_P(PlatformCollisionTest, MarginMakesTheArmsNearMissCount) {
  // Yawed towards each other, both arms pitch inward in 0.005 rad steps until
  // they touch; one step earlier they miss by a few millimetres.
  auto q = [&](Side side, double pitch) {
    return Pose(dof(), side == Side::kLeft ? -M_PI / 2 : M_PI / 2, pitch, 0.0);
  };
  double pitch = 0.0;
  while (pitch > -M_PI / 2 &&
         !collision_.ArmsCollide(q(Side::kLeft, pitch), q(Side::kRight, pitch))) {
    pitch -= 0.005;
  }
  ASSERT_LT(pitch, -0.1) << "the arms should touch only after pitching inward";
  ASSERT_GT(pitch, -M_PI / 2) << "the arms should touch before they are horizontal";
  const double miss = pitch + 0.005;
  EXPECT_FALSE(collision_.ArmsCollide(q(Side::kLeft, miss), q(Side::kRight, miss), 0.0));
  EXPECT_TRUE(collision_.ArmsCollide(q(Side::kLeft, miss), q(Side::kRight, miss), 0.01));
  EXPECT_FALSE(collision_.ArmsCollide(q(Side::kLeft, 0.0), q(Side::kRight, 0.0), 0.01));
}

class CollisionMeshTest : public PlatformCollisionTest {
 protected:
  /// The object frame at the left tool point at home, with e's axes.
  Eigen::Isometry3d AtLeftTool() const {
    return dMe(platform_, Side::kLeft, platform_.home(Side::kLeft));
  }
  bool Hits(int handle, const Eigen::Isometry3d& dMo, double margin_m = 0.0,
            PlatformCollision::Fingers fingers = PlatformCollision::Fingers::kInclude) {
    return collision_.ArmHitsMesh(Side::kLeft, platform_.home(Side::kLeft), handle, dMo, margin_m,
                                  fingers);
  }
};

INSTANTIATE_TEST_SUITE_P(ShippedConfigs, CollisionMeshTest,
                         ::testing::Values("platform_4dof.yaml", "platform_6dof.yaml"));

TEST_P(CollisionMeshTest, BoxWiderThanTheOpeningHitsTheFingers) {
  // The open fingers' inner faces are 0.12 m apart; a 0.13 m box crosses them.
  const int box = collision_.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.13)));
  EXPECT_TRUE(Hits(box, AtLeftTool()));
  EXPECT_FALSE(Hits(box, AtLeftTool(), 0.0, PlatformCollision::Fingers::kExclude));
}

TEST_P(CollisionMeshTest, BoxBetweenTheOpenFingersIsHitOnlyWithinTheMargin) {
  // A 0.10 m box leaves 0.01 m to each finger.
  const int box = collision_.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.10)));
  EXPECT_FALSE(Hits(box, AtLeftTool()));
  EXPECT_FALSE(Hits(box, AtLeftTool(), 0.008));
  EXPECT_TRUE(Hits(box, AtLeftTool(), 0.012));
  EXPECT_FALSE(Hits(box, AtLeftTool(), 0.012, PlatformCollision::Fingers::kExclude));
}

TEST_P(CollisionMeshTest, BoxOneMetreAwayIsNotHit) {
  const int box = collision_.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.13)));
  const Eigen::Isometry3d dMo = Eigen::Translation3d(1.0, 0.0, 0.0) * AtLeftTool();
  EXPECT_FALSE(Hits(box, dMo));
  EXPECT_FALSE(Hits(box, dMo, 0.5));
}

TEST_P(CollisionMeshTest, ArmInsideAClosedMeshIsHit) {
  // A 2 m box around the whole platform: no triangle is near the arm, but the
  // closed mesh is a solid.
  const TriangleMesh box = MakeBoxMesh(Eigen::Vector3d::Constant(2.0));
  ASSERT_TRUE(CheckMesh(box).IsClosed());
  const int handle = collision_.AddMesh(box);
  EXPECT_TRUE(Hits(handle, Eigen::Isometry3d::Identity()));
}

TEST_P(CollisionMeshTest, ArmInsideAnOpenMeshIsNotHit) {
  // The same box without one face is only a surface, 1 m from the arm.
  TriangleMesh box = MakeBoxMesh(Eigen::Vector3d::Constant(2.0));
  box.triangles.resize(box.triangles.size() - 2);
  const int handle = collision_.AddMesh(box);
  EXPECT_FALSE(Hits(handle, Eigen::Isometry3d::Identity()));
}

TEST_P(CollisionMeshTest, HandlesCountFromZero) {
  EXPECT_EQ(collision_.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.1))), 0);
  EXPECT_EQ(collision_.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.1))), 1);
}

TEST(PlatformCollisionErrorTest, UnknownMeshHandleThrowsWithTheCount) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  PlatformCollision collision(p);
  collision.AddMesh(MakeBoxMesh(Eigen::Vector3d::Constant(0.1)));
  try {
    collision.ArmHitsMesh(Side::kLeft, p.home(Side::kLeft), 3, Eigen::Isometry3d::Identity());
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_THAT(e.what(), HasSubstr("mesh handle 3 is not one AddMesh returned (there are 1"));
  }
}

TEST(PlatformCollisionErrorTest, MeshWithoutTrianglesIsRejected) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  PlatformCollision collision(p);
  TriangleMesh empty;
  empty.vertices.emplace_back(0.0, 0.0, 0.0);
  try {
    collision.AddMesh(empty);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("the mesh has no triangles"));
  }
}

TEST(PlatformCollisionErrorTest, MeshIndexOutOfRangeIsRejected) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  PlatformCollision collision(p);
  TriangleMesh mesh = MakeBoxMesh(Eigen::Vector3d::Constant(0.1));
  mesh.triangles[5][1] = 8;
  try {
    collision.AddMesh(mesh);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("triangle 5 has an index outside [0, 8)"));
  }
}

TEST(PlatformCollisionErrorTest, WrongJointCountThrowsWithBothCounts) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  const PlatformCollision collision(p);
  try {
    collision.ArmInSafeVolume(Side::kRight, Eigen::VectorXd::Zero(6));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("right arm q has 6 entries"));
    EXPECT_THAT(e.what(), HasSubstr("arm4.urdf has 4 joints"));
  }
}

TEST(PlatformCollisionErrorTest, NegativeMarginThrows) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  const PlatformCollision collision(p);
  try {
    collision.ArmsCollide(p.home(Side::kLeft), p.home(Side::kRight), -0.01);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("margin_m is -0.01"));
    EXPECT_THAT(e.what(), HasSubstr("must be finite and >= 0 m"));
  }
}

TEST(PlatformCollisionErrorTest, NonFiniteJointPositionsCountAsCollisions) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  const PlatformCollision collision(p);
  Eigen::VectorXd q = p.home(Side::kLeft);
  q[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(collision.ArmInSafeVolume(Side::kLeft, q));
  EXPECT_EQ(collision.DistanceToSafeVolume(Side::kLeft, q),
            -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(collision.ArmsCollide(q, p.home(Side::kRight)));
}

TEST(PlatformCollisionErrorTest, SafeVolumeOfMeshesOnlyIsRejected) {
  // A copy of the vehicle whose safe volume is a mesh.
  const std::string robots = std::string(AEROGRASP_DATA_DIR) + "/robots/";
  std::ifstream in(robots + "vehicle.urdf");
  std::stringstream text;
  text << in.rdbuf();
  const std::string urdf =
      std::regex_replace(text.str(), std::regex(R"(<box size="0.90 0.90 0.29"/>)"),
                         R"(<mesh filename="volume.stl"/>)");
  ASSERT_NE(urdf, text.str());
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("aerograsp_collision_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string vehicle = (dir / "vehicle.urdf").string();
  std::ofstream(vehicle) << urdf;

  PlatformConfig config = PlatformConfig::Load(Config("platform_4dof.yaml"));
  config.vehicle_urdf = vehicle;
  const Platform p = Platform::FromConfig(config);
  try {
    PlatformCollision collision(p);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("platform_4dof.yaml: vehicle.safe_volume_link"));
    EXPECT_THAT(e.what(), HasSubstr("has no box, cylinder or sphere collision shape"));
  }
  std::filesystem::remove_all(dir);
}

TEST(PlatformCollisionTest, MovedCheckerAnswersTheSame) {
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  PlatformCollision a(p);
  const double d = a.DistanceToSafeVolume(Side::kLeft, p.home(Side::kLeft));
  const PlatformCollision b = std::move(a);
  EXPECT_EQ(b.DistanceToSafeVolume(Side::kLeft, p.home(Side::kLeft)), d);
}

TEST(PlatformCollisionTest, ReportsTheTimePerQuery) {
  // Informative only (never asserted): run with --gtest_filter='*TimePerQuery*'.
  const Platform p = Platform::Load(Config("platform_4dof.yaml"));
  const PlatformCollision collision(p);
  const Eigen::VectorXd home_l = p.home(Side::kLeft), home_r = p.home(Side::kRight);
  const Eigen::VectorXd raised = Pose(4, 0.0, -1.745, -0.26);
  const Eigen::VectorXd down = Eigen::VectorXd::Zero(4);
  auto time_us = [](int n, auto&& query) {
    int hits = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) hits += query() ? 1 : 0;
    const std::chrono::duration<double, std::micro> t = std::chrono::steady_clock::now() - start;
    return std::make_pair(t.count() / n, hits);
  };
  const int n = 20000;
  const auto report = [](const char* what, std::pair<double, int> r) {
    std::cout << "  " << what << ": " << r.first << " us/query\n";
  };
  std::cout << "PlatformCollision, 4-DoF, " << n << " queries each:\n";
  report("ArmInSafeVolume at home",
         time_us(n, [&] { return collision.ArmInSafeVolume(Side::kLeft, home_l); }));
  report("ArmInSafeVolume at home, margin 0.02",
         time_us(n, [&] { return collision.ArmInSafeVolume(Side::kLeft, home_l, 0.02); }));
  report("ArmInSafeVolume raised (penetrating)",
         time_us(n, [&] { return collision.ArmInSafeVolume(Side::kLeft, raised); }));
  report("DistanceToSafeVolume at home",
         time_us(n, [&] { return collision.DistanceToSafeVolume(Side::kLeft, home_l) > 0; }));
  report("DistanceToSafeVolume straight down",
         time_us(n, [&] { return collision.DistanceToSafeVolume(Side::kLeft, down) > 0; }));
  report("DistanceToSafeVolume raised (penetrating)",
         time_us(n, [&] { return collision.DistanceToSafeVolume(Side::kLeft, raised) > 0; }));
  report("ArmsCollide at home", time_us(n, [&] { return collision.ArmsCollide(home_l, home_r); }));
  report("ArmsCollide at home, margin 0.05",
         time_us(n, [&] { return collision.ArmsCollide(home_l, home_r, 0.05); }));
}

}  // namespace
}  // namespace aerograsp
