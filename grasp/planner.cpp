#include "grasp/planner.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "core/collision.h"
#include "core/config.h"

namespace aerograsp {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

/// Best first; ties broken by the pair indices so the order is deterministic.
bool Better(const DualGrasp& a, const DualGrasp& b) {
  if (a.score != b.score) return a.score > b.score;
  if (a.left.pair != b.left.pair) return a.left.pair < b.left.pair;
  return a.right.pair < b.right.pair;
}

/// Plan's order of classes: robust and clear of edges 0, robust 1, clear of edges 2, neither 3.
int RankClass(const DualGrasp& d) { return (d.robust ? 0 : 2) + (d.clear_of_edges ? 0 : 1); }

IkOptions GraspAxisIkOptions(const GraspPlannerConfig& config) {
  IkOptions options;
  options.approach_samples = config.grasp_axis_approaches;
  options.depth_samples = config.grasp_axis_depths;
  return options;
}

}  // namespace

const char* InfeasibilityName(Infeasibility why) {
  switch (why) {
    case Infeasibility::kNone:
      return "feasible";
    case Infeasibility::kUnreachable:
      return "unreachable";
    case Infeasibility::kSafeVolume:
      return "safe volume";
    case Infeasibility::kObjectCollision:
      return "hits the object";
    case Infeasibility::kPrecatchUnreachable:
      return "pre-catch unreachable";
    case Infeasibility::kPrecatchCollision:
      return "pre-catch collides";
  }
  return "?";
}

std::string DescribeReasons(const ArmStats& stats) {
  std::string out;
  for (int r = 1; r < 6; ++r) {
    if (stats.by_reason[r] == 0) continue;
    out += (out.empty() ? "" : ", ") + std::to_string(stats.by_reason[r]) + " " +
           InfeasibilityName(static_cast<Infeasibility>(r));
  }
  return out;
}

void GraspPlannerConfig::Validate(const std::string& source, const std::string& prefix) const {
  contacts.Validate(source, prefix + "contacts.");
  friction.Validate(source, prefix + "friction.");
  CheckRange(source, prefix + "depth_min_m", depth_min_m, -0.02, 0.2, "m");
  CheckRange(source, prefix + "depth_max_m", depth_max_m, depth_min_m, kLongestFingerM, "m");
  CheckRange(source, prefix + "precatch_distance_m", precatch_distance_m, 0.0, 0.3, "m");
  CheckRange(source, prefix + "safe_volume_margin_m", safe_volume_margin_m, 0.0, 0.1, "m");
  CheckRange(source, prefix + "arms_margin_m", arms_margin_m, 0.0, 0.1, "m");
  CheckRange(source, prefix + "object_margin_m", object_margin_m, 0.0, 0.05, "m");
  CheckRange(source, prefix + "support_directions", support_directions, 12, 4096, "");
  CheckRange(source, prefix + "exact_top_k", exact_top_k, 0, 10000, "");
  CheckRange(source, prefix + "quality_weight", quality_weight, 0.0, 100.0, "");
  CheckRange(source, prefix + "task_weight", task_weight, 0.0, 100.0, "");
  CheckRange(source, prefix + "cost_weight_per_rad", cost_weight_per_rad, 0.0, 10.0, "");
  CheckRange(source, prefix + "reach_margin_m", reach_margin_m, 0.0, 0.1, "m");
  CheckRange(source, prefix + "robust_branch_rad", robust_branch_rad, 0.0, 6.3, "rad");
  CheckRange(source, prefix + "wrist_margin_rad", wrist_margin_rad, 0.0, 1.5, "rad");
  CheckRange(source, prefix + "edge_margin_m", edge_margin_m, 0.0, 0.05, "m");
  CheckRange(source, prefix + "grasp_axis_approaches", grasp_axis_approaches, 1, 64, "");
  CheckRange(source, prefix + "grasp_axis_depths", grasp_axis_depths, 1, 16, "");
}

void GraspPlannerConfig::CheckFingers(const GripperConfig& gripper, const std::string& source,
                                      const std::string& prefix) const {
  CheckRange(source, prefix + "depth_max_m", depth_max_m, depth_min_m, gripper.finger_length_m,
             "m (the gripper's finger length)");
}

