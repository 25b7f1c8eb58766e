// What a mission builds before take-off that depends on its configuration
// alone (the mission config, the arms, the object), not on its seed: the grasp
// planner (with the wrench qualities it has computed) and where the vehicle
// holds the object (the placement search, grasp/placement.h: about a second
// for the 4-DoF arms, ten for the 6-DoF ones) and the tracker's model cloud
// (detection/object_tracker.h, BuildTrackerModel). Missions that differ only in
// their seed share one (app/commands/mission_runs.h): the first builds it,
// the others reuse it, and fly as they would with their own.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "detection/model_cloud.h"
#include "grasp/placement.h"
#include "grasp/planner.h"

namespace aerograsp {

struct MissionSetup {
  /// The configuration it was built for (mission config, platform and object
  /// files); a mission of another one builds its own and replaces it.
  std::string key;
  std::shared_ptr<const GraspPlanner> planner;
  std::optional<Placement> placement;  ///< none when the config searches none
  /// The object's model cloud with the config's perception settings.
  std::shared_ptr<const ModelCloud> tracker_model;
};

}  // namespace aerograsp
