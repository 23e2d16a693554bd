// FluidNC's config.yaml (and Maslow 4's maslow.yaml) -> the machine it describes
// (docs/firmware-fluidnc.md). FluidNC reads a
// subset of YAML (bdring/FluidNC, FluidNC/src/Configuration/Tokenizer.cpp): "key: value" lines
// nested by spaces, whole-line '#' comments, values to the end of the line (quotes optional),
// keys matched without regard to case. This reader takes the same subset.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "pkm/firmware/fluidnc.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

struct Node {
  std::string key;
  std::string value;
  int line = 0;
  int indent = -1;
  std::vector<int> children;          // indices into Document::nodes
  std::vector<std::string> comments;  // whole-line comments inside the section, without '#'
};

struct Document {
  std::string source;
  std::vector<Node> nodes;  // nodes[0]: the file itself

  [[noreturn]] void fail(int line, const std::string& key, const std::string& why) const {
    throw FirmwareFileError(source + ":" + std::to_string(line) + ": " + key + ": " + why);
  }
  const Node* child(const Node& parent, std::string_view key) const {
    for (const int index : parent.children) {
      const std::string& name = nodes[index].key;
      if (name.size() == key.size() &&
          std::equal(name.begin(), name.end(), key.begin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) ==
                   std::tolower(static_cast<unsigned char>(b));
          })) {
        return &nodes[index];
      }
    }
    return nullptr;
  }
  const Node& require(const Node& parent, std::string_view key) const {
    const Node* found = child(parent, key);
    if (!found) {
      fail(parent.line, std::string(key),
           "missing" + (parent.key.empty() ? std::string() : " in " + parent.key + ":"));
    }
    return *found;
  }
  double number(const Node& node) const {
    const std::string& text = node.value;
    char* end = nullptr;
    const double value = text.empty() ? NAN : std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
      fail(node.line, node.key, "'" + text + "' is not a number");
    }
    return value;
  }
  std::optional<double> number(const Node& parent, std::string_view key) const {
    const Node* found = child(parent, key);
    if (!found) return std::nullopt;
    return number(*found);
  }
};

std::string trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\f");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\f");
  return std::string(text.substr(first, last - first + 1));
}

// FluidNC's line rules: indentation by spaces only, a key of identifier characters before ':'.
Document parse(std::string_view text, const std::string& source) {
  Document doc{source, {Node{}}};
  std::vector<int> open = {0};  // the sections enclosing the next line, innermost last
  std::istringstream lines{std::string(text)};
  std::string raw;
  for (int number = 1; std::getline(lines, raw); ++number) {
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    const auto indent_end = raw.find_first_not_of(' ');
    if (indent_end == std::string::npos) continue;
    const int indent = static_cast<int>(indent_end);
    const std::string_view line = std::string_view(raw).substr(indent_end);
    if (line.front() == '\t') doc.fail(number, "(indentation)", "use spaces, not tabs");
    while (open.size() > 1 && doc.nodes[open.back()].indent >= indent) open.pop_back();
    if (line.front() == '#') {
      doc.nodes[open.back()].comments.push_back(trim(line.substr(1)));
      continue;
    }
    const auto colon = line.find(':');
    const bool identifier =
        std::isalnum(static_cast<unsigned char>(line.front())) || line.front() == '_';
    if (colon == std::string_view::npos || !identifier) {
      doc.fail(number, trim(line.substr(0, colon)), "expected 'key: value' (FluidNC's YAML)");
    }
    Node node;
    node.key = trim(line.substr(0, colon));
    node.value = trim(line.substr(colon + 1));
    // A quoted value ends at its closing quote; FluidNC drops what follows (a comment).
    if (!node.value.empty() && (node.value.front() == '"' || node.value.front() == '\'')) {
      const auto close = node.value.find(node.value.front(), 1);
      if (close == std::string::npos) doc.fail(number, node.key, "no closing quote");
      node.value = node.value.substr(1, close - 1);
    }
    node.line = number;
    node.indent = indent;
    doc.nodes.push_back(std::move(node));
    const int index = static_cast<int>(doc.nodes.size()) - 1;
    doc.nodes[open.back()].children.push_back(index);
    open.push_back(index);
  }
  return doc;
}

