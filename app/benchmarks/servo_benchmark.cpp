#include "app/benchmarks/servo_benchmark.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <kdl/chainiksolvervel_wdls.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <stdexcept>

#include "app/cli_checks.h"
#include "app/report/report_folder.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "core/collision.h"
#include "core/data_dir.h"
#include "core/platform.h"
#include "core/thread_clock.h"
#include "core/transforms.h"
#include "servo/arm_servo.h"
#include "servo/collision_predicate.h"
#include "servo/ik.h"

namespace aerograsp {
namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

KDL::Frame ToKdl(const Eigen::Isometry3d& aMb) {
  const Eigen::Matrix3d& R = aMb.linear();
  const Eigen::Vector3d& t = aMb.translation();
  return KDL::Frame(KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0),
                                  R(2, 1), R(2, 2)),
                    KDL::Vector(t.x(), t.y(), t.z()));
}

Eigen::Isometry3d FromKdl(const KDL::Frame& f) {
  Eigen::Isometry3d aMb = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) aMb.linear()(r, c) = f.M(r, c);
    aMb.translation()[r] = f.p[r];
  }
  return aMb;
}

/// The KDL chain of an arm, built from ArmModel's joint origins and axes (one
/// fixed segment to the first joint, then one segment per joint that ends at
/// the next joint's frame, the last at the tool point).
KDL::Chain ToKdlChain(const ArmModel& arm) {
  KDL::Chain chain;
  chain.addSegment(KDL::Segment("to_" + arm.joint_names()[0], KDL::Joint(KDL::Joint::Fixed),
                                ToKdl(arm.joint_origin(0))));
  for (int i = 0; i < arm.dof(); ++i) {
    const Eigen::Vector3d& a = arm.joint_axis(i);
    const KDL::Joint::JointType type = arm.joint_type(i) == ArmModel::JointType::kRevolute
                                           ? KDL::Joint::RotAxis
                                           : KDL::Joint::TransAxis;
    const Eigen::Isometry3d& next = i + 1 < arm.dof() ? arm.joint_origin(i + 1) : arm.tip_offset();
    chain.addSegment(KDL::Segment(arm.joint_names()[i],
                                  KDL::Joint(arm.joint_names()[i], KDL::Vector::Zero(),
                                             KDL::Vector(a.x(), a.y(), a.z()), type),
                                  ToKdl(next)));
  }
  return chain;
}

KDL::JntArray ToJnt(const Eigen::VectorXd& q) {
  KDL::JntArray j(q.size());
  j.data = q;
  return j;
}

/// One arm's KDL solvers: ChainIkSolverPos_NR_JL (KDL's defaults: 100
/// iterations, eps 1e-6) over ChainIkSolverVel_wdls (eps 1e-5, 150 sweeps,
/// lambda 0). KDL 1.5's wdls fails an Eigen assertion on chains with fewer than
/// 6 joints (orocos_kinematics_dynamics issue 403), so those get KDL's SVD
/// pseudo-inverse ChainIkSolverVel_pinv instead.
struct KdlArm {
  KDL::Chain chain;
  KDL::JntArray q_min, q_max;
  std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk;
  std::unique_ptr<KDL::ChainIkSolverVel> ik_vel;
  std::unique_ptr<KDL::ChainIkSolverPos_NR_JL> ik;
  std::string velocity_solver;

  explicit KdlArm(const ArmModel& arm)
      : chain(ToKdlChain(arm)), q_min(ToJnt(arm.lower_limits())), q_max(ToJnt(arm.upper_limits())) {
    fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(chain);
    if (chain.getNrOfJoints() >= 6) {
      ik_vel = std::make_unique<KDL::ChainIkSolverVel_wdls>(chain);
      velocity_solver = "ChainIkSolverVel_wdls";
    } else {
      ik_vel = std::make_unique<KDL::ChainIkSolverVel_pinv>(chain);
      velocity_solver = "ChainIkSolverVel_pinv (wdls asserts below 6 joints, KDL issue 403)";
    }
    ik = std::make_unique<KDL::ChainIkSolverPos_NR_JL>(chain, q_min, q_max, *fk, *ik_vel);
  }
};