GraspPlanner::GraspPlanner(const Platform& platform, GraspObject object, ContactSet contacts,
                           const GraspPlannerConfig& config)
    : dMb_{platform.dMb(Side::kLeft), platform.dMb(Side::kRight)},
      object_(std::move(object)),
      contacts_(std::move(contacts)),
      config_(config),
      collision_(std::make_unique<PlatformCollision>(platform)),
      ik_{ArmIk(platform.arm(Side::kLeft), GraspAxisIkOptions(config)),
          ArmIk(platform.arm(Side::kRight), GraspAxisIkOptions(config))} {
  config_.Validate("grasp planner config", "planner.");
  config_.CheckFingers(platform.config().gripper, "grasp planner config", "planner.");
  if (object_.mesh_o.triangles.empty()) {
    throw std::invalid_argument("GraspPlanner: object '" + object_.name + "' has an empty mesh");
  }
  mesh_handle_ = collision_->AddMesh(object_.mesh_o);
  torque_scale_m_ = 0.0;
  for (const Eigen::Vector3d& v : object_.mesh_o.vertices) {
    torque_scale_m_ = std::max(torque_scale_m_, (v - object_.com_o).norm());
  }
  torque_scale_m_ = std::max(torque_scale_m_, 1e-3);
  const std::vector<Wrench> directions = SupportDirections(config_.support_directions);
  directions_ = static_cast<int>(directions.size());
  wrenches_.resize(contacts_.pairs.size());
  support_.resize(contacts_.pairs.size() * directions.size());
  for (std::size_t i = 0; i < contacts_.pairs.size(); ++i) {
    const ContactPair& p = contacts_.pairs[i];
    AppendContactWrenches(p.a.p_o, -p.a.n_o, object_.com_o, torque_scale_m_, config_.friction,
                          &wrenches_[i]);
    AppendContactWrenches(p.b.p_o, -p.b.n_o, object_.com_o, torque_scale_m_, config_.friction,
                          &wrenches_[i]);
    const std::vector<float> table = SupportTable(wrenches_[i], directions);
    std::copy(table.begin(), table.end(), support_.begin() + i * directions.size());
    clear_of_edges_.push_back(ContactsClearOfEdges(object_.mesh_o, p, config_.edge_margin_m));
  }
}

GraspPlanner::~GraspPlanner() = default;

WrenchQuality GraspPlanner::ExactQuality(int pair, int other) const {
  const std::pair<int, int> key(pair, other);
  {
    std::lock_guard<std::mutex> lock(quality_mutex_);
    const auto it = quality_cache_.find(key);
    if (it != quality_cache_.end()) return it->second;
  }
  std::vector<Wrench> w = wrenches_.at(pair);
  if (other >= 0) {
    const std::vector<Wrench>& b = wrenches_.at(other);
    w.insert(w.end(), b.begin(), b.end());
  }
  const WrenchQuality q = ComputeWrenchQuality(w);
  std::lock_guard<std::mutex> lock(quality_mutex_);
  quality_cache_.emplace(key, q);
  return q;
}

bool GraspPlanner::EvaluateArm(Side side, int pair, const Eigen::Isometry3d& dMo,
                               const Eigen::VectorXd& q_current, ArmGrasp* out,
                               Infeasibility* why) const {
  return Evaluate(side, pair, dMo, q_current, false, out, why);
}

bool GraspPlanner::EvaluateArmWithMargin(Side side, int pair, const Eigen::Isometry3d& dMo,
                                         const Eigen::VectorXd& q_current, ArmGrasp* out,
                                         Infeasibility* why) const {
  return Evaluate(side, pair, dMo, q_current, config_.wrist_margin_rad > 0.0, out, why);
}

