#include "pkm/linuxcnc/config_import.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "pkm/kinematics/registry.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/machine/toml_config.hpp"

namespace pkm::linuxcnc {

namespace {

constexpr std::string_view kAxisLetters = "XYZABCUVW";
// pkmkit's bounds on positions in machine files (file units or deg): LinuxCNC's "no limit"
// (1e99) is written as this.
constexpr double kLargestPosition = 1e6;
// The smallest limit that, the same -M..M on every joint or every axis, is a placeholder.
constexpr double kPlaceholderLimit = 1000.0;

// The module and its parameters, from the HAL line that loads it (loadrt [KINS]KINEMATICS) or
// else from [KINS] KINEMATICS itself.
struct KinematicsModule {
  std::string name;
  std::vector<std::string> parameters;
  const IniEntry* entry = nullptr;  // [KINS] KINEMATICS
};

// How the configuration's joints map onto the model: the model's own joints, then pass-through
// axes (0..5 = x..c), then joints left out (u v w, or what the model cannot pass through).
struct JointPlan {
  int model_joints = 0;
  bool model_joints_angular = false;
  std::vector<int> passthrough;    // axis index per pass-through joint
  std::vector<std::string> names;  // of the model's joints
};

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string joined(const std::vector<std::string>& words, const char* separator) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : separator) + word;
  return text;
}

KinematicsModule find_module(const IniFile& ini, const HalConfig& hal) {
  KinematicsModule module;
  module.entry = ini.find("KINS", "KINEMATICS");
  if (module.entry == nullptr) {
    ini.fail_missing("KINS", "KINEMATICS", "it names the kinematics module to import");
  }
  const std::vector<std::string> words = split_words(module.entry->value);
  if (words.empty()) ini.fail(*module.entry, "names no kinematics module");
  module.name = words.front();
  module.parameters.assign(words.begin() + 1, words.end());
  for (const HalModule& loaded : hal.modules()) {
    if (loaded.name == module.name) module.parameters = loaded.parameters;
  }
  if (module.name == "pkmkins") {
    // A configuration `pkm export linuxcnc` wrote: it runs a machine file already.
    std::string machine = "the machine file of its machine= parameter";
    for (const std::string& word : module.parameters) {
      if (word.rfind("machine=", 0) == 0) machine = word.substr(8);
    }
    ini.fail(*module.entry, "this configuration runs pkmkit's own module with " + machine +
                                ": use that machine file itself");
  }
  if (std::find(importable_kinematics().begin(), importable_kinematics().end(), module.name) ==
      importable_kinematics().end()) {
    ini.fail(*module.entry, "kinematics module '" + module.name +
                                "' cannot be imported; pkm import linuxcnc knows " +
                                joined(importable_kinematics(), ", "));
  }
  return module;
}

std::string parameter(const KinematicsModule& module, const std::string& name) {
  for (const std::string& word : module.parameters) {
    if (word.rfind(name + "=", 0) == 0) return word.substr(name.size() + 1);
  }
  return "";
}

// trivkins' joints: coordinates= (default XYZABCUVW), one letter per joint.
JointPlan trivkins_plan(const IniFile& ini, const KinematicsModule& module, int joints) {
  std::string letters = lower(parameter(module, "coordinates"));
  if (letters.empty()) letters = "xyzabcuvw";
  const auto refuse = [&](const std::string& why) {
    ini.fail(*module.entry, "trivkins coordinates=" + letters + ": " + why +
                                "; pkmkit's matrix model has joints x y z, then a b c passed "
                                "through, each once");
  };
  if (letters.size() < 3 || letters.substr(0, 3) != "xyz") refuse("the joints do not start x y z");
  JointPlan plan{3, false, {}, {"x", "y", "z"}};
  for (std::size_t i = 3; i < letters.size() && static_cast<int>(i) < joints; ++i) {
    const auto axis = static_cast<int>(
        kAxisLetters.find(static_cast<char>(std::toupper(static_cast<unsigned char>(letters[i])))));
    if (axis < 0) refuse(std::string("'") + letters[i] + "' is no axis letter");
    if (axis < 3 || std::count(letters.begin(), letters.end(), letters[i]) > 1) {
      refuse(std::string("axis ") + letters[i] + " has two joints (a gantry)");
    }
    // u v w have no pass-through in pkmkit: left out, which only works after every other joint.
    if (axis >= 6 && letters.find_first_of("abc", i) < static_cast<std::size_t>(joints)) {
      refuse("a b c come after u v w");
    }
    if (axis >= 6) break;
    plan.passthrough.push_back(axis);
  }
  return plan;
}

