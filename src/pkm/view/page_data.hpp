// The pieces every view's data is made of (internal to the view module): numbers rounded to what
// a screen shows, the machine's joints and drawing, the thinned path, chart series, summary rows,
// and the page itself from web/'s template.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pkm/view/recorders.hpp"

namespace pkm::view {

// printf into a string of at most 319 characters: a page's sentences.
inline std::string printed(const char* format, auto... values) {
  char text[320];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

// Six significant digits (null for NaN or infinity).
nlohmann::json rounded(double value);
nlohmann::json rounded_array(const std::vector<double>& values, double scale = 1.0);

// Each joint's name, unit and limits in interface units (mm or deg).
nlohmann::json joints_json(const machine::Machine& machine);
// {"fixed": [...], "t": [...], "frames": [{"parts": [...], "tool": [x, y, z]}]}; segments flat as
// part, x0 y0 z0, x1 y1 z1.
nlohmann::json drawing_json(const machine::Machine& machine, const std::vector<Moment>& moments);
// {"t", "x", "y", "z", "c"}: the thinned path as columns; with `pen`, "p" too: 1 where the pen
// was down on the way to the point, 0 where it was up.
nlohmann::json path_json(const std::vector<PathPoint>& points, bool pen = false);
// The line start nearest to G-code line `line` (which may have none: a move shorter than one
// period): its own, else the next line's that has one, else the last. `starts` not empty.
const LineStart& nearest_line_start(const std::map<int, LineStart>& starts, int line);
// A mark on the path: {"t", "x", "y", "z", "label"}.
nlohmann::json mark_json(const LineStart& at, const std::string& label);
// The "units shown" row: every page is in mm and deg, whatever the machine file's unit.
nlohmann::json units_row(const machine::Machine& machine);
// One chart series of a channel: min/max per bucket times `scale`, the band outside [lo, hi].
nlohmann::json series_json(const MinMaxBuckets& buckets, int channel, double scale, double lo,
                           double hi);
// Interface units per internal unit of a joint (deg per rad for rotary joints).
double interface_scale(const machine::JointSpec& joint);
// The charts' abscissa: each bucket's first and last x.
nlohmann::json chart_axis(const MinMaxBuckets& buckets, const std::string& label,
                          const std::string& unit);
// A summary row: `value` as the report has it (a number or a name), with its unit.
nlohmann::json row(const std::string& key, const std::string& label, const nlohmann::json& value,
                   const std::string& unit);
double number_or(const nlohmann::json& value, double fallback);

// The joint that comes nearest an end of its travel (as a fraction of the travel), its position
// being channel i of `buckets`: the charts of post, verify and view open on it, as plan's open on
// the joint nearest its speed or acceleration limit.
int joint_nearest_its_travel(const machine::Machine& machine, const MinMaxBuckets& buckets);

// kind, title, machine name, planar, joints and the report verbatim.
nlohmann::json base_data(const std::string& kind, const machine::Machine& machine,
                         const nlohmann::json& report, const std::string& title);
// The page: web/'s template with the title and the data (every '<' in it escaped).
std::string page_with(const nlohmann::json& data, const std::string& title);

}  // namespace pkm::view
