#include "pkm/post/homing_program.hpp"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <stdexcept>

namespace pkm::post {

namespace {

// The dialect's word for setting the position readings: G10 L20 P1 (G54), Mach3's G92.
std::string set_position_command(Dialect dialect) {
  return dialect == Dialect::mach3 ? "G92" : "G10 L20 P1";
}

bool rotary_letter(char letter) {
  return letter == 'A' || letter == 'B' || letter == 'C';
}

// " F300" or " F12.5": a feed per minute with at most 3 decimals.
std::string feed_word(double per_min) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3f", per_min);
  std::string value = text;
  while (value.back() == '0') value.pop_back();
  if (value.back() == '.') value.pop_back();
  return " F" + value;
}

// The program's lines, each checked against the dialect's longest line.
class ProgramText {
 public:
  ProgramText(const machine::Machine& machine, Dialect dialect)
      : machine_(machine), dialect_(dialect), rules_(rules_of(dialect)) {}

  void line(const std::string& text) {
    if (rules_.max_line > 0 && text.size() > rules_.max_line) {
      throw std::invalid_argument(machine_.source() + ": a line of " + std::to_string(text.size()) +
                                  " characters exceeds the " + std::to_string(rules_.max_line) +
                                  " dialect " + std::string(dialect_name(dialect_)) +
                                  " accepts: " + text);
    }
    text_ += text + "\n";
  }
  void comment(const std::string& before, const std::string& text, const std::string& after) {
    text_ += comment_line(dialect_, before, text, after);
  }
  // The words of `targets` (joint, value in mm or rad), in joint order as given.
  std::string words(const std::vector<std::pair<int, double>>& targets) const {
    std::string text;
    for (const auto& [joint, value] : targets) {
      text += joint_word(machine_.joints()[static_cast<std::size_t>(joint)], value, rules_);
    }
    return text;
  }
  // Sets the named joints' readings: G10 L20 P1 (G54), or Mach3's G92. After a probe LinuxCNC
  // gives the reading at the switch itself: the joint stopped past it, where it reads the switch
  // plus (current position #5420.. - trip point #5061..), both in G54.
  void set_position(const std::vector<std::pair<int, double>>& targets, bool after_probe) {
    if (!after_probe || dialect_ != Dialect::linuxcnc) {
      line(set_position_command(dialect_) + words(targets));
      return;
    }
    std::string text = "G10 L20 P1";
    for (const auto& [joint, value] : targets) {
      const machine::JointSpec& spec = machine_.joints()[static_cast<std::size_t>(joint)];
      const std::string word = joint_word(spec, value, rules_);  // " X160.00000"
      const auto index = static_cast<int>(std::string_view("XYZABCUVW").find(spec.axis_letter));
      text += " " + std::string(1, spec.axis_letter) + "[" + word.substr(2) + " + #" +
              std::to_string(5420 + index) + " - #" + std::to_string(5061 + index) + "]";
    }
    line(text);
  }
  // Units, G54 (the coordinate system joint programs run in) without a G92 offset on top.
  void preamble() {
    line("G21 G90 G94");
    line("G54");
    line("G92.1");
  }
  std::string text() const { return text_; }

 private:
  const machine::Machine& machine_;
  Dialect dialect_;
  DialectRules rules_;
  std::string text_;
};

constexpr Dialect kHomeDialects[] = {Dialect::linuxcnc, Dialect::mach3, Dialect::grbl,
                                     Dialect::grblhal};

// Why the dialect cannot write the program ("" when it can): an axis letter it does not have, or
// (`probes`) a homed joint on a rotary letter, which Mach3's G31 does not move.
std::string refusal(const machine::Machine& machine, Dialect dialect, bool probes) {
  const std::string_view axes = rules_of(dialect).axes;
  for (const machine::JointSpec& joint : machine.joints()) {
    if (axes.find(joint.axis_letter) == std::string_view::npos) {
      return "dialect " + std::string(dialect_name(dialect)) + " has no axis " + joint.axis_letter +
             " (joint '" + joint.name + "')";
    }
  }
  if (probes && dialect == Dialect::mach3) {
    for (const int j : machine.homing()->sequence) {
      const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(j)];
      if (rotary_letter(joint.axis_letter)) {
        return "Mach3's probe (G31) moves no rotary axis, and joint '" + joint.name + "' is " +
               joint.axis_letter;
      }
    }
  }
  return "";
}

void check_home_dialect(const machine::Machine& machine, Dialect dialect, bool probes) {
  const std::string why = refusal(machine, dialect, probes);
  if (why.empty()) return;
  std::string others;
  for (const Dialect other : kHomeDialects) {
    if (other != dialect && refusal(machine, other, probes).empty()) {
      others += (others.empty() ? "" : " or ") + std::string(dialect_name(other));
    }
  }
  throw std::invalid_argument(machine.source() + ": " + why + ": " +
                              (others.empty() ? "" : "use --dialect " + others + ", or ") +
                              "change the joints' axis letters in the machine file");
}

std::string joint_text(const machine::Machine& machine, int joint, double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3f %s", machine.joint_to_file(joint, value),
                machine.joint_file_unit(joint));
  return machine.joints()[static_cast<std::size_t>(joint)].name + " " + text;
}

