#include "pkm/calibration/calibration_pattern.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "pkm/calibration/measurements.hpp"

namespace pkm::calibration {

namespace {

using Json = nlohmann::json;

// Largest coordinate pattern.json may hold (mm): far beyond any machine.
constexpr double kLargestCoordinate_mm = 1e6;

// 1-based line and column of a byte offset in `text`.
std::string location_of(const std::string& source, const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  int line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') ++line, line_start = i + 1;
  }
  return source + ":" + std::to_string(line) + ":" + std::to_string(offset - line_start + 1);
}

// An input iterator over the text that tells how far the JSON parser has read.
class CountingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;
  CountingIterator(const char* position, std::size_t* read) : position_(position), read_(read) {}
  reference operator*() const { return *position_; }
  CountingIterator& operator++() {
    ++position_;
    ++*read_;
    return *this;
  }
  bool operator==(const CountingIterator& other) const { return position_ == other.position_; }
  bool operator!=(const CountingIterator& other) const { return position_ != other.position_; }

 private:
  const char* position_;
  std::size_t* read_;
};

// A SAX pass that records where each value starts, by JSON pointer ("/marks/3/x"): nlohmann's
// DOM keeps no positions. A value's token starts at the first character after the previous
// token that is no blank, ',' or ':' (the parser reads at most one character past a number).
class ValueLocations : public nlohmann::json_sax<Json> {
 public:
  explicit ValueLocations(const std::string& text) : text_(text) {}
  std::size_t read = 0;
  std::map<std::string, std::size_t> starts;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }
  bool key(string_t& name) override {
    token_start();
    frames_.back().key = name;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& error) override {
    error_position = position;
    error_message = error.what();
    return false;
  }
  std::size_t error_position = 0;
  std::string error_message;

 private:
  struct Frame {
    std::string pointer;
    bool array = false;
    int index = 0;
    std::string key;
  };
  std::size_t token_start() {
    std::size_t start = last_end_;
    while (start < text_.size() &&
           std::string_view(" \t\r\n,:").find(text_[start]) != std::string_view::npos)
      ++start;
    last_end_ = read;
    return start;
  }
  std::string pointer() const {
    if (frames_.empty()) return "";
    const Frame& top = frames_.back();
    return top.pointer + "/" + (top.array ? std::to_string(top.index) : top.key);
  }
  void advance() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }
  bool value() {
    starts[pointer()] = token_start();
    advance();
    return true;
  }
  bool open(bool array) {
    const std::string here = pointer();
    starts[here] = token_start();
    frames_.push_back({here, array, 0, {}});
    return true;
  }
  bool close() {
    last_end_ = read;
    frames_.pop_back();
    advance();
    return true;
  }
  const std::string& text_;
  std::size_t last_end_ = 0;
  std::vector<Frame> frames_;
};

