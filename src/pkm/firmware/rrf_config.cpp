#include "pkm/firmware/rrf_config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <optional>

#include "pkm/firmware/rrf_delta.hpp"
#include "pkm/firmware/rrf_hangprinter.hpp"
#include "pkm/firmware/rrf_rotary.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return std::string(text.substr(first, last - first + 1));
}

// The line without its `;` comment (a `;` inside a quoted string is text).
std::string_view without_comment(std::string_view line) {
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    if (line[k] == '"') quoted = !quoted;
    if (line[k] == ';' && !quoted) return line.substr(0, k);
  }
  return line;
}

// "M665 L300:300 R160" -> code and words; a quoted value may hold spaces.
std::optional<RrfCommand> command_of(const std::string& body, int line) {
  const bool is_code = body.size() >= 2 && std::strchr("GMT", std::toupper(body[0])) != nullptr &&
                       std::isdigit(static_cast<unsigned char>(body[1]));
  if (!is_code) return std::nullopt;
  RrfCommand command;
  command.line = line;
  std::size_t k = 0;
  while (k < body.size() && !std::isspace(static_cast<unsigned char>(body[k]))) {
    command.code += static_cast<char>(std::toupper(body[k++]));
  }
  while (k < body.size()) {
    if (std::isspace(static_cast<unsigned char>(body[k]))) {
      ++k;
      continue;
    }
    RrfWord word;
    word.letter = static_cast<char>(std::toupper(body[k++]));
    bool quoted = false;
    while (k < body.size() && (quoted || !std::isspace(static_cast<unsigned char>(body[k])))) {
      if (body[k] == '"') quoted = !quoted;
      word.value += body[k++];
    }
    command.words.push_back(std::move(word));
  }
  return command;
}

class ConfigReader {
 public:
  ConfigReader(std::string_view text, std::string source) : source_(std::move(source)) {
    commands_ = rrf_commands(text, skipped_);
    // The last line's number: a final newline ends it, it does not start another.
    line_count_ = static_cast<int>(std::count(text.begin(), text.end(), '\n')) +
                  (text.empty() || text.back() != '\n' ? 1 : 0);
  }
  machine::ImportedMachine read();

 private:
  [[noreturn]] void fail(int line, const std::string& key, const std::string& why) const {
    throw FirmwareFileError(source_ + ":" + std::to_string(line) + ": " + key + ": " + why);
  }
  std::vector<double> numbers(const RrfCommand& command, const RrfWord& word) const;
  double number(const RrfCommand& command, const RrfWord& word) const;
  void read_kinematics(const RrfCommand& command);
  void read_m665(const RrfCommand& command);
  void read_m666(const RrfCommand& command);
  void read_per_drive(const RrfCommand& command);
  void read_m208(const RrfCommand& command);
  double required(const std::string& key, const char* what) const;
  RrfLinearDelta settings() const;
  machine::ImportedMachine rotary() const;
  machine::ImportedMachine imported(const RrfLinearDelta& delta) const;

  std::string source_;
  std::vector<RrfCommand> commands_;
  std::vector<std::string> skipped_;
  int line_count_ = 0;
  std::map<std::string, std::vector<double>> values_;  // "M665 L", "M92 X", ... as last set
  std::map<std::string, int> lines_;                   // where each was set
  std::string name_;
  int kind_ = 0;  // M669 K: 3 linear delta, 10 rotary delta; 0 none yet
  std::map<std::string, std::vector<int>> ignored_;  // command -> lines
  std::vector<std::string> notes_;
};

std::vector<double> ConfigReader::numbers(const RrfCommand& command, const RrfWord& word) const {
  return rrf_numbers(command, word, source_);
}

double ConfigReader::number(const RrfCommand& command, const RrfWord& word) const {
  const std::vector<double> values = numbers(command, word);
  if (values.size() != 1) {
    fail(command.line, command.code + " " + word.letter,
         "one number expected, not '" + word.value + "'");
  }
  return values[0];
}

