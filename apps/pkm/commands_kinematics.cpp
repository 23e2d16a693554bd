// pkm ik, pkm fk, pkm check. They speak the machine file's units: lengths in its `units` (mm or
// inch), angles in degrees, for poses and joints alike.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "app.hpp"
#include "pkm/kinematics/hanging_cables.hpp"
#include "pkm/kinematics/leg_limits.hpp"
#include "pkm/machine/pose_tensions.hpp"
#include "pkm/machine/tension_region.hpp"

namespace pkm::app {

namespace {

struct IkOptions {
  std::string machine;
  bool json = false;
  std::vector<double> pose;
};

struct FkOptions {
  std::string machine;
  bool json = false;
  std::vector<double> seed;
  std::vector<double> joints;
};

struct CheckOptions {
  std::string machine;
  bool json = false;
  std::string job;  // with a job: the certified check of it (commands_certify.cpp)
  std::vector<double> origin;
};

nlohmann::json pose_json(const machine::Machine& machine, const geometry::Pose& pose) {
  const geometry::Vector6d values = pose.as_vector();
  nlohmann::json json = nlohmann::json::object();
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    json[std::string(geometry::kAxisNames[axis])] = machine.axis_to_file(axis, values[axis]);
  }
  return json;
}

// One line per controlled axis, "x = 750.000000 mm", each after `indent`.
void print_pose(const machine::Machine& machine, const geometry::Pose& pose,
                const char* indent = "") {
  const geometry::Vector6d values = pose.as_vector();
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    std::printf("%s%s = %.6f %s\n", indent, std::string(geometry::kAxisNames[axis]).c_str(),
                machine.axis_to_file(axis, values[axis]) + 0.0, machine.axis_file_unit(axis));
  }
}

// A hanging machine with a weight: how hard each cable pulls at rest, how far the effector tilts.
std::optional<kinematics::CableStatics> cable_statics_at(const machine::Machine& machine,
                                                         const geometry::Pose& pose) {
  const kinematics::HangingCables* cables = machine.kinematics().hanging_cables();
  if (cables == nullptr || !(cables->effector_mass_kg() > 0.0)) return std::nullopt;
  kinematics::CableStatics statics;
  if (!cables->statics(pose, Eigen::Vector2d::Zero(), statics).ok()) return std::nullopt;
  return statics;
}

void print_cable_statics(const machine::Machine& machine, const geometry::Pose& pose) {
  const std::optional<kinematics::CableStatics> statics = cable_statics_at(machine, pose);
  if (!statics) return;
  for (int cable = 0; cable < 2; ++cable) {
    std::printf("tension %s = %.3f N (%.3f .. %.3f along it)\n",
                machine.joints()[static_cast<std::size_t>(cable)].name.c_str(),
                statics->tension_N[cable], statics->lowest_N[cable], statics->highest_N[cable]);
  }
  if (machine.kinematics().hanging_cables()->effector_tilts()) {
    std::printf("tilt = %.4f deg\n", geometry::radians_to_degrees(statics->tilt_rad));
  }
}

// The same for --json: {"tension_N": [..], "lowest_N": [..], "highest_N": [..], "tilt_deg": t}.
void add_cable_statics(const machine::Machine& machine, const geometry::Pose& pose,
                       nlohmann::json& out) {
  const std::optional<kinematics::CableStatics> statics = cable_statics_at(machine, pose);
  if (!statics) return;
  out["cables"] = {{"tension_N", statics->tension_N},
                   {"lowest_N", statics->lowest_N},
                   {"highest_N", statics->highest_N},
                   {"tilt_deg", geometry::radians_to_degrees(statics->tilt_rad)}};
}

// An effector held by more cables than coordinates: each cable's tension at rest and its limits,
// "tension A = 39.650 N (limits [0, 70] N)", and where no tensions within them hold it, which
// cable would need what.
void print_pose_tensions(const machine::PoseTensions& t, const char* indent = "") {
  for (std::size_t c = 0; c < t.names.size(); ++c) {
    std::printf("%stension %s = %.3f N (limits %s)\n", indent, t.names[c].c_str(),
                t.tension_N[c] + 0.0, machine::cable_limits_text(t, c).c_str());
  }
  if (!t.held)
    std::printf("%sno tensions within the limits hold it: %s\n", indent, t.refusal.c_str());
}

