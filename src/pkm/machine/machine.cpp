#include "pkm/machine/machine.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "pkm/kinematics/registry.hpp"
#include "pkm/machine/toml_config.hpp"
#include "pkm/text/text_file.hpp"

namespace pkm::machine {

Machine::Machine(std::string name, std::string source, LengthUnit units,
                 std::unique_ptr<kinematics::Kinematics> kinematics, std::vector<JointSpec> joints,
                 CartesianLimits cartesian, geometry::Pose home)
    : name_(std::move(name)),
      source_(std::move(source)),
      units_(units),
      kinematics_(std::move(kinematics)),
      joints_(std::move(joints)),
      cartesian_(cartesian),
      home_(home),
      checks_envelope_(cartesian_.has_envelope()) {
  for (const JointSpec& joint : joints_) joint_names_.push_back(joint.name);
  // Home first: a hexapod's mode is each leg's side of the base plane at home.
  kinematics_->set_home(home_);
  home_assembly_mode_ = kinematics_->assembly_mode(home_);
}

Machine::Machine(const Machine& other)
    : name_(other.name_),
      source_(other.source_),
      units_(other.units_),
      kinematics_(other.kinematics_->clone()),
      joints_(other.joints_),
      joint_names_(other.joint_names_),
      cartesian_(other.cartesian_),
      home_(other.home_),
      tool_(other.tool_),
      homing_(other.homing_),
      controller_(other.controller_),
      home_assembly_mode_(other.home_assembly_mode_),
      checks_envelope_(other.checks_envelope_) {}

Machine& Machine::operator=(const Machine& other) {
  if (this != &other) *this = Machine(other);
  return *this;
}

kinematics::Status Machine::check_joint_limits(const kinematics::JointVector& joints) const {
  for (int i = 0; i < static_cast<int>(joints_.size()); ++i) {
    // Written so that NaN fails too (every comparison with NaN is false).
    if (!(joints[i] >= joints_[i].min && joints[i] <= joints_[i].max)) {
      return kinematics::Status::failure(kinematics::StatusCode::joint_limit, i);
    }
  }
  return kinematics::Status::success();
}

kinematics::Status Machine::check_envelope(const geometry::Pose& pose) const {
  if (!checks_envelope_) return kinematics::Status::success();
  const geometry::Dof dof = kinematics_->dof();
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    const double value = axis < 3 ? pose.position_mm[axis] : pose.orientation_rad[axis - 3];
    if (dof.controls(axis) &&
        !(value >= cartesian_.envelope_min[axis] && value <= cartesian_.envelope_max[axis])) {
      return kinematics::Status::outside(axis);
    }
  }
  return kinematics::Status::success();
}

kinematics::Status Machine::inverse(const geometry::Pose& pose,
                                    kinematics::JointVector& joints) const {
  if (!kinematics::all_finite(pose))
    return kinematics::Status::failure(kinematics::StatusCode::invalid_input);
  const kinematics::Status inside = check_envelope(pose);
  if (!inside.ok()) return inside;
  const kinematics::Status status = kinematics_->inverse(pose, joints);
  if (!status.ok()) return status;
  for (int i = 0; i < joints.size(); ++i) {
    // A pose far enough away overflows a model's arithmetic: no joint value, not a NaN one.
    if (!std::isfinite(joints[i]))
      return kinematics::Status::failure(kinematics::StatusCode::unreachable, i);
  }
  if (home_assembly_mode_ != 0 && kinematics_->assembly_mode(pose) != home_assembly_mode_) {
    return kinematics::Status::failure(kinematics::StatusCode::other_assembly);
  }
  return check_joint_limits(joints);
}

double Machine::joint_to_file(int joint, double internal) const {
  const JointSpec& spec = joints_[static_cast<std::size_t>(joint)];
  return spec.kind == kinematics::JointKind::rotary ? geometry::radians_to_degrees(internal)
                                                    : internal / mm_per_unit();
}

double Machine::joint_from_file(int joint, double value) const {
  const JointSpec& spec = joints_[static_cast<std::size_t>(joint)];
  return spec.kind == kinematics::JointKind::rotary ? geometry::degrees_to_radians(value)
                                                    : value * mm_per_unit();
}

const char* Machine::joint_file_unit(int joint) const {
  return joints_[static_cast<std::size_t>(joint)].kind == kinematics::JointKind::rotary
             ? "deg"
             : length_unit();
}