void ConfigReader::read_kinematics(const RrfCommand& command) {
  for (const RrfWord& word : command.words) {
    if (word.letter != 'K') continue;
    const double kind = number(command, word);
    if (kind != 3.0 && kind != 10.0) {
      fail(command.line, "M669 K",
           "kinematics " + rrf_number(kind) +
               ": pkmkit imports RRF's linear delta (K3), rotary delta (K10) and Hangprinter (K6)");
    }
    kind_ = static_cast<int>(kind);
    values_["M669 K"] = {kind};
    lines_["M669 K"] = command.line;
  }
  for (const RrfWord& word : command.words) {
    const std::string key = std::string("M669 ") + word.letter;
    if (word.letter == 'K') continue;
    if (kind_ == 3 && (word.letter == 'X' || word.letter == 'Y')) {
      fail(command.line, key, "towers beyond the first three: pkmkit's linear delta has three");
    }
    if (kind_ != 10 || std::strchr("ULHARBXYZ", word.letter) == nullptr) {
      ignored_[key].push_back(command.line);
      continue;
    }
    std::vector<double> values = numbers(command, word);
    const std::size_t count = word.letter == 'A' ? 2 : std::strchr("ULH", word.letter) ? 3 : 1;
    if (values.size() == 1 && count == 3) values.assign(3, values[0]);  // as RRF pads them
    if (values.size() != count) {
      fail(command.line, key, std::to_string(count) + " values expected, not '" + word.value + "'");
    }
    values_[key] = values;
    lines_[key] = command.line;
  }
}

void ConfigReader::read_m665(const RrfCommand& command) {
  for (const RrfWord& word : command.words) {
    const std::string key = std::string("M665 ") + word.letter;
    if (word.letter == 'L') {
      std::vector<double> rods = numbers(command, word);
      if (rods.size() > 3) {
        fail(command.line, key,
             std::to_string(rods.size()) +
                 " diagonals: more than three towers, and pkmkit's linear "
                 "delta has three");
      }
      while (rods.size() < 3) rods.push_back(rods[0]);  // as RRF fills them
      values_[key] = rods;
    } else if (std::strchr("RHBXYZ", word.letter) != nullptr) {
      values_[key] = {number(command, word)};
    } else {
      ignored_[key].push_back(command.line);
      continue;
    }
    lines_[key] = command.line;
  }
}

void ConfigReader::read_m666(const RrfCommand& command) {
  for (const RrfWord& word : command.words) {
    const std::string key = std::string("M666 ") + word.letter;
    if (std::strchr("XYZAB", word.letter) == nullptr) {
      ignored_[key].push_back(command.line);
      continue;
    }
    const double value = number(command, word);
    if ((word.letter == 'A' || word.letter == 'B') && value != 0.0) {
      fail(command.line, key,
           "a bed tilt of " + rrf_number(value) +
               " %: RRF raises every carriage by it, and pkmkit's linear delta has no such "
               "setting (calibrate the tilt away, or set it to 0)");
    }
    values_[key] = {value};
    lines_[key] = command.line;
  }
}

// M92, M203, M201: the X Y Z drives' values; the extruders' and other axes' are not read.
void ConfigReader::read_per_drive(const RrfCommand& command) {
  for (const RrfWord& word : command.words) {
    const std::string key = command.code + " " + word.letter;
    if (std::strchr("XYZ", word.letter) == nullptr) {
      ignored_[key].push_back(command.line);
      continue;
    }
    const double value = number(command, word);
    if (!(value > 0.0)) fail(command.line, key, "must be greater than 0, not " + word.value);
    values_[key] = {value};
    lines_[key] = command.line;
  }
}

// M208: Z's minimum (S1 Z.., or Z min:max); X and Y are M665 B's on a delta.
void ConfigReader::read_m208(const RrfCommand& command) {
  bool set_minimum = false;
  for (const RrfWord& word : command.words) {
    if (word.letter == 'S') set_minimum = number(command, word) == 1.0;
  }
  for (const RrfWord& word : command.words) {
    if (word.letter == 'S') continue;
    const std::string key = std::string("M208 ") + word.letter;
    if (word.letter != 'Z') {
      ignored_[key].push_back(command.line);
      continue;
    }
    const std::vector<double> values = numbers(command, word);
    if (values.size() > 2) fail(command.line, key, "min:max expected, not '" + word.value + "'");
    if (values.size() == 2 || set_minimum) {
      values_["M208 Z"] = {values[0]};
      lines_["M208 Z"] = command.line;
    }
    if (values.size() == 2 || !set_minimum) {
      values_["M208 Z max"] = {values.back()};
      lines_["M208 Z max"] = command.line;
    }
  }
}

double ConfigReader::required(const std::string& key, const char* what) const {
  const auto found = values_.find(key);
  if (found != values_.end()) return found->second[0];
  const std::string code = key.substr(0, key.find(' '));
  int line = line_count_;
  for (const RrfCommand& command : commands_) {
    if (command.code == code) line = command.line;
  }
  fail(line, key,
       std::string("not set (") + what + ")" +
           (line == line_count_ ? ": no " + code + " sets it before the end of the file" : ""));
}

