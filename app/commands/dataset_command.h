// `aerograsp dataset --object NAME --out DIR --count N --seed S`: labelled
// training images for the object's detector, rendered by the simulator's
// renderer with the D435 colour model: random camera pose around the object
// (distance 0.3-2.5 m, the object anywhere in the image, sometimes cut by the
// border or out of view), random object pose and tint, lighting, sky colour,
// clutter, other objects as distractors, and occluders in front. With
// --on-support F, a fraction F of the images shows the object as the world
// places it instead (world.cpp ObjectOnPipe): lying on the support pipe,
// along it or turned, seen by the vehicle's camera from 0.3-2.0 m and above
// the pipe, with the vehicle's arms (platform_4dof.yaml, near home) in view.
// F = 0 (the default) draws exactly the images it drew before F existed. Writes
//   DIR/images/NNNNNN.png  the network input (160x120 RGB, DetectorInput())
//   DIR/labels.csv         index, visible, x0, y0, x1, y1 (box of the visible
//                          object pixels in the 160x120 image), object_pixels (640x480),
//                          coverage (replay's visibility: the share of the object's
//                          front-facing model points in the image that the depth shows, [0, 1])
// The label comes from the renderer's exact object-id mask.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace aerograsp {

struct DatasetCommandOptions {
  std::string object;  ///< shipped name or model path
  std::string out_dir;
  int count = 1000;            ///< images, [1, 1e6]
  std::uint64_t seed = 1;      ///< the same seed gives the same images
  bool overwrite = false;      ///< replace an existing dataset in out_dir
  int min_object_pixels = 60;  ///< fewer visible object pixels (640x480) count as "not visible"
  double on_support = 0.0;     ///< fraction of images with the object on the support pipe, [0, 1]
};

/// The dataset is written aside and renamed to DIR at the end (app/report/report_folder.h).
/// @throws ConfigError / MeshError naming the object, ConfigError when DIR holds
/// a dataset and overwrite is false; std::runtime_error when it cannot be written.
void RunDatasetCommand(const DatasetCommandOptions& options, std::ostream& out,
                       std::ostream& progress);

/// Adds `dataset`'s options to `cmd` (a CLI11 subcommand).
void AddDatasetOptions(CLI::App* cmd, DatasetCommandOptions* options);

}  // namespace aerograsp
