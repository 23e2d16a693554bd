// The pages of pkm post and pkm verify: a joint program's blocks as forward kinematics traces
// them, coloured by each block's deviation from the job.
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "pkm/view/html_page.hpp"
#include "pkm/view/page_data.hpp"

namespace pkm::view {

namespace {

using nlohmann::json;

json block_quantities(const machine::Machine& machine, const MinMaxBuckets& buckets,
                      double tolerance_mm) {
  const int count = static_cast<int>(machine.joints().size());
  json position = json::array();
  for (int i = 0; i < count; ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
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

json verify_summary(const json& report, const machine::Machine& machine) {
  return json::array(
      {row("blocks", "blocks", report["blocks"], ""),
       row("max_deviation_mm", "largest deviation", report["max_deviation_mm"], "mm"),
       row("rms_deviation_mm", "RMS deviation", report["rms_deviation_mm"], "mm"),
       row("tolerance_mm", "tolerance", report["tolerance_mm"], "mm"),
       row("max_deviation_joint_line", "largest at joint-program line",
           report["max_deviation_joint_line"], ""),
       row("max_deviation_job_line", "held against job line", report["max_deviation_job_line"], ""),
       row("traced_mm", "job traced", report["coverage"]["traced_mm"], "mm"),
       row("job_length_mm", "job length", report["coverage"]["job_length_mm"], "mm"),
       row("deviation_violations", "blocks beyond the tolerance", count_of(report, "deviation"),
           ""),
       row("position_violations", "block ends beyond a joint's travel",
           count_of(report, "position"), ""),
       row("velocity_violations", "blocks beyond a joint's speed", count_of(report, "velocity"),
           ""),
       row("pen_violations", "pen stretches against the job", count_of(report, "pen"), ""),
       row("passed", "passed", report["passed"].get<bool>() ? "yes" : "no", ""),
       units_row(machine)});
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
       row("drawn_blocks", "blocks drawn", recorder.blocks(), ""), units_row(recorder.machine())});
}

// Where a finding lies, in words: "joint-program line 436, job line 12".
std::string lines_text(int line, int job_line) {
  return job_line > 0 ? printed("joint-program line %d, job line %d", line, job_line)
                      : printed("joint-program line %d", line);
}

// A joint, pen or deviation finding of the report as a sentence.
std::string finding_text(const std::string& kind, const json& v) {
  const std::string at = lines_text(v["line"].get<int>(), v["job_line"].get<int>());
  const double value = v["value"].get<double>(), limit = v["limit"].get<double>();
  const std::string unit = v["unit"].get<std::string>();
  const std::string joint = v.contains("joint") ? v["joint"].get<std::string>() : "";
  if (kind == "pen") {
    const std::string what = v.contains("detail") ? v["detail"].get<std::string>() : "pen wrong";
    return printed("%s for %.4g mm at %s", what.c_str(), value, at.c_str());
  }
  if (kind == "position") {
    return printed("joint %s at %.6g %s, beyond its travel (limit %.6g %s), at %s", joint.c_str(),
                   value, unit.c_str(), limit, unit.c_str(), at.c_str());
  }
  if (kind == "velocity") {
    return printed("joint %s at %.6g %s, beyond its max velocity %.6g %s, at %s", joint.c_str(),
                   value, unit.c_str(), limit, unit.c_str(), at.c_str());
  }
  return printed("deviation %.6g mm (tolerance %.6g mm) at %s", value, limit, at.c_str());
}

// verify's findings, worst first: the deviations from every block (the recorder kept the worst),
// then for joints and the pen the report's worst and its first few; each marked where its block
// ends. `shown` gets, per kind, how many are listed.
json verify_marks(const json& report, const BlockRecorder& recorder, double tolerance_mm,
                  std::map<std::string, long>& shown) {
  json marks = json::array();
  for (const WorstBlock& block : recorder.worst_blocks()) {
    if (!(block.deviation_mm > tolerance_mm)) break;
    marks.push_back(mark_json(
        block.at, printed("deviation %.6g mm (tolerance %.6g mm) at %s", block.deviation_mm,
                          tolerance_mm, lines_text(block.line, block.job_line).c_str())));
    ++shown["deviation"];
  }
  const std::map<int, LineStart>& starts = recorder.line_starts();
  if (starts.empty()) return marks;
  for (const char* kind : {"position", "velocity", "pen"}) {
    const json& summary = report["violations"][kind];
    json listed = json::array();
    if (summary.contains("worst")) listed.push_back(summary["worst"]);
    for (const json& v : summary["first"]) {
      if (listed.empty() || v != listed.front()) listed.push_back(v);
    }
    for (const json& v : listed) {
      marks.push_back(
          mark_json(nearest_line_start(starts, v["line"].get<int>()), finding_text(kind, v)));
      ++shown[kind];
    }
  }
  return marks;
}

// "first 100 of 379 deviations, worst first; ..." for the findings' heading.
std::string marks_note(const json& report, const std::map<std::string, long>& shown) {
  std::string note;
  for (const char* kind : {"deviation", "position", "velocity", "pen"}) {
    const long count = report["violations"][kind]["count"].get<long>();
    if (count == 0) continue;
    const auto listed = shown.find(kind);
    const long n = listed == shown.end() ? 0 : listed->second;
    if (!note.empty()) note += "; ";
    note += n < count ? printed("%s: the worst %ld of %ld", kind, n, count)
                      : printed("%s: all %ld", kind, count);
  }
  return note.empty() ? note : note + " (worst first)";
}

// Why the verification passed or failed, as one sentence (as the command's exit message).
std::string verdict(const json& report) {
  const json& coverage = report["coverage"];
  const double tolerance = report["tolerance_mm"].get<double>();
  std::string why;
  if (!coverage["complete"].get<bool>()) {
    why += report["blocks"].get<long>() == 0
               ? std::string("The joint program has no blocks: ")
               : printed("The joint program ends at its line %d: ",
                         coverage["stopped_at_joint_line"].get<int>());
    why += printed("it traces the job only to job line %d (%.1f of %.1f mm). ",
                   coverage["stopped_at_job_line"].get<int>(), coverage["traced_mm"].get<double>(),
                   coverage["job_length_mm"].get<double>());
  }
  const long deviations = report["violations"]["deviation"]["count"].get<long>();
  if (deviations > 0) {
    why += printed("%ld %s beyond the tolerance %.6g mm; the worst by %.6g mm at %s. ", deviations,
                   deviations == 1 ? "block strays" : "blocks stray", tolerance,
                   report["max_deviation_mm"].get<double>(),
                   lines_text(report["max_deviation_joint_line"].get<int>(),
                              report["max_deviation_job_line"].get<int>())
                       .c_str());
  }
  const long joints = report["violations"]["position"]["count"].get<long>() +
                      report["violations"]["velocity"]["count"].get<long>();
  if (joints > 0) {
    why += printed("%ld %s a joint's travel or speed. ", joints,
                   joints == 1 ? "finding passes" : "findings pass");
  }
  const long pen = report["violations"]["pen"]["count"].get<long>();
  if (pen > 0) {
    why += printed("%ld %s the pen wrong against the job. ", pen,
                   pen == 1 ? "stretch has" : "stretches have");
  }
  const json& downs = report["pen_downs"];
  if (downs["joint_program"] != downs["job"]) {
    why += printed("The pen goes down %ld times where the job puts it down %ld times. ",
                   downs["joint_program"].get<long>(), downs["job"].get<long>());
  }
  if (report["passed"].get<bool>()) {
    return printed("Passed: the whole job traced, every block within the tolerance %.6g mm.",
                   tolerance);
  }
  return "Failed. " + why;
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
  const machine::Machine& machine = recorder.machine();
  json data = base_data(kind, machine, report, title);
  data["summary"] = kind == "verify" ? verify_summary(report, machine)
                                     : post_summary(report, recorder, largest_deviation(recorder));
  data["worst_joint_index"] = joint_nearest_its_travel(machine, recorder.buckets());
  data["drawing"] = drawing_json(machine, recorder.moments().moments());
  data["path"] = path_json(recorder.path().points());
  data["block_ends"] = true;
  if (!outline.empty()) data["job_outline"] = path_json(outline);
  data["colour"] = {{"label", "deviation"}, {"unit", "mm"}};
  data["marks"] = json::array();
  data["marks_title"] = "Findings";
  if (kind == "verify") {
    std::map<std::string, long> shown;
    data["marks"] = verify_marks(report, recorder, tolerance_mm, shown);
    data["marks_note"] = marks_note(report, shown);
    data["verdict"] = verdict(report);
    data["passed"] = report["passed"];
  }
  // The abscissa is the polyline through the block ends, not the job's length: say so.
  data["charts"] = {
      {"x", chart_axis(recorder.buckets(), "path through home and the block ends", "mm")},
      {"quantities", block_quantities(machine, recorder.buckets(), tolerance_mm)}};
  data["slider"] = {{"label", "along the block ends' path"}, {"unit", "mm"}};
  return page_with(data, title);
}

}  // namespace pkm::view