RrfLinearDelta ConfigReader::settings() const {
  RrfLinearDelta delta;
  (void)required("M665 L", "the diagonal rods, mm");
  const std::vector<double>& rods = values_.at("M665 L");
  std::copy(rods.begin(), rods.end(), delta.diagonals_mm.begin());
  delta.radius_mm = required("M665 R", "the delta radius, mm");
  delta.homed_height_mm = required("M665 H", "the homed height, mm");
  auto optional = [&](const std::string& key, double fallback) {
    const auto found = values_.find(key);
    return found == values_.end() ? fallback : found->second[0];
  };
  delta.print_radius_mm = optional("M665 B", 80.0);
  delta.z_min_mm = optional("M208 Z", 0.0);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string drive(1, kRrfDriveLetters[k]);
    delta.angle_corrections_deg[k] = optional("M665 " + drive, 0.0);
    delta.endstop_adjustments_mm[k] = optional("M666 " + drive, 0.0);
    if (values_.count("M92 " + drive)) delta.steps_per_mm[k] = values_.at("M92 " + drive)[0];
    delta.max_speed_mm_per_min[k] = required("M203 " + drive, "the maximum speed, mm/min");
    delta.max_acceleration_mm_per_s2[k] =
        required("M201 " + drive, "the maximum acceleration, mm/s^2");
    if (!(delta.diagonals_mm[k] > delta.radius_mm)) {
      fail(lines_.at("M665 L"), "M665 L",
           "the diagonal " + rrf_number(delta.diagonals_mm[k]) +
               " mm is not longer than the delta radius " + rrf_number(delta.radius_mm) + " mm");
    }
  }
  if (!(delta.print_radius_mm > 0.0)) {
    fail(lines_.at("M665 B"), "M665 B", "the printable radius must be greater than 0");
  }
  return delta;
}

// "M569 (lines 3, 4), M906 (line 7)": what the file sets that pkmkit does not read.
std::string ignored_list(const std::map<std::string, std::vector<int>>& ignored) {
  std::string text;
  for (const auto& [code, lines] : ignored) {
    text += (text.empty() ? "" : ", ") + code + (lines.size() > 1 ? " (lines " : " (line ");
    for (std::size_t k = 0; k < lines.size(); ++k) {
      text += (k > 0 ? " " : "") + std::to_string(lines[k]);
    }
    text += ")";
  }
  return text;
}

machine::ImportedMachine ConfigReader::imported(const RrfLinearDelta& delta) const {
  machine::ImportedMachine result;
  result.name = "RepRapFirmware linear delta";
  kinematics::LinearDeltaForm form;
  for (int tower = 0; tower < 3; ++tower) {
    kinematics::LinearDeltaTower& column = form.towers[static_cast<std::size_t>(tower)];
    column.column_mm = rrf_tower_position(delta, tower);
    column.rod_mm = delta.diagonals_mm[static_cast<std::size_t>(tower)];
    column.carriage_offset_mm = 0.0;  // a joint reads RRF's motor position
  }
  result.kinematics_section =
      machine::kinematics_toml(*kinematics::make_form_kinematics(form), machine::LengthUnit::mm);
  // The lowest carriage: at M208's Z min, on the far side of the printable circle.
  for (int tower = 0; tower < 3; ++tower) {
    const std::size_t k = static_cast<std::size_t>(tower);
    machine::ImportedJoint joint;
    joint.name = std::string("tower_") + static_cast<char>('a' + tower);
    joint.max = rrf_homed_carriage_height(delta, tower);
    joint.home = joint.max;
    const double reach = delta.radius_mm + delta.print_radius_mm;
    joint.min =
        delta.z_min_mm +
        std::sqrt(std::max(delta.diagonals_mm[k] * delta.diagonals_mm[k] - reach * reach, 0.0));
    if (!(joint.min < joint.max)) {
      fail(lines_.count("M665 H") ? lines_.at("M665 H") : line_count_, "M665 H",
           "tower " + std::string(1, kRrfTowerNames[k]) + "'s carriage would be at its endstop (" +
               rrf_number(joint.max) + " mm) below its lowest position (" + rrf_number(joint.min) +
               " mm, at M208's Z min)");
    }
    joint.max_velocity = delta.max_speed_mm_per_min[2] / 60.0;
    joint.max_acceleration = delta.max_acceleration_mm_per_s2[2];
    joint.steps_per_unit = delta.steps_per_mm[k];
    result.joints.push_back(joint);
  }
  result.max_feed_per_min =
      *std::min_element(delta.max_speed_mm_per_min.begin(), delta.max_speed_mm_per_min.end());
  result.max_acceleration = *std::min_element(delta.max_acceleration_mm_per_s2.begin(),
                                              delta.max_acceleration_mm_per_s2.end());
  const double b = delta.print_radius_mm;
  result.envelope_min = std::vector<double>{-b, -b, delta.z_min_mm};
  // Home: every carriage at its endstop, the highest the effector goes.
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(form);
  kinematics::JointVector endstops(3);
  for (int tower = 0; tower < 3; ++tower) endstops[tower] = result.joints[tower].max;
  geometry::Pose home = geometry::Pose::from_mm_deg(0.0, 0.0, delta.homed_height_mm);
  std::array<double, 3> lowest{}, highest{};
  for (std::size_t k = 0; k < 3; ++k) {
    lowest[k] = result.joints[k].min;
    highest[k] = result.joints[k].max;
  }
  if (!model->forward(endstops, home).ok() || !lower_into_limits(*model, lowest, highest, home)) {
    fail(lines_.count("M665 H") ? lines_.at("M665 H") : line_count_, "M665 H",
         "the carriages at their endstops hold the effector nowhere");
  }
  const Eigen::Vector3d& top = home.position_mm;
  auto tidy = [](double value) { return std::abs(value) < 1e-9 ? 0.0 : value; };
  result.home = std::vector<double>{tidy(top.x()), tidy(top.y()), top.z()};
  result.envelope_max = std::vector<double>{b, b, top.z()};
  result.home_seed_z = delta.homed_height_mm;
  result.notes = notes_;
  result.notes.push_back(
      "joints tower_a tower_b tower_c are RRF's drives X Y Z (towers A B C); a reading is RRF's "
      "motor position (mm), its max the endstop (H + sqrt(L^2 - R^2) + M666), home there");
  result.notes.push_back(
      "RRF limits no carriage's own speed: each joint takes M203 Z / 60 and M201 Z, a vertical "
      "move's; its min is the lowest a carriage goes over M665 B's circle at M208's Z min");
  result.notes.push_back(
      "max_feed and max_acceleration: the least of M203 X Y Z and of M201 X Y Z; the envelope: x "
      "y within M665 B (RRF's circle, a box here), z from M208's Z min to home's");
  if (!values_.count("M665 B")) result.notes.push_back("no M665 B: RRF's default 80 mm");
  return result;
}

