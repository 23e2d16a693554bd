#include "pkm/io/json_reports.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::io {

namespace {

std::string joint_name(const machine::Machine& machine, int joint) {
  return joint >= 0 ? machine.joints()[static_cast<std::size_t>(joint)].name : "";
}

nlohmann::json to_json(const machine::Machine& machine, const verify::Violation& v,
                       const std::string& unit) {
  nlohmann::json json = {{"line", v.line},
                         {"job_line", v.job_line},
                         {"value", v.value},
                         {"limit", v.limit},
                         {"unit", violation_unit(machine, v, unit)}};
  if (v.joint >= 0) json["joint"] = joint_name(machine, v.joint);
  if (!v.detail.empty()) json["detail"] = v.detail;
  return json;
}

nlohmann::json to_json(const machine::Machine& machine, const verify::ViolationSummary& summary,
                       const std::string& unit) {
  nlohmann::json first = nlohmann::json::array();
  for (const verify::Violation& v : summary.first) first.push_back(to_json(machine, v, unit));
  nlohmann::json json = {{"count", summary.count}, {"first", first}};
  if (summary.count > 0) json["worst"] = to_json(machine, summary.worst, unit);
  return json;
}

// "F1500.0": a feed (mm/s inside) in the machine's length unit per minute.
std::string feed_text(const machine::Machine& machine, double mm_per_s) {
  return "F" + kinematics::formatted_number("%.1f", mm_per_s * 60.0 / machine.mm_per_unit());
}

// "at the G64 corner blend after line 43 (turn 90.0 deg, radius 0.0341 mm)", "on the arc (radius
// 1.52 mm)", or "" off curves.
std::string curve_text(const machine::Machine& machine, const motion::FeedLimit& limit) {
  const double radius = limit.radius_mm / machine.mm_per_unit();
  const std::string radius_text =
      "radius " + kinematics::formatted_number(radius < 1.0 ? "%.4f" : "%.3f", radius) + " " +
      machine.length_unit();
  switch (limit.curve) {
    case motion::CurveKind::blend:
      return " at the G64 corner blend after line " + std::to_string(limit.previous_line) +
             " (turn " +
             kinematics::formatted_number("%.1f", geometry::radians_to_degrees(limit.turn_rad)) +
             " deg, " + radius_text + ")";
    case motion::CurveKind::arc:
      return " on the arc (" + radius_text + ")";
    case motion::CurveKind::none:
      break;
  }
  return "";
}

// "99.9 % of " for the share `part / whole` of a limit.
std::string share_text(double part, double whole) {
  return kinematics::formatted_number("%.1f", 100.0 * part / whole) + " % of ";
}

// "; the tool's own v^2/r allows F384.0 (within 1200.0 mm/s^2, 100.0 % of max_acceleration
// 1200.0)"
std::string cartesian_curve_text(const machine::Machine& machine, const motion::FeedLimit& limit) {
  if (limit.curve == motion::CurveKind::none) return "";
  const double per_unit = machine.mm_per_unit();
  const double maximum = machine.cartesian().max_acceleration_mm_per_s2;
  return "; the tool's own v^2/r allows " + feed_text(machine, limit.curve_allowed_mm_per_s) +
         " (within " +
         kinematics::formatted_number("%.1f", limit.curve_acceleration_mm_per_s2 / per_unit) + " " +
         machine.length_unit() + "/s^2, " +
         share_text(limit.curve_acceleration_mm_per_s2, maximum) + "max_acceleration " +
         kinematics::formatted_number("%.1f", maximum / per_unit) + ")";
}

// "joint right's velocity would be 156.4 mm/s at F1500.0, over the 149.8 mm/s it may use (99.9 %
// of max_velocity 150.0)"
std::string joint_bound_text(const machine::Machine& machine, const motion::FeedLimit& limit) {
  const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(limit.joint)];
  const bool velocity = limit.bound == motion::JointBound::velocity;
  const std::string unit =
      std::string(machine.joint_file_unit(limit.joint)) + (velocity ? "/s" : "/s^2");
  const auto value = [&](double internal) {
    return kinematics::formatted_number("%.1f", machine.joint_to_file(limit.joint, internal)) +
           " " + unit;
  };
  const double programmed =
      std::min(limit.programmed_mm_per_s, machine.cartesian().max_feed_mm_per_s());
  std::string text = "joint " + joint.name + "'s " + (velocity ? "velocity" : "acceleration") +
                     " would be " + value(limit.needed_at_programmed) + " at " +
                     feed_text(machine, programmed) + ", over the " + value(limit.usable) +
                     " it may use";
  if (velocity) {
    return text + " (" + share_text(limit.usable, joint.max_velocity) + "max_velocity " +
           kinematics::formatted_number("%.1f",
                                        machine.joint_to_file(limit.joint, joint.max_velocity)) +
           ")";
  }
  return text + " on a bend (" + share_text(limit.usable, joint.max_acceleration) +
         "max_acceleration " +
         kinematics::formatted_number("%.1f",
                                      machine.joint_to_file(limit.joint, joint.max_acceleration)) +
         ")";
}

}  // namespace

