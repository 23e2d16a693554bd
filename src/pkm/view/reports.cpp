#include "pkm/view/reports.hpp"

namespace pkm::view {

namespace {

std::string joint_name(const Machine& machine, int joint) {
  return joint >= 0 ? machine.joints()[static_cast<std::size_t>(joint)].name : "";
}

nlohmann::json to_json(const Machine& machine, const verify::Violation& v,
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

nlohmann::json to_json(const Machine& machine, const verify::ViolationSummary& summary,
                       const std::string& unit) {
  nlohmann::json first = nlohmann::json::array();
  for (const verify::Violation& v : summary.first) first.push_back(to_json(machine, v, unit));
  nlohmann::json json = {{"count", summary.count}, {"first", first}};
  if (summary.count > 0) json["worst"] = to_json(machine, summary.worst, unit);
  return json;
}

}  // namespace

std::string violation_unit(const Machine& machine, const verify::Violation& v,
                           const std::string& unit) {
  if (v.joint < 0) return unit;
  return machine.joints()[static_cast<std::size_t>(v.joint)].interface_unit() + unit;
}

nlohmann::json plan_report_json(const Machine& machine, const motion::PlanReport& report,
                                const std::string& program, double period_s, bool estimate) {
  nlohmann::json joints = nlohmann::json::array();
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
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
         {"allowed_mm_per_min", limit.allowed_mm_per_s * 60.0}});
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

nlohmann::json verify_report_json(const Machine& machine, const std::string& joint_program,
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
          {"passed", report.passed()}};
}

}  // namespace pkm::view
