#include "grasp/placement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "core/config.h"

namespace aerograsp {
namespace {

/// At most this many of the best scored points are confirmed by a full plan.
constexpr int kConfirmations = 12;

/// The feasibility of every pair for one arm on a grid of object positions,
/// evaluated once per (point, pair) when first asked.
class FeasibilityGrid {
 public:
  FeasibilityGrid(const GraspPlanner& planner, Side side, const Eigen::VectorXd& q,
                  const Eigen::Vector3d& origin_d, double yaw_rad, double step_m,
                  const Eigen::Vector3i& half)
      : planner_(planner),
        side_(side),
        q_(q),
        origin_d_(origin_d),
        yaw_rad_(yaw_rad),
        step_m_(step_m),
        half_(half),
        size_(2 * half + Eigen::Vector3i::Ones()),
        pairs_(static_cast<int>(planner.contacts().pairs.size())),
        known_(static_cast<std::size_t>(size_.prod()) * pairs_, -1),
        edges_(pairs_, -1) {}

  Eigen::Vector3d Position(const Eigen::Vector3i& i) const {
    return origin_d_ + step_m_ * i.cast<double>();
  }

  /// The planner's flag of a pair (ArmGrasp::clear_of_edges), known once it was feasible somewhere.
  bool ClearOfEdges(int pair) const { return edges_[pair] == 1; }

  bool Feasible(const Eigen::Vector3i& i, int pair) {
    const Eigen::Vector3i j = i + half_;
    const std::size_t cell =
        (static_cast<std::size_t>(j.z()) * size_.y() + j.y()) * size_.x() + j.x();
    signed char& known = known_[cell * pairs_ + pair];
    if (known < 0) {
      ArmGrasp grasp;
      Infeasibility why;
      known = planner_.EvaluateArm(side_, pair, UprightDmo(Position(i), yaw_rad_), q_, &grasp, &why)
                  ? 1
                  : 0;
      if (known == 1) edges_[pair] = grasp.clear_of_edges ? 1 : 0;
    }
    return known == 1;
  }

  /// Feasible at i and at i moved by `steps` either way along each axis.
  bool Robust(const Eigen::Vector3i& i, int pair, int steps) {
    if (!Feasible(i, pair)) return false;
    for (int axis = 0; axis < 3 && steps > 0; ++axis) {
      for (int sign : {-1, 1}) {
        Eigen::Vector3i n = i;
        n[axis] += sign * steps;
        if (!Feasible(n, pair)) return false;
      }
    }
    return true;
  }