struct Pair {
  Eigen::VectorXd q[2];
};

/// Random joint vectors for both arms with neither arm within margin_m of the
/// safe volume and the arms apart by margin_m (up to 1000 draws).
Pair RandomAllowedPair(const Platform& platform, const PlatformCollision& collision,
                       double margin_m, std::mt19937* rng) {
  Pair p;
  for (int attempt = 0; attempt < 1000; ++attempt) {
    p.q[0] = DrawJointsWithinLimits(platform.arm(Side::kLeft), rng);
    p.q[1] = DrawJointsWithinLimits(platform.arm(Side::kRight), rng);
    if (!collision.ArmInSafeVolume(Side::kLeft, p.q[0], margin_m) &&
        !collision.ArmInSafeVolume(Side::kRight, p.q[1], margin_m) &&
        !collision.ArmsCollide(p.q[0], p.q[1], margin_m)) {
      return p;
    }
  }
  throw std::runtime_error(platform.config().source +
                           ": no allowed joint configuration in 1000 random draws");
}

/// Both arms' joints and servos; each servo's forbidden predicate is the safe
/// volume and the other arm at its joints q[other], and they share a right of way.
struct DualServo {
  Eigen::VectorXd q[2];
  RightOfWay right_of_way;
  std::unique_ptr<ArmServo> servo[2];

  /// Fresh servos (no goal, no motion history) with the arms at `start`.
  void Restart(const Platform& platform, const PlatformCollision& collision, double margin_m,
               const Eigen::VectorXd (&start)[2]) {
    right_of_way = RightOfWay{};
    for (int a = 0; a < 2; ++a) {
      q[a] = start[a];
      // Via configurations: hanging straight down, and home.
      const ArmModel& arm = platform.arm(kSides[a]);
      ServoConfig config;
      config.via_rad = {arm.Clamp(Eigen::VectorXd::Zero(arm.dof())), platform.home(kSides[a])};
      servo[a] = std::make_unique<ArmServo>(
          arm, config, MakeCollisionPredicate(collision, kSides[a], margin_m, &q[1 - a]),
          &right_of_way, a);
    }
  }
};

/// Throws unless the KDL chain's forward kinematics matches ArmModel's.
void CheckKdlChain(const ArmModel& arm, KdlArm* kdl, std::mt19937* rng) {
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = DrawJointsWithinLimits(arm, rng);
    KDL::Frame f;
    kdl->fk->JntToCart(ToJnt(q), f);
    const PoseError d = ComparePoses(FromKdl(f), arm.ForwardKinematics(q));
    if (d.translation_m > 1e-9 || d.rotation_rad > 1e-9) {
      throw std::logic_error(
          arm.source() + ": the KDL chain's forward kinematics differs from the model's by " +
          std::to_string(d.translation_m) + " m, " + std::to_string(d.rotation_rad) + " rad");
    }
  }
}

/// Why arm a did not converge in a trial, from the end state of both arms: its
/// last status, whether it was still moving, and what the other arm's joints
/// q[1 - a] block (the sampled goal q_goal[a], or the servo's own joint goal),
/// and whether the other arm reached its own target.
std::string ClassifyFailure(const PlatformCollision& collision, int a, ServoStatus status,
                            const ServoCommand& cmd, int still_steps, const Eigen::VectorXd (&q)[2],
                            const Eigen::VectorXd& q_goal_sampled, bool other_done,
                            double margin_m) {
  const auto collide = [&](const Eigen::VectorXd& q_a, const Eigen::VectorXd& q_b) {
    return a == 0 ? collision.ArmsCollide(q_a, q_b, margin_m)
                  : collision.ArmsCollide(q_b, q_a, margin_m);
  };
  std::string why = ServoStatusName(status);
  if (status == ServoStatus::kMoving) why = still_steps > 50 ? "stalled" : "still moving";
  const bool has_goal = cmd.q_goal_rad.size() == q_goal_sampled.size();
  if (!has_goal) {
    why += ", no joint goal";
  } else if (collide(cmd.q_goal_rad, q[1 - a])) {
    why += ", its joint goal blocked by the other arm";
  }
  if (collide(q_goal_sampled, q[1 - a])) why += ", the sampled goal blocked by the other arm";
  return why + (other_done ? "; the other arm at its target" : "; the other arm not at its target");
}

