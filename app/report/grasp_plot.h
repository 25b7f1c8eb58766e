// A picture of an object with its best dual grasps: the mesh shaded in an
// oblique view of the object frame, each grasp's contacts, closing axis and
// approach.
#pragma once

#include <string>
#include <vector>

#include "grasp/planner.h"

namespace aerograsp {

/// Draws `object` with up to `count` grasps of `ranked` (rank 1 boldest) seen
/// with the object at dMo (the view looks along the body's forward axis from
/// above and to the side). Writes a PNG.
/// @throws std::runtime_error naming the path when it cannot be written.
void WriteGraspPlot(const GraspObject& object, const ContactSet& contacts,
                    const std::vector<DualGrasp>& ranked, int count, const Eigen::Isometry3d& dMo,
                    const std::string& png_path);

}  // namespace aerograsp