 private:
  const GraspPlanner& planner_;
  Side side_;
  Eigen::VectorXd q_;
  Eigen::Vector3d origin_d_;
  double yaw_rad_, step_m_;
  Eigen::Vector3i half_, size_;
  int pairs_;
  std::vector<signed char> known_;  // per cell and pair: -1 unknown, 0, 1
  std::vector<signed char> edges_;  // per pair: -1 unknown, 0, 1
};

/// How strictly a pair counts, strictest first: robust through the sway, clear
/// of the ends and of its faces' edges; robust and clear of the ends; robust.
constexpr int kLevels = 3;

/// One grid point's counted pairs per level and arm.
struct Scored {
  Eigen::Vector3i index;
  std::array<std::array<int, 2>, kLevels> count{};
  double distance_m = 0.0;
  /// Larger is better: per level, the arm with fewer, then both; then nearer.
  auto Key() const {
    const auto level = [this](int l) {
      return std::make_pair(std::min(count[l][0], count[l][1]), count[l][0] + count[l][1]);
    };
    return std::make_tuple(level(0), level(1), level(2), -distance_m);
  }
  bool Has(int level) const { return std::min(count[level][0], count[level][1]) > 0; }
};

}  // namespace

void PlacementConfig::Validate(const std::string& source, const std::string& prefix) const {
  CheckRange(source, prefix + "search_x_m", search_x_m, 0.0, 0.3, "m");
  CheckRange(source, prefix + "search_y_m", search_y_m, 0.0, 0.3, "m");
  CheckRange(source, prefix + "search_z_m", search_z_m, 0.0, 0.3, "m");
  CheckRange(source, prefix + "step_m", step_m, 0.002, 0.1, "m");
  CheckRange(source, prefix + "end_margin_m", end_margin_m, 0.0, 0.1, "m");
  CheckRange(source, prefix + "object_yaw_rad", object_yaw_rad, -M_PI, M_PI, "rad");
}

Eigen::Isometry3d UprightDmo(const Eigen::Vector3d& p_d_m, double object_yaw_rad) {
  Eigen::Isometry3d dMo = Eigen::Isometry3d::Identity();
  dMo.linear() = (Eigen::AngleAxisd(object_yaw_rad, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
  dMo.translation() = p_d_m;
  return dMo;
}

std::vector<bool> PairsClearOfEnds(const TriangleMesh& mesh_o, const ContactSet& contacts,
                                   double end_margin_m) {
  const double lo = mesh_o.BoundsMin().x(), hi = mesh_o.BoundsMax().x();
  std::vector<bool> clear;
  clear.reserve(contacts.pairs.size());
  for (const ContactPair& p : contacts.pairs) {
    bool ok = true;
    for (const Contact* c : {&p.a, &p.b}) {
      ok = ok && std::min(c->p_o.x() - lo, hi - c->p_o.x()) >= end_margin_m - 1e-9;
    }
    clear.push_back(ok);
  }
  return clear;
}

Placement ChoosePlacement(const GraspPlanner& planner, const Eigen::Vector3d& nominal_dto_m,
                          const PlacementConfig& config, const Eigen::VectorXd& q_left,
                          const Eigen::VectorXd& q_right) {
  const double step = config.step_m;
  const double margin_m = planner.config().reach_margin_m;
  const int sway = margin_m > 0.0 ? std::max(1, static_cast<int>(std::lround(margin_m / step))) : 0;
  const Eigen::Vector3i search(static_cast<int>(std::floor(config.search_x_m / step + 1e-9)),
                               static_cast<int>(std::floor(config.search_y_m / step + 1e-9)),
                               static_cast<int>(std::floor(config.search_z_m / step + 1e-9)));
  const std::vector<bool> clear_of_ends =
      PairsClearOfEnds(planner.object().mesh_o, planner.contacts(), config.end_margin_m);
  const int pairs = static_cast<int>(clear_of_ends.size());
  FeasibilityGrid grid[2] = {{planner, Side::kLeft, q_left, nominal_dto_m, config.object_yaw_rad,
                              step, search + Eigen::Vector3i::Constant(sway)},
                             {planner, Side::kRight, q_right, nominal_dto_m, config.object_yaw_rad,
                              step, search + Eigen::Vector3i::Constant(sway)}};

  // Every point scored: its counted pairs per level and arm.
  std::vector<Scored> scored;
  std::vector<std::vector<signed char>> level_of;  // per point: per arm and pair, the strictest
                                                   // level it counts at (kLevels: none)
  for (int iz = -search.z(); iz <= search.z(); ++iz) {
    for (int iy = -search.y(); iy <= search.y(); ++iy) {
      for (int ix = -search.x(); ix <= search.x(); ++ix) {
        Scored s;
        s.index = Eigen::Vector3i(ix, iy, iz);
        s.distance_m = step * s.index.cast<double>().norm();
        std::vector<signed char> levels(2 * static_cast<std::size_t>(pairs), kLevels);
        for (int a = 0; a < 2; ++a) {
          for (int p = 0; p < pairs; ++p) {
            if (!grid[a].Robust(s.index, p, sway)) continue;
            const int level = !clear_of_ends[p] ? 2 : grid[a].ClearOfEdges(p) ? 0 : 1;
            levels[a * pairs + p] = static_cast<signed char>(level);
            for (int l = level; l < kLevels; ++l) ++s.count[l][a];
          }
        }
        scored.push_back(s);
        level_of.push_back(std::move(levels));
      }
    }
  }

  Placement out;
  out.points = static_cast<int>(scored.size());
  out.dMo = UprightDmo(nominal_dto_m, config.object_yaw_rad);
  std::vector<int> order(scored.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return scored[a].Key() > scored[b].Key(); });
  // The strictest level at which both arms have a pair somewhere.
  int level = 0;
  while (level < kLevels && (order.empty() || !scored[order[0]].Has(level))) ++level;
  for (const Scored& s : scored) {
    if (!s.index.isZero()) continue;
    for (int a = 0; a < 2; ++a) out.nominal_robust_pairs[a] = s.count[std::min(level, 2)][a];
  }
  if (level == kLevels) return out;  // one arm has no robust pair anywhere: the nominal point
  out.level = level;

  // Of the best points, one where the planner's first choice is a dual grasp
  // of two counted pairs (the one the mission follows), then the one where it
  // ranks the most such.
  int chosen = order[0], chosen_duals = 0;
  bool chosen_first = false;
  for (int k = 0; k < std::min<int>(kConfirmations, static_cast<int>(order.size())); ++k) {
    const int i = order[k];
    if (!scored[i].Has(level)) break;
    PlanQuery query;
    query.dMo = UprightDmo(grid[0].Position(scored[i].index), config.object_yaw_rad);
    query.q_left = q_left;
    query.q_right = q_right;
    const PlanResult plan = planner.Plan(query);
    const auto counts = [&](const DualGrasp& d) {
      return level_of[i][d.left.pair] <= level && level_of[i][pairs + d.right.pair] <= level;
    };
    const int duals =
        static_cast<int>(std::count_if(plan.ranked.begin(), plan.ranked.end(), counts));
    const bool first = !plan.ranked.empty() && counts(plan.ranked.front());
    if (std::make_pair(first, duals) > std::make_pair(chosen_first, chosen_duals)) {
      chosen = i;
      chosen_duals = duals;
      chosen_first = first;
    }
  }
  const Scored& best = scored[chosen];
  out.dMo = UprightDmo(grid[0].Position(best.index), config.object_yaw_rad);
  out.robust_pairs[0] = best.count[level][0];
  out.robust_pairs[1] = best.count[level][1];
  out.dual_grasps = chosen_duals;
  out.first_choice_counts = chosen_first;
  return out;
}

}  // namespace aerograsp