bool GraspPlanner::Evaluate(Side side, int pair, const Eigen::Isometry3d& dMo,
                            const Eigen::VectorXd& q_current, bool margin_first, ArmGrasp* out,
                            Infeasibility* why) const {
  const int s = static_cast<int>(side);
  const ArmIk& ik = ik_[s];
  const ContactPair& p = contacts_.pairs.at(pair);
  const Eigen::Isometry3d bMo = dMb_[s].inverse() * dMo;
  const Eigen::Vector3d c_b = bMo * p.center_o();
  const Eigen::Vector3d x_b = bMo.linear() * p.closing_axis_o();
  std::vector<GraspAxisSolution> solutions;
  *why = Infeasibility::kUnreachable;
  if (ik.SolveGraspAxis(c_b, x_b, config_.depth_min_m, config_.depth_max_m, q_current,
                        &solutions) == 0) {
    return false;
  }
  if (margin_first) {
    std::stable_partition(solutions.begin(), solutions.end(), [&](const GraspAxisSolution& sol) {
      return ik.WristMargin(sol.q) >= config_.wrist_margin_rad;
    });
  }
  // The furthest any solution got, so the reason names the real obstacle.
  Infeasibility furthest = Infeasibility::kSafeVolume;
  auto note = [&furthest](Infeasibility w) { furthest = std::max(furthest, w); };
  Eigen::VectorXd q_pre;
  for (const GraspAxisSolution& sol : solutions) {
    if (collision_->ArmInSafeVolume(side, sol.q, config_.safe_volume_margin_m)) {
      note(Infeasibility::kSafeVolume);
      continue;
    }
    if (collision_->ArmHitsMesh(side, sol.q, mesh_handle_, dMo, config_.object_margin_m,
                                PlatformCollision::Fingers::kInclude)) {
      note(Infeasibility::kObjectCollision);
      continue;
    }
    // Pre-catch: the tool point back along the approach. A 4-DoF arm reaches a
    // point with the approach its position dictates, so the pre-catch approach
    // may differ slightly from the grasp's; the roll keeps the closing axis.
    const Eigen::Vector3d z_b = sol.bMe.linear().col(2);
    const Eigen::Vector3d p_pre_b = sol.bMe.translation() - config_.precatch_distance_m * z_b;
    if (!ik.SolvePositionNearest(p_pre_b, sol.bMe.linear().col(0), sol.q, &q_pre)) {
      note(Infeasibility::kPrecatchUnreachable);
      continue;
    }
    if (collision_->ArmInSafeVolume(side, q_pre, config_.safe_volume_margin_m) ||
        collision_->ArmHitsMesh(side, q_pre, mesh_handle_, dMo, config_.object_margin_m,
                                PlatformCollision::Fingers::kInclude)) {
      note(Infeasibility::kPrecatchCollision);
      continue;
    }
    out->pair = pair;
    out->side = side;
    out->clear_of_edges = clear_of_edges_[pair];
    out->q_grasp = sol.q;
    out->q_precatch = q_pre;
    out->dMg = dMb_[s] * sol.bMe;
    out->dMp = dMb_[s] * ik.model().ForwardKinematics(q_pre);
    out->depth_m = sol.depth_m;
    out->cost_rad = (sol.q - q_current).norm();
    *why = Infeasibility::kNone;
    return true;
  }
  *why = furthest;
  return false;
}

bool GraspPlanner::Robust(Side side, const ArmGrasp& g, const Eigen::Isometry3d& dMo,
                          const Eigen::VectorXd& q) const {
  if (ik_[static_cast<int>(side)].WristMargin(g.q_grasp) < config_.wrist_margin_rad) return false;
  if (config_.reach_margin_m <= 0.0) return true;
  const bool same_branch = config_.robust_branch_rad > 0.0;
  ArmGrasp moved_grasp;
  Infeasibility why;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      Eigen::Isometry3d moved = dMo;
      moved.translation()[axis] += sign * config_.reach_margin_m;
      if (!EvaluateArm(side, g.pair, moved, same_branch ? g.q_grasp : q, &moved_grasp, &why) ||
          (same_branch &&
           (moved_grasp.q_grasp - g.q_grasp).cwiseAbs().maxCoeff() > config_.robust_branch_rad)) {
        return false;
      }
    }
  }
  return true;
}

void GraspPlanner::EvaluateArms(const PlanQuery& query, bool robust, PlanResult* result) const {
  const int n = static_cast<int>(contacts_.pairs.size());
  for (Side side : kSides) {
    const Eigen::VectorXd& q = side == Side::kLeft ? query.q_left : query.q_right;
    std::vector<ArmGrasp>& feasible = side == Side::kLeft ? result->left : result->right;
    ArmStats& stats = side == Side::kLeft ? result->left_stats : result->right_stats;
    const Clock::time_point t0 = Clock::now();
    ArmGrasp grasp;
    Infeasibility why;
    for (int i = 0; i < n; ++i) {
      ++stats.candidates;
      if (EvaluateArmWithMargin(side, i, query.dMo, q, &grasp, &why)) {
        if (robust) grasp.robust = Robust(side, grasp, query.dMo, q);
        feasible.push_back(grasp);
      }
      ++stats.by_reason[static_cast<int>(why)];
    }
    stats.feasible = static_cast<int>(feasible.size());
    stats.seconds = Seconds(t0);
  }
}