// The marks of a parsed pattern.json; `where` gives a value's file:line:column by pointer.
std::vector<PatternMark> marks_of(const Json& document,
                                  const std::function<std::string(const std::string&)>& where) {
  const auto fail = [&](const std::string& pointer, const std::string& message) {
    throw PatternFileError(where(pointer) + ": " + message);
  };
  if (!document.is_object()) fail("", "expected an object {\"marks\": [...]}");
  for (const auto& [key, value] : document.items()) {
    if (key != "marks") fail("/" + key, "unknown key '" + key + "' (expected only \"marks\")");
  }
  if (!document.contains("marks")) fail("", "no \"marks\": expected {\"marks\": [...]}");
  const Json& list = document["marks"];
  if (!list.is_array() || list.empty()) fail("/marks", "\"marks\" must be a non-empty array");
  std::vector<PatternMark> marks;
  std::map<long long, std::string> first_of_id;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string at = "/marks/" + std::to_string(i);
    const Json& entry = list[i];
    if (!entry.is_object()) fail(at, "a mark must be an object {\"id\": 1, \"x\": .., \"y\": ..}");
    for (const auto& [key, value] : entry.items()) {
      if (key != "id" && key != "x" && key != "y")
        fail(at + "/" + key, "unknown key '" + key + "' in a mark (expected id, x, y)");
    }
    for (const char* key : {"id", "x", "y"}) {
      if (!entry.contains(key)) fail(at, std::string("the mark has no \"") + key + "\"");
    }
    const Json& id = entry["id"];
    if (!id.is_number_integer() || id.get<long long>() < 1 || id.get<long long>() > 1000000)
      fail(at + "/id", "a mark's id must be a whole number 1..1000000");
    const long long number = id.get<long long>();
    if (const auto seen = first_of_id.find(number); seen != first_of_id.end())
      fail(at + "/id",
           "mark " + std::to_string(number) + " appears twice (first at " + seen->second + ")");
    PatternMark mark;
    mark.id = static_cast<int>(number);
    mark.location = where(at);
    first_of_id[number] = mark.location;
    for (int axis = 0; axis < 2; ++axis) {
      const std::string key = axis == 0 ? "x" : "y";
      const Json& value = entry[key];
      if (!value.is_number()) fail(at + "/" + key, key + " must be a number (mm)");
      const double coordinate = value.get<double>();
      if (!std::isfinite(coordinate) || std::abs(coordinate) > kLargestCoordinate_mm)
        fail(at + "/" + key, key + " must be a finite number of at most 1e6 mm in size");
      mark.position_mm[axis] = coordinate;
    }
    marks.push_back(mark);
  }
  return marks;
}

// The seven-segment stroke font: polylines per digit on a 1 x 2 cell (x right, y up), each
// digit drawn with as few pen lifts as its shape allows.
using Polyline = std::vector<Eigen::Vector2d>;
const std::array<std::vector<Polyline>, 10>& digit_strokes() {
  using V = Eigen::Vector2d;
  static const std::array<std::vector<Polyline>, 10> font = {{
      {{V(0, 0), V(1, 0), V(1, 2), V(0, 2), V(0, 0)}},                      // 0
      {{V(0.5, 1.6), V(1, 2), V(1, 0)}},                                    // 1
      {{V(0, 2), V(1, 2), V(1, 1), V(0, 1), V(0, 0), V(1, 0)}},             // 2
      {{V(0, 2), V(1, 2), V(1, 0), V(0, 0)}, {V(0, 1), V(1, 1)}},           // 3
      {{V(0, 2), V(0, 1), V(1, 1)}, {V(1, 2), V(1, 0)}},                    // 4
      {{V(1, 2), V(0, 2), V(0, 1), V(1, 1), V(1, 0), V(0, 0)}},             // 5
      {{V(1, 2), V(0, 2), V(0, 0), V(1, 0), V(1, 1), V(0, 1)}},             // 6
      {{V(0, 2), V(1, 2), V(1, 0)}},                                        // 7
      {{V(0, 0), V(1, 0), V(1, 2), V(0, 2), V(0, 0)}, {V(0, 1), V(1, 1)}},  // 8
      {{V(1, 1), V(0, 1), V(0, 2), V(1, 2), V(1, 0), V(0, 0)}},             // 9
  }};
  return font;
}

// The footprint of a mark around its centre: the cross (+-size) and the number to its upper
// right (up to 3 digits: 2.5 size wide, 1.4 size high): the points a mark must reach.
std::vector<Eigen::Vector2d> footprint(const Eigen::Vector2d& centre, double size, double margin) {
  const double left = -size - margin, right = 3.0 * size + margin;
  const double bottom = -size - margin, top = 1.5 * size + margin;
  std::vector<Eigen::Vector2d> points{centre};
  constexpr int kPerSide = 4;
  for (int k = 0; k <= kPerSide; ++k) {
    const double u = static_cast<double>(k) / kPerSide;
    points.push_back(centre + Eigen::Vector2d(left + u * (right - left), bottom));
    points.push_back(centre + Eigen::Vector2d(left + u * (right - left), top));
    points.push_back(centre + Eigen::Vector2d(left, bottom + u * (top - bottom)));
    points.push_back(centre + Eigen::Vector2d(right, bottom + u * (top - bottom)));
  }
  return points;
}