JointPlan joint_plan(const IniFile& ini, const KinematicsModule& module, int joints) {
  if (module.name == "genhexkins") {
    return {6, false, {}, {"leg0", "leg1", "leg2", "leg3", "leg4", "leg5"}};
  }
  if (module.name == "trivkins") return trivkins_plan(ini, module, joints);
  JointPlan plan;
  if (module.name == "lineardeltakins") plan = {3, false, {}, {"joint0", "joint1", "joint2"}};
  if (module.name == "rotarydeltakins") plan = {3, true, {}, {"joint0", "joint1", "joint2"}};
  if (module.name == "matrixkins") plan = {3, false, {}, {"x", "y", "z"}};
  // These modules pass joints 3..8 through as a b c u v w; pkmkit passes a b c through (not on
  // the rotary delta, whose model has no pass-through axes).
  if (module.name != "rotarydeltakins") {
    for (int axis = 3; axis < 6 && axis < joints; ++axis) plan.passthrough.push_back(axis);
  }
  return plan;
}

// The [kinematics] section as the machine file writes it.
class SectionText {
 public:
  explicit SectionText(const std::string& type) { line("[kinematics]\ntype = \"" + type + "\""); }
  void line(const std::string& text) { out_ << text << "\n"; }
  void number(const std::string& key, double value) {
    line(key + " = " + machine::toml_number(value));
  }
  void points(const std::string& key, const std::vector<std::array<double, 3>>& points) {
    line(key + " = [");
    for (const auto& p : points) {
      line("  [" + machine::toml_number(p[0]) + ", " + machine::toml_number(p[1]) + ", " +
           machine::toml_number(p[2]) + "],");
    }
    line("]");
  }
  void passthrough(const std::vector<int>& axes) {
    if (axes.empty()) return;
    std::string names;
    for (const int axis : axes) {
      names += std::string(names.empty() ? "" : ", ") + "\"" +
               static_cast<char>(std::tolower(static_cast<unsigned char>(kAxisLetters[axis]))) +
               "\"";
    }
    line("passthrough = [" + names + "]");
  }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

// Reads kinematics pins: a constant of the configuration, or the module's default.
class PinReader {
 public:
  PinReader(const IniFile& ini, const HalConfig& hal, const KinematicsModule& module)
      : ini_(ini), hal_(hal), module_(module) {}

  // A pin of the geometry: refused when it follows another pin at run time.
  double geometry(const std::string& pin, double fallback) const {
    if (const auto source = hal_.driven_by(pin)) {
      ini_.fail(*module_.entry, pin + " is connected to " + *source +
                                    " (a value at run time); pkmkit needs the geometry as "
                                    "constants: setp or sets it");
    }
    return hal_.number_of(pin).value_or(fallback);
  }
  // An offset that may follow another pin (genhexkins' tool-offset follows the tool length of
  // motion): then it is 0, as it is when no tool is loaded, and the note says so.
  double offset(const std::string& pin, std::vector<std::string>& notes) const {
    if (const auto source = hal_.driven_by(pin)) {
      notes.push_back(pin + " follows " + *source +
                      " at run time; imported as 0 (its value with no tool offset, G49)");
      return 0.0;
    }
    return hal_.number_of(pin).value_or(0.0);
  }
  std::optional<HalValue> value(const std::string& pin) const { return hal_.value_of(pin); }

