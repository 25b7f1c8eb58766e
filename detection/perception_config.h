// The perception pipeline's settings (PerceptionOptions) from a YAML file, so
// they can be tuned without recompiling. data/config/perception_default.yaml is
// the reference: every field with its default, unit and range. One section per
// stage (model, cloud, icp, global, ekf, track) and the pipeline's own fields
// at the top level; the key paths are the field paths of PerceptionOptions,
// e.g. icp.max_iterations.
#pragma once

#include <string>

#include "detection/object_tracker.h"

namespace aerograsp {

/// Reads a perception YAML; absent keys (and absent sections) keep their value
/// in `defaults`. The bounds are PerceptionOptions::Validate's; the seeds are
/// read as integers in [0, 2^31 - 1].
/// @throws ConfigError "<file>: <key path>: ..." for a missing or malformed
/// file, unknown keys, wrong types or values out of range.
PerceptionOptions LoadPerceptionOptions(const std::string& path,
                                        const PerceptionOptions& defaults = {});

}  // namespace aerograsp