bool reaches(const machine::Machine& machine, const Eigen::Vector2d& point) {
  geometry::Pose pose = machine.home();
  pose.position_mm.x() = point.x();
  pose.position_mm.y() = point.y();
  kinematics::JointVector joints;
  return machine.inverse(pose, joints).ok() &&
         planar_conditioning(machine.kinematics(), pose) >= kMinPatternConditioning;
}

// Farthest-point sampling: the candidate nearest the sheet's top left corner first, then each
// time the candidate farthest from every mark chosen so far.
std::vector<Eigen::Vector2d> spread(const std::vector<Eigen::Vector2d>& candidates, int count,
                                    const Eigen::Vector2d& corner) {
  std::vector<double> nearest(candidates.size(), std::numeric_limits<double>::infinity());
  std::vector<Eigen::Vector2d> chosen;
  std::size_t next = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if ((candidates[i] - corner).norm() < (candidates[next] - corner).norm()) next = i;
  }
  while (static_cast<int>(chosen.size()) < count) {
    chosen.push_back(candidates[next]);
    for (std::size_t i = 0; i < candidates.size(); ++i)
      nearest[i] = std::min(nearest[i], (candidates[i] - candidates[next]).norm());
    next = static_cast<std::size_t>(std::max_element(nearest.begin(), nearest.end()) -
                                    nearest.begin());
  }
  return chosen;
}

double closest_pair(const std::vector<Eigen::Vector2d>& points) {
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < points.size(); ++a) {
    for (std::size_t b = a + 1; b < points.size(); ++b)
      closest = std::min(closest, (points[a] - points[b]).norm());
  }
  return closest;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value + 0.0);
  return text;
}

}  // namespace

double planar_conditioning(const kinematics::Kinematics& kinematics, const geometry::Pose& pose) {
  kinematics::JointJacobian jacobian;
  if (!kinematics.jacobian(pose, jacobian).ok()) return 0.0;
  const Eigen::MatrixXd columns = jacobian.leftCols(2);
  if (!columns.allFinite()) return 0.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(columns);
  const Eigen::VectorXd values = svd.singularValues();
  if (values.size() < 2 || !(values[0] > 0.0)) return 0.0;
  return values[1] / values[0];
}

std::vector<PatternMark> parse_pattern_json(const std::string& text,
                                            const std::string& source_name) {
  ValueLocations locations(text);
  if (!Json::sax_parse(CountingIterator(text.data(), &locations.read),
                       CountingIterator(text.data() + text.size(), &locations.read), &locations)) {
    // nlohmann counts the bytes read up to the end of the offending token; its message starts
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ".
    std::string message = locations.error_message;
    if (const auto colon = message.rfind("column "); colon != std::string::npos)
      message = message.substr(message.find(": ", colon) + 2);
    else if (const auto bracket = message.find("] "); bracket != std::string::npos)
      message = message.substr(bracket + 2);
    const std::size_t at = locations.error_position == 0 ? 0 : locations.error_position - 1;
    throw PatternFileError(location_of(source_name, text, at) + ": not JSON: " + message);
  }
  const Json document = Json::parse(text);
  const auto where = [&](const std::string& pointer) {
    const auto found = locations.starts.find(pointer);
    return location_of(source_name, text, found == locations.starts.end() ? 0 : found->second);
  };
  return marks_of(document, where);
}

std::vector<PatternMark> read_pattern_json(const std::filesystem::path& path) {
  std::string text;
  try {
    text = read_text_file(path);
  } catch (const MeasurementFileError& error) {
    throw PatternFileError(error.what());
  }
  return parse_pattern_json(text, path.string());
}