 private:
  const IniFile& ini_;
  const HalConfig& hal_;
  const KinematicsModule& module_;
};

// genhexkins' geometry when no pin is set (its header's defaults, the hexapod-sim's numbers).
constexpr std::array<std::array<double, 3>, 6> kGenhexBase{{{-22.950, 13.250, 0.0},
                                                            {22.950, 13.250, 0.0},
                                                            {22.950, 13.250, 0.0},
                                                            {0.000, -26.500, 0.0},
                                                            {0.000, -26.500, 0.0},
                                                            {-22.950, 13.250, 0.0}}};
constexpr std::array<std::array<double, 3>, 6> kGenhexPlatform{{{-1.000, 11.500, 0.0},
                                                                {1.000, 11.500, 0.0},
                                                                {10.459, -4.884, 0.0},
                                                                {9.459, -6.616, 0.0},
                                                                {-9.459, -6.616, 0.0},
                                                                {-10.459, -4.884, 0.0}}};

// genhexkins adds tool-offset + spindle-offset to the z of every base joint and every platform
// joint. Moving the platform joints by t along the platform's z is pkmkit's tool_length = t (the
// tool tip t below them); moving the base joints by t is moving the base: the same joints for the
// same pose.
std::string genhexkins_section(const PinReader& pins, std::vector<std::string>& notes) {
  if (const auto lead = pins.value("genhexkins.screw-lead")) {
    const std::optional<double> value = parse_config_number(lead->text);
    if (!value || *value != 0.0) {
      throw ConfigError(lead->where.file, lead->where.line, "genhexkins.screw-lead",
                        "screw-lead " + lead->text +
                            ": genhexkins' strut length correction for screw actuators has no "
                            "counterpart in pkmkit's hexapod; set it to 0 to import");
    }
  }
  const double offset = pins.offset("genhexkins.tool-offset", notes) +
                        pins.offset("genhexkins.spindle-offset", notes);
  std::vector<std::array<double, 3>> base, platform;
  for (int leg = 0; leg < 6; ++leg) {
    std::array<double, 3> b{}, p{};
    for (int c = 0; c < 3; ++c) {
      const std::string suffix = "." + std::to_string(leg) + "." + "xyz"[c];
      b[c] = pins.geometry("genhexkins.base" + suffix, kGenhexBase[leg][c]);
      p[c] = pins.geometry("genhexkins.platform" + suffix, kGenhexPlatform[leg][c]);
    }
    b[2] += offset;
    base.push_back(b);
    platform.push_back(p);
  }
  if (offset != 0.0) {
    notes.push_back("genhexkins' tool-offset + spindle-offset " + machine::toml_number(offset) +
                    " is tool_length, and raises the base joints' z by as much (as genhexkins "
                    "does): the joints equal genhexkins' for the same pose");
  }
  SectionText section("hexapod");
  section.points("base", base);
  section.points("platform", platform);
  section.number("tool_length", offset);
  return section.text();
}

// lineardeltakins: tower 0 at (0, R), tower 1 at (-R sin 60, -R cos 60), tower 2 at
// (R sin 60, -R cos 60) (its source; its manual's "clockwise" is the other way round), carriage
// reading z + sqrt(L^2 - horizontal distance^2): a glide with vertical rails through z = 0.
std::string lineardeltakins_section(const PinReader& pins, const JointPlan& plan) {
  const double r = pins.geometry("lineardeltakins.R", 198.25 - 33.0 - 35.0);
  const double l = pins.geometry("lineardeltakins.L", 269.0);
  const double sin60 = std::sqrt(3.0) / 2.0;
  const std::array<std::array<double, 2>, 3> towers{
      {{0.0, r}, {-sin60 * r, -0.5 * r}, {sin60 * r, -0.5 * r}}};
  SectionText section("glide");
  section.passthrough(plan.passthrough);
  for (const auto& tower : towers) {
    section.line("");
    section.line("[[kinematics.rails]]");
    section.line("origin = [" + machine::toml_number(tower[0]) + ", " +
                 machine::toml_number(tower[1]) + ", 0.0]");
    section.line("direction = [0.0, 0.0, 1.0]");
    section.number("strut", l);
    section.line("attach = [0.0, 0.0, 0.0]");
  }
  return section.text();
}

// rotarydeltakins' pins under the names of pkmkit's rotary_delta (the same conventions).
std::string rotarydeltakins_section(const PinReader& pins) {
  SectionText section("rotary_delta");
  section.number("base_radius", pins.geometry("rotarydeltakins.platformradius", 10.0));
  section.number("arm_length", pins.geometry("rotarydeltakins.thighlength", 10.0));
  section.number("forearm_length", pins.geometry("rotarydeltakins.shinlength", 14.0));
  section.number("platform_radius", pins.geometry("rotarydeltakins.footradius", 6.0));
  return section.text();
}

// matrixkins' C_xx .. C_zz (identity by default); trivkins is the identity.
std::string matrix_section(const PinReader& pins, const JointPlan& plan, bool matrixkins) {
  SectionText section("matrix");
  if (matrixkins) {
    section.line("matrix = [");
    for (const char row : std::string("xyz")) {
      std::string text = "  [";
      for (const char column : std::string("xyz")) {
        const std::string pin = std::string("matrixkins.C_") + row + column;
        text += (column == 'x' ? "" : ", ") +
                machine::toml_number(pins.geometry(pin, row == column ? 1.0 : 0.0));
      }
      section.line(text + "],");
    }
    section.line("]");
  }
  section.passthrough(plan.passthrough);
  return section.text();
}

// [TRAJ] LINEAR_UNITS: mm (or metric) and inch (in, imperial); ANGULAR_UNITS must be degrees.
bool read_inch(const IniFile& ini, std::vector<std::string>& notes) {
  if (const IniEntry* angular = ini.find("TRAJ", "ANGULAR_UNITS")) {
    const std::string unit = lower(angular->value);
    // A number is units per degree (LinuxCNC reads one too): 1 is degrees.
    if (unit != "degree" && unit != "degrees" && unit != "deg" &&
        parse_config_number(unit) != std::optional<double>(1.0)) {
      ini.fail(*angular, "'" + angular->value +
                             "': pkmkit's angles are degrees; the import "
                             "takes configurations in degree only");
    }
  }
  const IniEntry* linear = ini.find("TRAJ", "LINEAR_UNITS");
  if (linear == nullptr) {
    notes.push_back("[TRAJ] LINEAR_UNITS is not set: mm, as LinuxCNC assumes");
    return false;
  }
  const std::string unit = lower(linear->value);
  if (unit == "mm" || unit == "metric") return false;
  if (unit == "inch" || unit == "in" || unit == "imperial") return true;
  // A number is units per mm, as LinuxCNC reads it: 1 is mm, 1/25.4 inch.
  if (const std::optional<double> per_mm = parse_config_number(unit)) {
    if (std::abs(*per_mm - 1.0) < 1e-9) return false;
    if (std::abs(*per_mm * 25.4 - 1.0) < 1e-6) return true;
  }
  ini.fail(*linear, "'" + linear->value + "' is not a unit pkmkit knows (mm or inch)");
}

// A number key of the section, or LinuxCNC's default for it (noted).
double number_or_default(const IniFile& ini, const std::string& section, const std::string& key,
                         double fallback, std::vector<std::string>& notes) {
  if (const std::optional<double> value = ini.number(section, key)) return *value;
  notes.push_back("[" + section + "] " + key + " is not set: LinuxCNC's default " +
                  machine::toml_number(fallback));
  return fallback;
}

// A position limit; absent, or LinuxCNC's "no limit" (1e99), it becomes pkmkit's largest
// position of the limit's sign (`sign`), noted.
double position_limit(std::optional<double> value, double sign, const std::string& what,
                      std::vector<std::string>& notes) {
  if (value && std::abs(*value) <= kLargestPosition) return *value;
  const double largest = std::copysign(kLargestPosition, value ? *value : sign);
  notes.push_back(
      what + (value ? " " + machine::toml_number(*value) : std::string(" is not set (no limit)")) +
      ": written as " + machine::toml_number(largest) +
      ", the largest position a machine file takes");
  return largest;
}

// A stepper joint's steps per unit, for `pkm export grbl` and `pkm stream`: the magnitude of
// STEP_SCALE or SCALE; its sign is the motor's direction, which is the wiring's (grbl's $3).
std::optional<double> steps_per_unit(const IniFile& ini, const std::string& section,
                                     std::vector<std::string>& notes) {
  for (const char* key : {"STEP_SCALE", "SCALE"}) {
    const std::optional<double> scale = ini.number(section, key);
    if (!scale || *scale == 0.0 || !std::isfinite(*scale)) continue;
    if (*scale < 0.0) {
      notes.push_back("[" + section + "] " + key + " " + machine::toml_number(*scale) +
                      ": steps_per_unit " + machine::toml_number(-*scale) +
                      "; the minus sign (the motor's direction) is not carried: on grbl it is $3");
    }
    return std::abs(*scale);
  }
  return std::nullopt;
}

ImportedJoint read_joint(const IniFile& ini, int index, const std::string& name, bool angular,
                         bool model_joint, std::vector<std::string>& notes) {
  const std::string section = "JOINT_" + std::to_string(index);
  ImportedJoint joint;
  joint.name = name;
  joint.angular = angular;
  // LinuxCNC's defaults where a key is missing: no soft limits, 1 unit/s and 1 unit/s^2.
  joint.min =
      position_limit(ini.number(section, "MIN_LIMIT"), -1.0, "[" + section + "] MIN_LIMIT", notes);
  joint.max =
      position_limit(ini.number(section, "MAX_LIMIT"), 1.0, "[" + section + "] MAX_LIMIT", notes);
  if (!(joint.min < joint.max)) {
    const IniEntry* max = ini.find(section, "MAX_LIMIT");
    if (max == nullptr) ini.fail_missing(section, "MAX_LIMIT", "it must lie above MIN_LIMIT");
    ini.fail(*max, "must be greater than MIN_LIMIT (" + machine::toml_number(joint.min) +
                       "): pkmkit needs the joint's travel");
  }
  joint.max_velocity = number_or_default(ini, section, "MAX_VELOCITY", 1.0, notes);
  joint.max_acceleration = number_or_default(ini, section, "MAX_ACCELERATION", 1.0, notes);
  joint.home = ini.number(section, "HOME").value_or(0.0);
  joint.steps_per_unit = steps_per_unit(ini, section, notes);
  const IniEntry* type = ini.find(section, "TYPE");
  const bool config_angular = type != nullptr && lower(type->value) == "angular";
  if (type != nullptr && !config_angular && lower(type->value) != "linear") {
    ini.fail(*type, "'" + type->value + "' is neither LINEAR nor ANGULAR");
  }
  if (config_angular != angular) {
    const std::string expected = angular ? "ANGULAR" : "LINEAR";
    if (model_joint) {
      if (type == nullptr) ini.fail_missing(section, "TYPE", "this joint is " + expected);
      ini.fail(*type, "this kinematics' joint " + std::to_string(index) + " is " + expected);
    }
    notes.push_back("[" + section + "] is TYPE " + (config_angular ? "ANGULAR" : "LINEAR") +
                    "; pkmkit passes axis " + name + " through as an angle (deg), same numbers");
  }
  return joint;
}

std::vector<ImportedJoint> read_joints(const IniFile& ini, const JointPlan& plan, int count,
                                       std::vector<std::string>& notes) {
  std::vector<ImportedJoint> joints;
  for (int i = 0; i < plan.model_joints; ++i) {
    joints.push_back(read_joint(ini, i, plan.names[static_cast<std::size_t>(i)],
                                plan.model_joints_angular, true, notes));
  }
  for (std::size_t k = 0; k < plan.passthrough.size(); ++k) {
    const int axis = plan.passthrough[k];
    joints.push_back(read_joint(
        ini, plan.model_joints + static_cast<int>(k),
        std::string(
            1, static_cast<char>(std::tolower(static_cast<unsigned char>(kAxisLetters[axis])))),
        axis >= 3, false, notes));
  }
  const int imported = static_cast<int>(joints.size());
  if (imported < count) {
    notes.push_back("joints " + std::to_string(imported) + ".." + std::to_string(count - 1) +
                    " ([KINS] JOINTS = " + std::to_string(count) +
                    ", axes the module passes through) are not imported: pkmkit's model has no "
                    "joint for them");
  }
  return joints;
}

// The smallest of the limits the configuration sets on the tool's linear motion: [TRAJ] (the
// planner's) and the [AXIS_x] of x y z (each axis's own); LinuxCNC's default of an axis (1 unit/s
// or unit/s^2) when none is set.
double cartesian_limit(const IniFile& ini, const char* traj_key, const char* axis_key,
                       const std::string& label, std::vector<std::string>& notes) {
  std::optional<double> smallest;
  std::string from = std::string("LinuxCNC's default [AXIS_x] ") + axis_key;
  const auto consider = [&](const std::string& section, const char* key) {
    const std::optional<double> value = ini.number(section, key);
    if (value && !(*value > 0.0)) ini.fail(*ini.find(section, key), "must be greater than 0");
    if (value && (!smallest || *value < *smallest)) {
      smallest = value;
      from = "[" + section + "] " + key;
    }
  };
  consider("TRAJ", traj_key);
  for (const char* axis : {"AXIS_X", "AXIS_Y", "AXIS_Z"}) consider(axis, axis_key);
  notes.push_back(label + " from " + from + ", the smallest of [TRAJ]'s and the x y z axes'");
  return smallest.value_or(1.0);
}

// [AXIS_x] MIN_LIMIT and MAX_LIMIT of the pose's coordinates. A coordinate the machine controls
// without both limits: no envelope (noted). One it does not control (b c of a delta passing a
// through) takes the widest range: pkmkit does not check it.
void read_envelope(const IniFile& ini, ImportedConfig& config,
                   const std::vector<bool>& controlled) {
  std::vector<double> min, max;
  for (int axis = 0; axis < config.pose_size; ++axis) {
    const std::string section = std::string("AXIS_") + kAxisLetters[static_cast<std::size_t>(axis)];
    const std::optional<double> low = ini.number(section, "MIN_LIMIT");
    const std::optional<double> high = ini.number(section, "MAX_LIMIT");
    if (controlled[static_cast<std::size_t>(axis)] && (!low || !high)) {
      config.notes.push_back("no work envelope: [" + section +
                             "] does not give both MIN_LIMIT and MAX_LIMIT");
      return;
    }
    const std::string what = "[" + section + "] ";
    // An axis the machine does not control is not checked: no note about its limits.
    std::vector<std::string> unchecked;
    std::vector<std::string>& notes =
        controlled[static_cast<std::size_t>(axis)] ? config.notes : unchecked;
    min.push_back(position_limit(low, -1.0, what + "MIN_LIMIT", notes));
    max.push_back(position_limit(high, 1.0, what + "MAX_LIMIT", notes));
  }
  config.envelope_min = min;
  config.envelope_max = max;
}

// Placeholder limits: every one of `ranges` is the same -M..M with M at least
// kPlaceholderLimit units (LinuxCNC's simulators write +-1000 where the machine has no travel
// to describe). The M when they are, for the warning.
std::optional<double> placeholder_limit(const std::vector<std::pair<double, double>>& ranges) {
  if (ranges.empty()) return std::nullopt;
  const double m = ranges.front().second;
  for (const auto& [low, high] : ranges) {
    if (!(high >= kPlaceholderLimit) || high != m || low != -m) return std::nullopt;
  }
  return m;
}

std::string unit_name(const ImportedConfig& config) {
  return config.inch ? "in" : "mm";
}

// "-1000 .. 1000 in".
std::string placeholder_range(const ImportedConfig& config, double m) {
  char text[96];
  std::snprintf(text, sizeof text, "-%g .. %g %s", m, m, unit_name(config).c_str());
  return text;
}

// The model's linear joints with placeholder limits: kept (pkmkit needs a travel and the
// configuration gives no other), said loudly.
void warn_placeholder_joints(ImportedConfig& config, int model_joints) {
  std::vector<std::pair<double, double>> ranges;
  for (int i = 0; i < model_joints; ++i) {
    const ImportedJoint& joint = config.joints[static_cast<std::size_t>(i)];
    if (joint.angular) return;
    ranges.emplace_back(joint.min, joint.max);
  }
  const std::optional<double> m = placeholder_limit(ranges);
  if (!m) return;
  config.warnings.push_back(
      "[JOINT_0] .. [JOINT_" + std::to_string(model_joints - 1) + "] MIN_LIMIT/MAX_LIMIT are " +
      placeholder_range(config, *m) +
      " on every joint: placeholders, not the joints' travel. Written as they are (the "
      "configuration gives no other); set each [[joints]] min and max to the real travel before "
      "trusting workspace, check or certify");
}

// X Y Z with placeholder limits: no work envelope (pkmkit then takes what the joints reach).
void drop_placeholder_envelope(ImportedConfig& config) {
  if (!config.envelope_min || !config.envelope_max) return;
  std::vector<std::pair<double, double>> ranges;
  for (std::size_t axis = 0; axis < 3; ++axis)
    ranges.emplace_back((*config.envelope_min)[axis], (*config.envelope_max)[axis]);
  const std::optional<double> m = placeholder_limit(ranges);
  if (!m) return;
  config.envelope_min.reset();
  config.envelope_max.reset();
  const std::string message = "[AXIS_X] [AXIS_Y] [AXIS_Z] MIN_LIMIT/MAX_LIMIT are " +
                              placeholder_range(config, *m) +
                              " on every axis: placeholders, not a work envelope. No [cartesian] "
                              "min/max written: the machine's reach is what its joints allow";
  config.warnings.push_back(message);
}

// [TRAJ] HOME lists x y z a b c u v w; the pose's coordinates are its first ones.
void read_home(const IniFile& ini, ImportedConfig& config) {
  std::optional<std::vector<double>> home = ini.numbers("TRAJ", "HOME");
  if (!home) return;
  home->resize(static_cast<std::size_t>(config.pose_size), 0.0);
  config.home = home;
}

std::string machine_name(const IniFile& ini) {
  if (const IniEntry* machine = ini.find("EMC", "MACHINE")) {
    if (!machine->value.empty()) return machine->value;
  }
  return ini.path().stem().string();
}

int joint_count(const IniFile& ini) {
  const std::optional<double> joints = ini.number("KINS", "JOINTS");
  if (!joints) ini.fail_missing("KINS", "JOINTS", "the number of joints");
  if (!(*joints >= 1 && *joints <= 16 && *joints == std::floor(*joints))) {
    ini.fail(*ini.find("KINS", "JOINTS"), "must be a whole number of joints, 1..16");
  }
  return static_cast<int>(*joints);
}

std::string kinematics_section(const KinematicsModule& module, const PinReader& pins,
                               const JointPlan& plan, std::vector<std::string>& notes) {
  if (module.name == "genhexkins") return genhexkins_section(pins, notes);
  if (module.name == "lineardeltakins") return lineardeltakins_section(pins, plan);
  if (module.name == "rotarydeltakins") return rotarydeltakins_section(pins);
  return matrix_section(pins, plan, module.name == "matrixkins");
}

// Tcl lines the import cannot evaluate: refused when they set the kinematics' pins (the geometry
// would silently be the default), else noted.
void note_unread_lines(const HalConfig& hal, const KinematicsModule& module,
                       std::vector<std::string>& notes) {
  for (const std::string& file : hal.tcl_files()) {
    notes.push_back(file +
                    " is Tcl: only its plain setp, sets, net and loadrt lines were read "
                    "(not its procedures, variables or the files it sources)");
  }
  for (const HalConfig::UnreadLine& line : hal.unread()) {
    if (line.text.find(module.name + ".") != std::string::npos) {
      throw ConfigError(line.where.file, line.where.line,
                        "'" + line.text + "' sets " + module.name +
                            " through Tcl, which the import does not evaluate; write the value "
                            "as a plain setp line (setp PIN NUMBER)");
    }
    notes.push_back("not read (Tcl): " + line.where.file + ":" + std::to_string(line.where.line) +
                    ": " + line.text);
  }
}

}  // namespace

