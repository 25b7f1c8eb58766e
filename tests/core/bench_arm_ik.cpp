// The grasp-axis IK the planner runs for every contact pair, arm and object
// pose (and the mission for its followed pair every servo cycle), on both
// shipped arms: the 4-DoF arm's exact closed form against the 6-DoF arm's
// closed-form pose IK at 8 approach angles and both closing signs, each
// followed by the pre-catch pose (the nearest position solution 8 cm back).
//   build/tests/aerograsp_core_benchmarks --benchmark_filter=GraspAxis
// prints the time per grasp: one of 2,000 reachable ones, seeded near it.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "core/arm_ik.h"

namespace aerograsp {
namespace {

struct Grasp {
  Eigen::Vector3d c_b, x_b;
  Eigen::VectorXd q_seed;
};

void GraspAxis(benchmark::State& state, const std::string& urdf) {
  const ArmModel arm = ArmModel::FromUrdfFile(std::string(AEROGRASP_DATA_DIR) + "/robots/" + urdf,
                                              "base_link", "tool");
  const ArmIk ik(arm);
  std::mt19937 rng(11);
  std::vector<Grasp> grasps;
  for (int k = 0; k < 2000; ++k) {
    Eigen::VectorXd q(arm.dof());
    for (int i = 0; i < arm.dof(); ++i) {
      q[i] =
          std::uniform_real_distribution<double>(arm.lower_limits()[i], arm.upper_limits()[i])(rng);
    }
    const Eigen::Isometry3d bMe = arm.ForwardKinematics(q);
    const double depth = std::uniform_real_distribution<double>(0.0, 0.08)(rng);
    grasps.push_back({bMe.translation() - depth * bMe.linear().col(2), bMe.linear().col(0),
                      arm.Clamp(q + Eigen::VectorXd::Constant(arm.dof(), 0.05))});
  }
  std::vector<GraspAxisSolution> solutions;
  Eigen::VectorXd q_pre;
  std::size_t k = 0;
  for (auto _ : state) {
    const Grasp& g = grasps[k++ % grasps.size()];
    if (ik.SolveGraspAxis(g.c_b, g.x_b, 0.0, 0.08, g.q_seed, &solutions) > 0) {
      const Eigen::Isometry3d& bMe = solutions.front().bMe;
      benchmark::DoNotOptimize(
          ik.SolvePositionNearest(bMe.translation() - 0.08 * bMe.linear().col(2),
                                  bMe.linear().col(0), solutions.front().q, &q_pre));
    }
  }
}

void BM_GraspAxis4Dof(benchmark::State& state) { GraspAxis(state, "arm4.urdf"); }
void BM_GraspAxis6Dof(benchmark::State& state) { GraspAxis(state, "arm6.urdf"); }
BENCHMARK(BM_GraspAxis4Dof);
BENCHMARK(BM_GraspAxis6Dof);

}  // namespace
}  // namespace aerograsp
