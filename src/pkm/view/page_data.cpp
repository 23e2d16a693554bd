#include "pkm/view/page_data.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <string_view>

#include "pkm/machine/pose_tensions.hpp"
#include "pkm/view/machine_drawing.hpp"
#include "pkm/view/web_assets.hpp"

namespace pkm::view {

using nlohmann::json;

// Six significant digits: a thousandth of a millimetre on a metre-wide machine, and a third of
// the bytes of a double's full digits. NaN (an empty bucket) becomes null.
json rounded(double value) {
  if (!std::isfinite(value)) return nullptr;
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return std::strtod(text, nullptr);
}

json rounded_array(const std::vector<double>& values, double scale) {
  json out = json::array();
  for (double value : values) out.push_back(rounded(value * scale));
  return out;
}

json joints_json(const machine::Machine& machine) {
  json joints = json::array();
  for (const machine::JointSpec& joint : machine.joints()) {
    joints.push_back({{"name", joint.name},
                      {"unit", joint.interface_unit()},
                      {"min", rounded(joint.to_interface(joint.min))},
                      {"max", rounded(joint.to_interface(joint.max))},
                      {"max_velocity", rounded(joint.to_interface(joint.max_velocity))},
                      {"max_acceleration", rounded(joint.to_interface(joint.max_acceleration))}});
  }
  return joints;
}

static void append_segments(json& flat, const std::vector<Segment>& segments) {
  for (const Segment& segment : segments) {
    flat.push_back(static_cast<int>(segment.part));
    for (const Eigen::Vector3d* point : {&segment.from, &segment.to}) {
      for (int k = 0; k < 3; ++k) flat.push_back(rounded((*point)[k]));
    }
  }
}

// The cables' tensions at rest at a drawn moment: {"N": [..], "held": b}; null where the
// cables have no balance there.
static json frame_tensions(const machine::Machine& machine, const geometry::Pose& pose) {
  const std::optional<machine::PoseTensions> tensions = machine::pose_tensions(machine, pose);
  if (!tensions) return nullptr;
  return {{"N", rounded_array(tensions->tension_N)}, {"held", tensions->held}};
}

// The machine: fixed parts once, moving parts at each moment (flat: part, x0 y0 z0, x1 y1 z1);
// for a machine hung on cables, their names and limits and each moment's tensions at rest.
json drawing_json(const machine::Machine& machine, const std::vector<Moment>& moments) {
  json fixed = json::array();
  append_segments(fixed, fixed_parts(machine));
  const bool tensions = machine::lists_tensions(machine);
  json times = json::array(), frames = json::array();
  for (const Moment& moment : moments) {
    times.push_back(rounded(moment.t));
    json flat = json::array();
    append_segments(flat, moving_parts(machine, moment.pose, moment.joints));
    json tool = json::array();
    for (int k = 0; k < 3; ++k) tool.push_back(rounded(moment.pose.position_mm[k]));
    frames.push_back({{"parts", flat}, {"tool", tool}});
    if (tensions) frames.back()["tensions"] = frame_tensions(machine, moment.pose);
  }
  json out = {{"fixed", fixed}, {"t", times}, {"frames", frames}};
  if (const auto at_home =
          tensions ? machine::pose_tensions(machine, machine.home()) : std::nullopt) {
    out["cables"] = {{"names", at_home->names},
                     {"limits", machine::limits_text(*at_home)},
                     {"home_N", rounded_array(at_home->tension_N)}};
  }
  return out;
}

json path_json(const std::vector<PathPoint>& points, bool pen) {
  json t = json::array(), x = json::array(), y = json::array(), z = json::array(),
       c = json::array(), p = json::array();
  for (const PathPoint& point : points) {
    t.push_back(rounded(point.t));
    x.push_back(rounded(point.position.x()));
    y.push_back(rounded(point.position.y()));
    z.push_back(rounded(point.position.z()));
    c.push_back(rounded(point.colour));
    if (pen) p.push_back(point.pen_down ? 1 : 0);
  }
  json out = {{"t", t}, {"x", x}, {"y", y}, {"z", z}, {"c", c}};
  if (pen) out["p"] = p;
  return out;
}

const LineStart& nearest_line_start(const std::map<int, LineStart>& starts, int line) {
  const auto next = starts.lower_bound(line);
  return next != starts.end() ? next->second : std::prev(starts.end())->second;
}

json mark_json(const LineStart& at, const std::string& label) {
  return {{"t", rounded(at.t)},
          {"x", rounded(at.position.x())},
          {"y", rounded(at.position.y())},
          {"z", rounded(at.position.z())},
          {"label", label}};
}

json units_row(const machine::Machine& machine) {
  const bool inch = machine.units() == machine::LengthUnit::inch;
  return row("units", "units shown",
             inch ? "mm and deg (the machine file is in inches)" : "mm and deg", "");
}

// One chart series: a channel's buckets in interface units, with the band outside [lo, hi].
json series_json(const MinMaxBuckets& buckets, int channel, double scale, double lo, double hi) {
  return {{"min", rounded_array(buckets.min(channel), scale)},
          {"max", rounded_array(buckets.max(channel), scale)},
          {"lo", rounded(lo)},
          {"hi", rounded(hi)}};
}

// Interface units per internal unit of joint i (deg per rad for rotary joints).
double interface_scale(const machine::JointSpec& joint) {
  return joint.to_interface(1.0);
}

json chart_axis(const MinMaxBuckets& buckets, const std::string& label, const std::string& unit) {
  return {{"label", label},
          {"unit", unit},
          {"first", rounded_array(buckets.x_first())},
          {"last", rounded_array(buckets.x_last())}};
}

// A summary row: `value` as the report has it (a number or a name), with its unit.
json row(const std::string& key, const std::string& label, const json& value,
         const std::string& unit) {
  return {{"key", key}, {"label", label}, {"value", value}, {"unit", unit}};
}

double number_or(const json& value, double fallback) {
  return value.is_number() ? value.get<double>() : fallback;
}

static std::string escaped_html(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// The page: the template with its title and data; every '<' of the data escaped so that no
// string in it (a job's name) can end the script element that holds it.
std::string page_with(const json& data, const std::string& title) {
  std::string text = data.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string safe;
  safe.reserve(text.size());
  for (char c : text) {
    if (c == '<')
      safe += "\\u003c";
    else
      safe += c;
  }
  std::string page(kViewPage);
  const auto replace = [&page](std::string_view marker, const std::string& with) {
    for (std::size_t at = page.find(marker); at != std::string::npos;
         at = page.find(marker, at + with.size())) {
      page.replace(at, marker.size(), with);
    }
  };
  replace("@PKM_TITLE@", escaped_html(title));
  replace("@PKM_DATA@", safe);
  return page;
}

json base_data(const std::string& kind, const machine::Machine& machine, const json& report,
               const std::string& title) {
  return {{"kind", kind},
          {"title", title},
          {"machine", machine.name()},
          {"planar", drawn_planar(machine)},
          {"joints", joints_json(machine)},
          {"report", report}};
}

int joint_nearest_its_travel(const machine::Machine& machine, const MinMaxBuckets& buckets) {
  const std::vector<machine::JointSpec>& joints = machine.joints();
  int nearest = 0;
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const double travel = joints[i].max - joints[i].min;
    if (!(travel > 0.0) || !std::isfinite(travel)) continue;
    const int channel = static_cast<int>(i);
    for (double low : buckets.min(channel)) {
      if (std::isfinite(low) && (low - joints[i].min) / travel < least) {
        least = (low - joints[i].min) / travel;
        nearest = channel;
      }
    }
    for (double high : buckets.max(channel)) {
      if (std::isfinite(high) && (joints[i].max - high) / travel < least) {
        least = (joints[i].max - high) / travel;
        nearest = channel;
      }
    }
  }
  return nearest;
}

}  // namespace pkm::view
