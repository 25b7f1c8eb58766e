#include "app/runtime/mission_startup.h"

#include <fmt/format.h>

#include <filesystem>
#include <utility>

#include "app/runtime/mission_setup.h"
#include "core/data_dir.h"
#include "detection/box_detector.h"
#include "detection/object_tracker.h"
#include "detection/perception_config.h"
#include "grasp/contacts.h"
#include "grasp/placement.h"
#include "grasp/planner.h"
#include "hardware/hardware_factory.h"
#include "hardware/sim/world.h"
#include "hardware/sim/world_config.h"

namespace aerograsp {

namespace fs = std::filesystem;

MissionConfig LoadMissionConfig(const MissionOptions& options) {
  MissionConfig config = LoadMissionConfig(options.config_path);
  if (options.timeout_s > 0) config.timeout_s = options.timeout_s;
  return config;
}

MissionConfig LoadMissionConfig(const std::string& path) {
  return MissionConfig::Load(path.empty() ? DataPath("config/mission_default.yaml") : path);
}

std::unique_ptr<Hardware> OpenMissionHardware(const MissionOptions& options,
                                              const MissionConfig& config,
                                              DeviceHealthLimits* health) {
  if (options.arm_type != "4dof" && options.arm_type != "6dof") {
    throw ConfigError("--arm: '" + options.arm_type + "' is not one of 4dof, 6dof");
  }
  const std::string platform_path = DataPath("config/platform_" + options.arm_type + ".yaml");
  HardwareConfig hw_config;
  if (options.hardware_path.empty()) {
    hw_config = HardwareConfig::InProcessSimulation(platform_path, config.world);
  } else {
    hw_config = HardwareConfig::Load(options.hardware_path);
    hw_config.world = config.world;  // simulated devices fly the mission's world
  }
  const auto adjust = [&](WorldConfig* w) {
    if (!options.object.empty()) w->object.name = options.object;
    if (!options.motion.empty()) w->object.motion = options.motion;
    if (options.object_speed_mps >= 0) w->object.speed_mps = options.object_speed_mps;
    if (options.sway_amplitude_m >= 0) {
      w->vehicle.sway_amplitude_m = Eigen::Vector3d(1.0, 1.0, 2.0 / 3.0) * options.sway_amplitude_m;
    }
    if (options.sway_frequency_hz >= 0)
      w->vehicle.sway_frequency_hz.setConstant(options.sway_frequency_hz);
    if (options.adjust_world) options.adjust_world(w);
  };
  if (options.adjust_hardware) options.adjust_hardware(&hw_config);
  std::unique_ptr<Hardware> hw = Hardware::Open(hw_config, options.seed, adjust);
  *health = hw_config.health;
  return hw;
}

ObjectModel LoadMissionObject(const MissionOptions& options, const World* world) {
  return LoadMissionObject(options.object, world);
}

ObjectModel LoadMissionObject(const std::string& object, const World* world) {
  if (world) return world->object();
  return ObjectModel::Load(object.empty() ? "crawler" : object);
}

PerceptionOptions LoadMissionPerception(const MissionConfig& config) {
  return config.perception.empty() ? PerceptionOptions{} : LoadPerceptionOptions(config.perception);
}

std::unique_ptr<ObjectTracker> MakeMissionTracker(const ObjectModel& object,
                                                  const MissionConfig& config,
                                                  std::shared_ptr<const ModelCloud> model) {
  std::unique_ptr<BoxDetector> detector;
  const std::string onnx = ObjectDetectorPath(object);
  if (!onnx.empty()) detector = std::make_unique<BoxDetector>(onnx);
  return std::make_unique<ObjectTracker>(object, LoadMissionPerception(config), std::move(detector),
                                         std::move(model));
}

std::unique_ptr<GraspPlanner> MakeMissionPlanner(const Platform& platform,
                                                 const ObjectModel& object,
                                                 const MissionConfig& config) {
  GraspPlannerConfig planner_config = config.planner;
  planner_config.CheckFingers(platform.config().gripper, config.source, "planner.");
  GraspObject grasp_object{object.name, object.mesh_o, object.mass_kg, object.center_of_mass_o};
  ContactSet contacts =
      ComputeContactPairs(object.mesh_o, platform.config().gripper, planner_config.contacts);
  return std::make_unique<GraspPlanner>(platform, std::move(grasp_object), std::move(contacts),
                                        planner_config);
}

std::shared_ptr<const MissionSetup> MissionSetupFor(const MissionOptions& options,
                                                    const Platform& platform,
                                                    const ObjectModel& object,
                                                    const MissionConfig& config) {
  const std::string key =
      fmt::format("{}\n{}\n{}", config.source, platform.config().source, object.source);
  if (options.setup && options.setup->key == key && options.setup->planner &&
      options.setup->tracker_model)
    return options.setup;
  auto setup = std::make_shared<MissionSetup>();
  setup->key = key;
  setup->planner = MakeMissionPlanner(platform, object, config);
  if (config.placement.Searches()) {
    setup->placement = ChoosePlacement(*setup->planner, config.grasp_dto_m, config.placement,
                                       platform.home(Side::kLeft), platform.home(Side::kRight));
  }
  setup->tracker_model = BuildTrackerModel(object, LoadMissionPerception(config).model);
  if (options.setup) *options.setup = *setup;
  return setup;
}

std::string PlaceMissionObject(const MissionSetup& setup, MissionConfig* config) {
  if (!setup.placement) return "";
  const Placement& placement = *setup.placement;
  const Eigen::Vector3d& p = placement.dMo.translation();
  const std::string line = fmt::format(
      "placement: the object at [{:.3f}, {:.3f}, {:.3f}] m in the body frame ({} "
      "points searched around [{:.3f}, {:.3f}, {:.3f}] m): left {}, right {} "
      "grasps clear of its ends through the sway (at the centre: {}, {}); {} dual "
      "grasps of them ranked",
      p.x(), p.y(), p.z(), placement.points, config->grasp_dto_m.x(), config->grasp_dto_m.y(),
      config->grasp_dto_m.z(), placement.robust_pairs[0], placement.robust_pairs[1],
      placement.nominal_robust_pairs[0], placement.nominal_robust_pairs[1], placement.dual_grasps);
  config->grasp_dto_m = p;
  return line;
}

}  // namespace aerograsp
