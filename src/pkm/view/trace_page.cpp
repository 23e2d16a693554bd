// The page of pkm view: what a joint program draws without its job, the pen's strokes solid and
// its travel grey and dashed, coloured by how much of a joint's travel the tool uses, and each
// joint's position at the block ends against its travel.
#include <cstdio>

#include "pkm/view/html_page.hpp"
#include "pkm/view/page_data.hpp"

namespace pkm::view {

namespace {

using nlohmann::json;

json trace_quantities(const machine::Machine& machine, const MinMaxBuckets& buckets) {
  json position = json::array();
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    const double s = interface_scale(joint);
    position.push_back(series_json(buckets, static_cast<int>(i), s, joint.min * s, joint.max * s));
  }
  return json::array({{{"name", "position at block ends"}, {"per_s", 0}, {"series", position}}});
}

json extent_row(const json& report, const char* axis) {
  const json& extent = report["drawn_extent_mm"][axis];
  const std::string text =
      extent.is_null() ? "nothing drawn"
                       : printed("%.6g .. %.6g", extent[0].get<double>(), extent[1].get<double>());
  return row(std::string("drawn_") + axis, std::string("drawing's extent in ") + axis, text, "mm");
}

json trace_summary(const json& report, const machine::Machine& machine) {
  const bool pen = report["pen_channel"].get<bool>();
  json rows = json::array({row("blocks", "blocks", report["blocks"], "")});
  if (pen) rows.push_back(row("pen_downs", "pen downs", report["pen_downs"], ""));
  rows.push_back(
      row("drawn_mm", pen ? "drawn (pen down)" : "drawn (G1 blocks)", report["drawn_mm"], "mm"));
  rows.push_back(row("travel_mm", pen ? "travel with the pen up" : "travel (G0 blocks)",
                     report["travel_mm"], "mm"));
  rows.push_back(row("rapid_mm", "of it rapid (G0)", report["rapid_mm"], "mm"));
  rows.push_back(extent_row(report, "x"));
  rows.push_back(extent_row(report, "y"));
  for (const json& joint : report["joints"]) {
    const json& margin = joint["margin_low"].get<double>() < joint["margin_high"].get<double>()
                             ? joint["margin_low"]
                             : joint["margin_high"];
    rows.push_back(row("margin_" + joint["name"].get<std::string>(),
                       "joint " + joint["name"].get<std::string>() + ": least margin to its travel",
                       margin, joint["unit"].get<std::string>()));
  }
  rows.push_back(row("position_violations", "block ends beyond a joint's travel",
                     report["violations"]["position"]["count"], ""));
  rows.push_back(units_row(machine));
  return rows;
}

// The report's worst and first few block ends beyond a joint's travel, marked at the block's end.
json trace_marks(const json& report, const TraceRecorder& recorder) {
  json marks = json::array();
  const std::map<int, LineStart>& ends = recorder.line_starts();
  const json& summary = report["violations"]["position"];
  if (ends.empty() || summary["count"].get<long>() == 0) return marks;
  json listed = json::array({summary["worst"]});
  for (const json& v : summary["first"]) {
    if (v != listed.front()) listed.push_back(v);
  }
  for (const json& v : listed) {
    const int line = v["line"].get<int>();
    marks.push_back(
        mark_json(nearest_line_start(ends, line),
                  printed("line %d: %s", line, v["detail"].get<std::string>().c_str())));
  }
  return marks;
}

std::string trace_verdict(const json& report) {
  const long beyond = report["violations"]["position"]["count"].get<long>();
  if (beyond > 0) {
    return printed("%ld block %s beyond a joint's travel, the first at line %d.", beyond,
                   beyond == 1 ? "end lies" : "ends lie",
                   report["violations"]["position"]["first"][0]["line"].get<int>());
  }
  return "Every block end within the joints' travel.";
}

}  // namespace

std::string view_page(const json& report, const TraceRecorder& recorder, const std::string& title) {
  const machine::Machine& machine = recorder.machine();
  json data = base_data("view", machine, report, title);
  data["summary"] = trace_summary(report, machine);
  data["worst_joint_index"] = joint_nearest_its_travel(machine, recorder.buckets());
  data["drawing"] = drawing_json(machine, recorder.moments().moments());
  data["path"] = path_json(recorder.path().points(), true);
  data["colour"] = {{"label", "joint travel used"}, {"unit", "% of half the travel"}};
  data["marks"] = trace_marks(report, recorder);
  data["marks_title"] = "Beyond a joint's travel";
  data["verdict"] = trace_verdict(report);
  data["passed"] = report["violations"]["position"]["count"].get<long>() == 0;
  data["charts"] = {{"x", chart_axis(recorder.buckets(), "tool path from home", "mm")},
                    {"quantities", trace_quantities(machine, recorder.buckets())}};
  data["slider"] = {{"label", "along the tool path"}, {"unit", "mm"}};
  return page_with(data, title);
}

}  // namespace pkm::view