nlohmann::json pose_tensions_json(const machine::PoseTensions& t) {
  nlohmann::json max = nlohmann::json::array();
  for (const double value : t.max_N) {
    max.push_back(std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr));
  }
  nlohmann::json out{{"names", t.names}, {"tension_N", t.tension_N},
                     {"min_N", t.min_N}, {"max_N", max},
                     {"held", t.held},   {"mass_kg", t.effector_mass_kg}};
  if (!t.held) out["refusal"] = t.refusal;
  return out;
}

// The N-cable tensions of a cable_tensions() model (the plotter's balance prints its own, with
// the tension along each cable and the tilt).
std::optional<machine::PoseTensions> distributed_tensions(const machine::Machine& machine,
                                                          const geometry::Pose& pose) {
  if (machine.kinematics().cable_tensions() == nullptr) return std::nullopt;
  return machine::pose_tensions(machine, pose);
}

void print_tensions(const machine::Machine& machine, const geometry::Pose& pose) {
  if (const auto t = distributed_tensions(machine, pose)) {
    print_pose_tensions(*t);
  } else {
    print_cable_statics(machine, pose);
  }
}

void add_tensions(const machine::Machine& machine, const geometry::Pose& pose,
                  nlohmann::json& out) {
  if (const auto t = distributed_tensions(machine, pose)) {
    out["tensions"] = pose_tensions_json(*t);
  } else {
    add_cable_statics(machine, pose, out);
  }
}

// IK's refusal; a tension refusal adds the tensions nearest to holding the effector, by name.
std::string ik_refusal(const machine::Machine& machine, const geometry::Pose& pose,
                       const kinematics::Status& status) {
  std::string text = machine.explain(pose, status);
  if (status.code != kinematics::StatusCode::tension) return text;
  const std::optional<machine::PoseTensions> t = distributed_tensions(machine, pose);
  if (!t || t->held) return text;
  return text + "; the tensions nearest to holding it: " + machine::tensions_text(*t) +
         " (limits " + machine::limits_text(*t) + ")";
}

void run_ik(const IkOptions& options) {
  const machine::Machine machine = load_machine_or_default(options.machine);
  const geometry::Pose pose = pose_from_arguments(machine, options.pose);
  kinematics::JointVector joints;
  const kinematics::Status status = machine.inverse(pose, joints);
  if (!status.ok()) {
    throw CommandError("pose is not reachable on " + machine.name() + ": " +
                       ik_refusal(machine, pose, status));
  }
  if (options.json) {
    nlohmann::json values = nlohmann::json::array();
    for (int i = 0; i < joints.size(); ++i) values.push_back(machine.joint_to_file(i, joints[i]));
    nlohmann::json out{
        {"joints", values}, {"names", machine.joint_names()}, {"units", machine.length_unit()}};
    add_tensions(machine, pose, out);
    std::cout << out.dump() << "\n";
    return;
  }
  for (int i = 0; i < joints.size(); ++i) {
    std::printf("%s = %.6f %s\n", machine.joints()[i].name.c_str(),
                machine.joint_to_file(i, joints[i]), machine.joint_file_unit(i));
  }
  print_tensions(machine, pose);
}

void run_fk(FkOptions options) {
  const machine::Machine machine = load_machine_or_default(options.machine);
  const std::size_t joint_count = machine.joints().size();
  if (!options.seed.empty() && options.joints.size() < joint_count) {
    // `--seed x y z a b c j1 .. j6`: the option takes every number; the last ones are the joints.
    options.seed.insert(options.seed.end(), options.joints.begin(), options.joints.end());
    const std::size_t split = options.seed.size() - std::min(options.seed.size(), joint_count);
    options.joints.assign(options.seed.begin() + static_cast<std::ptrdiff_t>(split),
                          options.seed.end());
    options.seed.resize(split);
  }
  if (options.joints.size() != joint_count) {
    throw CommandError(machine.name() + " has " + std::to_string(joint_count) + " joints; got " +
                       std::to_string(options.joints.size()) + " values");
  }
  kinematics::JointVector joints(static_cast<int>(joint_count));
  for (std::size_t i = 0; i < joint_count; ++i) {
    joints[static_cast<int>(i)] = machine.joint_from_file(static_cast<int>(i), options.joints[i]);
  }
  geometry::Pose pose = machine.home();
  if (!options.seed.empty()) {
    try {
      pose = pose_from_arguments(machine, options.seed);
    } catch (const CommandError& error) {
      throw CommandError(std::string(error.what()) + " for --seed, before the " +
                         std::to_string(joint_count) + " joint values");
    }
  }
  const geometry::Pose seed = pose;
  const kinematics::Status status = machine.forward(joints, pose);
  if (!status.ok()) {
    const bool limit = status.code == kinematics::StatusCode::joint_limit && status.joint >= 0;
    const std::string why =
        machine.kinematics().why_forward_refused(joints, seed, status, machine.joint_names());
    throw CommandError("no pose for these joints on " + machine.name() + ": " +
                       (limit         ? machine.explain_joint(status.joint, joints[status.joint])
                        : why.empty() ? machine.describe(status)
                                      : machine.describe(status) + ": " + why));
  }
  // Where the joints put the pen is not always where the machine may go: say so.
  kinematics::JointVector again;
  const kinematics::Status allowed = machine.inverse(pose, again);
  if (options.json) {
    nlohmann::json out{{"pose", pose_json(machine, pose)}, {"units", machine.length_unit()}};
    add_tensions(machine, pose, out);
    if (allowed.code == kinematics::StatusCode::tension)
      out["refused"] = machine.explain(pose, allowed);
    std::cout << out.dump() << "\n";
    return;
  }
  print_pose(machine, pose);
  print_tensions(machine, pose);
  if (allowed.code == kinematics::StatusCode::tension) {
    std::printf("note: IK refuses this pose: %s\n", machine.explain(pose, allowed).c_str());
  }
}

