#include "app/commands/plan_command.h"

#include <fmt/format.h>
#include <fmt/ostream.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "app/cli_checks.h"
#include "app/report/grasp_plot.h"
#include "app/report/report_folder.h"
#include "app/report/statistics.h"
#include "app/report/summary_file.h"
#include "app/runtime/mission_config.h"
#include "app/runtime/mission_startup.h"
#include "core/config.h"
#include "core/data_dir.h"
#include "core/object_model.h"
#include "core/platform.h"
#include "core/transforms.h"
#include "grasp/contact_cache.h"
#include "grasp/placement.h"
#include "grasp/planner.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// An object by name (an object folder, ObjectModel::Load) or a mesh file,
/// whose mass is `--mass` (a bare mesh carries none).
GraspObject LoadObject(const PlanCommandOptions& options, std::string* source) {
  const ObjectModel model = ObjectModel::Load(options.object);
  GraspObject object;
  object.name = model.name;
  object.mesh_o = model.mesh_o;
  object.mass_kg = model.mass_estimated ? options.mass_kg : model.mass_kg;
  object.com_o = model.center_of_mass_o;
  *source = model.source;
  return object;
}

std::string DefaultCacheDir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return (fs::path(xdg) / "aerograsp").string();
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return (fs::path(home) / ".cache" / "aerograsp").string();
  }
  return (fs::temp_directory_path() / "aerograsp-cache").string();
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Why there is no grasp, in words a user can act on.
std::string ExplainNoGrasp(const PlanResult& plan, const ContactSet& contacts,
                           const GripperConfig& gripper, const TriangleMesh& mesh,
                           const Platform& platform, const Eigen::Isometry3d& dMo) {
  std::ostringstream why;
  if (contacts.pairs.empty() && contacts.pairs_too_wide == 0) {
    // Nothing was too wide: the rays found no contacts at all.
    const Eigen::Vector3d extent = mesh.BoundsMax() - mesh.BoundsMin();
    why << fmt::format(
        "no contact pair on the object: {} of {} rays {} m apart met it ({} grazing a face); its "
        "bounding box is {:.3g} x {:.3g} x {:.3g} m{}",
        contacts.rays_hit, contacts.rays, contacts.resolution_m, contacts.rays_skipped, extent.x(),
        extent.y(), extent.z(),
        extent.maxCoeff() < contacts.resolution_m
            ? ", smaller than the rays' spacing: is the mesh in metres?"
            : "");
    return why.str();
  }
  if (contacts.pairs.empty()) {
    const Eigen::Vector3d extent = mesh.BoundsMax() - mesh.BoundsMin();
    why << fmt::format(
        "the object is too big for the gripper: no ray finds two opposite contacts within "
        "{:.3f} m (max_aperture_m {:.3f} - 2 x finger_clearance_m {:.3f}); its bounding box is "
        "{:.3f} x {:.3f} x {:.3f} m ({} combinations were too wide)",
        contacts.max_width_m, gripper.max_aperture_m, gripper.finger_clearance_m, extent.x(),
        extent.y(), extent.z(), contacts.pairs_too_wide);
    return why.str();
  }
  for (Side side : kSides) {
    const ArmStats& s = side == Side::kLeft ? plan.left_stats : plan.right_stats;
    if (s.feasible > 0) continue;
    const ArmModel& arm = platform.arm(side);
    const Eigen::Vector3d shoulder_d = platform.dMb(side) * arm.ShoulderPosition();
    why << fmt::format("{} arm: none of {} contact pairs is feasible ({}", SideName(side),
                       s.candidates, DescribeReasons(s));
    why << fmt::format("); the object centre is {:.3f} m from its shoulder, reach {:.3f} m. ",
                       (dMo * PlacementCentre(mesh) - shoulder_d).norm(), arm.StretchedReach());
  }
  if (why.str().empty()) {
    why << fmt::format(
        "each arm has feasible grasps (left {}, right {}) but no pair works: {} lack force "
        "closure, {} make the arms collide",
        plan.left_stats.feasible, plan.right_stats.feasible, plan.pair_stats.no_force_closure,
        plan.pair_stats.arms_collide);
  }
  return why.str();
}

