// The pages of pkm post and pkm verify: a joint program's blocks as forward kinematics traces
// them, coloured by each block's deviation from the job.
#include <cstdio>
#include <limits>

#include "pkm/view/html_page.hpp"
#include "pkm/view/page_data.hpp"

namespace pkm::view {

namespace {

using nlohmann::json;

json block_quantities(const Machine& machine, const MinMaxBuckets& buckets, double tolerance_mm) {
  const int count = static_cast<int>(machine.joints().size());
  json position = json::array();
  for (int i = 0; i < count; ++i) {
    const JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    const double s = interface_scale(joint);
    position.push_back(series_json(buckets, i, s, joint.min * s, joint.max * s));
  }
  json deviation = json::array(
      {series_json(buckets, count, 1.0, std::numeric_limits<double>::quiet_NaN(), tolerance_mm)});
  return json::array({{{"name", "position at block ends"}, {"per_s", 0}, {"series", position}},
                      {{"name", "deviation"}, {"unit", "mm"}, {"series", deviation}}});
}

json count_of(const json& report, const char* kind) {
  return report["violations"][kind]["count"];
}

json verify_summary(const json& report) {
  return json::array(
      {row("blocks", "blocks", report["blocks"], ""),
       row("max_deviation_mm", "largest deviation", report["max_deviation_mm"], "mm"),
       row("rms_deviation_mm", "RMS deviation", report["rms_deviation_mm"], "mm"),
       row("tolerance_mm", "tolerance", report["tolerance_mm"], "mm"),
       row("max_deviation_joint_line", "largest at line", report["max_deviation_joint_line"], ""),
       row("traced_mm", "job traced", report["coverage"]["traced_mm"], "mm"),
       row("job_length_mm", "job length", report["coverage"]["job_length_mm"], "mm"),
       row("deviation_violations", "blocks beyond the tolerance", count_of(report, "deviation"),
           ""),
       row("position_violations", "block ends beyond a joint's travel",
           count_of(report, "position"), ""),
       row("velocity_violations", "blocks beyond a joint's speed", count_of(report, "velocity"),
           ""),
       row("pen_violations", "pen stretches against the job", count_of(report, "pen"), ""),
       row("passed", "passed", report["passed"].get<bool>() ? "yes" : "no", "")});
}

json post_summary(const json& report, const BlockRecorder& recorder, double measured_mm) {
  return json::array(
      {row("blocks", "blocks", report["blocks"], ""),
       row("moves", "programmed moves", report["moves"], ""),
       row("max_deviation_mm",
           report["bounded"].get<bool>() ? "deviation bound" : "largest sampled deviation",
           report["max_deviation_mm"], "mm"),
       row("max_deviation_line", "at job line", report["max_deviation_line"], ""),
       row("tolerance_mm", "tolerance", report["tolerance_mm"], "mm"),
       row("measured_max_deviation_mm", "largest deviation measured (verify)", rounded(measured_mm),
           "mm"),
       row("warnings", "warnings", report["warnings"].size(), ""),
       row("drawn_blocks", "blocks drawn", recorder.blocks(), "")});
}

// verify's findings (the first few of each kind) marked where their block ends.
json verify_marks(const json& report, const std::map<int, LineStart>& starts) {
  json marks = json::array();
  for (const char* kind : {"deviation", "position", "velocity", "pen"}) {
    for (const json& v : report["violations"][kind]["first"]) {
      const auto start = starts.find(v["line"].get<int>());
      if (start == starts.end()) continue;
      char label[200];
      std::snprintf(label, sizeof label, "line %d (job line %d): %s%s %.6g of %.6g %s",
                    v["line"].get<int>(), v["job_line"].get<int>(), kind,
                    v.contains("joint") ? (" of " + v["joint"].get<std::string>()).c_str() : "",
                    v["value"].get<double>(), v["limit"].get<double>(),
                    v["unit"].get<std::string>().c_str());
      const Eigen::Vector3d& p = start->second.position;
      marks.push_back({{"t", rounded(start->second.t)},
                       {"x", rounded(p.x())},
                       {"y", rounded(p.y())},
                       {"z", rounded(p.z())},
                       {"label", label}});
    }
  }
  return marks;
}

double largest_deviation(const BlockRecorder& recorder) {
  const std::size_t channel = recorder.machine().joints().size();
  double largest = 0.0;
  for (double value : recorder.buckets().max(static_cast<int>(channel))) {
    if (value > largest) largest = value;
  }
  return largest;
}

}  // namespace

std::string blocks_page(const std::string& kind, const json& report, const BlockRecorder& recorder,
                        double tolerance_mm, const std::vector<PathPoint>& outline,
                        const std::string& title) {
  const Machine& machine = recorder.machine();
  json data = base_data(kind, machine, report, title);
  data["summary"] = kind == "verify" ? verify_summary(report)
                                     : post_summary(report, recorder, largest_deviation(recorder));
  data["drawing"] = drawing_json(machine, recorder.moments().moments());
  data["path"] = path_json(recorder.path().points());
  data["block_ends"] = true;
  if (!outline.empty()) data["job_outline"] = path_json(outline);
  data["colour"] = {{"label", "deviation"}, {"unit", "mm"}};
  data["marks"] = kind == "verify" ? verify_marks(report, recorder.line_starts()) : json::array();
  data["marks_title"] = "Findings";
  data["charts"] = {{"x", chart_axis(recorder.buckets(), "tool path", "mm")},
                    {"quantities", block_quantities(machine, recorder.buckets(), tolerance_mm)}};
  data["slider"] = {{"label", "along the path"}, {"unit", "mm"}};
  return page_with(data, title);
}

json post_report_json(const Machine& machine, const std::string& program, const std::string& output,
                      const post::PostReport& report, double tolerance_mm) {
  json warnings = json::array();
  for (const gcode::Warning& warning : report.warnings) {
    warnings.push_back({{"line", warning.line}, {"message", warning.message}});
  }
  return {{"machine", machine.name()},
          {"program", program},
          {"output", output},
          {"blocks", report.blocks},
          {"moves", report.moves},
          {"max_deviation_mm", report.max_deviation_mm},
          {"bounded", report.bounded},
          {"max_deviation_line", report.max_deviation_line},
          {"tolerance_mm", tolerance_mm},
          {"warnings", warnings}};
}

}  // namespace pkm::view