struct CheckSummary {
  kinematics::JointVector home_joints;
  std::vector<machine::AxisExtent> extents;
  double conditioning = 0.0;                       // relative_conditioning_at_home
  std::optional<machine::TensionRegion> tensions;  // a hanging effector's: tension_region
  // An effector on more cables than coordinates: its tensions at rest at home.
  std::optional<machine::PoseTensions> home_tensions;
};

// "x 0.000..2978.400 y -1200.000..0.000 mm" in the machine file's units.
std::string region_box_text(const machine::Machine& machine, const Eigen::Vector2d& min_mm,
                            const Eigen::Vector2d& max_mm) {
  char text[160];
  std::snprintf(
      text, sizeof text, "x %.1f..%.1f y %.1f..%.1f %s", machine.axis_to_file(0, min_mm.x()) + 0.0,
      machine.axis_to_file(0, max_mm.x()) + 0.0, machine.axis_to_file(1, min_mm.y()) + 0.0,
      machine.axis_to_file(1, max_mm.y()) + 0.0, machine.length_unit());
  return text;
}

// "x 1489.2 y -204.1 mm" in the machine file's units.
std::string point_text(const machine::Machine& machine, const Eigen::Vector2d& at_mm) {
  char text[96];
  std::snprintf(text, sizeof text, "x %.1f y %.1f %s", machine.axis_to_file(0, at_mm.x()) + 0.0,
                machine.axis_to_file(1, at_mm.y()) + 0.0, machine.length_unit());
  return text;
}

nlohmann::json region_json(const machine::Machine& machine, const machine::GridRegion& region,
                           int points) {
  if (region.points == 0 || points == 0) return {{"share", 0.0}};
  return {
      {"share", static_cast<double>(region.points) / points},
      {"x",
       {machine.axis_to_file(0, region.min_mm.x()), machine.axis_to_file(0, region.max_mm.x())}},
      {"y",
       {machine.axis_to_file(1, region.min_mm.y()), machine.axis_to_file(1, region.max_mm.y())}}};
}

nlohmann::json tension_region_json(const machine::Machine& machine,
                                   const std::optional<machine::TensionRegion>& t) {
  if (!t) return nullptr;
  const kinematics::HangingCables& cables = *machine.kinematics().hanging_cables();
  const int points = t->columns * t->rows;
  const auto at = [&](const Eigen::Vector2d& p) {
    return nlohmann::json{machine.axis_to_file(0, p.x()), machine.axis_to_file(1, p.y())};
  };
  nlohmann::json per_cable = nlohmann::json::array();
  for (std::size_t c = 0; c < 2; ++c) {
    per_cable.push_back({{"name", machine.joints()[c].name},
                         {"slack", region_json(machine, t->slack[c], t->reached.points)},
                         {"over_max", region_json(machine, t->over_max[c], t->reached.points)}});
  }
  const bool limited = cables.tension_limited();
  return {{"limits_N",
           {cables.tension_min_N(),
            limited ? nlohmann::json(cables.tension_max_N()) : nlohmann::json(nullptr)}},
          {"grid", {t->columns, t->rows}},
          {"x", {machine.axis_to_file(0, t->min_mm.x()), machine.axis_to_file(0, t->max_mm.x())}},
          {"y", {machine.axis_to_file(1, t->min_mm.y()), machine.axis_to_file(1, t->max_mm.y())}},
          {"reached", region_json(machine, t->reached, points)},
          {"within", region_json(machine, t->within, t->reached.points)},
          {"lowest_N", t->lowest_N},
          {"lowest_at", at(t->lowest_at_mm)},
          {"highest_N", t->highest_N},
          {"highest_at", at(t->highest_at_mm)},
          {"cables", per_cable}};
}

