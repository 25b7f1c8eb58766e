// The mission's start-up: its config, devices, object, tracker, planner and
// the object's placement, built from the command's options before take-off.
// app/runtime/mission_runner.cpp wires them together and runs the loop.
#pragma once

#include <memory>
#include <string>

#include "app/runtime/mission_config.h"
#include "app/runtime/mission_runner.h"
#include "core/object_model.h"
#include "detection/object_tracker.h"

namespace aerograsp {

class GraspPlanner;
class Hardware;
class Platform;
class World;
struct DeviceHealthLimits;
struct MissionSetup;

/// The mission config `options` names (data/config/mission_default.yaml when
/// none), with the options' timeout.
/// @throws ConfigError on a bad file
MissionConfig LoadMissionConfig(const MissionOptions& options);

/// The mission config at `path` (data/config/mission_default.yaml when empty).
/// @throws ConfigError on a bad file
MissionConfig LoadMissionConfig(const std::string& path);

/// The devices: every one simulated in-process, or the options' hardware file's
/// (its simulated devices fly the config's world), the world changed by the
/// options' object, motion, speed and sway. `health` receives what the
/// hardware file treats as a device fault.
/// @throws ConfigError on an unknown arm type or a bad file
std::unique_ptr<Hardware> OpenMissionHardware(const MissionOptions& options,
                                              const MissionConfig& config,
                                              DeviceHealthLimits* health);

/// The object to grasp: the simulated world's, else the options' (the crawler
/// when none).
ObjectModel LoadMissionObject(const MissionOptions& options, const World* world);

/// The object to grasp: the simulated world's, else `object` (a shipped name
/// or a model path; the crawler when empty).
ObjectModel LoadMissionObject(const std::string& object, const World* world);

/// The perception settings the config names (the code's defaults when none).
/// @throws ConfigError on a bad file
PerceptionOptions LoadMissionPerception(const MissionConfig& config);

/// The tracker of `object` with the config's perception settings and the
/// object's detector when it has one (detector.onnx beside its model), on
/// `model` (the setup's, BuildTrackerModel; null: built here).
std::unique_ptr<ObjectTracker> MakeMissionTracker(
    const ObjectModel& object, const MissionConfig& config,
    std::shared_ptr<const ModelCloud> model = nullptr);

/// The dual-grasp planner of `object` on `platform` with the config's settings.
/// @throws ConfigError when the planner's fingers do not fit the gripper
std::unique_ptr<GraspPlanner> MakeMissionPlanner(const Platform& platform,
                                                 const ObjectModel& object,
                                                 const MissionConfig& config);

/// The planner of `object` on `platform` (MakeMissionPlanner), where the
/// vehicle holds the object, searched for this object and these arms when the
/// config's placement asks for it, and the tracker's model cloud: options.setup's when it was built
/// for this configuration (the same mission config, platform and object files), else built now, and
/// options.setup (when given) filled with them.
std::shared_ptr<const MissionSetup> MissionSetupFor(const MissionOptions& options,
                                                    const Platform& platform,
                                                    const ObjectModel& object,
                                                    const MissionConfig& config);

/// `config->grasp_dto_m` moves to the setup's placement. Returns the line to
/// log (empty: no search).
std::string PlaceMissionObject(const MissionSetup& setup, MissionConfig* config);

}  // namespace aerograsp
