#include "pkm/firmware/rrf_hangprinter.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <optional>

#include "pkm/firmware/rrf_delta.hpp"
#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

// HangprinterKinematics' anchor letters in M669, in order (ANCHOR_CHARS): four up to RRF 3.5,
// M669 N up to 5 (the fifth is I) from RRF 3.6.
constexpr const char* kAnchorLetters = "ABCDI";
constexpr std::size_t kFourAnchors = 4;
constexpr std::size_t kMaxAnchors = 5;
// A home farther than this from x = y = z = 0 (mm) is not where RRF counts the lines from.
constexpr double kHomeTolerance_mm = 1e-9;

std::string anchor_word(char letter, const Eigen::Vector3d& anchor) {
  return std::string(1, letter) + rrf_number(anchor.x()) + ":" + rrf_number(anchor.y()) + ":" +
         rrf_number(anchor.z());
}

void check_hangprinter(const FirmwareMachine& fm, const kinematics::CableRobotForm& form) {
  const std::string& source = fm.machine.source();
  if (form.planar) {
    throw ExportRefused(source +
                        ": rrf's Hangprinter moves the tool in x y z; this cable robot is planar "
                        "(its cables hold x y only)");
  }
  if (fm.form.passthrough.count() > 0) {
    throw ExportRefused(source + ": rrf's Hangprinter drives its lines only; this machine passes " +
                        std::to_string(fm.form.passthrough.count()) + " more joint(s) through");
  }
  if (form.anchors_mm.size() > kMaxAnchors) {
    throw ExportRefused(source + ": rrf's Hangprinter holds at most 5 anchors (M669 N5, RRF " +
                        "3.6; 4 before), and this machine has " +
                        std::to_string(form.anchors_mm.size()) + " cables");
  }
  const Eigen::Vector3d home = fm.machine.home().position_mm;
  if (home.norm() > kHomeTolerance_mm) {
    throw ExportRefused(
        source + ": rrf's Hangprinter counts each line from its length at x 0 y 0 z 0 (where it " +
        "starts and where homeall.g sets the position), and this machine's home is x " +
        rrf_number(home.x()) + " y " + rrf_number(home.y()) + " z " + rrf_number(home.z()) +
        " mm. Move the machine file's frame so that home is its origin (the anchors less home)");
  }
}

const kinematics::CableRobotKinematics& robot(const FirmwareMachine& fm) {
  return dynamic_cast<const kinematics::CableRobotKinematics&>(fm.machine.kinematics());
}

bool has_spools(const FirmwareMachine& fm) {
  const auto& cables = robot(fm).geometry().cables;
  return std::any_of(cables.begin(), cables.end(),
                     [](const kinematics::RobotCable& cable) { return cable.spool.has_value(); });
}

// One M666 array word: letter, then each cable's value joined by ':'.
template <typename Value>
std::string per_cable(char letter, const std::vector<kinematics::RobotCable>& cables, Value value) {
  std::string word = std::string(" ") + letter;
  for (std::size_t i = 0; i < cables.size(); ++i) {
    word += (i == 0 ? "" : ":") + rrf_number(value(cables[i]));
  }
  return word;
}

std::string spool_line(const FirmwareMachine& fm) {
  const kinematics::CableRobotGeometry& g = robot(fm).geometry();
  if (!has_spools(fm)) {
    return "M666 Q0 ; no spool buildup: the motors turn in proportion to the lines' lengths "
           "(their steps per mm from RRF's M666 R U O L H J, not set here)\n";
  }
  for (std::size_t i = 0; i < g.cables.size(); ++i) {
    if (!g.cables[i].spool) {
      throw ExportRefused(fm.machine.source() + ": cable " + std::to_string(i + 1) +
                          " has no spool_radius and others have: RRF's M666 R U O L H J set "
                          "every line's spool");
    }
  }
  using Cable = kinematics::RobotCable;
  return "M666 Q" + rrf_number(g.spool_buildup_mm) +
         per_cable('R', g.cables, [](const Cable& c) { return c.spool->radius_mm; }) +
         per_cable('U', g.cables,
                   [](const Cable& c) { return double(c.spool->mechanical_advantage); }) +
         per_cable('O', g.cables, [](const Cable& c) { return double(c.spool->lines_per_spool); }) +
         per_cable('L', g.cables,
                   [](const Cable& c) { return double(c.spool->motor_gear_teeth); }) +
         per_cable('H', g.cables,
                   [](const Cable& c) { return double(c.spool->spool_gear_teeth); }) +
         per_cable('J', g.cables,
                   [](const Cable& c) { return double(c.spool->full_steps_per_rev); }) +
         " ; spools: buildup Q (mm), radii R at line position 0 (mm), mechanical advantage U, "
         "lines per spool O, motor and spool gear teeth L H, full steps per motor turn J\n";
}