// The home FluidNC's frame starts at, from the startup line pkmkit writes ("G10 L2 P1 X.. Y..
// [Z..]": G54's origin at -home); (0, 0, 0) without one.
std::vector<double> read_home(const Document& doc, bool has_z, std::vector<std::string>& notes) {
  std::vector<double> home = {0.0, 0.0, 0.0};
  const Node* macros = doc.child(doc.nodes[0], "macros");
  const Node* line = macros ? doc.child(*macros, "startup_line0") : nullptr;
  if (!line || line->value.rfind("G10 L2 P1 ", 0) != 0) {
    notes.push_back(
        "home (0, 0): FluidNC's WallPlotter starts with the pen at its frame's origin, and no "
        "'startup_line0: G10 L2 P1 ...' moves G54 elsewhere");
    return home;
  }
  std::istringstream words(line->value.substr(10));
  std::string word;
  while (words >> word) {
    const int axis = word[0] == 'X' ? 0 : word[0] == 'Y' ? 1 : word[0] == 'Z' ? 2 : -1;
    Node value = *line;
    value.value = word.substr(1);
    if (axis < 0 || (axis == 2 && !has_z)) doc.fail(line->line, line->key, "unexpected " + word);
    home[axis] = -doc.number(value);
  }
  notes.push_back("home = the pen's place at power-on, from macros: startup_line0 (" + line->value +
                  ")");
  return home;
}

// The machine file's limits pkmkit writes as a comment ("pkmkit limits: MIN .. MAX mm").
std::optional<std::pair<double, double>> pkmkit_limits(const Node& axis) {
  for (const std::string& comment : axis.comments) {
    double low = 0.0, high = 0.0;
    char unit[8] = {};
    if (std::sscanf(comment.c_str(), "pkmkit limits: %lf .. %lf %7s", &low, &high, unit) == 3) {
      return std::make_pair(low, high);
    }
  }
  return std::nullopt;
}

machine::ImportedJoint read_axis(const Document& doc, const Node& axes, const char* letter,
                                 const std::string& name, double home_reading,
                                 std::vector<std::string>& notes, bool angular = false,
                                 std::optional<double> fallback_min = std::nullopt) {
  const Node& axis = doc.require(axes, letter);
  machine::ImportedJoint joint;
  joint.name = name;
  joint.angular = angular;
  const std::string where = std::string("axes: ") + letter + ": ";
  // FluidNC's defaults (Machine/Axis.h) where the file leaves a setting out.
  auto setting = [&](const char* key, double fallback) {
    if (const std::optional<double> value = doc.number(axis, key)) return *value;
    notes.push_back(where + key + " is not set: FluidNC's default " +
                    machine::toml_number(fallback));
    return fallback;
  };
  joint.max_velocity = setting("max_rate_mm_per_min", 1000.0) / 60.0;
  joint.max_acceleration = setting("acceleration_mm_per_sec2", 25.0);
  const double travel = setting("max_travel_mm", 1000.0);
  joint.steps_per_unit = doc.number(axis, "steps_per_mm");
  if (const auto limits = pkmkit_limits(axis)) {
    joint.min = limits->first;
    joint.max = limits->second;
  } else {
    // FluidNC's WallPlotter has no limits: a range of max_travel_mm around home; a delta's arms
    // from up_degrees on.
    joint.min = fallback_min ? *fallback_min
                             : std::max(home_reading - travel / 2.0,
                                        letter[0] == 'z' || angular ? -INFINITY : 0.0);
    joint.max = joint.min + travel;
    notes.push_back(where + "limits " + machine::toml_number(joint.min) + " .. " +
                    machine::toml_number(joint.max) + (angular ? " deg" : " mm") +
                    (fallback_min ? ": from up_degrees, max_travel_mm on"
                                  : ": FluidNC checks none; max_travel_mm placed about the start"));
  }
  joint.home = home_reading;
  return joint;
}

std::vector<std::string> ignored_sections(const Document& doc) {
  std::vector<std::string> ignored;
  for (const int index : doc.nodes[0].children) {
    const std::string& key = doc.nodes[index].key;
    if (key != "kinematics" && key != "axes" && key != "macros" && key != "name") {
      ignored.push_back(key);
    }
  }
  return ignored;
}