nlohmann::json GraspJson(const ArmGrasp& g, const ContactSet& contacts) {
  const ContactPair& p = contacts.pairs[g.pair];
  auto vec = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.data(), v.data() + v.size());
  };
  const Eigen::Vector4d q = QuaternionWxyz(g.dMg);
  return {{"pair", g.pair},
          {"contact_a_o", vec(p.a.p_o)},
          {"contact_b_o", vec(p.b.p_o)},
          {"width_m", p.width_m()},
          {"depth_m", g.depth_m},
          {"q_grasp_rad", vec(g.q_grasp)},
          {"q_precatch_rad", vec(g.q_precatch)},
          {"dMg_xyz_m", vec(g.dMg.translation())},
          {"dMg_q_wxyz", vec(q)},
          {"cost_rad", g.cost_rad}};
}

}  // namespace

void RunPlanCommand(const PlanCommandOptions& options, std::ostream& out) {
  const Platform platform = Platform::Load(options.config_path);
  const GripperConfig& gripper = platform.config().gripper;
  std::string mesh_source;
  GraspObject object = LoadObject(options, &mesh_source);
  GraspPlannerConfig config;
  config.contacts.resolution_m = options.resolution_m;
  config.depth_min_m = options.depth_min_m;
  config.reach_margin_m = options.reach_margin_m;
  config.edge_margin_m = options.edge_margin_m;
  std::optional<MissionConfig> mission;
  if (options.place) {
    mission = LoadMissionConfig(std::string());  // the default mission's
    config = mission->planner;
  }
  config.Validate("command line", "");
  config.CheckFingers(gripper, "command line", "");

  ReportFolder folder(options.out_dir, options.overwrite);

  // Contacts: from the cache when it is valid, else generated and cached.
  const ContactCacheKey key = MakeContactCacheKey(object.mesh_o, gripper, config.contacts);
  const std::string cache_dir = options.cache_dir.empty() ? DefaultCacheDir() : options.cache_dir;
  const std::string cache_path =
      (fs::path(cache_dir) / fmt::format("{}_{:016x}.contacts", object.name, key.mesh_hash))
          .string();
  ContactSet contacts;
  std::string cache_state = "disabled";
  double cache_load_ms = 0.0;
  if (options.use_cache && fs::exists(cache_path)) {
    const Clock::time_point t0 = Clock::now();
    const CacheReadResult r = DeserializeContacts(ReadFile(cache_path), key, &contacts);
    cache_load_ms = MsSince(t0);
    cache_state = CacheStatusName(r.status);
    if (r.status != CacheStatus::kOk) {
      out << fmt::format("contact cache {}: {} ({}); regenerating\n", cache_path, r.reason,
                         cache_state);
    }
  } else if (options.use_cache) {
    cache_state = "missing";
  }
  const bool from_cache = cache_state == "ok";
  // Generation is timed every run (the benchmark of the contact stage).
  std::vector<double> generation_ms;
  for (int i = 0; i < std::max(1, options.repeats); ++i) {
    const Clock::time_point t0 = Clock::now();
    ContactSet fresh = ComputeContactPairs(object.mesh_o, gripper, config.contacts);
    generation_ms.push_back(MsSince(t0));
    if (!from_cache && i == 0) contacts = std::move(fresh);
  }
  if (options.use_cache && !from_cache) {
    fs::create_directories(cache_dir);
    std::ofstream file(cache_path, std::ios::binary | std::ios::trunc);
    const std::string bytes = SerializeContacts(contacts, key);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!file) throw std::runtime_error(cache_path + ": cannot write the contact cache");
  }

  const GraspPlanner planner(platform, object, contacts, config);
  PlanQuery query;
  // The object's bounding-box centre where asked, whatever its frame's origin.
  query.dMo = PlaceByCentre(
      MakeTransform(options.object_xyz_m, options.object_rpy_deg * M_PI / 180.0), object.mesh_o);
  query.q_left = platform.home(Side::kLeft);
  query.q_right = platform.home(Side::kRight);
  std::optional<Placement> placement;
  if (mission) {
    PlacementConfig place = mission->placement;
    place.object_yaw_rad = std::remainder(options.object_rpy_deg.z() * M_PI / 180.0, 2.0 * M_PI);
    placement =
        ChoosePlacement(planner, query.dMo.translation(), place, query.q_left, query.q_right);
    query.dMo = placement->dMo;
  }

  PlanResult plan;
  std::vector<double> feas_us, qual_us, exact_us;
  for (int i = 0; i < std::max(1, options.repeats); ++i) {
    plan = planner.Plan(query);
    const int evaluated = plan.left_stats.candidates + plan.right_stats.candidates;
    if (evaluated > 0) {
      feas_us.push_back(1e6 * (plan.left_stats.seconds + plan.right_stats.seconds) / evaluated);
    }
    if (plan.pair_stats.considered > 0) {
      qual_us.push_back(1e6 * plan.pair_stats.quality_seconds / plan.pair_stats.considered);
    }
    if (plan.pair_stats.exact_evaluations > 0) {
      exact_us.push_back(1e6 * plan.pair_stats.exact_seconds / plan.pair_stats.exact_evaluations);
    }
  }
  // Exact single-grasp quality of every pair (Qhull), for the record.
  int single_force_closure = 0;
  const Clock::time_point ts = Clock::now();
  for (int i = 0; i < static_cast<int>(contacts.pairs.size()); ++i) {
    single_force_closure += planner.ExactQuality(i).force_closure;
  }
  const double single_exact_us =
      contacts.pairs.empty() ? 0.0 : 1e3 * MsSince(ts) / static_cast<double>(contacts.pairs.size());

  // Report.
  const double contacts_ms = Percentile(generation_ms, 0.5);
  out << fmt::format(
      "Object '{}' ({}): {} triangles, mass {:.3f} kg, centre of mass [{:.4f} {:.4f} {:.4f}] m\n",
      object.name, mesh_source, object.mesh_o.triangles.size(), object.mass_kg, object.com_o.x(),
      object.com_o.y(), object.com_o.z());
  const Eigen::Vector3d centre_o = PlacementCentre(object.mesh_o);
  out << fmt::format(
      "Placed with its bounding-box centre ([{:.4f} {:.4f} {:.4f}] m in o) at xyz [{:.3f} {:.3f} "
      "{:.3f}] m, rpy [{:.1f} {:.1f} {:.1f}] deg (body frame d, FRD); arms at home\n",
      centre_o.x(), centre_o.y(), centre_o.z(), options.object_xyz_m.x(), options.object_xyz_m.y(),
      options.object_xyz_m.z(), options.object_rpy_deg.x(), options.object_rpy_deg.y(),
      options.object_rpy_deg.z());
  if (placement) {
    const Eigen::Vector3d& p = placement->dMo.translation();
    out << fmt::format(
        "Placement (the mission's): the object's origin at [{:.3f} {:.3f} {:.3f}] m in d, upright "
        "at yaw {:.1f} deg ({} points searched): left {}, right {} grasps clear of its ends "
        "through the sway (at --object-xyz: {}, {}); {} dual grasps of them ranked{}\n",
        p.x(), p.y(), p.z(), options.object_rpy_deg.z(), placement->points,
        placement->robust_pairs[0], placement->robust_pairs[1], placement->nominal_robust_pairs[0],
        placement->nominal_robust_pairs[1], placement->dual_grasps,
        placement->first_choice_counts ? ", the first among them" : "");
  }
  out << fmt::format(
      "Friction: mu {:.2f}, {}-edge cones, torsional {:.4f} m (soft finger); torques about the "
      "centre of mass / {:.3f} m\n",
      config.friction.mu, config.friction.cone_edges, config.friction.torsional_m,
      planner.torque_scale_m());
  out << fmt::format(
      "Contacts: {} rays at {:.3f} m, {} hit, {} skipped, {} pairs fit the gripper (<= {:.3f} m), "
      "{} too wide; {:.2f} ms to generate, cache {} ({})\n",
      contacts.rays, contacts.resolution_m, contacts.rays_hit, contacts.rays_skipped,
      contacts.pairs.size(), contacts.max_width_m, contacts.pairs_too_wide, contacts_ms,
      cache_state, cache_path);
  for (Side side : kSides) {
    const ArmStats& s = side == Side::kLeft ? plan.left_stats : plan.right_stats;
    const std::vector<ArmGrasp>& grasps = side == Side::kLeft ? plan.left : plan.right;
    out << fmt::format(
        "{:>5} arm: {} of {} feasible ({} robust)", SideName(side), s.feasible, s.candidates,
        std::count_if(grasps.begin(), grasps.end(), [](const ArmGrasp& g) { return g.robust; }));
    const std::string reasons = DescribeReasons(s);
    out << (reasons.empty() ? "" : ", ") << reasons << "\n";
  }
  const PairStats& ps = plan.pair_stats;
  out << fmt::format(
      "Dual pairs: {} considered, {} without force closure, {} arms collide, {} dropped by the "
      "exact hull, {} valid ({} robust to {:.3f} m, {} clear of edges by {:.3f} m)\n",
      ps.considered, ps.no_force_closure, ps.arms_collide, ps.exact_dropped, ps.valid,
      std::count_if(plan.ranked.begin(), plan.ranked.end(),
                    [](const DualGrasp& d) { return d.robust; }),
      config.reach_margin_m,
      std::count_if(plan.ranked.begin(), plan.ranked.end(),
                    [](const DualGrasp& d) { return d.clear_of_edges; }),
      config.edge_margin_m);
  out << fmt::format("Single grasps in force closure (exact): {} of {}\n", single_force_closure,
                     contacts.pairs.size());
  out << fmt::format(
      "Timing (one core, median of {}): contacts {:.2f} ms, feasibility {:.2f} us/grasp, quality "
      "{:.3f} us/pair (bound), exact Qhull {:.1f} us/dual pair, {:.1f} us/single grasp\n",
      std::max(1, options.repeats), contacts_ms, Percentile(feas_us, 0.5), Percentile(qual_us, 0.5),
      Percentile(exact_us, 0.5), single_exact_us);

  std::string no_grasp_reason;
  if (plan.ranked.empty()) {
    no_grasp_reason = ExplainNoGrasp(plan, contacts, gripper, object.mesh_o, platform, query.dMo);
    out << "No feasible dual grasp: " << no_grasp_reason << "\n";
  } else {
    out << fmt::format("\n{:>4} {:>6} {:>6} {:>9} {:>5} {:>6} {:>6} {:>7} {:>8} {:>8} {:>8}\n",
                       "rank", "left", "right", "epsilon", "exact", "task", "L.share", "cost",
                       "score", "L.width", "R.width");
    const int rows = std::min<int>(options.top, static_cast<int>(plan.ranked.size()));
    for (int i = 0; i < rows; ++i) {
      const DualGrasp& d = plan.ranked[i];
      out << fmt::format(
          "{:>4} {:>6} {:>6} {:>9.5f} {:>5} {:>6.3f} {:>6.2f} {:>7.3f} {:>8.5f} {:>8.3f} "
          "{:>8.3f}\n",
          i + 1, d.left.pair, d.right.pair, d.epsilon, d.epsilon_exact ? "yes" : "no", d.task,
          d.left_share, d.left.cost_rad + d.right.cost_rad, d.score,
          contacts.pairs[d.left.pair].width_m(), contacts.pairs[d.right.pair].width_m());
    }
  }

  const std::string png = (fs::path(folder.path()) / "grasps.png").string();
  WriteGraspPlot(object, contacts, plan.ranked, 3, query.dMo, png);

  nlohmann::json j;
  j["object"] = object.name;
  j["mesh"] = mesh_source;
  j["platform"] = options.config_path;
  j["centre_xyz_m"] = {options.object_xyz_m.x(), options.object_xyz_m.y(),
                       options.object_xyz_m.z()};
  j["dMo_xyz_m"] = {query.dMo.translation().x(), query.dMo.translation().y(),
                    query.dMo.translation().z()};
  j["dMo_rpy_deg"] = {options.object_rpy_deg.x(), options.object_rpy_deg.y(),
                      options.object_rpy_deg.z()};
  if (placement) {
    const Eigen::Vector3d& p = placement->dMo.translation();
    j["placement"] = {{"dMo_xyz_m", {p.x(), p.y(), p.z()}},
                      {"points", placement->points},
                      {"robust_pairs", {placement->robust_pairs[0], placement->robust_pairs[1]}},
                      {"nominal_robust_pairs",
                       {placement->nominal_robust_pairs[0], placement->nominal_robust_pairs[1]}},
                      {"dual_grasps", placement->dual_grasps}};
  }
  j["resolution_m"] = contacts.resolution_m;
  j["friction"] = {{"mu", config.friction.mu},
                   {"cone_edges", config.friction.cone_edges},
                   {"torsional_m", config.friction.torsional_m},
                   {"torque_scale_m", planner.torque_scale_m()}};
  j["contacts_ms"] = contacts_ms;
  j["contacts_cache"] = cache_state;
  j["contacts_cache_load_ms"] = cache_load_ms;
  j["rays"] = contacts.rays;
  j["candidates"] = contacts.pairs.size();
  j["feasible_left"] = plan.left_stats.feasible;
  j["feasible_right"] = plan.right_stats.feasible;
  j["dual_pairs"] = ps.valid;
  j["dual_pairs_considered"] = ps.considered;
  j["single_force_closure"] = single_force_closure;
  j["feasibility_us_per_grasp"] = Percentile(feas_us, 0.5);
  j["quality_us_per_grasp"] = Percentile(qual_us, 0.5);
  j["quality_exact_us_per_dual_grasp"] = Percentile(exact_us, 0.5);
  j["quality_exact_us_per_single_grasp"] = single_exact_us;
  j["timing_repeats"] = std::max(1, options.repeats);
  j["feasible"] = !plan.ranked.empty();
  if (!no_grasp_reason.empty()) j["no_grasp_reason"] = no_grasp_reason;
  nlohmann::json top = nlohmann::json::array();
  for (int i = 0; i < std::min<int>(options.top, static_cast<int>(plan.ranked.size())); ++i) {
    const DualGrasp& d = plan.ranked[i];
    top.push_back({{"rank", i + 1},
                   {"epsilon", d.epsilon},
                   {"epsilon_exact", d.epsilon_exact},
                   {"task", d.task},
                   {"left_share", d.left_share},
                   {"score", d.score},
                   {"left", GraspJson(d.left, contacts)},
                   {"right", GraspJson(d.right, contacts)}});
  }
  j["top"] = top;
  const std::string summary = WriteSummaryFile(folder.path(), j.dump(2));
  folder.Commit();
  out << "\nWrote " << folder.Final(png) << "\n";
  out << "Wrote " << folder.Final(summary) << "\n";
}