double Machine::axis_to_file(int axis, double internal) const {
  return axis < 3 ? internal / mm_per_unit() : geometry::radians_to_degrees(internal);
}

double Machine::axis_from_file(int axis, double value) const {
  return axis < 3 ? value * mm_per_unit() : geometry::degrees_to_radians(value);
}

kinematics::Status Machine::forward(const kinematics::JointVector& joints,
                                    geometry::Pose& pose_inout) const {
  return forward_with(joints, pose_inout, nullptr);
}

kinematics::Status Machine::forward(const kinematics::JointVector& joints,
                                    geometry::Pose& pose_inout,
                                    kinematics::ForwardTrack& track) const {
  return forward_with(joints, pose_inout, &track);
}

kinematics::Status Machine::forward_with(const kinematics::JointVector& joints,
                                         geometry::Pose& pose_inout,
                                         kinematics::ForwardTrack* track) const {
  if (joints.size() != static_cast<int>(joints_.size())) {
    return kinematics::Status::failure(kinematics::StatusCode::invalid_input);
  }
  if (!kinematics::all_finite(joints))
    return kinematics::Status::failure(kinematics::StatusCode::invalid_input);
  const kinematics::Status limits = check_joint_limits(joints);
  if (!limits.ok()) return limits;
  geometry::Pose solved = pose_inout;
  kinematics::Status status = track != nullptr ? kinematics_->forward_along(joints, solved, *track)
                                               : kinematics_->forward(joints, solved);
  const auto wrong_mode = [&] {
    return status.ok() && home_assembly_mode_ != 0 &&
           kinematics_->assembly_mode(solved) != home_assembly_mode_;
  };
  if (status.code == kinematics::StatusCode::branch_changed ||
      status.code == kinematics::StatusCode::not_converged || wrong_mode()) {
    // A seed across a singularity from the answer leads FK astray (or to the mirror-image pose);
    // home is on the machine's side by definition, so it is the seed of last resort.
    const int iterations_from_seed = status.iterations;
    if (track != nullptr) track->restart();
    solved = home_;
    status = kinematics_->forward(joints, solved);
    const int iterations = iterations_from_seed + status.iterations;
    if (wrong_mode()) status = kinematics::Status::failure(kinematics::StatusCode::branch_changed);
    status.iterations = iterations;
  }
  if (status.ok() && !kinematics::all_finite(solved))
    status = kinematics::Status::failure(kinematics::StatusCode::not_converged);
  if (status.ok()) pose_inout = solved;
  return status;
}