const std::vector<std::string>& importable_kinematics() {
  static const std::vector<std::string> modules{"genhexkins", "lineardeltakins", "rotarydeltakins",
                                                "matrixkins", "trivkins"};
  return modules;
}

}  // namespace pkm::linuxcnc

namespace pkm::linuxcnc {

ImportedConfig read_linuxcnc_config(const std::filesystem::path& ini_path,
                                    const ImportOptions& options) {
  const IniFile ini = IniFile::read(ini_path);
  const HalConfig hal = HalConfig::read(ini, options.hallib);
  const KinematicsModule module = find_module(ini, hal);
  ImportedConfig config;
  config.source = ini_path.string();
  config.module = module.name;
  config.name = machine_name(ini);
  config.inch = read_inch(ini, config.notes);
  const int count = joint_count(ini);
  const JointPlan plan = joint_plan(ini, module, count);
  if (count < plan.model_joints) {
    ini.fail(*ini.find("KINS", "JOINTS"), "pkmkit's model of " + module.name + " has " +
                                              std::to_string(plan.model_joints) + " joints (" +
                                              joined(plan.names, " ") + "), the configuration " +
                                              std::to_string(count));
  }
  const PinReader pins(ini, hal, module);
  config.kinematics_section = kinematics_section(module, pins, plan, config.notes);
  config.joints = read_joints(ini, plan, count, config.notes);

  std::vector<bool> controlled(6, false);
  const bool orientation = module.name == "genhexkins";
  for (int axis = 0; axis < 6; ++axis)
    controlled[static_cast<std::size_t>(axis)] = axis < 3 || orientation;
  for (const int axis : plan.passthrough) controlled[static_cast<std::size_t>(axis)] = true;
  config.pose_size =
      std::find(controlled.begin() + 3, controlled.end(), true) != controlled.end() ? 6 : 3;
  config.max_feed_per_min =
      60.0 * cartesian_limit(ini, "MAX_LINEAR_VELOCITY", "MAX_VELOCITY", "max_feed", config.notes);
  config.max_acceleration = cartesian_limit(ini, "MAX_LINEAR_ACCELERATION", "MAX_ACCELERATION",
                                            "max_acceleration", config.notes);
  read_home(ini, config);
  read_envelope(ini, config, controlled);
  warn_placeholder_joints(config, plan.model_joints);
  drop_placeholder_envelope(config);
  for (const std::string& warning : config.warnings) config.notes.push_back("WARNING: " + warning);
  note_unread_lines(hal, module, config.notes);
  return config;
}

std::string machine_file_text(const ImportedConfig& config, const std::string& output_name) {
  machine::ImportedMachine imported = config;
  imported.origin = "Imported by `pkm import linuxcnc` from " + config.source + " (kinematics " +
                    config.module + ").";
  // A hexapod's platform is above its base: the seed picks that assembly.
  if (config.module == "genhexkins" && !config.joints.empty()) {
    double mean = 0.0;
    for (const ImportedJoint& joint : config.joints) mean += joint.home;
    imported.home_seed_z = mean / static_cast<double>(config.joints.size());
  }
  try {
    return machine::machine_file_text(imported, output_name);
  } catch (const machine::ImportedMachineError& error) {
    throw ConfigError(config.source, error.what());
  }
}

}  // namespace pkm::linuxcnc
