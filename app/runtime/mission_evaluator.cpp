#include "app/runtime/mission_evaluator.h"

#include <fmt/format.h>

#include <cmath>

#include "core/collision.h"
#include "core/symmetry.h"
#include "hardware/sim/world.h"

namespace aerograsp {
MissionEvaluator::MissionEvaluator(const World& world, const Platform& platform,
                                   const PlatformCollision& collision, ObjectSymmetry symmetry,
                                   std::function<void(const std::string&)> log)
    : world_(world),
      platform_(platform),
      collision_(collision),
      symmetry_(std::move(symmetry)),
      log_(std::move(log)) {}

Eigen::Vector3d MissionEvaluator::TrueGraspInTool(int a) const {
  Eigen::Isometry3d wMo_true = world_.wMo();
  const Eigen::Matrix3d wRd = world_.wMd().linear();
  wMo_true.linear() = wRd * ClosestSymmetricRotation(wRd.transpose() * wMo_true.linear(),
                                                     closing_dRo_estimate_[a], symmetry_);
  return world_.wMe(kSides[a]).inverse() * (wMo_true * closing_target_o_[a]);
}

void MissionEvaluator::Step() {
  for (int a = 0; a < 2; ++a) {
    if (!closing_[a] || closing_logged_[a]) continue;
    // The pads against the true grasp while the gripper closes: where they are
    // when they hold, or when their opening reaches the pair's width.
    const Eigen::Vector3d e_p = TrueGraspInTool(a);
    const double dt = world_.now_s() - closing_e_p_t_s_[a];
    const Eigen::Vector3d e_v =
        dt > 0.0 ? Eigen::Vector3d((e_p - closing_e_p_[a]) / dt) : Eigen::Vector3d::Zero();
    closing_e_p_[a] = e_p;
    closing_e_p_t_s_[a] = world_.now_s();
    const GripperState g = world_.gripper(kSides[a]);
    if (!g.holding && g.aperture_m > closing_width_m_[a]) continue;
    closing_logged_[a] = true;
    log_(fmt::format(
        "servo   {} pads at {:.0f} mm ({}): the true grasp at [{:.1f}, {:.1f}, {:.1f}] mm in the "
        "tool frame (closing, pads' width, depth), moving [{:.0f}, {:.0f}, {:.0f}] mm/s",
        kArmNames[a], 1e3 * g.aperture_m, g.holding ? "holding" : "the pair's width", 1e3 * e_p.x(),
        1e3 * e_p.y(), 1e3 * e_p.z(), 1e3 * e_v.x(), 1e3 * e_v.y(), 1e3 * e_v.z()));
  }
  for (int a = 0; a < 2; ++a) {
    const bool inside =
        collision_.ArmInSafeVolume(kSides[a], world_.arm(kSides[a]).q_true_rad(), 0.0);
    if (inside && !in_safe_volume_[a]) ++safe_volume_entries_;
    in_safe_volume_[a] = inside;
  }
  const bool contact = collision_.ArmsCollide(world_.arm(Side::kLeft).q_true_rad(),
                                              world_.arm(Side::kRight).q_true_rad(), 0.0);
  if (contact && !in_contact_) {
    ++arm_contacts_;
    log_("servo   the arms touch each other (true joints)");
  }
  in_contact_ = contact;
}

void MissionEvaluator::FrameTaken(double stamp_s) {
  dMo_at_frame_[stamp_s] = world_.wMd().inverse() * world_.wMo();
}

void MissionEvaluator::FramePerceived(double stamp_s, bool estimate_valid,
                                      const Eigen::Isometry3d& cMo_estimate, bool counts,
                                      MissionSample* s) {
  for (int a = 0; a < 2; ++a) s->q_target_rad[a] = world_.arm(kSides[a]).target_rad();
  const auto it = dMo_at_frame_.find(stamp_s);
  if (it == dMo_at_frame_.end()) return;
  const Eigen::Isometry3d dMo_truth = it->second;
  dMo_at_frame_.erase(dMo_at_frame_.begin(), std::next(it));
  s->dto_truth_m = dMo_truth.translation();
  if (!estimate_valid) return;
  const Eigen::Matrix3d cRo_true = (platform_.dMc().inverse() * dMo_truth).linear();
  s->rotation_error_deg =
      SymmetricRotationError(cMo_estimate.linear(), cRo_true, symmetry_) * 180.0 / M_PI;
  // Accuracy where it matters: frames found while grasping (a lock on clutter
  // during the approach, beyond the geofence, is not followed).
  if (counts) {
    sq_position_ += (s->dto_estimate_m - s->dto_truth_m).squaredNorm();
    sq_rotation_ += s->rotation_error_deg * s->rotation_error_deg;
    ++frames_;
  }
}

void MissionEvaluator::Closing(int a, const ClosingView& view) {
  // Where the gripper closes against its grasp on the true object (the truth
  // taken in its symmetric equivalent nearest the estimate).
  const Eigen::Isometry3d& dMo_est = view.dMo_estimate;
  Eigen::Isometry3d dMo_true = world_.wMd().inverse() * world_.wMo();
  dMo_true = WithSymmetricRotation(
      dMo_true, ClosestSymmetricRotation(dMo_true.linear(), dMo_est.linear(), symmetry_),
      symmetry_);
  const Eigen::Isometry3d dMb = platform_.dMb(kSides[a]);
  const Eigen::Vector3d tool_d = view.dMe.translation();
  const Eigen::Vector3d target_o = (dMo_est.inverse() * dMb * view.bMg_target).translation();
  const Eigen::Vector3d error_o =
      dMo_est.linear().transpose() * (dMo_est.translation() - dMo_true.translation());
  closing_[a] = true;
  closing_target_o_[a] = target_o;
  closing_dRo_estimate_[a] = dMo_est.linear();
  closing_width_m_[a] = view.pair_width_m;
  closing_logged_[a] = false;
  closing_e_p_[a] = TrueGraspInTool(a);
  closing_e_p_t_s_[a] = world_.now_s();
  const Eigen::Vector3d e_target = view.dMe.inverse() * (dMb * view.bMg_target).translation();
  log_(fmt::format(
      "servo   {} arm closes: in the tool frame the target is at [{:.1f}, {:.1f}, {:.1f}] mm, "
      "the true grasp at [{:.1f}, {:.1f}, {:.1f}] mm",
      kArmNames[a], 1e3 * e_target.x(), 1e3 * e_target.y(), 1e3 * e_target.z(),
      1e3 * closing_e_p_[a].x(), 1e3 * closing_e_p_[a].y(), 1e3 * closing_e_p_[a].z()));
  log_(fmt::format(
      "servo   {} arm closes: the tool is {:.1f} mm from its target and {:.1f} mm from the "
      "grasp "
      "on the true object (target at [{:.3f}, {:.3f}, {:.3f}] m in o; estimate off by {:.1f} "
      "mm "
      "([{:.1f}, {:.1f}, {:.1f}] mm in o), {:.1f} deg; {}; target solved {:.0f} ms before)",
      kArmNames[a], 1e3 * (tool_d - dMo_est * target_o).norm(),
      1e3 * (tool_d - dMo_true * target_o).norm(), target_o.x(), target_o.y(), target_o.z(),
      1e3 * (dMo_est.translation() - dMo_true.translation()).norm(), 1e3 * error_o.x(),
      1e3 * error_o.y(), 1e3 * error_o.z(),
      SymmetricRotationError(dMo_est.linear(), dMo_true.linear(), symmetry_) * 180.0 / M_PI,
      view.object_held_in_world ? "object held in the world" : "object seen",
      1e3 * view.target_age_s));
}

void MissionEvaluator::Closed(int a) {
  const Side side = kSides[a];
  const Eigen::Isometry3d oMe = world_.wMo().inverse() * world_.wMe(side);
  const GripperState g = world_.gripper(side);
  GripperClose close;
  close.t_s = world_.now_s();
  close.arm = a;
  close.holds = g.holding;
  if (closing_[a]) {
    // The grasp point on the true object, in the symmetric twin nearest the
    // estimate the close aimed with; the tool against it, in d.
    Eigen::Isometry3d dMo_true = world_.wMd().inverse() * world_.wMo();
    dMo_true = WithSymmetricRotation(
        dMo_true, ClosestSymmetricRotation(dMo_true.linear(), closing_dRo_estimate_[a], symmetry_),
        symmetry_);
    const Eigen::Vector3d tool_d = (world_.wMd().inverse() * world_.wMe(side)).translation();
    close.tool_error_m = (tool_d - dMo_true * closing_target_o_[a]).norm();
    closing_[a] = false;
  }
  closes_.push_back(close);
  const Eigen::Vector3d p = 1e3 * oMe.translation(), x = oMe.linear().col(0),
                        z = oMe.linear().col(2);
  log_(
      fmt::format("servo   {} gripper closed: {} at {:.0f} mm; the tool at [{:.1f}, {:.1f}, "
                  "{:.1f}] mm in the "
                  "true o ({:.1f} mm from its grasp), closing along [{:.2f}, {:.2f}, {:.2f}], "
                  "approaching along [{:.2f}, {:.2f}, {:.2f}]",
                  kArmNames[a], g.holding ? "holds" : "empty", 1e3 * g.aperture_m, p.x(), p.y(),
                  p.z(), 1e3 * close.tool_error_m, x.x(), x.y(), x.z(), z.x(), z.y(), z.z()));
}

bool MissionEvaluator::both_hold() const {
  return world_.held_by(Side::kLeft) && world_.held_by(Side::kRight);
}

double MissionEvaluator::pose_rmse_m() const {
  return frames_ > 0 ? std::sqrt(sq_position_ / frames_) : -1.0;
}

double MissionEvaluator::rotation_rmse_deg() const {
  return frames_ > 0 ? std::sqrt(sq_rotation_ / frames_) : -1.0;
}

}  // namespace aerograsp