namespace {

constexpr std::string_view kAxisLetters = "XYZABCUVW";

// Positions within a kilometre (or that many degrees: a rotary axis may turn many times);
// speeds and accelerations from a crawl to far beyond any machine. Outside these a number is a
// typo, and tiny limits would make a plan run for ever.
constexpr double kMaxPosition = 1e6;
constexpr double kMinRate = 1e-3;
constexpr double kMaxVelocity = 1e6;
constexpr double kMaxAcceleration = 1e9;
// As the planner's own bound on a jerk limit (motion/planner.hpp's kMaxJerkPerS3).
constexpr double kMaxJerk = 1e12;

// A number of the file (in its units), refused outside [low, high].
double ranged(const kinematics::ModelConfig& table, std::string_view key, double low, double high,
              const std::string& unit) {
  const double value = table.number(key);
  if (!(value >= low && value <= high)) {
    table.fail(key, "must be between " + kinematics::formatted_number("%g", low) + " and " +
                        kinematics::formatted_number("%g", high) + " " + unit + ", not " +
                        kinematics::formatted_number("%g", value));
  }
  return value;
}

JointSpec read_joint(const kinematics::ModelConfig& table, kinematics::JointKind kind,
                     double mm_per_unit) {
  JointSpec joint;
  joint.name = table.string("name");
  joint.kind = kind;
  // Rotary joints are in degrees in the file and radians inside.
  const bool rotary = kind == kinematics::JointKind::rotary;
  const double scale = rotary ? geometry::degrees_to_radians(1.0) : mm_per_unit;
  const std::string unit = rotary ? "deg" : (mm_per_unit == 1.0 ? "mm" : "in");
  joint.min = ranged(table, "min", -kMaxPosition, kMaxPosition, unit) * scale;
  joint.max = ranged(table, "max", -kMaxPosition, kMaxPosition, unit) * scale;
  if (!(joint.min < joint.max)) table.fail("max", "must be greater than min");
  joint.max_velocity = ranged(table, "max_velocity", kMinRate, kMaxVelocity, unit + "/s") * scale;
  joint.max_acceleration =
      ranged(table, "max_acceleration", kMinRate, kMaxAcceleration, unit + "/s^2") * scale;
  if (table.has("max_jerk")) {
    joint.max_jerk = ranged(table, "max_jerk", kMinRate, kMaxJerk, unit + "/s^3") * scale;
  }
  joint.home_switch = read_home_switch(table, joint, scale);
  if (table.has("steps_per_unit")) {
    // Steps per file unit (per inch in an inch file, per deg for a rotary joint): to per mm.
    constexpr double kMaxStepsPerUnit = 1e6;
    const double steps = table.number("steps_per_unit");
    if (!(steps > 0.0 && steps <= kMaxStepsPerUnit)) {
      table.fail("steps_per_unit", "must be greater than 0 and at most " +
                                       kinematics::formatted_number("%g", kMaxStepsPerUnit) +
                                       " steps/" + unit + ", not " +
                                       kinematics::formatted_number("%g", steps));
    }
    joint.steps_per_unit = rotary ? steps : steps / mm_per_unit;
  }
  return joint;
}

// The letter each joint takes in joint-space G-code: its `axis`, else a pass-through joint's own
// axis (a pass-through of c is C), else the first of X Y Z A B C U V W no other joint takes.
void assign_axis_letters(const std::vector<std::unique_ptr<kinematics::ModelConfig>>& tables,
                         const kinematics::Kinematics& kinematics, std::vector<JointSpec>& joints) {
  std::vector<std::string> why(joints.size());
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const kinematics::ModelConfig& table = *tables[i];
    const int passthrough = kinematics.passthrough_axis(static_cast<int>(i));
    if (table.has("axis")) {
      const std::string letter = table.string("axis");
      const char upper =
          letter.size() == 1
              ? static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])))
              : '?';
      if (kAxisLetters.find(upper) == std::string_view::npos) {
        table.fail("axis", "must be one letter of X Y Z A B C U V W");
      }
      joints[i].axis_letter = upper;
      why[i] = "axis = \"" + std::string(1, upper) + "\"";
    } else if (passthrough >= 0) {
      joints[i].axis_letter = static_cast<char>(std::toupper(geometry::kAxisNames[passthrough][0]));
      why[i] = "the pass-through of " + std::string(geometry::kAxisNames[passthrough]);
    } else {
      joints[i].axis_letter = 0;  // chosen below, from the letters left
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (joints[i].axis_letter != 0 && joints[j].axis_letter == joints[i].axis_letter) {
        table.fail(table.has("axis") ? "axis" : "name",
                   std::string("letter ") + joints[i].axis_letter + " is used by two joints: '" +
                       joints[j].name + "' (" + why[j] + ") and '" + joints[i].name + "' (" +
                       why[i] + "); give one of them another axis letter");
      }
    }
  }
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].axis_letter != 0) continue;
    for (const char letter : kAxisLetters) {
      const bool taken = std::any_of(joints.begin(), joints.end(),
                                     [&](const JointSpec& j) { return j.axis_letter == letter; });
      if (!taken) {
        joints[i].axis_letter = letter;
        break;
      }
    }
    if (joints[i].axis_letter == 0) tables[i]->fail("name", "no axis letter is left for it");
  }
}

std::vector<JointSpec> read_joints(
    const std::vector<std::unique_ptr<kinematics::ModelConfig>>& tables,
    const kinematics::Kinematics& kinematics, double mm_per_unit) {
  std::vector<JointSpec> joints;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    joints.push_back(
        read_joint(*tables[i], kinematics.joint_kind(static_cast<int>(i)), mm_per_unit));
  }
  assign_axis_letters(tables, kinematics, joints);
  return joints;
}

// x y [z [a b c]] in the file's units and degrees, to mm and rad.
geometry::Vector6d pose_values(const TomlSection& cartesian, const std::vector<double>& values) {
  geometry::Vector6d pose = geometry::Vector6d::Zero();
  for (std::size_t i = 0; i < values.size() && i < geometry::kPoseSize; ++i) {
    pose[static_cast<int>(i)] =
        i < 3 ? values[i] * cartesian.mm_per_file_unit() : geometry::degrees_to_radians(values[i]);
  }
  return pose;
}