std::string feed_limit_text(const machine::Machine& machine, const motion::FeedLimit& limit) {
  std::string text = feed_text(machine, limit.programmed_mm_per_s) + " lowered to " +
                     feed_text(machine, limit.allowed_mm_per_s) + curve_text(machine, limit) + ": ";
  if (limit.cause == motion::LimitCause::tension) {
    text += limit.joint < 0
                ? std::string("the cables' balance would fail at a higher speed")
                : "the " + machine.joints()[static_cast<std::size_t>(limit.joint)].name +
                      " cable would " + (limit.slack ? "go slack" : "pass its maximum tension") +
                      " at a higher speed";
    return text + cartesian_curve_text(machine, limit);
  }
  return text + joint_bound_text(machine, limit) + cartesian_curve_text(machine, limit);
}

std::string violation_unit(const machine::Machine& machine, const verify::Violation& v,
                           const std::string& unit) {
  if (v.joint < 0) return unit;
  return machine.joints()[static_cast<std::size_t>(v.joint)].interface_unit() + unit;
}

namespace {

// {"limit": "velocity", "unit": "mm/s", "at_programmed_feed": 156.4, "usable": 148.5}, in the
// joint's interface units (mm or deg); for a cable's tension {"limit": "tension", "bound": "min"}
// ("min": faster, it would go slack; "max": over its maximum).
nlohmann::json limit_bound_json(const machine::Machine& machine, const motion::FeedLimit& limit) {
  if (limit.cause == motion::LimitCause::tension) {
    return {{"limit", "tension"}, {"bound", limit.slack ? "min" : "max"}};
  }
  if (limit.joint < 0) return nullptr;
  const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(limit.joint)];
  const bool velocity = limit.bound == motion::JointBound::velocity;
  return {{"limit", velocity ? "velocity" : "acceleration"},
          {"unit", std::string(joint.interface_unit()) + (velocity ? "/s" : "/s^2")},
          {"at_programmed_feed", joint.to_interface(limit.needed_at_programmed)},
          {"usable", joint.to_interface(limit.usable)}};
}

// {"kind": "blend", "after_line": 43, "turn_deg": 90, "radius_mm": ..,
// "cartesian_allowed_mm_per_min": .., "cartesian_acceleration_mm_per_s2": ..}, or null off curves.
nlohmann::json curve_json(const motion::FeedLimit& limit) {
  if (limit.curve == motion::CurveKind::none) return nullptr;
  nlohmann::json json = {{"kind", limit.curve == motion::CurveKind::blend ? "blend" : "arc"},
                         {"radius_mm", limit.radius_mm},
                         {"cartesian_allowed_mm_per_min", limit.curve_allowed_mm_per_s * 60.0},
                         {"cartesian_acceleration_mm_per_s2", limit.curve_acceleration_mm_per_s2}};
  if (limit.curve == motion::CurveKind::blend) {
    json["after_line"] = limit.previous_line;
    json["turn_deg"] = geometry::radians_to_degrees(limit.turn_rad);
  }
  return json;
}

}  // namespace

