// `pkm import grblhal`: a grblHAL settings file (a `$$` dump, or what `pkm export grblhal` wrote)
// as the wall plotter its WallPlotter kinematics drives (docs/firmware-grblhal.md). The machine
// file's frame is grblHAL's turned 180 deg about z (pkmkit's plotters hang below their anchors,
// y up): the G54 offset of a `G10 L2 P1` line, where the file has one, is the right anchor.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>

#include "pkm/firmware/grblhal.hpp"
#include "pkm/firmware/grblhal_settings.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace grblhal {
namespace {

std::string without_comments(std::string_view line) {
  std::string kept;
  bool in_parentheses = false;
  for (const char c : line) {
    if (in_parentheses) {
      in_parentheses = c != ')';
    } else if (c == '(') {
      in_parentheses = true;
    } else if (c == ';') {
      break;
    } else if (c != ' ' && c != '\t' && c != '\r') {
      kept += c;
    }
  }
  return kept;
}

// "$130=1500" -> 130, "1500"; none for other `$` commands ($H, $X, $I).
std::optional<std::pair<int, std::string>> setting_line(const std::string& line) {
  const std::size_t equals = line.find('=');
  if (line.size() < 3 || equals == std::string::npos || equals == 1) return std::nullopt;
  for (std::size_t i = 1; i < equals; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(line[i]))) return std::nullopt;
  }
  return std::pair<int, std::string>(std::stoi(line.substr(1, equals - 1)),
                                     line.substr(equals + 1));
}

// The X Y Z words of "G10L2P1X1500Y0Z0"; false for any other line.
bool read_g54_line(const std::string& line, int number, SettingsFile& file) {
  std::map<char, std::string> words;
  char letter = 0;
  for (const char c : line) {
    if (std::isalpha(static_cast<unsigned char>(c))) {
      letter = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      words[letter];
    } else if (letter != 0) {
      words[letter] += c;
    }
  }
  if (words.size() < 3 || words['G'] != "10" || words['L'] != "2" || words['P'] != "1") {
    return false;
  }
  for (const char axis : {'X', 'Y', 'Z'}) {
    if (words.count(axis)) file.g54[axis] = {words[axis], number};
  }
  return true;
}

}  // namespace

SettingsFile scan(std::string_view text, const std::string& source) {
  SettingsFile file;
  file.source = source;
  std::size_t start = 0;
  int number = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++number;
    const std::string line = without_comments(text.substr(start, end - start));
    start = end + 1;
    if (line.empty()) continue;
    file.last_line = number;
    if (line[0] == '$') {
      if (const auto setting = setting_line(line)) {
        file.settings[setting->first] = {setting->second, number};
        continue;
      }
    } else if (read_g54_line(line, number, file)) {
      continue;
    }
    file.ignored.push_back("line " + std::to_string(number) + ": " + line);
  }
  return file;
}

double number_of(const SettingsFile& file, const std::string& key, const Setting& setting) {
  const char* begin = setting.value.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (setting.value.empty() || end != begin + setting.value.size() || !std::isfinite(value)) {
    throw FirmwareFileError(file.source + ":" + std::to_string(setting.line) + ": " + key + ": '" +
                            setting.value + "' is not a number");
  }
  return value;
}

double required(const SettingsFile& file, int number, const std::string& what) {
  const std::string key = "$" + std::to_string(number);
  const auto found = file.settings.find(number);
  if (found == file.settings.end()) {
    throw FirmwareFileError(file.source + ":" + std::to_string(file.last_line) + ": " + key +
                            ": missing (" + what + ")");
  }
  const double value = number_of(file, key, found->second);
  if (!(value > 0.0)) {
    throw FirmwareFileError(file.source + ":" + std::to_string(found->second.line) + ": " + key +
                            ": " + found->second.value + " must be above 0 (" + what + ")");
  }
  return value;
}

std::optional<double> optional_number(const SettingsFile& file, int number) {
  const auto found = file.settings.find(number);
  if (found == file.settings.end()) return std::nullopt;
  return number_of(file, "$" + std::to_string(number), found->second);
}

void note_unused(const SettingsFile& file, const std::vector<int>& used,
                 std::vector<std::string>& notes) {
  std::string list;
  for (const auto& [number, setting] : file.settings) {
    if (std::find(used.begin(), used.end(), number) == used.end()) {
      list += (list.empty() ? "$" : ", $") + std::to_string(number);
    }
  }
  if (!list.empty())
    notes.push_back("settings not imported (not the kinematics' or its axes'): " + list);
  for (const std::string& line : file.ignored) notes.push_back("ignored " + line);
}

}  // namespace grblhal