geometry::Pose read_home(const TomlSection& cartesian, const kinematics::Kinematics& kinematics) {
  const std::vector<double> values = cartesian.number_list("home");
  if (values.size() < 2 || values.size() > 6) {
    cartesian.fail("home", "needs 2 to 6 numbers: x y [z [a b c]] in mm and deg");
  }
  for (int axis = static_cast<int>(values.size()); axis < geometry::kPoseSize; ++axis) {
    if (kinematics.dof().controls(axis)) {
      cartesian.fail("home", "this machine controls " + std::string(geometry::kAxisNames[axis]) +
                                 ", so home needs a value for it");
    }
  }
  return geometry::Pose::from_vector(pose_values(cartesian, values));
}

// The optional work envelope: min and max list x y [z [a b c]] like home, as many values.
void read_envelope(const TomlSection& cartesian, const geometry::Pose& home,
                   CartesianLimits& limits) {
  if (!cartesian.has("min") && !cartesian.has("max")) return;
  const char* missing = cartesian.has("min") ? "max" : "min";
  if (!cartesian.has(missing)) {
    cartesian.fail(cartesian.has("min") ? "min" : "max",
                   "needs its partner: give both min and max");
  }
  const std::size_t count = cartesian.number_list("home").size();
  for (const char* key : {"min", "max"}) {
    if (cartesian.number_list(key).size() != count) {
      cartesian.fail(key, "needs " + std::to_string(count) +
                              " numbers, one per coordinate of home (x y [z [a b c]])");
    }
  }
  const geometry::Vector6d min = pose_values(cartesian, cartesian.number_list("min"));
  const geometry::Vector6d max = pose_values(cartesian, cartesian.number_list("max"));
  const geometry::Vector6d at_home = home.as_vector();
  for (int axis = 0; axis < static_cast<int>(count); ++axis) {
    const std::string name(geometry::kAxisNames[axis]);
    if (!(min[axis] < max[axis])) cartesian.fail("max", name + ": must be greater than min");
    if (!(at_home[axis] >= min[axis] && at_home[axis] <= max[axis])) {
      cartesian.fail("home", name + " lies outside the work envelope (min, max)");
    }
    limits.envelope_min[axis] = min[axis];
    limits.envelope_max[axis] = max[axis];
  }
}

CartesianLimits read_cartesian(const TomlSection& cartesian, const geometry::Pose& home) {
  const std::string unit = cartesian.mm_per_file_unit() == 1.0 ? "mm" : "in";
  CartesianLimits limits;
  limits.max_feed_mm_per_min =
      ranged(cartesian, "max_feed", kMinRate, 60.0 * kMaxVelocity, unit + "/min") *
      cartesian.mm_per_file_unit();
  limits.max_acceleration_mm_per_s2 =
      ranged(cartesian, "max_acceleration", kMinRate, kMaxAcceleration, unit + "/s^2") *
      cartesian.mm_per_file_unit();
  read_envelope(cartesian, home, limits);
  return limits;
}

// The words of one line of G-code (comments left out): letter and the text of its value.
std::vector<std::pair<char, std::string>> gcode_words(const std::string& line) {
  std::vector<std::pair<char, std::string>> words;
  for (std::size_t i = 0; i < line.size();) {
    const char c = line[i];
    if (c == ';') break;
    if (c == '(') {
      const std::size_t close = line.find(')', i);
      i = close == std::string::npos ? line.size() : close + 1;
      continue;
    }
    if (!std::isalpha(static_cast<unsigned char>(c))) {
      ++i;
      continue;
    }
    std::string value;
    for (++i; i < line.size() &&
              std::string_view("+-.0123456789 ").find(line[i]) != std::string_view::npos;
         ++i) {
      if (line[i] != ' ') value += line[i];
    }
    words.emplace_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))), value);
  }
  return words;
}