void AddPlanOptions(CLI::App* cmd, PlanCommandOptions* o) {
  o->config_path = DataPath("config/platform_4dof.yaml");
  // Three numbers each on the command line, vectors in the options once parsed.
  const auto xyz = std::make_shared<std::vector<double>>();
  const auto rpy = std::make_shared<std::vector<double>>();
  cmd->add_option("object", o->object, "Object name (shipped or imported) or a mesh file")
      ->required();
  cmd->add_option("--out", o->out_dir, "Output folder (summary.json, grasps.png)")->required();
  cmd->add_flag("--overwrite", o->overwrite, "Replace a report already in --out");
  cmd->add_option("--config", o->config_path, "Platform YAML")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  cmd->add_option("--object-xyz", *xyz,
                  "Object centre (bounding box) in the body frame d (FRD), m [default 0.10 0 0.46]")
      ->expected(3)
      ->check(cli::Finite());
  cmd->add_option("--object-rpy", *rpy, "Object roll pitch yaw in d, deg [default 180 0 90]")
      ->expected(3)
      ->check(cli::Finite());
  cmd->add_option("--resolution", o->resolution_m, "Contact ray grid, m")
      ->capture_default_str()
      ->check(cli::Finite());
  cmd->add_option("--depth-min", o->depth_min_m,
                  "Contacts at least this far behind the tool point, m")
      ->capture_default_str()
      ->check(cli::Finite());
  cmd->add_option("--reach-margin", o->reach_margin_m,
                  "A grasp is robust when it stays feasible with the object moved this far along "
                  "each axis, m")
      ->capture_default_str()
      ->check(cli::Finite());
  cmd->add_option("--edge-margin", o->edge_margin_m,
                  "Grasps whose contacts stay on their faces with the object shifted this far "
                  "along them rank first, m")
      ->capture_default_str()
      ->check(cli::Finite());
  cmd->add_flag("--place", o->place,
                "Plan where the mission holds the object: the placement searched around "
                "--object-xyz, upright at --object-rpy's yaw, with the mission's planner and "
                "placement settings (data/config/mission_default.yaml; the planner options "
                "above are then ignored)");
  cmd->add_option("--mass", o->mass_kg, "Mass of a bare mesh, kg")
      ->capture_default_str()
      ->check(cli::Range(1e-6, 1e4));
  cmd->add_option("--cache-dir", o->cache_dir, "Contact cache folder [~/.cache/aerograsp]");
  cmd->add_flag("!--no-cache", o->use_cache, "Neither read nor write the contact cache");
  cmd->add_option("--top", o->top, "Rows of the table")
      ->capture_default_str()
      ->check(cli::Range(1, 1000));
  cmd->add_option("--repeats", o->repeats, "Timing repetitions (median)")
      ->capture_default_str()
      ->check(cli::Range(1, 1000));
  cmd->callback([o, xyz, rpy] {
    if (!xyz->empty()) o->object_xyz_m = Eigen::Vector3d((*xyz)[0], (*xyz)[1], (*xyz)[2]);
    if (!rpy->empty()) o->object_rpy_deg = Eigen::Vector3d((*rpy)[0], (*rpy)[1], (*rpy)[2]);
  });
}

}  // namespace aerograsp
