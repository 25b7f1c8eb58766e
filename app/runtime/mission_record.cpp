#include "app/runtime/mission_record.h"

#include "detection/object_tracker.h"

namespace aerograsp {

MissionSnapshot FrameSnapshot(double t_s, const ColorImage& color, const CameraIntrinsics& K,
                              const FrameReport& report) {
  MissionSnapshot snap;
  snap.t_s = t_s;
  snap.color = color;
  snap.K = K;
  if (report.detection) {
    snap.has_box = true;
    snap.box_x0 = report.detection->box.x0;
    snap.box_y0 = report.detection->box.y0;
    snap.box_x1 = report.detection->box.x1;
    snap.box_y1 = report.detection->box.y1;
  }
  snap.has_pose = report.estimate.valid;
  snap.cMo = report.estimate.cMo;
  return snap;
}

}  // namespace aerograsp