std::string flex_line(const FirmwareMachine& fm) {
  const kinematics::CableRobotGeometry& g = robot(fm).geometry();
  if (!g.flex_compensation) {
    return "M666 F0 ; no flex compensation: the machine file's lines do not stretch\n";
  }
  using Cable = kinematics::RobotCable;
  const double low = g.tension_min_N, high = g.tension_max_N;
  return "M666 F1 W" + rrf_number(g.effector_mass_kg) + " S" + rrf_number(g.line_stiffness_N) +
         per_cable('I', g.cables, [low](const Cable&) { return low; }) +
         per_cable('X', g.cables, [high](const Cable&) { return high; }) +
         per_cable('Y', g.cables, [](const Cable& c) { return c.guy_wire_mm; }) +
         " B0 P0 ; flex compensation (its least-squares forces): mover weight W (kg), line "
         "stiffness S (N), min and max planned force I X (N), guy wires Y (mm)\n";
}

std::string drive_lines(const FirmwareMachine& fm, const kinematics::CableRobotForm&) {
  return spool_line(fm) + flex_line(fm);
}

}  // namespace

ExportedFile write_rrf_hangprinter(const FirmwareMachine& fm, const ExportContext& context) {
  const auto& form = std::get<kinematics::CableRobotForm>(fm.form.geometry);
  check_hangprinter(fm, form);
  const machine::Machine& machine = fm.machine;
  const RrfBounds bounds = rrf_bounds(machine);
  ExportedFile file;
  file.text += header_comment(fm, context, "; ");
  file.text +=
      "; RepRapFirmware config.g lines (HangprinterKinematics): they replace the M669, M666, M203, "
      "M201 and M208 lines of config.g; they need the HangprinterKinematics with M666 F. Each "
      "line's motor counts from its position at x 0 y 0 z 0, the machine's home, where homeall.g "
      "must set the position (G92 X0 Y0 Z0)\n";
  file.text += "M669 K6 ; Hangprinter\n";
  std::string anchors = "M669";
  if (form.anchors_mm.size() != kFourAnchors) {
    anchors += " N" + std::to_string(form.anchors_mm.size());
  }
  for (std::size_t i = 0; i < form.anchors_mm.size(); ++i) {
    anchors += " " + anchor_word(kAnchorLetters[i], form.anchors_mm[i]);
  }
  file.text += anchors + " P" + rrf_number(bounds.print_radius_mm) +
               " ; anchors (mm): each line's pivot on the frame less its tie point on the "
               "effector; P: the largest circle about x 0 y 0 in the work envelope" +
               (form.anchors_mm.size() != kFourAnchors ? "; N: RRF 3.6 or later" : "") + "\n";
  file.text += drive_lines(fm, form);
  const double speed = machine.cartesian().max_feed_mm_per_min;
  const double acceleration = machine.cartesian().max_acceleration_mm_per_s2;
  file.text += "M203 X" + rrf_number(speed) + " Y" + rrf_number(speed) + " Z" + rrf_number(speed) +
               " ; maximum speeds (mm/min)\n";
  file.text += "M201 X" + rrf_number(acceleration) + " Y" + rrf_number(acceleration) + " Z" +
               rrf_number(acceleration) + " ; maximum accelerations (mm/s^2)\n";
  file.text += "M208 S1 Z" + rrf_number(bounds.z_min_mm) + " ; lowest Z (mm)\n";
  file.text += "M208 Z" + rrf_number(bounds.z_max_mm) + " ; highest Z (mm)\n";
  for (const machine::JointSpec& joint : machine.joints()) {
    if (joint.steps_per_unit && !has_spools(fm)) {
      file.warnings.push_back("joint '" + joint.name + "': " + rrf_number(*joint.steps_per_unit) +
                              " steps/mm in the machine file: RRF computes a line's steps per mm "
                              "from M666 R U O L H J and the microstepping; set those to match");
    }
  }
  return file;
}

bool rrf_is_hangprinter(const std::vector<RrfCommand>& commands) {
  for (const RrfCommand& command : commands) {
    if (command.code != "M669") continue;
    for (const RrfWord& word : command.words) {
      if (word.letter == 'K' && word.value == "6") return true;
    }
  }
  return false;
}