// Why a pen command would do more than switch the pen, or empty: post writes it between its
// own blocks, so it may not move the mechanism (a word of a joint's axis) nor change how the
// controller reads the next block (any G code but a rapid of the other axes, G0, and a dwell,
// G4: G1 in post's inverse time would need an F, G91 or G20 would change every later block).
std::string pen_command_problem(const std::string& command, const std::vector<JointSpec>& joints) {
  bool rapid = false;
  std::vector<char> axes;
  for (const auto& [letter, value] : gcode_words(command)) {
    if (letter == 'G') {
      char* end = nullptr;
      const double code = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || (code != 0.0 && code != 4.0)) {
        return "holds G" + value + ": a pen command may use G0 (of axes no joint uses) and G4 only";
      }
      rapid |= code == 0.0;
    } else if (std::string_view("XYZABCUVW").find(letter) != std::string_view::npos) {
      for (const JointSpec& joint : joints) {
        if (joint.axis_letter == letter) {
          return std::string("moves joint '") + joint.name + "' (its axis " + letter +
                 "): post writes every move of the joints itself";
        }
      }
      axes.push_back(letter);
    } else if (std::string_view("IJKR").find(letter) != std::string_view::npos) {
      return std::string("holds the arc word ") + letter + ": a pen command does not move";
    }
  }
  if (!axes.empty() && !rapid) {
    return std::string("moves axis ") + axes.front() +
           " without G0: the modal motion there is post's (G1 in inverse time)";
  }
  return "";
}

// Why grbl 1.1 cannot run a pen command, or empty: an M code it lacks (gcode.c takes M0 M1 M2 M30,
// which end or pause the program, M3 M4 M5, M8 M9; M7 only in builds with ENABLE_M7).
std::string grbl_pen_command_problem(const std::string& command) {
  for (const auto& [letter, value] : gcode_words(command)) {
    if (letter != 'M') continue;
    if (value != "3" && value != "4" && value != "5" && value != "8" && value != "9") {
      return "holds M" + value +
             ", which grbl 1.1 does not take for a pen (M3 M4 M5 switch its spindle output, M8 "
             "M9 its coolant output): e.g. down = \"M3 S1000\", up = \"M5\"";
    }
  }
  return "";
}

// The height of the pen: `down_below` (the default, 0) or `down_above`, not both.
void read_pen_height(const TomlSection& tool, ToolChannel& channel) {
  if (tool.has("down_below") && tool.has("down_above")) {
    tool.fail("down_above",
              "down_below is given too: one height says on which side of it the pen draws");
  }
  channel.down_above = tool.has("down_above");
  const char* key = channel.height_key();
  channel.pen_height_mm = tool.length_or(key, 0.0);
  if (!(std::abs(channel.pen_height_mm) <= kMaxPosition)) {
    tool.fail(key, "must be within a kilometre of 0");
  }
}

// The optional [tool] table: the pen channel of machines that do not move in Z.
ToolChannel read_tool(const TomlSection& tool, const kinematics::Kinematics& kinematics,
                      const std::vector<JointSpec>& joints,
                      const std::optional<ControllerSettings>& controller) {
  ToolChannel channel;
  const std::string z = tool.string("z");
  if (z == "pen") {
    channel.z = ToolZ::pen;
  } else if (z == "ignore") {
    channel.z = ToolZ::ignore;
  } else {
    tool.fail("z", "must be \"pen\" or \"ignore\", not \"" + z + "\"");
  }
  if (kinematics.dof().controls(2)) {
    tool.fail("z", "this machine moves in Z itself; a [tool] channel is for machines that do not");
  }
  read_pen_height(tool, channel);
  if (tool.has("down")) channel.down_command = tool.string("down");
  if (tool.has("up")) channel.up_command = tool.string("up");
  channel.delay_s = tool.number_or("delay", 0.0);
  if (!(channel.delay_s >= 0.0 && channel.delay_s <= 60.0)) {
    tool.fail("delay", "must be between 0 and 60 s");
  }
  for (const auto* key : {"down", "up"}) {
    const std::string& command = key[0] == 'd' ? channel.down_command : channel.up_command;
    if (command.find_first_of("\n\r") != std::string::npos) {
      tool.fail(key, "must be one line of G-code");
    }
    std::string problem = pen_command_problem(command, joints);
    if (problem.empty() && controller && controller->kind == ControllerKind::grbl) {
      problem = grbl_pen_command_problem(command);
    }
    if (!problem.empty()) tool.fail(key, "\"" + command + "\" " + problem);
  }
  return channel;
}

double read_units(const toml::table& document, const std::shared_ptr<KeyTracker>& tracker) {
  const TomlSection unit_reader(document, "", tracker, 1.0, {});
  if (!unit_reader.has("units")) return 1.0;
  const std::string unit_name = unit_reader.string("units");
  if (unit_name == "inch") return 25.4;
  if (unit_name != "mm") {
    unit_reader.fail("units", "must be \"mm\" or \"inch\", not \"" + unit_name + "\"");
  }
  return 1.0;
}