// FluidNC's parallel_delta: pkmkit's rotary delta with the triangles' sides turned back into
// radii (r = side / (2 sqrt(3))); the arms' readings are FluidNC's motor positions (deg).
machine::ImportedMachine read_parallel_delta(const Document& doc, const Node& delta) {
  const Node& root = doc.nodes[0];
  machine::ImportedMachine imported;
  imported.source = doc.source;
  imported.origin =
      "Imported by `pkm import fluidnc " + doc.source + "` from FluidNC's parallel_delta";
  const Node* name = doc.child(root, "name");
  imported.name =
      name && !name->value.empty() ? name->value : "FluidNC rotary delta (" + doc.source + ")";
  const double to_radius = 1.0 / (2.0 * std::sqrt(3.0));
  kinematics::RotaryDeltaForm form;
  form.arm_length_mm = doc.number(doc.require(delta, "crank_mm"));
  form.base_radius_mm = doc.number(doc.require(delta, "base_triangle_mm")) * to_radius;
  form.forearm_length_mm = doc.number(doc.require(delta, "linkage_mm"));
  form.platform_radius_mm = doc.number(doc.require(delta, "end_effector_triangle_mm")) * to_radius;
  imported.kinematics_section =
      machine::kinematics_toml(*kinematics::make_form_kinematics(form), machine::LengthUnit::mm);
  const Node& axes = doc.require(root, "axes");
  const char* letters[] = {"x", "y", "z"};
  const double up_degrees = doc.number(delta, "up_degrees").value_or(-30.0);  // FluidNC's default
  for (int arm = 0; arm < 3; ++arm) {
    imported.joints.push_back(read_axis(doc, axes, letters[arm], "arm" + std::to_string(arm), 0.0,
                                        imported.notes, true, up_degrees));
  }
  // FluidNC's start, unhomed: the arms horizontal; below the pivots by about a forearm.
  imported.home_seed_z = -form.forearm_length_mm;
  imported.max_feed_per_min = 6000.0;
  imported.max_acceleration = 1000.0;
  imported.notes.push_back(
      "[cartesian] max_feed 6000 mm/min and max_acceleration 1000 mm/s^2: FluidNC limits the "
      "arms only; set the tool's");
  imported.notes.push_back("home = the arms horizontal, where FluidNC starts unhomed");
  return imported;
}

// Maslow's MaslowKinematics: four belts tl tr bl br on axes a b c d, one swivel arm of
// beltEndExtension + armLength, the tie points at the router's z less each corner's Z.
machine::ImportedMachine read_maslow(const Document& doc, const Node& maslow) {
  const Node& root = doc.nodes[0];
  const Node& axes = doc.require(root, "axes");
  machine::ImportedMachine imported;
  imported.source = doc.source;
  imported.origin = "Imported by `pkm import fluidnc " + doc.source + "` from MaslowKinematics";
  const Node* name = doc.child(root, "name");
  imported.name = name && !name->value.empty() ? name->value : "Maslow 4 (" + doc.source + ")";
  kinematics::CableRobotForm form;
  form.planar = true;
  form.cables_follow_z = true;
  const double arm = doc.number(doc.require(maslow, "beltEndExtension")) +
                     doc.number(doc.require(maslow, "armLength"));
  const char* corners[] = {"tl", "tr", "bl", "br"};
  for (const char* corner : corners) {
    const std::string c(corner);
    form.anchors_mm.emplace_back(doc.number(doc.require(maslow, c + "X")),
                                 doc.number(doc.require(maslow, c + "Y")),
                                 -doc.number(doc.require(maslow, c + "Z")));
    form.cable_offsets_mm.push_back(0.0);
    form.swivel_arms_mm.push_back(arm);
  }
  const Eigen::Vector2d centre = maslow_centre(form.anchors_mm);
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(
      form, kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy()));
  imported.kinematics_section = machine::kinematics_toml(*model, machine::LengthUnit::mm);
  const char letters[][2] = {"a", "b", "c", "d"};
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& a = form.anchors_mm[k];
    const double plan = (a.head<2>() - centre).norm() - arm;
    imported.joints.push_back(
        read_axis(doc, axes, letters[k], corners[k], std::hypot(plan, a.z()), imported.notes));
  }
  imported.joints.push_back(read_axis(doc, axes, "z", "z", 0.0, imported.notes));
  double feed = INFINITY, acceleration = INFINITY;
  for (int k = 0; k < 4; ++k) {
    feed = std::min(feed, imported.joints[k].max_velocity * 60.0);
    acceleration = std::min(acceleration, imported.joints[k].max_acceleration);
  }
  imported.max_feed_per_min = feed;
  imported.max_acceleration = acceleration;
  imported.notes.push_back(
      "[cartesian] max_feed and max_acceleration: the belts' (FluidNC limits the motors only)");
  imported.notes.push_back(
      "home = Maslow's origin, the crossing of the frame's diagonals; joint reading = the belt's "
      "length (mm)");
  imported.home = std::vector<double>{centre.x(), centre.y(), 0.0};
  std::string unread;
  for (const int index : maslow.children) {
    const std::string& key = doc.nodes[index].key;
    if (key.size() != 3 && key != "beltEndExtension" && key != "armLength") {
      unread += (unread.empty() ? "" : ", ") + key;
    }
  }
  for (const std::string& key : ignored_sections(doc)) unread += (unread.empty() ? "" : ", ") + key;
  if (!unread.empty()) imported.notes.push_back("not imported (not these kinematics): " + unread);
  return imported;
}

}  // namespace