std::string pattern_json_text(const std::vector<PatternMark>& marks) {
  std::string text = "{\"marks\": [\n";
  char line[128];
  for (std::size_t i = 0; i < marks.size(); ++i) {
    std::snprintf(line, sizeof line, "  {\"id\": %d, \"x\": %.3f, \"y\": %.3f}%s\n", marks[i].id,
                  marks[i].position_mm.x() + 0.0, marks[i].position_mm.y() + 0.0,
                  i + 1 < marks.size() ? "," : "");
    text += line;
  }
  return text + "]}\n";
}

}  // namespace pkm::calibration

namespace pkm::calibration {

CalibrationPattern design_pattern(const machine::Machine& machine, const PatternOptions& options) {
  if (options.marks < 3 || options.marks > 999) {
    throw std::invalid_argument("the pattern needs 3..999 marks, not " +
                                std::to_string(options.marks));
  }
  machine::PoseBox box = machine::reach_box(machine);
  if (!box.axes.controls(0) || !box.axes.controls(1)) {
    throw std::invalid_argument("a calibration pattern needs a machine that moves in x and y");
  }
  if (options.sheet_mm) {
    const auto& sheet = *options.sheet_mm;
    if (!(sheet[2] > sheet[0]) || !(sheet[3] > sheet[1]))
      throw std::invalid_argument("the sheet needs x min < x max and y min < y max");
    box.min[0] = sheet[0], box.min[1] = sheet[1], box.max[0] = sheet[2], box.max[1] = sheet[3];
  }
  CalibrationPattern pattern;
  pattern.sheet_min_x_mm = box.min[0];
  pattern.sheet_max_x_mm = box.max[0];
  pattern.sheet_min_y_mm = box.min[1];
  pattern.sheet_max_y_mm = box.max[1];
  const double width = box.max[0] - box.min[0], height = box.max[1] - box.min[1];
  pattern.cross_size_mm = options.cross_size_mm > 0.0
                              ? options.cross_size_mm
                              : std::clamp(std::min(width, height) / 80.0, 2.0, 10.0);
  // A margin of 2 % of the sheet around every mark's footprint keeps marks off the reach's edge,
  // where a machine a little off its nominal geometry may not follow.
  const double margin = 0.02 * std::max(width, height);
  constexpr int kGrid = 25;
  std::vector<Eigen::Vector2d> candidates;
  for (int row = 0; row <= kGrid; ++row) {
    for (int column = 0; column <= kGrid; ++column) {
      const Eigen::Vector2d centre(box.min[0] + width * column / kGrid,
                                   box.max[1] - height * row / kGrid);
      const auto points = footprint(centre, pattern.cross_size_mm, margin);
      if (std::all_of(points.begin(), points.end(),
                      [&](const Eigen::Vector2d& p) { return reaches(machine, p); }))
        candidates.push_back(centre);
    }
  }
  if (static_cast<int>(candidates.size()) < options.marks) {
    throw std::invalid_argument(
        "the machine reaches room for only " + std::to_string(candidates.size()) + " of " +
        std::to_string(options.marks) + " marks of " + number(pattern.cross_size_mm) +
        " mm with a margin of " + number(margin) + " mm: ask for fewer marks or smaller ones");
  }
  std::vector<Eigen::Vector2d> chosen =
      spread(candidates, options.marks, Eigen::Vector2d(box.min[0], box.max[1]));
  // A mark spans 4 sizes across (cross and number): closer than 5 they would run together.
  const double closest = closest_pair(chosen);
  if (closest < 5.0 * pattern.cross_size_mm) {
    throw std::invalid_argument(
        std::to_string(options.marks) + " marks of " + number(pattern.cross_size_mm) +
        " mm would stand " + number(closest) + " mm apart and run together (at least " +
        number(5.0 * pattern.cross_size_mm) + " mm): ask for fewer marks or smaller ones");
  }
  // Numbered as read: top row first, left to right.
  std::sort(chosen.begin(), chosen.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.y() != b.y() ? a.y() > b.y() : a.x() < b.x();
  });
  for (std::size_t i = 0; i < chosen.size(); ++i)
    pattern.marks.push_back({static_cast<int>(i) + 1, chosen[i], {}});
  return pattern;
}