namespace {

using grblhal::required;
using grblhal::SettingsFile;

std::optional<double> optional_steps(const SettingsFile& file, int number) {
  if (!file.settings.count(number)) return std::nullopt;
  return required(file, number, "steps/mm");
}

machine::ImportedJoint cord(const SettingsFile& file, const std::string& name, int axis,
                            double longest_mm) {
  machine::ImportedJoint joint;
  joint.name = name;
  joint.min = 0.0;
  joint.max = longest_mm;
  joint.max_velocity = required(file, 110 + axis, "max rate, mm/min") / 60.0;
  joint.max_acceleration = required(file, 120 + axis, "acceleration, mm/s^2");
  joint.steps_per_unit = optional_steps(file, 100 + axis);
  return joint;
}

bool has_z(const SettingsFile& file) {
  return file.settings.count(112) || file.settings.count(122) || file.settings.count(132);
}

machine::ImportedJoint z_joint(const SettingsFile& file) {
  machine::ImportedJoint joint;
  joint.name = "z";
  joint.min = -required(file, 132, "Z max travel, mm");
  joint.max = 0.0;
  joint.max_velocity = required(file, 112, "Z max rate, mm/min") / 60.0;
  joint.max_acceleration = required(file, 122, "Z acceleration, mm/s^2");
  joint.steps_per_unit = optional_steps(file, 102);
  return joint;
}

double g54_word(const SettingsFile& file, char axis) {
  const auto found = file.g54.find(axis);
  if (found == file.g54.end()) return 0.0;
  return grblhal::number_of(file, std::string("G10 L2 P1 ") + axis, found->second);
}

void add_notes(machine::ImportedMachine& imported, const SettingsFile& file) {
  imported.warnings.push_back(
      "grblHAL's frame is this machine file's turned 180 deg about z: grblHAL's G54 X Y are this "
      "file's -x -y (the G54 offset is the right anchor)");
  imported.notes.push_back(imported.warnings.back());
  imported.notes.push_back(
      "motor A ($1x0, X) is joint 'right', motor B ($1x1, Y) joint 'left'; each reads the cord's "
      "length from its anchor (cable offsets 0)");
  imported.notes.push_back(
      "the cords' limits are our choice: 0 to $131 (grblHAL has no setting for them); home is "
      "ours: midway between the anchors, the cords halfway between W/2 and $131");
  grblhal::note_unused(file, {100, 101, 102, 110, 111, 112, 120, 121, 122, 130, 131, 132},
                       imported.notes);
}

}  // namespace

machine::ImportedMachine grblhal_read(std::string_view text, const std::string& source) {
  const SettingsFile file = grblhal::scan(text, source);
  if (grblhal::is_delta_file(file)) return grblhal::read_rotary_delta(file);
  const double width = required(file, 130, "X max travel: WallPlotter's motor A to motor B, mm");
  const double longest = required(file, 131, "Y max travel: the longest cord, mm");
  if (!(longest > 0.5 * width)) {
    throw FirmwareFileError(source + ":" + std::to_string(file.settings.at(131).line) +
                            ": $131: " + file.settings.at(131).value +
                            " mm: the cords must reach below the motors' midpoint (more than "
                            "half $130)");
  }
  kinematics::WallPlotterForm form;
  const Eigen::Vector2d right(g54_word(file, 'X'), g54_word(file, 'Y'));
  form.anchors_mm = {right - Eigen::Vector2d(width, 0.0), right};
  const bool z = has_z(file);
  const kinematics::PassThroughAxes passthrough =
      z ? kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy())
        : kinematics::PassThroughAxes();

  machine::ImportedMachine imported;
  imported.source = source;
  imported.origin = "Imported by `pkm import grblhal` from " + source + " (WallPlotter)";
  imported.name = "grblHAL wall plotter";
  imported.kinematics_section = machine::kinematics_toml(
      *kinematics::make_form_kinematics(form, passthrough), machine::LengthUnit::mm);
  imported.joints = {cord(file, "left", 1, longest), cord(file, "right", 0, longest)};
  if (z) imported.joints.push_back(z_joint(file));
  imported.max_feed_per_min =
      std::min(imported.joints[0].max_velocity, imported.joints[1].max_velocity) * 60.0;
  imported.max_acceleration =
      std::min(imported.joints[0].max_acceleration, imported.joints[1].max_acceleration);
  const double home_cord = 0.5 * (0.5 * width + longest);
  const double depth = std::sqrt(home_cord * home_cord - 0.25 * width * width);
  imported.home = std::vector<double>{right.x() - 0.5 * width, right.y() - depth, 0.0};
  add_notes(imported, file);
  return imported;
}

}  // namespace pkm::firmware