std::vector<std::string> read_joint_names(
    const std::vector<std::unique_ptr<kinematics::ModelConfig>>& tables) {
  std::vector<std::string> joint_names;
  for (const auto& table : tables) {
    const std::string joint_name = table->string("name");
    if (joint_name.empty()) table->fail("name", "must not be empty");
    for (const std::string& seen : joint_names) {
      if (seen == joint_name) table->fail("name", "joint '" + joint_name + "' is named twice");
    }
    joint_names.push_back(joint_name);
  }
  return joint_names;
}

// Which joints follow a pose coordinate (a pen's Z) rather than move the mechanism.
std::vector<bool> passthrough_joints(const kinematics::Kinematics& kinematics) {
  std::vector<bool> passthrough;
  for (int i = 0; i < kinematics.joint_count(); ++i) {
    passthrough.push_back(kinematics.passthrough_axis(i) >= 0);
  }
  return passthrough;
}

}  // namespace

Machine parse_machine(std::string_view toml_text, const std::string& source_name) {
  refuse_unbounded_toml(toml_text, source_name);
  toml::table document;
  try {
    document = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& error) {
    throw MachineFileError(source_name, static_cast<int>(error.source().begin.line), "(syntax)",
                           std::string(error.description()));
  }
  auto tracker = std::make_shared<KeyTracker>(source_name);
  const double mm_per_unit = read_units(document, tracker);
  TomlSection root(document, "", tracker, mm_per_unit, {});
  const std::string name = root.string("name");

  const auto joint_tables = root.table_list("joints");
  root.set_joint_names(read_joint_names(joint_tables));

  TomlSection kinematics_section = root.section("kinematics");
  std::unique_ptr<kinematics::Kinematics> kinematics =
      kinematics::make_kinematics(kinematics_section);
  if (kinematics->joint_count() != static_cast<int>(joint_tables.size())) {
    root.fail("joints", "the " + std::string(kinematics->type()) + " kinematics here has " +
                            std::to_string(kinematics->joint_count()) + " joints; the file lists " +
                            std::to_string(joint_tables.size()) + " [[joints]] tables");
  }
  std::vector<JointSpec> joints = read_joints(joint_tables, *kinematics, mm_per_unit);

  const TomlSection cartesian_section = root.section("cartesian");
  const geometry::Pose home = read_home(cartesian_section, *kinematics);
  const CartesianLimits cartesian = read_cartesian(cartesian_section, home);

  std::optional<ControllerSettings> controller;
  if (root.has("controller")) {
    controller = read_controller_table(root.section("controller"), joints, joint_tables);
  }
  ToolChannel tool;
  if (root.has("tool")) tool = read_tool(root.section("tool"), *kinematics, joints, controller);
  std::optional<TomlSection> homing_section;
  std::optional<HomingTable> homing;
  if (root.has("homing")) {
    homing_section.emplace(root.section("homing"));
    homing =
        read_homing_table(*homing_section, joints, passthrough_joints(*kinematics), mm_per_unit);
  }

  tracker->check_all_read();
  Machine machine(name, source_name, mm_per_unit == 1.0 ? LengthUnit::mm : LengthUnit::inch,
                  std::move(kinematics), std::move(joints), cartesian, home);
  machine.set_tool(std::move(tool));
  machine.set_homing(std::move(homing));
  machine.set_controller(controller);
  kinematics::JointVector home_joints;
  const kinematics::Status home_status = machine.inverse(home, home_joints);
  if (!home_status.ok()) {
    cartesian_section.fail("home", "is not a usable pose: " + machine.explain(home, home_status));
  }
  // A machine singular at home cannot leave it under control; one whose geometry is degenerate
  // (parallel legs, rails or cables in one line) is singular everywhere.
  if (const std::string singular = singular_at_home(machine); !singular.empty()) {
    cartesian_section.fail("home", singular);
  }
  // The procedure's checks need the whole machine: joints known after their switch stay within
  // their limits.
  if (homing_section) homing_moves(machine, &*homing_section);
  return machine;
}

Machine load_machine(const std::filesystem::path& path) {
  std::string text;
  try {
    text = text::read_text_file(path, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw MachineFileError(path.string(), error.what());
  }
  return parse_machine(text, path.string());
}

}  // namespace pkm::machine
