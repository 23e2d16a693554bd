#include "pkm/firmware/rrf_hangprinter.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include "pkm/firmware/rrf_delta.hpp"
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

}  // namespace

ExportedFile write_rrf_hangprinter(const FirmwareMachine& fm, const ExportContext& context) {
  const auto& form = std::get<kinematics::CableRobotForm>(fm.form.geometry);
  check_hangprinter(fm, form);
  const machine::Machine& machine = fm.machine;
  const RrfBounds bounds = rrf_bounds(machine);
  ExportedFile file;
  file.text += header_comment(fm, context, "; ");
  file.text +=
      "; RepRapFirmware config.g lines (HangprinterKinematics): they replace the M669, M666 Q F, "
      "M203, M201 and M208 lines of config.g. Each line's motor counts its length less its "
      "length at x 0 y 0 z 0, the machine's home, where homeall.g must set the position (G92 X0 "
      "Y0 Z0)\n";
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
  file.text +=
      "M666 Q0 F0 ; no spool buildup (the motors turn in proportion to the lines' lengths), no "
      "flex compensation: the machine file's lines are straight and do not stretch\n";
  const double speed = machine.cartesian().max_feed_mm_per_min;
  const double acceleration = machine.cartesian().max_acceleration_mm_per_s2;
  file.text += "M203 X" + rrf_number(speed) + " Y" + rrf_number(speed) + " Z" + rrf_number(speed) +
               " ; maximum speeds (mm/min)\n";
  file.text += "M201 X" + rrf_number(acceleration) + " Y" + rrf_number(acceleration) + " Z" +
               rrf_number(acceleration) + " ; maximum accelerations (mm/s^2)\n";
  file.text += "M208 S1 Z" + rrf_number(bounds.z_min_mm) + " ; lowest Z (mm)\n";
  file.text += "M208 Z" + rrf_number(bounds.z_max_mm) + " ; highest Z (mm)\n";
  file.text +=
      "; Not written: M666 R U O L H J (spool radii, mechanical advantage, lines per spool, gear "
      "teeth, full steps), which set RRF's steps per mm of line; RRF checks the print radius and "
      "Z, not the lines' travel\n";
  for (const machine::JointSpec& joint : machine.joints()) {
    if (joint.steps_per_unit) {
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
  const bool spool = command.code == "M666" && std::strchr("QF", word.letter);
  const bool limits =
      (command.code == "M203" || command.code == "M201" || command.code == "M208") &&
      std::strchr("XYZS", word.letter);
  if (!kinematics && !spool && !limits) return false;
  read.values[key] = rrf_numbers(command, word, source);
  read.lines[key] = command.line;
  if (key == "M666 F" && read.values[key] != std::vector<double>{0.0}) {
    fail(source, command.line, key,
         "flex compensation: RRF lengthens each line by its stretch under the tensions it "
         "plans; pkmkit's cable robot has straight lines that do not stretch: not imported");
  }
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
  kinematics::CableRobotForm form;
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    form.anchors_mm.push_back(anchors[i]);
    form.cable_offsets_mm.push_back(0.0);
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
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(form);
  imported.kinematics_section = machine::kinematics_toml(*model, machine::LengthUnit::mm);
  imported.max_feed_per_min = speed;
  imported.max_acceleration = acceleration;
  imported.home = std::vector<double>{0.0, 0.0, 0.0};
  imported.envelope_min = std::vector<double>{low.x(), low.y(), low.z()};
  imported.envelope_max = std::vector<double>{high.x(), high.y(), high.z()};
  imported.notes = read.notes;
  imported.notes.push_back(
      "each line's reading is its length; RRF's motor position is that less its length at x 0 "
      "y 0 z 0, pkmkit's home; the work envelope is the square around M669 P from M208 Z min to "
      "max");
  if (read.values.count("M666 Q") && read.values.at("M666 Q") != std::vector<double>{0.0}) {
    imported.notes.push_back(
        "M666 Q" + rrf_number(read.values.at("M666 Q")[0]) +
        ": RRF's spool buildup turns each motor nonlinearly in its line's length; pkmkit's joints "
        "are the lengths, so no steps_per_unit (an export writes Q0)");
  }
  return imported;
}

}  // namespace pkm::firmware