nlohmann::json plan_report_json(const machine::Machine& machine, const motion::PlanReport& report,
                                const std::string& program, double period_s, bool estimate) {
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    const motion::JointStatistics& s = report.joints[i];
    joints.push_back(
        {{"name", joint.name},
         {"unit", joint.interface_unit()},
         {"min", joint.to_interface(s.min)},
         {"max", joint.to_interface(s.max)},
         {"limit_min", joint.to_interface(joint.min)},
         {"limit_max", joint.to_interface(joint.max)},
         {"peak_velocity", joint.to_interface(s.peak_velocity)},
         {"max_velocity", joint.to_interface(joint.max_velocity)},
         {"peak_acceleration", estimate ? nlohmann::json(nullptr)
                                        : nlohmann::json(joint.to_interface(s.peak_acceleration))},
         {"max_acceleration", joint.to_interface(joint.max_acceleration)}});
  }
  nlohmann::json limits = nlohmann::json::array();
  for (const motion::FeedLimit& limit : report.feed_limits) {
    limits.push_back(
        {{"line", limit.line},
         {"joint",
          limit.joint < 0
              ? nlohmann::json(nullptr)
              : nlohmann::json(machine.joints()[static_cast<std::size_t>(limit.joint)].name)},
         {"cause", limit.cause == motion::LimitCause::tension ? "tension" : "joint"},
         {"programmed_mm_per_min", limit.programmed_mm_per_s * 60.0},
         {"allowed_mm_per_min", limit.allowed_mm_per_s * 60.0},
         {"bound", limit_bound_json(machine, limit)},
         {"curve", curve_json(limit)},
         {"reason", feed_limit_text(machine, limit)}});
  }
  nlohmann::json tensions = nlohmann::json::array();
  for (const motion::TensionLimitedMove& move : report.tension_limits) {
    tensions.push_back(
        {{"line", move.line},
         {"cable",
          move.cable < 0
              ? nlohmann::json(nullptr)
              : nlohmann::json(machine.joints()[static_cast<std::size_t>(move.cable)].name)},
         {"bound", move.slack ? "min" : "max"},
         {"machine_mm_per_s2", move.machine_mm_per_s2},
         {"allowed_mm_per_s2", move.allowed_mm_per_s2}});
  }
  nlohmann::json warnings = nlohmann::json::array();
  for (const gcode::Warning& warning : report.warnings) {
    warnings.push_back({{"line", warning.line}, {"message", warning.message}});
  }
  return {{"machine", machine.name()},
          {"program", program},
          {"estimate", estimate},
          {"period_s", period_s},
          {"duration_s", report.duration_s},
          {"samples", report.samples},
          {"path_length_mm", report.path_length_mm},
          {"pen_changes", report.pen_changes},
          {"joints", joints},
          {"feed_limited_by_joints", limits},
          {"acceleration_limited_by_tensions", tensions},
          {"warnings", warnings}};
}