machine::ImportedMachine ConfigReader::rotary() const {
  RrfRotaryDelta delta;
  auto list = [&](const std::string& key, double fallback) {
    const auto found = values_.find(key);
    std::array<double, 3> values{fallback, fallback, fallback};
    if (found != values_.end()) std::copy_n(found->second.begin(), 3, values.begin());
    return values;
  };
  auto optional = [&](const std::string& key, double fallback) {
    const auto found = values_.find(key);
    return found == values_.end() ? fallback : found->second[0];
  };
  (void)required("M669 U", "the arms, mm");
  (void)required("M669 L", "the rods, mm");
  delta.arm_lengths_mm = list("M669 U", 0.0);
  delta.rod_lengths_mm = list("M669 L", 0.0);
  delta.bearing_heights_mm = list("M669 H", 250.0);  // RRF's defaults below
  delta.radius_mm = required("M669 R", "the delta radius, mm");
  delta.print_radius_mm = optional("M669 B", 80.0);
  const auto angles = values_.find("M669 A");
  delta.min_arm_angle_deg = angles == values_.end() ? -45.0 : angles->second[0];
  delta.max_arm_angle_deg = angles == values_.end() ? 45.0 : angles->second[1];
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string drive(1, kRrfDriveLetters[k]);
    delta.angle_corrections_deg[k] = optional("M669 " + drive, 0.0);
    delta.endstop_adjustments_deg[k] = optional("M666 " + drive, 0.0);
    if (values_.count("M92 " + drive)) delta.steps_per_deg[k] = values_.at("M92 " + drive)[0];
  }
  delta.max_speed_mm_per_min = std::min({required("M203 X", "the maximum speed, mm/min"),
                                         required("M203 Y", "the maximum speed, mm/min"),
                                         required("M203 Z", "the maximum speed, mm/min")});
  delta.max_acceleration_mm_per_s2 =
      std::min({required("M201 X", "the maximum acceleration, mm/s^2"),
                required("M201 Y", "the maximum acceleration, mm/s^2"),
                required("M201 Z", "the maximum acceleration, mm/s^2")});
  delta.z_min_mm = optional("M208 Z", 0.0);
  delta.z_max_mm = optional("M208 Z max", 200.0);
  try {
    machine::ImportedMachine result = rrf_rotary_machine(delta);
    result.name = "RepRapFirmware rotary delta";
    return result;
  } catch (const RrfSettingRefused& refused) {
    const auto line = lines_.find(refused.key());
    fail(line != lines_.end() ? line->second : lines_.at("M669 K"), refused.key(), refused.what());
  }
}