// {"max_joint_angle_deg": [inner, platform] (null where unchecked), "leg_diameter": d or null}.
nlohmann::json leg_limits_json(const machine::Machine& machine) {
  const kinematics::LegLimitSettings* settings = machine.kinematics().leg_limit_settings();
  if (settings == nullptr) return nullptr;
  nlohmann::json angles = nlohmann::json::array();
  for (const double angle : settings->max_joint_angle_rad) {
    // Rounded to 1e-10 deg: the file's 30 comes back as 30, not 29.999999999999996.
    const double degrees = std::round(geometry::radians_to_degrees(angle) * 1e10) / 1e10;
    angles.push_back(std::isfinite(angle) ? nlohmann::json(degrees) : nullptr);
  }
  return {{"max_joint_angle_deg", angles},
          {"leg_diameter", settings->leg_diameter_mm > 0.0
                               ? nlohmann::json(settings->leg_diameter_mm / machine.mm_per_unit())
                               : nlohmann::json(nullptr)}};
}

void print_leg_limits(const machine::Machine& machine) {
  const kinematics::LegLimitSettings* settings = machine.kinematics().leg_limit_settings();
  if (settings == nullptr) return;
  std::printf("  leg limits:");
  if (settings->checks_angles()) {
    std::printf(" max_joint_angle %g deg (inner), %g deg (platform);",
                geometry::radians_to_degrees(settings->max_joint_angle_rad[0]),
                geometry::radians_to_degrees(settings->max_joint_angle_rad[1]));
  }
  if (settings->leg_diameter_mm > 0.0) {
    std::printf(" leg_diameter %g %s", settings->leg_diameter_mm / machine.mm_per_unit(),
                machine.length_unit());
  }
  std::printf("\n");
}

nlohmann::json check_json(const machine::Machine& machine, const CheckSummary& summary) {
  nlohmann::json joints = nlohmann::json::array();
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    joints.push_back({{"name", joint.name},
                      {"axis", std::string(1, joint.axis_letter)},
                      {"unit", machine.joint_file_unit(i)},
                      {"min", machine.joint_to_file(i, joint.min)},
                      {"max", machine.joint_to_file(i, joint.max)},
                      {"max_velocity", machine.joint_to_file(i, joint.max_velocity)},
                      {"max_acceleration", machine.joint_to_file(i, joint.max_acceleration)},
                      {"home", machine.joint_to_file(i, summary.home_joints[i])}});
  }
  nlohmann::json extent = nlohmann::json::object();
  for (const machine::AxisExtent& e : summary.extents) {
    extent[std::string(geometry::kAxisNames[e.axis])] = {machine.axis_to_file(e.axis, e.min),
                                                         machine.axis_to_file(e.axis, e.max)};
  }
  nlohmann::json envelope = nullptr;
  if (machine.cartesian().has_envelope()) {
    envelope = nlohmann::json::object();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!machine.kinematics().dof().controls(axis)) continue;
      envelope[std::string(geometry::kAxisNames[axis])] = {
          machine.axis_to_file(axis, machine.cartesian().envelope_min[axis]),
          machine.axis_to_file(axis, machine.cartesian().envelope_max[axis])};
    }
  }
  nlohmann::json parameters = nlohmann::json::array();
  for (const kinematics::Parameter& p : machine.kinematics().parameters()) {
    parameters.push_back({{"name", p.name}, {"value", p.value}, {"unit", p.unit}});
  }
  return {{"name", machine.name()},
          {"source", machine.source()},
          {"type", std::string(machine.kinematics().type())},
          {"units", machine.length_unit()},
          {"valid", true},
          {"singular_at_home", summary.conditioning < machine::kSingularAtHome},
          {"conditioning_at_home", summary.conditioning},
          {"joints", joints},
          {"home", pose_json(machine, machine.home())},
          {"envelope", envelope},
          {"extent", extent},
          {"tensions", tension_region_json(machine, summary.tensions)},
          {"home_tensions", summary.home_tensions ? pose_tensions_json(*summary.home_tensions)
                                                  : nlohmann::json(nullptr)},
          {"leg_limits", leg_limits_json(machine)},
          {"parameters", parameters}};
}

