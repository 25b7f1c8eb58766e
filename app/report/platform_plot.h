// A picture of the platform: side (x-z) and front (y-z) views of the vehicle's
// safe volume, the camera's field of view, and both arms' collision shapes at
// given joint positions.
#pragma once

#include <Eigen/Core>
#include <string>

namespace aerograsp {

class Platform;

/// Draws the platform with the arms at q_left / q_right (rad) and writes a PNG.
/// @throws std::runtime_error naming the path when it cannot be written.
void WritePlatformPlot(const Platform& platform, const Eigen::VectorXd& q_left,
                       const Eigen::VectorXd& q_right, const std::string& png_path);

}  // namespace aerograsp
