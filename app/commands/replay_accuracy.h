// Accuracy of a pose estimator over a recorded sequence against its ground
// truth (`aerograsp replay`): translation and rotation errors (rotations up to
// the object's symmetries), detection recall, ADD-S recall, and how soon the
// object is found again after it was fully hidden.
#pragma once

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

namespace aerograsp {

struct ModelCloud;

/// Accuracy of one estimator over a sequence.
struct Accuracy {
  std::vector<double> t_err_m, r_err_deg;  // frames with truth and a found estimate
  int visible = 0, found_visible = 0, add_s_ok = 0;
  int reacquisitions = 0, max_reacquire_frames = 0, never_reacquired = 0;
  std::vector<double> add_s_m;
};

/// The accuracy as summary.json's fields (RMSE, medians, recalls,
/// reacquisitions; the ADD-S threshold is a tenth of `diameter_m`).
nlohmann::json AccuracyJson(const Accuracy& a, double diameter_m);

/// `fields`' non-finite numbers (a figure of no frames) become null, as
/// summary.json writes them.
void NullNonFiniteFields(nlohmann::json* fields);

/// Per-frame bookkeeping of accuracy for one estimator.
class AccuracyCounter {
 public:
  /// `model` must outlive the counter.
  explicit AccuracyCounter(const ModelCloud& model) : model_(model) {}
  /// One frame: the object `visible` in the truth (`truth`: the true cMo, when
  /// the frame has it), the estimator `found` it at `cMo`.
  void Add(bool visible, const std::optional<Eigen::Isometry3d>& truth, bool found,
           const Eigen::Isometry3d& cMo);
  /// The accuracy over the frames added (a hide not ended by a find counts as never reacquired).
  Accuracy Finish();

 private:
  const ModelCloud& model_;
  Accuracy a_;
  bool was_visible_ = false, seen_before_ = false;
  int waiting_ = -1;
};

}  // namespace aerograsp