void print_check_joints(const machine::Machine& machine, const CheckSummary& summary) {
  std::printf("  joints (position at home, limits, max velocity and acceleration):\n");
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    const char* unit = machine.joint_file_unit(i);
    std::printf("    %-10s %c  %12.4f %s  range [%.4f, %.4f]  %.1f %s/s  %.1f %s/s^2\n",
                joint.name.c_str(), joint.axis_letter,
                machine.joint_to_file(i, summary.home_joints[i]), unit,
                machine.joint_to_file(i, joint.min), machine.joint_to_file(i, joint.max),
                machine.joint_to_file(i, joint.max_velocity), unit,
                machine.joint_to_file(i, joint.max_acceleration), unit);
  }
}

// A hanging effector's tensions at rest over the frame: where both cables hold it within their
// limits, and where each goes slack or passes its maximum.
void print_tension_region(const machine::Machine& machine, const machine::TensionRegion& t) {
  const kinematics::HangingCables& cables = *machine.kinematics().hanging_cables();
  const bool limited = cables.tension_limited();
  const double reached = t.reached.points;
  const auto share = [&](const machine::GridRegion& r) {
    return reached > 0 ? 100.0 * r.points / reached : 0.0;
  };
  char limits[96];
  if (limited) {
    std::snprintf(limits, sizeof limits, "tension_limits %g..%g N", cables.tension_min_N(),
                  cables.tension_max_N());
  } else {
    std::snprintf(limits, sizeof limits, "no tension_limits: both cables pull");
  }
  std::printf(
      "  tensions at rest (%g kg effector, %s), at the %d of %d grid points over %s the "
      "joints reach:\n",
      cables.effector_mass_kg(), limits, t.reached.points, t.columns * t.rows,
      region_box_text(machine, t.min_mm, t.max_mm).c_str());
  if (t.reached.points == 0) return;
  std::printf("    within the limits at %.1f %%", share(t.within));
  if (t.within.points > 0) {
    std::printf(" (%s)", region_box_text(machine, t.within.min_mm, t.within.max_mm).c_str());
  }
  std::printf("\n");
  if (t.lowest_cable >= 0) {
    std::printf("    lowest %.1f N (%s) at %s; highest %.1f N (%s) at %s\n", t.lowest_N,
                machine.joints()[static_cast<std::size_t>(t.lowest_cable)].name.c_str(),
                point_text(machine, t.lowest_at_mm).c_str(), t.highest_N,
                machine.joints()[static_cast<std::size_t>(t.highest_cable)].name.c_str(),
                point_text(machine, t.highest_at_mm).c_str());
  }
  for (std::size_t c = 0; c < 2; ++c) {
    std::printf("    %-10s slack at %5.1f %%", machine.joints()[c].name.c_str(), share(t.slack[c]));
    if (t.slack[c].points > 0) {
      std::printf(" (%s)", region_box_text(machine, t.slack[c].min_mm, t.slack[c].max_mm).c_str());
    }
    if (limited) {
      std::printf(", above %g N at %.1f %%", cables.tension_max_N(), share(t.over_max[c]));
      if (t.over_max[c].points > 0) {
        std::printf(" (%s)",
                    region_box_text(machine, t.over_max[c].min_mm, t.over_max[c].max_mm).c_str());
      }
    }
    std::printf("\n");
  }
}

