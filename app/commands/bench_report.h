// The bench's measurements (perception against the tags and, simulated,
// against the truth; the arms' servo error) and its report: summary.json,
// index.html and its plots.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "app/report/pose_plot.h"
#include "app/runtime/mission_record.h"
#include "calib/tag_board.h"
#include "core/mesh.h"
#include "core/transforms.h"

namespace aerograsp {

/// Pose errors, one per compared frame.
struct BenchStats {
  std::vector<double> t_err_m, r_err_deg;
  void Add(const PoseError& e);
  /// Root mean square; NaN when empty.
  static double Rms(const std::vector<double>& v);
};

/// One arm's servo error over time: to the commanded target and, in
/// simulation, to the same target on the true object.
struct BenchServoTrace {
  std::vector<double> t_s, to_target_m, to_truth_m;
};

/// What a bench run measured.
struct BenchResults {
  int frames = 0;
  BenchStats perception_vs_tags, tags_vs_truth, perception_vs_truth;
  int tag_frames = 0, found_frames = 0, plans = 0, no_grasp_plans = 0, switches = 0;
  std::vector<double> frame_ms;
  std::vector<double> servo_error_tracking_m, servo_error_all_m, servo_error_to_truth_m;
  BenchServoTrace servo_traces[2];
  std::map<std::string, int> status_cycles;  ///< servo cycles per status, both arms
  PoseTrace tags_trace, est_trace;
  MissionRecord record;
};

/// What the report names besides the results.
struct BenchReportInfo {
  std::string out_dir;
  std::string object_name;
  TriangleMesh object_mesh_o;
  std::string hardware;  ///< the hardware file or the in-process simulation
  std::uint64_t seed = 0;
  std::string perception;  ///< the perception file or "code defaults"
  double hover_m = 0.0;
  TagBoardConfig board;
  Eigen::Isometry3d oMt = Eigen::Isometry3d::Identity();
};

/// Appends one frame's pose (NaN when not `ok`) to a pose plot's trace.
void AddBenchTrace(PoseTrace* trace, double t_s, bool ok, const Eigen::Isometry3d& cMo,
                   double rotation_error_deg);

/// Writes DIR/summary.json, the plots and DIR/index.html, and prints the
/// headline figures on `out` (the command says where the report is).
void WriteBenchReport(const BenchReportInfo& info, const BenchResults& run, std::ostream& out);

}  // namespace aerograsp