std::vector<std::vector<Eigen::Vector2d>> mark_strokes(const PatternMark& mark,
                                                       double cross_size_mm) {
  const Eigen::Vector2d& c = mark.position_mm;
  const double s = cross_size_mm;
  std::vector<Polyline> strokes{{c + Eigen::Vector2d(-s, 0), c + Eigen::Vector2d(s, 0)},
                                {c + Eigen::Vector2d(0, -s), c + Eigen::Vector2d(0, s)}};
  // Digits 0.5 s wide and s high, 0.8 s apart, starting 0.4 s right of and above the centre.
  const std::string digits = std::to_string(mark.id);
  for (std::size_t k = 0; k < digits.size(); ++k) {
    const Eigen::Vector2d origin = c + Eigen::Vector2d((0.4 + 0.8 * k) * s, 0.4 * s);
    for (const Polyline& line : digit_strokes()[digits[k] - '0']) {
      Polyline placed;
      for (const Eigen::Vector2d& p : line) placed.push_back(origin + 0.5 * s * p);
      strokes.push_back(placed);
    }
  }
  return strokes;
}

PenHeights default_pen_heights(const machine::Machine& machine) {
  if (machine.kinematics().dof().controls(2)) {
    const double home_z = machine.home().position_mm.z();
    return {0.0, home_z > 0.0 ? home_z : 5.0};
  }
  const machine::ToolChannel& tool = machine.tool();
  if (tool.z != machine::ToolZ::pen) return {-1.0, 5.0};
  const double side = tool.down_above ? -1.0 : 1.0;  // towards the pen's up side
  return {tool.pen_height_mm - side, tool.pen_height_mm + 5.0 * side};
}

std::string pattern_gcode(const machine::Machine& machine, const CalibrationPattern& pattern,
                          const PenHeights& pen) {
  const double down = pen.down_mm, up = pen.up_mm;
  const double feed = 0.5 * machine.cartesian().max_feed_mm_per_min;
  const auto check = [&](const Eigen::Vector2d& point, double z) {
    geometry::Pose pose = machine.home();
    pose.position_mm = Eigen::Vector3d(point.x(), point.y(), z);
    kinematics::JointVector joints;
    const kinematics::Status status = machine.inverse(pose, joints);
    if (!status.ok()) {
      throw std::invalid_argument("the pattern leaves the machine's reach at " +
                                  machine.explain(pose, status));
    }
  };
  std::string text = "(pkm calibrate pattern: " + std::to_string(pattern.marks.size()) +
                     " numbered crosses for tape-measure calibration of " + machine.name() +
                     ")\n(measure between the crosses' centres: docs/calibration.md)\n";
  text += "G21 G90\nG0 Z" + number(up) + "\nF" + number(feed) + "\n";
  for (const PatternMark& mark : pattern.marks) {
    text += "(mark " + std::to_string(mark.id) + " at x " + number(mark.position_mm.x()) + " y " +
            number(mark.position_mm.y()) + ")\n";
    for (const Polyline& stroke : mark_strokes(mark, pattern.cross_size_mm)) {
      check(stroke.front(), up);
      text += "G0 X" + number(stroke.front().x()) + " Y" + number(stroke.front().y()) + "\n";
      text += "G1 Z" + number(down) + "\n";
      for (std::size_t k = 1; k < stroke.size(); ++k) {
        check(stroke[k], down);
        text += "G1 X" + number(stroke[k].x()) + " Y" + number(stroke[k].y()) + "\n";
      }
      text += "G0 Z" + number(up) + "\n";
    }
  }
  return text + "M2\n";
}

}  // namespace pkm::calibration