// M501 loads config-override.g, where M500 saves what auto-calibration found (M665, M666), and
// M98 runs another file: settings there override or add to this file's, unread.
std::vector<std::string> other_files(const std::vector<RrfCommand>& commands) {
  std::vector<std::string> warnings;
  for (const RrfCommand& command : commands) {
    const std::string at = "line " + std::to_string(command.line) + ": ";
    if (command.code == "M501") {
      warnings.push_back(at +
                         "M501 loads config-override.g, where M500 saves auto-calibration's M665 "
                         "and M666; they were not read: import config.g and config-override.g as "
                         "one file (cat config.g config-override.g)");
    }
    if (command.code != "M98") continue;
    for (const RrfWord& word : command.words) {
      if (word.letter == 'P') {
        warnings.push_back(at + "M98 runs " + word.value + ", whose settings were not read");
      }
    }
  }
  return warnings;
}

machine::ImportedMachine ConfigReader::read() {
  for (const RrfCommand& command : commands_) {
    if (command.code == "M669") {
      read_kinematics(command);
    } else if (command.code == "M665") {
      read_m665(command);
    } else if (command.code == "M666") {
      read_m666(command);
    } else if (command.code == "M92" || command.code == "M203" || command.code == "M201") {
      read_per_drive(command);
    } else if (command.code == "M208") {
      read_m208(command);
    } else if (command.code == "M550") {
      for (const RrfWord& word : command.words) {
        if (word.letter == 'P') name_ = word.value;
      }
      name_.erase(std::remove(name_.begin(), name_.end(), '"'), name_.end());
    } else {
      ignored_[command.code].push_back(command.line);
    }
  }
  machine::ImportedMachine result;
  if (kind_ == 10) {
    result = rotary();
  } else if (values_.count("M665 L") || kind_ == 3) {
    result = imported(settings());
  } else {
    fail(line_count_, "M665",
         "no delta in this file: RRF's linear delta is M665 L R H (and M669 K3), its rotary "
         "delta M669 K10 U L R");
  }
  result.source = source_;
  result.origin = "Imported by `pkm import rrf` from " + source_ + " (RepRapFirmware " +
                  (kind_ == 10 ? "rotary" : "linear") + " delta)";
  if (!name_.empty()) result.name = name_;
  if (!values_.count("M208 Z")) result.notes.push_back("no M208 Z minimum: RRF's default 0 mm");
  if (!ignored_.empty()) result.notes.push_back("not read: " + ignored_list(ignored_));
  if (!skipped_.empty()) {
    result.notes.push_back("not read: " + std::to_string(skipped_.size()) +
                           " line(s) of meta commands, first " + skipped_.front());
  }
  result.warnings = other_files(commands_);
  for (const std::string& warning : result.warnings) result.notes.push_back("WARNING: " + warning);
  return result;
}

}  // namespace

std::vector<double> rrf_numbers(const RrfCommand& command, const RrfWord& word,
                                const std::string& source) {
  const std::string key = command.code + " " + word.letter;
  std::vector<double> values;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = word.value.find(':', start);
    const std::string item = word.value.substr(start, end - start);
    char* stop = nullptr;
    const double value = std::strtod(item.c_str(), &stop);
    if (item.empty() || *stop != '\0' || !std::isfinite(value)) {
      throw FirmwareFileError(source + ":" + std::to_string(command.line) + ": " + key + ": '" +
                              word.value + "' is not a number" +
                              (word.value.find(':') != std::string::npos ? " list" : ""));
    }
    values.push_back(value);
    if (end == std::string::npos) return values;
    start = end + 1;
  }
}

std::vector<RrfCommand> rrf_commands(std::string_view text, std::vector<std::string>& skipped) {
  std::vector<RrfCommand> commands;
  int line = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    ++line;
    const std::string body = trimmed(without_comment(text.substr(start, end - start)));
    if (!body.empty()) {
      if (std::optional<RrfCommand> command = command_of(body, line)) {
        commands.push_back(std::move(*command));
      } else {
        skipped.push_back("line " + std::to_string(line) + ": " + body);
      }
    }
    start = end + 1;
  }
  return commands;
}

machine::ImportedMachine read_rrf_config(std::string_view text, const std::string& source) {
  std::vector<std::string> skipped;
  const std::vector<RrfCommand> commands = rrf_commands(text, skipped);
  if (rrf_is_hangprinter(commands)) return read_rrf_hangprinter(commands, source);
  return ConfigReader(text, source).read();
}

}  // namespace pkm::firmware