std::vector<DualGrasp> GraspPlanner::Combine(const PlanQuery& query, const PlanResult& arms,
                                             PairStats* ps) const {
  const Eigen::Vector3d g_o = query.dMo.linear().transpose() * query.gravity_d.normalized();
  std::vector<DualGrasp> candidates;
  const Clock::time_point t0 = Clock::now();
  for (const ArmGrasp& l : arms.left) {
    const float* hl = &support_[static_cast<std::size_t>(l.pair) * directions_];
    const Eigen::Vector3d cl = contacts_.pairs[l.pair].center_o();
    for (const ArmGrasp& r : arms.right) {
      if (l.pair == r.pair) continue;
      ++ps->considered;
      const double eps = EpsilonUpperBound(
          hl, &support_[static_cast<std::size_t>(r.pair) * directions_], directions_);
      if (eps <= 0.0) {
        ++ps->no_force_closure;
        continue;
      }
      const WeightShare share = ComputeWeightShare(cl, contacts_.pairs[r.pair].center_o(),
                                                   object_.com_o, g_o, torque_scale_m_);
      DualGrasp d;
      d.left = l;
      d.right = r;
      d.robust = l.robust && r.robust;
      d.clear_of_edges = l.clear_of_edges && r.clear_of_edges;
      d.epsilon = eps;
      d.task = share.term;
      d.left_share = share.left_share;
      d.score = config_.quality_weight * eps + config_.task_weight * share.term -
                config_.cost_weight_per_rad * (l.cost_rad + r.cost_rad);
      candidates.push_back(std::move(d));
    }
  }
  ps->quality_seconds = Seconds(t0);
  std::sort(candidates.begin(), candidates.end(), Better);
  return candidates;
}

bool GraspPlanner::ArmsClear(const DualGrasp& d) const {
  return !collision_->ArmsCollide(d.left.q_grasp, d.right.q_grasp, config_.arms_margin_m) &&
         !collision_->ArmsCollide(d.left.q_precatch, d.right.q_precatch, config_.arms_margin_m);
}

void GraspPlanner::SetExactEpsilon(const WrenchQuality& q, DualGrasp* d) const {
  d->score -= config_.quality_weight * (d->epsilon - q.epsilon);
  d->epsilon = q.epsilon;
  d->epsilon_exact = true;
}

PlanResult GraspPlanner::Plan(const PlanQuery& query) const {
  PlanResult result;
  EvaluateArms(query, /*robust=*/true, &result);
  PairStats& ps = result.pair_stats;
  std::vector<DualGrasp> candidates = Combine(query, result, &ps);

  // The two arms must clear each other at the grasp and at the pre-catch.
  Clock::time_point t0 = Clock::now();
  for (DualGrasp& d : candidates) {
    if (!ArmsClear(d)) {
      ++ps.arms_collide;
      continue;
    }
    result.ranked.push_back(std::move(d));
  }
  ps.collision_seconds = Seconds(t0);
  // Robust grasps first, and among each those clear of edges (RankClass), so
  // that the exact epsilon goes to the ones that will rank first.
  const auto put_first = [](std::vector<DualGrasp>* ranked) {
    std::stable_sort(ranked->begin(), ranked->end(), [](const DualGrasp& a, const DualGrasp& b) {
      return RankClass(a) < RankClass(b);
    });
  };
  put_first(&result.ranked);

  // Exact epsilon for the best few; those without force closure are dropped.
  t0 = Clock::now();
  std::vector<DualGrasp> top;
  std::size_t next = 0;
  while (static_cast<int>(top.size()) < config_.exact_top_k && next < result.ranked.size()) {
    DualGrasp d = result.ranked[next++];
    const WrenchQuality q = ExactQuality(d.left.pair, d.right.pair);
    ++ps.exact_evaluations;
    if (!q.force_closure) {
      ++ps.exact_dropped;
      continue;
    }
    SetExactEpsilon(q, &d);
    top.push_back(std::move(d));
  }
  ps.exact_seconds = Seconds(t0);
  std::sort(top.begin(), top.end(), Better);
  top.insert(top.end(), std::make_move_iterator(result.ranked.begin() + next),
             std::make_move_iterator(result.ranked.end()));
  result.ranked = std::move(top);
  put_first(&result.ranked);
  ps.valid = static_cast<long long>(result.ranked.size());
  return result;
}