void write_move(ProgramText& program, const machine::HomingMove& move, Dialect dialect) {
  const std::string feed = feed_word(move.feed_per_min);
  switch (move.kind) {
    case machine::HomingMoveKind::pay_out:
    case machine::HomingMoveKind::back_off:
      program.line("G91 G1" + program.words(move.targets) + feed);
      break;
    case machine::HomingMoveKind::probe:
      program.line(std::string(dialect == Dialect::mach3 ? "G91 G31" : "G91 G38.2") +
                   program.words(move.targets) + feed);
      break;
    case machine::HomingMoveKind::set_position:
      program.set_position(move.targets, true);
      break;
    case machine::HomingMoveKind::go_home:
      program.line("G90 G1" + program.words(move.targets) + feed);
      break;
  }
}

}  // namespace

std::string homing_program(const machine::Machine& machine, Dialect dialect) {
  const std::vector<machine::HomingMove> moves = machine::homing_moves(machine);
  check_home_dialect(machine, dialect, true);
  ProgramText program(machine, dialect);
  program.comment("homing program by pkmkit for ", machine.name(),
                  ", dialect " + std::string(dialect_name(dialect)));
  for (const int joint : machine.homing()->sequence) {
    const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
    program.comment(
        "switch of ", joint_text(machine, joint, spec.home_switch->position),
        std::string(", probed towards its ") + (spec.home_switch->toward_max ? "max" : "min"));
  }
  program.preamble();
  const machine::ToolChannel& tool = machine.tool();
  if (tool.z == machine::ToolZ::pen) {
    program.line(tool.up_command);
    if (tool.delay_s > 0.0) {
      char dwell[32];
      std::snprintf(dwell, sizeof dwell, "G4 P%.3f", tool.delay_s);
      program.line(dwell);
    }
  }
  int step_of = -2;
  for (const machine::HomingMove& move : moves) {
    if (move.homed_joint != step_of) {
      step_of = move.homed_joint;
      if (step_of >= 0) {
        program.comment("home ", machine.joints()[static_cast<std::size_t>(step_of)].name, "");
      } else {
        program.comment("to home: ", machine.format_pose(machine.home()), "");
      }
    }
    write_move(program, move, dialect);
  }
  program.line("M2");
  return program.text();
}

std::vector<int> measured_joint_indices(const machine::Machine& machine) {
  std::vector<int> indices;
  for (int joint = 0; joint < static_cast<int>(machine.joints().size()); ++joint) {
    if (machine.kinematics().passthrough_axis(joint) < 0) indices.push_back(joint);
  }
  return indices;
}

MeasuredJoints measured_joints(const machine::Machine& machine, const std::vector<double>& values) {
  const std::vector<int> indices = measured_joint_indices(machine);
  std::string names;
  for (const int joint : indices) {
    names += (names.empty() ? "" : " ") + machine.joints()[static_cast<std::size_t>(joint)].name;
  }
  if (values.size() != indices.size()) {
    throw std::invalid_argument("--measured takes " + std::to_string(indices.size()) +
                                " readings, one per joint of the mechanism (" + names + "), not " +
                                std::to_string(values.size()));
  }
  MeasuredJoints measured;
  if (!machine.inverse(machine.home(), measured.joints).ok()) {
    throw std::invalid_argument(machine.source() + ": home is not usable");
  }
  std::string readings;
  for (std::size_t i = 0; i < indices.size(); ++i) {
    measured.joints[indices[i]] = machine.joint_from_file(indices[i], values[i]);
    readings += (readings.empty() ? "" : ", ") +
                joint_text(machine, indices[i], measured.joints[indices[i]]);
  }
  measured.pose = machine.home();
  const kinematics::Status status = machine.forward(measured.joints, measured.pose);
  if (!status.ok()) {
    const bool limit = status.code == kinematics::StatusCode::joint_limit && status.joint >= 0;
    throw std::invalid_argument(
        "no pose has the readings " + readings + " on " + machine.name() + ": " +
        (limit ? machine.explain_joint(status.joint, measured.joints[status.joint])
               : "forward kinematics finds none (" + machine.describe(status) + ")") +
        "; measure again, from the same point of each cable as the joint's zero");
  }
  kinematics::JointVector check;
  const kinematics::Status reachable = machine.inverse(measured.pose, check);
  if (!reachable.ok()) {
    throw std::invalid_argument(
        "the readings " + readings +
        " put the machine where it cannot be: " + machine.explain(measured.pose, reachable));
  }
  return measured;
}

std::string set_position_line(const machine::Machine& machine, Dialect dialect,
                              const kinematics::JointVector& joints) {
  std::string line = set_position_command(dialect);
  const DialectRules rules = rules_of(dialect);
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    line += joint_word(machine.joints()[i], joints[static_cast<Eigen::Index>(i)], rules);
  }
  return line;
}

MeasuredJoints joints_at_home(const machine::Machine& machine) {
  MeasuredJoints at_home;
  at_home.pose = machine.home();
  machine.inverse(at_home.pose, at_home.joints);  // checked when the machine file was loaded
  at_home.source = "at home";
  return at_home;
}

std::string set_position_program(const machine::Machine& machine, Dialect dialect,
                                 const MeasuredJoints& measured) {
  check_home_dialect(machine, dialect, false);
  ProgramText program(machine, dialect);
  program.comment("set-position block by pkmkit for ", machine.name(),
                  ", dialect " + std::string(dialect_name(dialect)));
  std::vector<std::pair<int, double>> targets;
  for (const int joint : measured_joint_indices(machine)) {
    targets.emplace_back(joint, measured.joints[joint]);
    program.comment(measured.source + ": ", joint_text(machine, joint, measured.joints[joint]), "");
  }
  program.comment("pose ", machine.format_pose(measured.pose), "");
  program.preamble();
  program.set_position(targets, false);
  program.line("M2");
  return program.text();
}

}  // namespace pkm::post