void print_check(const machine::Machine& machine, const CheckSummary& summary) {
  const kinematics::Kinematics& kinematics = machine.kinematics();
  std::printf("%s\n  file: %s\n  units: %s and deg\n  kinematics: %s, %d joints, controls",
              machine.name().c_str(), machine.source().c_str(),
              machine.units() == machine::LengthUnit::inch ? "inch" : "mm",
              std::string(kinematics.type()).c_str(), kinematics.joint_count());
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (kinematics.dof().controls(axis))
      std::printf(" %s", std::string(geometry::kAxisNames[axis]).c_str());
  }
  std::printf("\n");
  print_check_joints(machine, summary);
  print_leg_limits(machine);
  const double per_unit = machine.mm_per_unit();
  std::printf("  cartesian: max feed %.1f %s/min, max acceleration %.1f %s/s^2\n",
              machine.cartesian().max_feed_mm_per_min / per_unit, machine.length_unit(),
              machine.cartesian().max_acceleration_mm_per_s2 / per_unit, machine.length_unit());
  std::printf("  home:\n");
  print_pose(machine, machine.home(), "    ");
  std::printf("  reachable extent along lines through home (IK, joint limits%s):\n",
              machine.cartesian().has_envelope() ? ", work envelope" : "");
  for (const machine::AxisExtent& e : summary.extents) {
    const bool clipped = machine.cartesian().envelope_min[e.axis] == e.min ||
                         machine.cartesian().envelope_max[e.axis] == e.max;
    std::printf(
        "    %s  %12.4f .. %12.4f %s%s\n", std::string(geometry::kAxisNames[e.axis]).c_str(),
        machine.axis_to_file(e.axis, e.min) + 0.0, machine.axis_to_file(e.axis, e.max) + 0.0,
        machine.axis_file_unit(e.axis), clipped ? "  (clipped by the envelope)" : "");
  }
  if (summary.tensions) print_tension_region(machine, *summary.tensions);
  if (const std::optional<machine::PoseTensions>& t = summary.home_tensions) {
    std::printf("  tensions at home at rest (%g kg effector, %s):\n", t->effector_mass_kg,
                t->limited ? ("tension_limits " + machine::limits_text(*t)).c_str()
                           : "no tension_limits: the least that hold it");
    print_pose_tensions(*t, "    ");
  }
  std::printf("  ok: machine file is valid\n");
}

void run_check(const CheckOptions& options) {
  const machine::Machine machine = load_machine_or_default(options.machine);
  if (!options.job.empty()) {
    run_certified_check(machine, {options.job, options.origin, options.json});
    return;
  }
  if (!options.origin.empty()) throw CommandError("--origin is only read with a JOB");
  CheckSummary summary;
  machine.inverse(machine.home(), summary.home_joints);  // checked when the file was loaded
  summary.extents = machine::reachable_extent(machine);
  summary.conditioning = machine::relative_conditioning_at_home(machine);
  summary.tensions = machine::tension_region(machine);
  summary.home_tensions = distributed_tensions(machine, machine.home());
  if (options.json) {
    std::cout << check_json(machine, summary).dump(2) << "\n";
  } else {
    print_check(machine, summary);
  }
}

}  // namespace

void register_kinematics_commands(CLI::App& app) {
  auto ik = std::make_shared<IkOptions>();
  CLI::App* ik_command =
      app.add_subcommand("ik", "Joint values for a tool pose (inverse kinematics)");
  ik_command->add_option("-m,--machine", ik->machine, "Machine file (default: embedded hexapod)");
  ik_command->add_flag("--json", ik->json, "Print {\"joints\": [..], \"names\": [..]}");
  ik_command->add_option("pose", ik->pose, "x y z [a b c] in the machine file's units and deg")
      ->required()
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  ik_command->callback([ik] { run_ik(*ik); });

  auto fk = std::make_shared<FkOptions>();
  CLI::App* fk_command =
      app.add_subcommand("fk", "Tool pose for joint values (forward kinematics)");
  fk_command->add_option("-m,--machine", fk->machine, "Machine file (default: embedded hexapod)");
  fk_command->add_flag("--json", fk->json, "Print {\"pose\": {\"x\": .., ..}}");
  fk_command
      ->add_option("--seed", fk->seed,
                   "Pose to start from, x y z [a b c] in the machine file's units and deg "
                   "(default: home); the joint values may follow it directly")
      ->expected(2, -1)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  fk_command
      ->add_option("joints", fk->joints,
                   "Joint values in the machine file's units (deg for rotary joints)")
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  fk_command->callback([fk] { run_fk(*fk); });

  auto check = std::make_shared<CheckOptions>();
  CLI::App* check_command = app.add_subcommand(
      "check",
      "Validate a machine file; print joints, limits and reachable extent. With a JOB: prove "
      "that every pose of its path keeps the machine's limits, or name the first move where not");
  check_command->add_option("-m,--machine", check->machine,
                            "Machine file (default: embedded hexapod)");
  check_command->add_flag("--json", check->json,
                          "Print the summary (or the job's verdict) as JSON");
  check_command->add_option("job", check->job, "A G-code job to check along its whole path");
  add_pose_option(*check_command, "--origin", check->origin,
                  "With a JOB: where its X0 Y0 Z0 sits in machine coordinates, in the machine "
                  "file's units (mm or inch) and deg");
  check_command->callback([check] { run_check(*check); });
}

}  // namespace pkm::app