nlohmann::json verify_report_json(const machine::Machine& machine, const std::string& joint_program,
                                  const std::string& job, const verify::VerifyReport& report) {
  return {{"joint_program", joint_program},
          {"job", job},
          {"blocks", report.blocks},
          {"tolerance_mm", report.tolerance_mm},
          {"max_deviation_mm", report.max_deviation_mm},
          {"rms_deviation_mm", report.rms_deviation_mm},
          {"max_deviation_joint_line", report.max_deviation_joint_line},
          {"max_deviation_job_line", report.max_deviation_job_line},
          {"coverage",
           {{"complete", report.covered},
            {"job_length_mm", report.job_length_mm},
            {"traced_mm", report.traced_mm},
            {"stopped_at_job_line", report.coverage_stopped_job_line},
            {"stopped_at_joint_line", report.coverage_stopped_joint_line}}},
          {"violations",
           {{"deviation", to_json(machine, report.deviation, "mm")},
            {"position", to_json(machine, report.position, "")},
            {"velocity", to_json(machine, report.velocity, "/s")},
            {"pen", to_json(machine, report.pen, "mm")}}},
          {"pen_downs", {{"joint_program", report.pen_downs}, {"job", report.job_pen_downs}}},
          {"commands_mismatch", report.commands_mismatch},
          {"passed", report.passed()}};
}

namespace {

// A joint's range used from home on against its travel, in its interface unit (mm or deg), with
// the margin left at each end (negative: beyond it).
nlohmann::json joint_range_json(const machine::JointSpec& joint, const verify::JointRange& range) {
  return {{"name", joint.name},
          {"unit", joint.kind == kinematics::JointKind::rotary ? "deg" : "mm"},
          {"min", joint.to_interface(joint.min)},
          {"max", joint.to_interface(joint.max)},
          {"low", joint.to_interface(range.low)},
          {"low_line", range.low_line},
          {"high", joint.to_interface(range.high)},
          {"high_line", range.high_line},
          {"margin_low", joint.to_interface(range.low) - joint.to_interface(joint.min)},
          {"margin_high", joint.to_interface(joint.max) - joint.to_interface(range.high)}};
}

nlohmann::json extent_json(double low, double high) {
  if (!std::isfinite(low) || !std::isfinite(high)) return nullptr;
  return nlohmann::json::array({low, high});
}

}  // namespace

nlohmann::json view_report_json(const machine::Machine& machine, const std::string& joint_program,
                                const verify::TraceReport& report) {
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < report.joints.size(); ++i) {
    joints.push_back(joint_range_json(machine.joints()[i], report.joints[i]));
  }
  return {{"machine", machine.name()},
          {"joint_program", joint_program},
          {"blocks", report.blocks},
          {"pen_channel", report.has_pen},
          {"pen_downs", report.pen_downs},
          {"drawn_mm", report.drawn_mm},
          {"travel_mm", report.travel_mm},
          {"rapid_mm", report.rapid_mm},
          {"drawn_extent_mm",
           {{"x", extent_json(report.drawn_min.x(), report.drawn_max.x())},
            {"y", extent_json(report.drawn_min.y(), report.drawn_max.y())}}},
          {"joints", joints},
          {"violations", {{"position", to_json(machine, report.position, "")}}}};
}

nlohmann::json post_report_json(const machine::Machine& machine, const std::string& program,
                                const std::string& output, const post::PostReport& report,
                                double tolerance_mm) {
  nlohmann::json warnings = nlohmann::json::array();
  for (const gcode::Warning& warning : report.warnings) {
    warnings.push_back({{"line", warning.line}, {"message", warning.message}});
  }
  nlohmann::json result = {{"machine", machine.name()},
                           {"program", program},
                           {"output", output},
                           {"blocks", report.blocks},
                           {"moves", report.moves},
                           {"max_deviation_mm", report.max_deviation_mm},
                           {"bounded", report.bounded},
                           {"max_deviation_line", report.max_deviation_line},
                           {"tolerance_mm", tolerance_mm},
                           {"warnings", warnings}};
  if (report.controller && machine.controller()) {
    const controller::GrblPrediction& prediction = *report.controller;
    result["controller"] = {{"kind", machine::controller_kind_name(machine.controller()->kind)},
                            {"predicted_time_s", prediction.time_s},
                            {"motion_start_s", prediction.motion_start_s},
                            {"unlimited_look_ahead_s", prediction.unlimited_time_s},
                            {"blocks", prediction.blocks}};
  }
  return result;
}

}  // namespace pkm::io
