#include "pkm/view/html_page.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "pkm/files/atomic_file.hpp"
#include "pkm/view/machine_drawing.hpp"
#include "pkm/view/page_data.hpp"

namespace pkm::view {

namespace {

using nlohmann::json;

json plan_quantities(const machine::Machine& machine, const MinMaxBuckets& buckets) {
  const int count = static_cast<int>(machine.joints().size());
  json position = json::array(), velocity = json::array(), acceleration = json::array();
  for (int i = 0; i < count; ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    const double s = interface_scale(joint);
    position.push_back(series_json(buckets, i, s, joint.min * s, joint.max * s));
    velocity.push_back(
        series_json(buckets, count + i, s, -joint.max_velocity * s, joint.max_velocity * s));
    acceleration.push_back(series_json(buckets, 2 * count + i, s, -joint.max_acceleration * s,
                                       joint.max_acceleration * s));
  }
  return json::array({{{"name", "position"}, {"per_s", 0}, {"series", position}},
                      {{"name", "velocity"}, {"per_s", 1}, {"series", velocity}},
                      {{"name", "acceleration"}, {"per_s", 2}, {"series", acceleration}}});
}

// The joint nearest a limit of its speed or acceleration (the larger of the two fractions):
// its index, -1 when there are no joints; `use` gets the fraction, `of_velocity` whether it is
// the velocity's (else the acceleration's).
int worst_joint(const json& joints, double& use, bool& of_velocity) {
  int worst = -1;
  use = -1.0;
  of_velocity = true;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const json& joint = joints[i];
    const double velocity =
        number_or(joint["peak_velocity"], 0.0) / number_or(joint["max_velocity"], 1.0);
    const double acceleration =
        number_or(joint["peak_acceleration"], 0.0) / number_or(joint["max_acceleration"], 1.0);
    if (std::max(velocity, acceleration) > use) {
      use = std::max(velocity, acceleration);
      of_velocity = velocity >= acceleration;
      worst = static_cast<int>(i);
    }
  }
  return worst;
}

json worst_joint_rows(const json& joints) {
  double use = 0.0;
  bool of_velocity = true;
  const int worst = worst_joint(joints, use, of_velocity);
  if (worst < 0) return json::array();
  return json::array(
      {row("worst_joint", "worst joint", joints[static_cast<std::size_t>(worst)]["name"], ""),
       row("worst_joint_use",
           of_velocity ? "its peak velocity, of its velocity limit"
                       : "its peak acceleration, of its acceleration limit",
           100.0 * use, "%")});
}

// A plotter's pen: how often it went down or up, and a plain word when it never went down.
void add_pen_rows(json& rows, const json& report, const PlanRecorder& recorder) {
  if (!recorder.has_pen()) return;
  rows.push_back(row("pen_changes", "pen down or up", report["pen_changes"], "times"));
  if (!recorder.pen_ever_down()) {
    rows.push_back(row("pen_never_down", "pen", "never down: this job draws nothing", ""));
  }
}

json plan_summary(const json& report, const PlanRecorder& recorder) {
  json rows = json::array({row("duration_s", "duration", report["duration_s"], "s"),
                           row("path_length_mm", "path length", report["path_length_mm"], "mm"),
                           row("samples", "samples", report["samples"], "")});
  for (const json& worst : worst_joint_rows(report["joints"])) rows.push_back(worst);
  add_pen_rows(rows, report, recorder);
  rows.push_back(row("feed_limited_by_joints", "moves slowed by a joint",
                     report["feed_limited_by_joints"].size(), ""));
  rows.push_back(row("acceleration_limited_by_tensions", "moves eased by a cable's tension",
                     report["acceleration_limited_by_tensions"].size(), ""));
  rows.push_back(
      row("warnings", "warnings", report.contains("warnings") ? report["warnings"].size() : 0, ""));
  rows.push_back(units_row(recorder.machine()));
  return rows;
}

// The moves a joint (or a cable's tension) slowed, every one of the report's, placed where their
// first sample lies; a move shorter than one period has none, and is placed at the next sample.
json plan_marks(const json& report, const std::map<int, LineStart>& starts) {
  json marks = json::array();
  if (starts.empty()) return marks;
  for (const json& limit : report["feed_limited_by_joints"]) {
    const int line = limit["line"].get<int>();
    const LineStart& start = nearest_line_start(starts, line);
    // The report's sentence (io/json_reports.hpp, feed_limit_text): the limit, its numbers, the
    // corner or arc.
    if (limit.contains("reason") && limit["reason"].is_string()) {
      marks.push_back(mark_json(
          start, "line " + std::to_string(line) + ": " + limit["reason"].get<std::string>()));
      continue;
    }
    char label[160];
    const std::string by = limit["joint"].is_string() ? limit["joint"].get<std::string>() : "-";
    std::snprintf(label, sizeof label, "line %d: F%.0f slowed to F%.0f by %s%s", line,
                  limit["programmed_mm_per_min"].get<double>(),
                  limit["allowed_mm_per_min"].get<double>(),
                  limit["cause"] == "tension" ? "the tension of " : "joint ", by.c_str());
    marks.push_back(mark_json(start, label));
  }
  return marks;
}

}  // namespace

std::string plan_page(const json& report, const PlanRecorder& recorder, const std::string& title) {
  const machine::Machine& machine = recorder.machine();
  json data = base_data("plan", machine, report, title);
  data["summary"] = plan_summary(report, recorder);
  double use = 0.0;
  bool of_velocity = true;
  data["worst_joint_index"] = worst_joint(report["joints"], use, of_velocity);
  data["marks_title"] = "Moves slowed by a joint";
  data["drawing"] = drawing_json(machine, recorder.moments().moments());
  data["path"] = path_json(recorder.path().points(), recorder.has_pen());
  data["colour"] = {{"label", "tool speed"}, {"unit", "mm/s"}};
  data["marks"] = plan_marks(report, recorder.line_starts());
  data["charts"] = {{"x", chart_axis(recorder.joint_buckets(), "time", "s")},
                    {"quantities", plan_quantities(machine, recorder.joint_buckets())}};
  data["slider"] = {{"label", "time"}, {"unit", "s"}};
  return page_with(data, title);
}

void write_page(const std::filesystem::path& path, const std::string& html) {
  files::write_file_atomically(path, html);
}

}  // namespace pkm::view