struct Entries {
  long commands = 0;
  long safe_volume = 0;  ///< commands whose target puts an arm in the safe volume (margin 0)
  long arms = 0;         ///< commands whose targets make the arms touch

  void Check(const PlatformCollision& collision, const Eigen::VectorXd (&q)[2]) {
    for (int a = 0; a < 2; ++a) {
      ++commands;
      if (collision.ArmInSafeVolume(kSides[a], q[a], 0.0)) ++safe_volume;
    }
    if (collision.ArmsCollide(q[0], q[1], 0.0)) ++arms;
  }
};

nlohmann::json RunConfig(const std::string& config_path, const ServoBenchmarkOptions& options,
                         std::ostream& out) {
  const Platform platform = Platform::Load(config_path);
  const PlatformCollision collision(platform);
  const std::string name = platform.config().arm_type;
  const int dof = platform.arm(Side::kLeft).dof();
  // A 4-DoF arm meets position and approach axis; its roll is reported apart.
  PoseTolerance tolerance;
  if (dof < 6) tolerance.roll_rad = M_PI;
  PoseTolerance with_roll;
  std::mt19937 rng(options.seed);
  const int steps = static_cast<int>(std::ceil(options.trial_timeout_s / options.dt_s));

  // Convergence trials: both arms at once, targets the FK of allowed random
  // joints; even trials start from home, odd ones from allowed random joints.
  DualServo dual;
  KdlArm kdl[2] = {KdlArm(platform.arm(Side::kLeft)), KdlArm(platform.arm(Side::kRight))};
  for (int a = 0; a < 2; ++a) CheckKdlChain(platform.arm(kSides[a]), &kdl[a], &rng);
  std::vector<double> step_us, step_cpu_us, kdl_solve_us, kdl_step_us;
  std::vector<double> iterations;
  std::map<std::string, int> failures, failure_classes;
  int converged[2] = {0, 0}, converged_with_roll = 0, kdl_converged = 0, targets = 0;
  Entries entries;
  fmt::print(out, "[{}] {} convergence trials (2 targets each) from {}\n", name, options.trials,
             config_path);
  for (int trial = 0; trial < options.trials; ++trial) {
    if (options.trials >= 10 && trial % (options.trials / 10) == 0 && trial > 0) {
      fmt::print(out, "[{}]   {}/{} trials\n", name, trial, options.trials);
      out.flush();
    }
    const Pair goal = RandomAllowedPair(platform, collision, options.margin_m, &rng);
    const Pair start = trial % 2 == 0
                           ? Pair{{platform.home(Side::kLeft), platform.home(Side::kRight)}}
                           : RandomAllowedPair(platform, collision, options.margin_m, &rng);
    Eigen::Isometry3d bMg[2];
    int done_at[2] = {-1, -1};
    bool roll_met[2] = {false, false};
    ServoStatus last_status[2] = {ServoStatus::kMoving, ServoStatus::kMoving};
    ServoCommand last_cmd[2];
    int still_steps[2] = {0, 0};
    dual.Restart(platform, collision, options.margin_m, start.q);
    for (int a = 0; a < 2; ++a) bMg[a] = platform.arm(kSides[a]).ForwardKinematics(goal.q[a]);
    for (int k = 0; k < steps && (done_at[0] < 0 || done_at[1] < 0); ++k) {
      const double t = k * options.dt_s;
      ServoCommand cmd[2];
      const Clock::time_point t0 = Clock::now();
      const double cpu0_ms = ThreadCpuMs();
      for (int a = 0; a < 2; ++a) {
        dual.servo[a]->SetTarget(bMg[a], t);
        last_status[a] = dual.servo[a]->Step(dual.q[a], t, options.dt_s, &cmd[a]);
      }
      step_cpu_us.push_back(1e3 * (ThreadCpuMs() - cpu0_ms));
      step_us.push_back(MicrosecondsSince(t0));
      for (int a = 0; a < 2; ++a) {
        if (done_at[a] < 0 && last_status[a] == ServoStatus::kMoving &&
            tolerance.Met(cmd[a].error)) {
          done_at[a] = k;
          roll_met[a] = with_roll.Met(cmd[a].error);
        }
        dual.q[a] = cmd[a].q_target_rad;  // an ideal arm follows its targets
        still_steps[a] = cmd[a].dq_rad_s.cwiseAbs().maxCoeff() < 1e-3 ? still_steps[a] + 1 : 0;
        last_cmd[a] = cmd[a];
      }
      entries.Check(collision, dual.q);
    }
    for (int a = 0; a < 2; ++a) {
      ++targets;
      if (done_at[a] >= 0) {
        ++converged[trial % 2];
        converged_with_roll += roll_met[a];
        iterations.push_back(done_at[a]);
      } else {
        ++failures[ServoStatusName(last_status[a])];
        ++failure_classes[ClassifyFailure(collision, a, last_status[a], last_cmd[a], still_steps[a],
                                          dual.q, goal.q[a], done_at[1 - a] >= 0,
                                          options.margin_m)];
      }
      // The same target by KDL from the same start.
      KdlArm& solver = kdl[a];
      KDL::JntArray q_out(dof);
      Clock::time_point t0 = Clock::now();
      const int rc = solver.ik->CartToJnt(ToJnt(start.q[a]), ToKdl(bMg[a]), q_out);
      kdl_solve_us.push_back(MicrosecondsSince(t0));
      KDL::Frame f;
      solver.fk->JntToCart(q_out, f);
      const ApproachError kdl_error = ComputeApproachError(FromKdl(f), bMg[a]);
      if (rc >= 0 && tolerance.Met(kdl_error)) ++kdl_converged;
    }
    // One Newton step of KDL for both arms (FK + wdls velocity solve), the
    // counterpart of one servo step.
    const Clock::time_point t0 = Clock::now();
    for (int a = 0; a < 2; ++a) {
      KDL::Frame f;
      KDL::JntArray dq(dof);
      kdl[a].fk->JntToCart(ToJnt(start.q[a]), f);
      kdl[a].ik_vel->CartToJnt(ToJnt(start.q[a]), KDL::diff(f, ToKdl(bMg[a])), dq);
    }
    kdl_step_us.push_back(MicrosecondsSince(t0));
  }

  nlohmann::json result;
  const int per_start = options.trials;  // targets from home (even trials) and from random starts
  result["config"] = config_path;
  result["targets"] = targets;
  result["convergence_rate"] = targets ? double(converged[0] + converged[1]) / targets : 0.0;
  result["convergence_rate_from_home"] =
      per_start ? double(converged[0]) / (2 * ((per_start + 1) / 2)) : 0.0;
  result["convergence_rate_from_random"] =
      per_start / 2 ? double(converged[1]) / (2 * (per_start / 2)) : 0.0;
  result["convergence_rate_with_roll"] = targets ? double(converged_with_roll) / targets : 0.0;
  result["median_iterations"] = Percentile(iterations, 0.5);
  result["p95_iterations"] = Percentile(iterations, 0.95);
  result["step_us_both_arms"] = Percentile(step_us, 0.5);
  result["step_us_both_arms_p99"] = Percentile(step_us, 0.99);
  result["step_us_both_arms_max"] =
      step_us.empty() ? 0.0 : *std::max_element(step_us.begin(), step_us.end());
  result["step_cpu_us_both_arms"] = Percentile(step_cpu_us, 0.5);
  result["step_cpu_us_both_arms_p99"] = Percentile(step_cpu_us, 0.99);
  result["step_cpu_us_both_arms_max"] =
      step_cpu_us.empty() ? 0.0 : *std::max_element(step_cpu_us.begin(), step_cpu_us.end());
  result["safe_volume_entries"] = entries.safe_volume;
  result["arm_collision_entries"] = entries.arms;
  result["commands"] = entries.commands;
  result["failures"] = failures;
  result["failure_classes"] = failure_classes;
  result["kdl_convergence_rate"] = targets ? double(kdl_converged) / targets : 0.0;
  result["kdl_solve_us"] = Percentile(kdl_solve_us, 0.5);
  result["kdl_step_us"] = Percentile(kdl_step_us, 0.5);
  result["kdl_velocity_solver"] = kdl[0].velocity_solver;
  result["tolerance"] = {{"position_m", tolerance.position_m},
                         {"approach_rad", tolerance.approach_rad},
                         {"roll_rad", tolerance.roll_rad}};

  fmt::print(out,
             "[{}] convergence {:.2f} % of {} targets (from home {:.2f} %, from random {:.2f} %; "
             "with roll {:.2f} %), median {} iterations (p95 {})\n",
             name, 100.0 * result["convergence_rate"].get<double>(), targets,
             100.0 * result["convergence_rate_from_home"].get<double>(),
             100.0 * result["convergence_rate_from_random"].get<double>(),
             100.0 * result["convergence_rate_with_roll"].get<double>(),
             result["median_iterations"].get<double>(), result["p95_iterations"].get<double>());
  for (const auto& [status, count] : failures)
    fmt::print(out, "[{}]   not converged, last status '{}': {}\n", name, status, count);
  for (const auto& [why, count] : failure_classes)
    fmt::print(out, "[{}]     {}: {}\n", name, why, count);
  fmt::print(out, "[{}] step both arms: median {:.1f} us, p99 {:.1f} us, max {:.1f} us\n", name,
             result["step_us_both_arms"].get<double>(),
             result["step_us_both_arms_p99"].get<double>(),
             result["step_us_both_arms_max"].get<double>());
  fmt::print(out,
             "[{}] step both arms, thread CPU: median {:.1f} us, p99 {:.1f} us, max {:.1f} us\n",
             name, result["step_cpu_us_both_arms"].get<double>(),
             result["step_cpu_us_both_arms_p99"].get<double>(),
             result["step_cpu_us_both_arms_max"].get<double>());
  fmt::print(out, "[{}] safe-volume entries {} and arm contacts {} in {} commands\n", name,
             entries.safe_volume, entries.arms, entries.commands);
  fmt::print(out,
             "[{}] KDL NR_JL + {}: convergence {:.2f} %, solve median {:.1f} us per arm, "
             "one Newton step both arms {:.1f} us\n",
             name, kdl[0].velocity_solver, 100.0 * result["kdl_convergence_rate"].get<double>(),
             result["kdl_solve_us"].get<double>(), result["kdl_step_us"].get<double>());

  // Safety run: any target (the FK of random joints, also inside the safe volume
  // or the other arm), switched at half time, from allowed random starts.
  if (options.safety_trials > 0) {
    Entries safety;
    std::map<std::string, long> statuses;
    const int safety_steps = static_cast<int>(std::ceil(options.safety_trial_s / options.dt_s));
    fmt::print(out, "[{}] {} safety trials of {} s\n", name, options.safety_trials,
               options.safety_trial_s);
    for (int trial = 0; trial < options.safety_trials; ++trial) {
      if (options.safety_trials >= 10 && trial % (options.safety_trials / 10) == 0 && trial > 0) {
        fmt::print(out, "[{}]   {}/{} safety trials, {} entries so far\n", name, trial,
                   options.safety_trials, safety.safe_volume);
        out.flush();
      }
      const Pair start = RandomAllowedPair(platform, collision, options.margin_m, &rng);
      Eigen::Isometry3d bMg[2][2];
      dual.Restart(platform, collision, options.margin_m, start.q);
      for (int a = 0; a < 2; ++a) {
        for (int h = 0; h < 2; ++h) {
          bMg[h][a] = platform.arm(kSides[a]).ForwardKinematics(
              DrawJointsWithinLimits(platform.arm(kSides[a]), &rng));
        }
      }
      for (int k = 0; k < safety_steps; ++k) {
        const double t = k * options.dt_s;
        const int half = k < safety_steps / 2 ? 0 : 1;
        for (int a = 0; a < 2; ++a) {
          ServoCommand cmd;
          dual.servo[a]->SetTarget(bMg[half][a], t, k == safety_steps / 2);
          ++statuses[ServoStatusName(dual.servo[a]->Step(dual.q[a], t, options.dt_s, &cmd))];
          dual.q[a] = cmd.q_target_rad;
        }
        safety.Check(collision, dual.q);
      }
    }
    result["safety"] = {{"trials", options.safety_trials},
                        {"commands", safety.commands},
                        {"safe_volume_entries", safety.safe_volume},
                        {"arm_collision_entries", safety.arms},
                        {"statuses", statuses}};
    fmt::print(out, "[{}] safety: {} safe-volume entries and {} arm contacts in {} commands\n",
               name, safety.safe_volume, safety.arms, safety.commands);
  }
  return result;
}

}  // namespace