machine::ImportedMachine read_fluidnc(std::string_view text, const std::string& source) {
  const Document doc = parse(text, source);
  const Node& root = doc.nodes[0];
  const Node& kinematics = doc.require(root, "kinematics");
  if (const Node* delta = doc.child(kinematics, "parallel_delta")) {
    return read_parallel_delta(doc, *delta);
  }
  if (const Node* maslow = doc.child(kinematics, "MaslowKinematics")) {
    return read_maslow(doc, *maslow);
  }
  const Node* wall = doc.child(kinematics, "WallPlotter");
  if (!wall) {
    const std::string found =
        kinematics.children.empty() ? std::string("none") : doc.nodes[kinematics.children[0]].key;
    doc.fail(kinematics.line, "kinematics",
             found +
                 ": pkmkit imports FluidNC's WallPlotter, parallel_delta and Maslow's "
                 "MaslowKinematics only");
  }
  for (const char* key : {"left_axis", "right_axis"}) {
    const Node* axis = doc.child(*wall, key);
    const double expected = key[0] == 'l' ? 0.0 : 1.0;
    if (axis && doc.number(*axis) != expected) {
      doc.fail(axis->line, key,
               "FluidNC's WallPlotter drives axes 0 and 1 (cartesian_to_motors); only " +
                   machine::toml_number(expected) + " moves this cord");
    }
  }
  const Node& axes = doc.require(root, "axes");
  const bool has_z = doc.child(axes, "z") != nullptr;

  machine::ImportedMachine imported;
  imported.source = source;
  imported.origin = "Imported by `pkm import fluidnc " + source + "` from FluidNC's WallPlotter";
  const Node* name = doc.child(root, "name");
  imported.name =
      name && !name->value.empty() ? name->value : "FluidNC wall plotter (" + source + ")";
  const std::vector<double> home = read_home(doc, has_z, imported.notes);
  kinematics::WallPlotterForm form;
  for (int k = 0; k < 2; ++k) {
    const char* side = k == 0 ? "left" : "right";
    const double x = doc.number(doc.require(*wall, std::string(side) + "_anchor_x"));
    const double y = doc.number(doc.require(*wall, std::string(side) + "_anchor_y"));
    form.anchors_mm[k] = Eigen::Vector2d(x + home[0], y + home[1]);
  }
  const kinematics::PassThroughAxes passthrough =
      has_z ? kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy())
            : kinematics::PassThroughAxes();
  imported.kinematics_section = machine::kinematics_toml(
      *kinematics::make_form_kinematics(form, passthrough), machine::LengthUnit::mm);
  const Eigen::Vector2d home_xy(home[0], home[1]);
  imported.joints.push_back(
      read_axis(doc, axes, "x", "left", (form.anchors_mm[0] - home_xy).norm(), imported.notes));
  imported.joints.push_back(
      read_axis(doc, axes, "y", "right", (form.anchors_mm[1] - home_xy).norm(), imported.notes));
  if (has_z) imported.joints.push_back(read_axis(doc, axes, "z", "z", home[2], imported.notes));
  imported.max_feed_per_min =
      std::min(imported.joints[0].max_velocity, imported.joints[1].max_velocity) * 60.0;
  imported.max_acceleration =
      std::min(imported.joints[0].max_acceleration, imported.joints[1].max_acceleration);
  imported.notes.push_back(
      "[cartesian] max_feed and max_acceleration: the cords' (FluidNC limits the motors only)");
  imported.notes.push_back("joint reading = the cord's length from its anchor (mm)");
  imported.home = has_z ? home : std::vector<double>{home[0], home[1], 0.0};
  const std::vector<std::string> ignored = ignored_sections(doc);
  if (!ignored.empty()) {
    std::string list;
    for (const std::string& key : ignored) list += (list.empty() ? "" : ", ") + key;
    imported.notes.push_back("not imported (not kinematics): " + list);
  }
  return imported;
}

}  // namespace pkm::firmware
