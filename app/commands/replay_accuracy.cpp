#include "app/commands/replay_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "app/report/statistics.h"
#include "core/transforms.h"
#include "detection/model_cloud.h"

namespace aerograsp {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// ADD-S (m): mean over model points of the distance from the estimate's point
/// to the nearest point of the model at the truth, capped at the grid margin.
double AddS(const ModelCloud& model, const Eigen::Isometry3d& cMo_est,
            const Eigen::Isometry3d& cMo_true) {
  const Eigen::Isometry3f oMo = (cMo_true.inverse() * cMo_est).cast<float>();
  const std::size_t step = std::max<std::size_t>(1, model.points_o.size() / 500);
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < model.points_o.size(); i += step, ++n) {
    const Eigen::Vector3f p = oMo * model.points_o[i];
    const int j = model.Nearest(p);
    sum +=
        j < 0 ? model.margin_m : std::min<double>(model.margin_m, (p - model.points_o[j]).norm());
  }
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

nlohmann::json AccuracyJson(const Accuracy& a, double diameter_m) {
  auto rms = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x * x;
    return v.empty() ? std::numeric_limits<double>::quiet_NaN() : std::sqrt(s / v.size());
  };
  nlohmann::json j;
  j["frames_visible"] = a.visible;
  j["detection_recall"] = a.visible ? double(a.found_visible) / a.visible : 0.0;
  j["translation_rmse_m"] = rms(a.t_err_m);
  j["rotation_rmse_deg"] = rms(a.r_err_deg);
  j["translation_median_m"] = Percentile(a.t_err_m, 0.5, kNaN);
  j["rotation_median_deg"] = Percentile(a.r_err_deg, 0.5, kNaN);
  j["add_s_recall"] = a.visible ? double(a.add_s_ok) / a.visible : 0.0;
  j["add_s_threshold_m"] = 0.1 * diameter_m;
  j["add_s_median_m"] = Percentile(a.add_s_m, 0.5, kNaN);
  j["reacquisitions"] = a.reacquisitions;
  j["reacquire_max_frames"] = a.max_reacquire_frames;
  j["never_reacquired"] = a.never_reacquired;
  NullNonFiniteFields(&j);
  return j;
}

void NullNonFiniteFields(nlohmann::json* fields) {
  for (auto& [key, value] : fields->items()) {
    if (value.is_number_float() && !std::isfinite(value.get<double>())) value = nullptr;
  }
}

void AccuracyCounter::Add(bool visible, const std::optional<Eigen::Isometry3d>& truth, bool found,
                          const Eigen::Isometry3d& cMo) {
  if (visible) {
    ++a_.visible;
    if (found) ++a_.found_visible;
    if (!was_visible_ && seen_before_) waiting_ = 0;  // reappeared after a full hide
    if (waiting_ >= 0) {
      if (found) {
        ++a_.reacquisitions;
        a_.max_reacquire_frames = std::max(a_.max_reacquire_frames, waiting_ + 1);
        waiting_ = -1;
      } else {
        ++waiting_;
      }
    }
    seen_before_ = true;
  }
  was_visible_ = visible;
  if (truth && found) {
    const PoseError e = ComparePoses(*truth, cMo);
    a_.t_err_m.push_back(e.translation_m);
    a_.r_err_deg.push_back(SymmetricRotationError(cMo.linear(), truth->linear(), model_.symmetry) *
                           180.0 / M_PI);
  }
  if (truth && visible) {
    const double add_s =
        found ? AddS(model_, cMo, *truth) : std::numeric_limits<double>::infinity();
    if (found) a_.add_s_m.push_back(add_s);
    if (add_s < 0.1 * model_.diameter_m) ++a_.add_s_ok;
  }
}

Accuracy AccuracyCounter::Finish() {
  if (waiting_ >= 0) ++a_.never_reacquired;
  return a_;
}

}  // namespace aerograsp