namespace {

// The Hangprinter lines' values, as last set (key "M669 A"), and where.
struct HangprinterLines {
  std::map<std::string, std::vector<double>> values;
  std::map<std::string, int> lines;
  std::vector<std::string> notes;
  std::string name;
};

[[noreturn]] void fail(const std::string& source, int line, const std::string& key,
                       const std::string& why) {
  throw FirmwareFileError(source + ":" + std::to_string(line) + ": " + key + ": " + why);
}

bool read_value(const RrfCommand& command, const RrfWord& word, const std::string& source,
                HangprinterLines& read) {
  const std::string key = command.code + " " + word.letter;
  const bool kinematics = command.code == "M669" && std::strchr("ABCDINP", word.letter);
  const bool spool = command.code == "M666" && std::strchr("QRUOLHJFWSIXYBP", word.letter);
  const bool limits =
      (command.code == "M203" || command.code == "M201" || command.code == "M208") &&
      std::strchr("XYZS", word.letter);
  if (!kinematics && !spool && !limits) return false;
  read.values[key] = rrf_numbers(command, word, source);
  read.lines[key] = command.line;
  if (command.code == "M208" && word.letter == 'Z') {
    const bool low = std::any_of(command.words.begin(), command.words.end(), [](const RrfWord& w) {
      return w.letter == 'S' && w.value == "1";
    });
    read.values[low ? "M208 Z min" : "M208 Z max"] = read.values[key];
    read.lines[low ? "M208 Z min" : "M208 Z max"] = command.line;
  }
  return true;
}

HangprinterLines read_lines(const std::vector<RrfCommand>& commands, const std::string& source) {
  HangprinterLines read;
  std::map<std::string, int> ignored;
  for (const RrfCommand& command : commands) {
    if (command.code == "M550") {
      for (const RrfWord& word : command.words) {
        if (word.letter == 'P') read.name = word.value;
      }
      read.name.erase(std::remove(read.name.begin(), read.name.end(), '"'), read.name.end());
      continue;
    }
    for (const RrfWord& word : command.words) {
      if (command.code == "M669" && word.letter == 'K') {
        read.lines["M669 K"] = command.line;
        continue;
      }
      if (!read_value(command, word, source, read)) ++ignored[command.code];
    }
  }
  for (const auto& [code, count] : ignored) {
    read.notes.push_back("not read: " + code + " (" + std::to_string(count) + " value(s))");
  }
  return read;
}

double required(const HangprinterLines& read, const std::string& key, const std::string& source,
                std::size_t count) {
  const auto found = read.values.find(key);
  if (found == read.values.end()) {
    // At the M669 K6 line that made this a Hangprinter.
    const auto kinematics = read.lines.find("M669 K");
    fail(source, kinematics == read.lines.end() ? 1 : kinematics->second, key,
         "must be given (RRF's default is a placeholder; RepRapFirmware's Hangprinter needs it)");
  }
  if (found->second.size() != count) {
    fail(source, read.lines.at(key), key,
         std::to_string(count) + " value(s) expected, not " + std::to_string(found->second.size()));
  }
  return found->second.front();
}

std::vector<Eigen::Vector3d> read_anchors(const HangprinterLines& read, const std::string& source) {
  std::size_t count = kFourAnchors;
  if (read.values.count("M669 N")) {
    const double n = required(read, "M669 N", source, 1);
    if (n != 4.0 && n != 5.0) {
      fail(source, read.lines.at("M669 N"), "M669 N",
           rrf_number(n) + " anchors: pkmkit reads 4 or 5 (A B C D I)");
    }
    count = static_cast<std::size_t>(n);
  }
  std::vector<Eigen::Vector3d> anchors;
  for (std::size_t i = 0; i < count; ++i) {
    const std::string key = std::string("M669 ") + kAnchorLetters[i];
    required(read, key, source, 3);
    const std::vector<double>& xyz = read.values.at(key);
    anchors.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  return anchors;
}

// M666's value per anchor (RRF's TryGetFloatArray wants one per anchor), or RRF's default, noted.
std::vector<double> per_anchor(const HangprinterLines& read, const std::string& key,
                               const std::string& source, std::size_t count, double fallback,
                               std::vector<std::string>& notes) {
  const auto found = read.values.find(key);
  if (found == read.values.end()) {
    notes.push_back(key + " not set: RRF's default " + rrf_number(fallback) + " taken");
    return std::vector<double>(count, fallback);
  }
  if (found->second.size() != count) {
    fail(source, read.lines.at(key), key,
         std::to_string(count) + " values expected (one per anchor), not " +
             std::to_string(found->second.size()));
  }
  return found->second;
}

int whole(const HangprinterLines& read, const std::string& key, const std::string& source,
          double value) {
  if (!(value >= 1.0 && value <= 100000.0) || value != std::floor(value)) {
    fail(source, read.lines.at(key), key,
         "must be a whole number of 1 or more, not " + rrf_number(value));
  }
  return static_cast<int>(value);
}

double single(const HangprinterLines& read, const std::string& key, const std::string& source,
              double fallback) {
  return read.values.count(key) ? required(read, key, source, 1) : fallback;
}

// M666 Q R U O L H J: every line's spool, RRF's defaults (Init) for what is not set.
void read_spools(const HangprinterLines& read, const std::string& source,
                 kinematics::CableRobotGeometry& geometry, std::vector<std::string>& notes) {
  // Q0 alone (what a spool-less export writes): no spools, the motors' steps per mm as set.
  const bool any = std::any_of(read.values.begin(), read.values.end(), [](const auto& entry) {
    return entry.first.size() == 6 && entry.first.rfind("M666 ", 0) == 0 &&
           std::strchr("RUOLHJ", entry.first[5]);
  });
  if (!any && single(read, "M666 Q", source, 0.0) == 0.0) return;
  const std::size_t n = geometry.cables.size();
  geometry.spool_buildup_mm = single(read, "M666 Q", source, 0.007);
  if (!(geometry.spool_buildup_mm >= 0.0)) {
    fail(source, read.lines.at("M666 Q"), "M666 Q", "must be 0 or more (mm)");
  }
  const std::vector<double> radii = per_anchor(read, "M666 R", source, n, 75.0, notes);
  const char* letters = "UOLHJ";
  const double fallbacks[] = {2.0, 1.0, 20.0, 255.0, 25.0};
  std::vector<std::vector<double>> counts;
  for (int k = 0; k < 5; ++k) {
    counts.push_back(
        per_anchor(read, std::string("M666 ") + letters[k], source, n, fallbacks[k], notes));
  }
  for (std::size_t i = 0; i < n; ++i) {
    kinematics::CableSpool spool;
    spool.radius_mm = radii[i];
    if (!(spool.radius_mm > 0.0))
      fail(source, read.lines.at("M666 R"), "M666 R", "must be above 0");
    int* fields[] = {&spool.mechanical_advantage, &spool.lines_per_spool, &spool.motor_gear_teeth,
                     &spool.spool_gear_teeth, &spool.full_steps_per_rev};
    for (int k = 0; k < 5; ++k) {
      const std::string key = std::string("M666 ") + letters[k];
      *fields[k] = read.values.count(key) ? whole(read, key, source, counts[k][i])
                                          : static_cast<int>(counts[k][i]);
    }
    geometry.cables[i].spool = spool;
  }
}

// M666 F1 (and W S I X Y): RRF's flex compensation with its least-squares forces.
void read_flex(const HangprinterLines& read, const std::string& source,
               kinematics::CableRobotGeometry& geometry, std::vector<std::string>& notes) {
  const double flex = single(read, "M666 F", source, 0.0);
  if (flex == 0.0) {
    for (const char* key : {"M666 W", "M666 S", "M666 I", "M666 X", "M666 Y"}) {
      if (read.values.count(key)) {
        notes.push_back(std::string(key) + " not used: flex compensation is off (no M666 F1)");
      }
    }
    return;
  }
  const int line = read.lines.at("M666 F");
  if (flex == 2.0) {
    fail(source, line, "M666 F",
         "2 is RRF's Tikhonov flex compensation (a fixed number of damped gradient steps), "
         "which pkmkit does not model; F1 (least squares within M666 I X) it does");
  }
  if (flex != 1.0) fail(source, line, "M666 F", "must be 0, 1 or 2, not " + rrf_number(flex));
  for (const char* key : {"M666 B", "M666 P"}) {
    if (single(read, key, source, 0.0) != 0.0) {
      fail(source, read.lines.at(key), key,
           "RRF's flex without gravity (B1) or pretension (P1) is not modelled: only B0 P0");
    }
  }
  const std::size_t n = geometry.cables.size();
  const std::vector<double> low = per_anchor(read, "M666 I", source, n, 0.0, notes);
  const std::vector<double> high = per_anchor(read, "M666 X", source, n, 70.0, notes);
  for (const auto& [key, values] : {std::pair{"M666 I", low}, std::pair{"M666 X", high}}) {
    if (std::adjacent_find(values.begin(), values.end(), std::not_equal_to<>()) != values.end()) {
      fail(source, read.lines.at(key), key,
           "pkmkit's tension_limits are the same for every line: give one value for all");
    }
  }
  if (!(low[0] >= 0.0 && high[0] > low[0])) {
    fail(source, read.lines.count("M666 X") ? read.lines.at("M666 X") : line, "M666 X",
         "the max planned force must be above the min (M666 I), which must be 0 or more");
  }
  geometry.flex_compensation = true;
  geometry.tension_limited = true;
  geometry.tension_min_N = low[0];
  geometry.tension_max_N = high[0];
  geometry.effector_mass_kg = single(read, "M666 W", source, 0.0);
  geometry.line_stiffness_N = single(read, "M666 S", source, 20000.0);
  const std::vector<double> guy = per_anchor(read, "M666 Y", source, n, 0.0, notes);
  for (std::size_t i = 0; i < n; ++i) geometry.cables[i].guy_wire_mm = guy[i];
  try {
    kinematics::validate_cable_robot_geometry(geometry);
  } catch (const std::invalid_argument& error) {
    fail(source, line, "M666 F", error.what());
  }
}

}  // namespace

machine::ImportedMachine read_rrf_hangprinter(const std::vector<RrfCommand>& commands,
                                              const std::string& source) {
  const HangprinterLines read = read_lines(commands, source);
  const std::vector<Eigen::Vector3d> anchors = read_anchors(read, source);
  const double radius = required(read, "M669 P", source, 1);
  const double z_min = read.values.count("M208 Z min") ? read.values.at("M208 Z min")[0] : 0.0;
  const double z_max = required(read, "M208 Z max", source, 1);
  const double speed = required(read, "M203 X", source, 1);
  const double acceleration = required(read, "M201 X", source, 1);
  machine::ImportedMachine imported;
  imported.source = source;
  imported.origin = "Imported by `pkm import rrf` from " + source + " (RepRapFirmware Hangprinter)";
  imported.name = read.name.empty()
                      ? "RRF Hangprinter (" + source.substr(source.find_last_of('/') + 1) + ")"
                      : read.name;
  const Eigen::Vector3d low(-radius, -radius, z_min), high(radius, radius, z_max);
  kinematics::CableRobotGeometry geometry;
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    kinematics::RobotCable cable;
    cable.anchor_mm = anchors[i];
    geometry.cables.push_back(cable);
    machine::ImportedJoint joint;
    joint.name = std::string(1, kAnchorLetters[i]);
    // A line within the envelope is at most as long as the way to its farthest corner.
    joint.max = (anchors[i] - low).cwiseAbs().cwiseMax((high - anchors[i]).cwiseAbs()).norm();
    joint.min = 0.0;
    joint.home = anchors[i].norm();
    joint.max_velocity = speed / 60.0;  // a line never runs faster than the tool
    joint.max_acceleration = acceleration;
    imported.joints.push_back(joint);
  }
  imported.notes = read.notes;
  read_spools(read, source, geometry, imported.notes);
  read_flex(read, source, geometry, imported.notes);
  const kinematics::CableRobotKinematics model(geometry);
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    // The unstretched length at home (the origin) with flex compensation.
    kinematics::JointVector home;
    if (model.inverse(geometry::Pose::from_mm_deg(0.0, 0.0, 0.0), home).ok()) {
      imported.joints[i].home = home[static_cast<Eigen::Index>(i)];
    }
  }
  imported.kinematics_section = machine::kinematics_toml(model, machine::LengthUnit::mm);
  imported.max_feed_per_min = speed;
  imported.max_acceleration = acceleration;
  imported.home = std::vector<double>{0.0, 0.0, 0.0};
  imported.envelope_min = std::vector<double>{low.x(), low.y(), low.z()};
  imported.envelope_max = std::vector<double>{high.x(), high.y(), high.z()};
  imported.notes.push_back(
      "each line's reading is its length (unstretched with flex compensation); RRF's motor "
      "position counts from its value at x 0 y 0 z 0, pkmkit's home; the work envelope is the "
      "square around M669 P from M208 Z min to "
      "max");
  return imported;
}

}  // namespace pkm::firmware