PlanResult GraspPlanner::PlanFront(const PlanQuery& query, int left_pair, int right_pair) const {
  const std::pair<int, int> kept(left_pair, right_pair);
  PlanResult arms;
  EvaluateArms(query, /*robust=*/false, &arms);
  PlanResult result;
  result.left_stats = arms.left_stats;
  result.right_stats = arms.right_stats;
  PairStats& ps = result.pair_stats;
  std::vector<DualGrasp> candidates = Combine(query, arms, &ps);
  const Clock::time_point t0 = Clock::now();

  // What Plan computes for every candidate, here only for those the walk
  // below reaches: each arm grasp's robustness (by side and pair) and
  // whether the two arms clear each other (by candidate).
  const int n = static_cast<int>(contacts_.pairs.size());
  std::vector<signed char> robust[2] = {std::vector<signed char>(n, -1),
                                        std::vector<signed char>(n, -1)};
  const auto arm_robust = [&](ArmGrasp* g) {
    signed char& known = robust[static_cast<int>(g->side)][g->pair];
    if (known < 0) {
      known = Robust(g->side, *g, query.dMo, g->side == Side::kLeft ? query.q_left : query.q_right);
    }
    g->robust = known != 0;
    return g->robust;
  };
  // The candidate's class (RankClass), both arms' robustness asked.
  const auto rank_class = [&](DualGrasp* d) {
    const bool left = arm_robust(&d->left), right = arm_robust(&d->right);
    d->robust = left && right;
    return RankClass(*d);
  };
  // Is the candidate of class c? The right arm asked only when the left does not decide.
  const auto in_class = [&](DualGrasp* d, int c) {
    if (d->clear_of_edges != (c % 2 == 0)) return false;
    d->robust = arm_robust(&d->left) && arm_robust(&d->right);
    return d->robust == (c < 2);
  };
  std::vector<signed char> clear(candidates.size(), -1);
  const auto arms_clear = [&](std::size_t k) {
    if (clear[k] < 0) {
      clear[k] = ArmsClear(candidates[k]) ? 1 : 0;
      ps.arms_collide += clear[k] == 0;
    }
    return clear[k] != 0;
  };

  // The kept pair: where it stands in Plan's order (its class, its index in
  // candidates), if Plan ranks it at all.
  std::size_t kept_k = candidates.size();
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (candidates[k].left.pair == kept.first && candidates[k].right.pair == kept.second) {
      kept_k = k;
      break;
    }
  }
  int kept_class = 4;
  if (kept_k < candidates.size()) {
    kept_class = rank_class(&candidates[kept_k]);
    if (!arms_clear(kept_k)) kept_k = candidates.size();
  }
  bool kept_ranked = kept_k < candidates.size(), kept_visited = false;

  // Plan's order of the valid candidates is by class, then by Better: walk it
  // as Plan's exact-epsilon loop does, until the ranking's first entry and
  // the kept pair's entry are both known.
  const std::size_t k_exact = static_cast<std::size_t>(config_.exact_top_k);
  std::vector<DualGrasp> top;
  const DualGrasp* first_valid = nullptr;  // the first entry when no epsilon is exact
  bool done = false;
  for (int c = 0; c < 4 && !done; ++c) {
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      DualGrasp& d = candidates[k];
      if (!in_class(&d, c) || !arms_clear(k)) continue;
      // (c, k) is the next entry in Plan's order; the exact epsilons stop at k_exact.
      const bool exact_done = top.size() >= k_exact;
      const bool kept_known = !kept_ranked || kept_visited || exact_done || c > kept_class ||
                              (c == kept_class && k > kept_k);
      const bool front_known = k_exact == 0 ? first_valid != nullptr
                                            : exact_done || (!top.empty() && c > RankClass(top[0]));
      if (kept_known && front_known) {
        done = true;
        break;
      }
      if (!first_valid) first_valid = &d;
      if (exact_done) continue;
      const WrenchQuality q = ExactQuality(d.left.pair, d.right.pair);
      ++ps.exact_evaluations;
      kept_visited |= k == kept_k;
      if (!q.force_closure) {
        ++ps.exact_dropped;
        kept_ranked &= k != kept_k;
        continue;
      }
      top.push_back(d);
      SetExactEpsilon(q, &top.back());
    }
  }

  // Plan's first entry: the best exact one of the first class with any, or
  // with no exact epsilon the first valid candidate.
  if (!top.empty()) {
    const int c = RankClass(top[0]);
    const DualGrasp* best = &top[0];
    for (const DualGrasp& d : top) {
      if (RankClass(d) == c && Better(d, *best)) best = &d;
    }
    result.ranked.push_back(*best);
  } else if (k_exact == 0 && first_valid) {
    result.ranked.push_back(*first_valid);
  }
  if (kept_ranked) {
    const DualGrasp* entry = &candidates[kept_k];
    for (const DualGrasp& d : top) {
      if (d.left.pair == kept.first && d.right.pair == kept.second) entry = &d;
    }
    if (result.ranked.empty() || result.ranked[0].left.pair != kept.first ||
        result.ranked[0].right.pair != kept.second) {
      result.ranked.push_back(*entry);
    }
  }
  // Both arms' robustness, as Plan gives it, on the entries returned.
  for (DualGrasp& d : result.ranked) rank_class(&d);
  ps.exact_seconds = Seconds(t0);
  ps.valid = static_cast<long long>(result.ranked.size());
  return result;
}

}  // namespace aerograsp