void AddServoBenchmarkOptions(CLI::App* cmd, ServoBenchmarkOptions* options) {
  cmd->add_option("--out", options->out_dir, "Folder for summary.json")->required();
  cmd->add_flag("--overwrite", options->overwrite, "Replace a report already in --out");
  cmd->add_option("--config", options->configs,
                  "Platform YAML (repeatable; default: platform_4dof.yaml and platform_6dof.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--trials", options->trials, "Dual-arm trials per config (2 targets each)")
      ->capture_default_str()
      ->check(cli::Range(1, 10000000));
  cmd->add_option("--safety-trials", options->safety_trials,
                  "Random trials counting safe-volume entries (0 skips)")
      ->capture_default_str()
      ->check(cli::Range(0, 10000000));
  cmd->add_option("--seed", options->seed, "Seed of targets and starts")
      ->capture_default_str()
      ->check(cli::Seed());
  cmd->add_option("--margin", options->margin_m,
                  "Clearance kept from the safe volume and the other arm (m)")
      ->capture_default_str()
      ->check(cli::Range(0.0, 0.2));
}

void RunServoBenchmark(const ServoBenchmarkOptions& options, std::ostream& out) {
  ReportFolder folder(options.out_dir, options.overwrite);
  std::vector<std::string> configs = options.configs;
  if (configs.empty()) {
    configs = {DataPath("config/platform_4dof.yaml"), DataPath("config/platform_6dof.yaml")};
  }
  nlohmann::json summary;
  summary["trials"] = options.trials;
  summary["safety_trials"] = options.safety_trials;
  summary["seed"] = options.seed;
  summary["dt_s"] = options.dt_s;
  summary["trial_timeout_s"] = options.trial_timeout_s;
  summary["margin_m"] = options.margin_m;
  for (const std::string& config : configs) {
    nlohmann::json arm = RunConfig(config, options, out);
    summary["arms"][Platform::Load(config).config().arm_type] = arm;
  }
  const std::string path = WriteSummaryFile(folder.path(), summary.dump(2));
  folder.Commit();
  fmt::print(out, "wrote {}\n", folder.Final(path));
}

}  // namespace aerograsp
