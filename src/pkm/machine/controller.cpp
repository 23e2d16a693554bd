#include "pkm/machine/controller.hpp"

#include <cmath>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

namespace {

// grblHAL's default axis letters in its order (nuts_bolts.h: AXIS3..AXIS7 are A B C U V).
constexpr std::string_view kGrblhalLetters = "XYZABCUV";
constexpr int kGrblAxes = 3;  // grbl 1.1: N_AXIS 3
constexpr int kGrblhalMaxAxes = 8;

struct KindDefaults {
  int planner_blocks;
  int rx_buffer_bytes;
  int min_rx_buffer_bytes;  // the longest line post writes for it, with its newline
  int max_rx_buffer_bytes;
};

// grbl 1.1h: BLOCK_BUFFER_SIZE 16, RX_BUFFER_SIZE 128 (at most 254: its indices are bytes),
// lines of 80 characters. grblHAL: 35 planner blocks as the issue and older builds have it
// (newer builds default to 100, its $398), RX_BUFFER_SIZE 1024, lines of 256 characters.
KindDefaults defaults_of(ControllerKind kind) {
  if (kind == ControllerKind::grbl) return {16, 128, 81, 254};
  return {35, 1024, 257, 1 << 20};
}

// A whole number of the table within [low, high], or `fallback` when the key is absent.
int whole_number(const kinematics::ModelConfig& table, std::string_view key, int low, int high,
                 const std::string& unit, int fallback) {
  if (!table.has(key)) return fallback;
  const double value = table.number(key);
  if (value != std::floor(value)) {
    table.fail(key, "must be a whole number of " + unit + ", not " +
                        kinematics::formatted_number("%g", value));
  }
  if (!(value >= low && value <= high)) {
    table.fail(key, "must be between " + std::to_string(low) + " and " + std::to_string(high) +
                        " " + unit + ", not " + kinematics::formatted_number("%g", value));
  }
  return static_cast<int>(value);
}

ControllerKind read_kind(const kinematics::ModelConfig& table) {
  const std::string kind = table.string("kind");
  if (kind == "grbl") return ControllerKind::grbl;
  if (kind == "grblhal") return ControllerKind::grblhal;
  table.fail("kind", "must be \"grbl\" or \"grblhal\", not \"" + kind + "\"");
}

int read_axes(const kinematics::ModelConfig& table, ControllerKind kind) {
  if (kind == ControllerKind::grbl) {
    const int axes = whole_number(table, "axes", 1, kGrblhalMaxAxes, "axes", kGrblAxes);
    if (axes != kGrblAxes) {
      table.fail("axes", "grbl 1.1 has 3 axes (X Y Z), not " + std::to_string(axes) +
                             "; a build with more axes is kind = \"grblhal\"");
    }
    return axes;
  }
  return whole_number(table, "axes", kGrblAxes, kGrblhalMaxAxes, "axes", kGrblAxes);
}

// Every joint has its steps, a letter the controller has, and there are no more joints than axes.
void check_joints(const kinematics::ModelConfig& table, const ControllerSettings& settings,
                  const std::vector<JointSpec>& joints,
                  const std::vector<std::unique_ptr<kinematics::ModelConfig>>& joint_tables) {
  const std::string kind = controller_kind_name(settings.kind);
  if (static_cast<int>(joints.size()) > settings.axes) {
    table.fail(table.has("axes") ? "axes" : "kind",
               "this machine has " + std::to_string(joints.size()) + " joints; " + kind +
                   (table.has("axes") ? " built with " : " has ") + std::to_string(settings.axes) +
                   " axes drives " + std::to_string(settings.axes) + " at most" +
                   (settings.kind == ControllerKind::grblhal
                        ? " (a build with more axes: set axes = N)"
                        : " (grblHAL builds go to 8 axes: kind = \"grblhal\")"));
  }
  const std::string_view letters = controller_axis_letters(settings.kind, settings.axes);
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const kinematics::ModelConfig& joint_table = *joint_tables[i];
    if (!joints[i].steps_per_unit) {
      joint_table.fail("steps_per_unit", "joint '" + joints[i].name +
                                             "' has no steps_per_unit, and the [controller] "
                                             "table needs every joint's (steps per mm, or per "
                                             "deg for a rotary joint)");
    }
    if (letters.find(joints[i].axis_letter) == std::string_view::npos) {
      std::string spaced;
      for (const char letter : letters)
        spaced += (spaced.empty() ? "" : " ") + std::string(1, letter);
      joint_table.fail(joint_table.has("axis") ? "axis" : "name",
                       "joint '" + joints[i].name + "' is on axis " + joints[i].axis_letter +
                           ", which " + kind + " with " + std::to_string(settings.axes) +
                           " axes lacks (it has " + spaced + ")");
    }
  }
}

}  // namespace

std::string_view controller_axis_letters(ControllerKind kind, int axes) {
  if (kind == ControllerKind::grbl) return kGrblhalLetters.substr(0, kGrblAxes);
  return kGrblhalLetters.substr(0, static_cast<std::size_t>(axes));
}

ControllerSettings read_controller_table(
    const kinematics::ModelConfig& table, const std::vector<JointSpec>& joints,
    const std::vector<std::unique_ptr<kinematics::ModelConfig>>& joint_tables) {
  ControllerSettings settings;
  settings.kind = read_kind(table);
  const KindDefaults defaults = defaults_of(settings.kind);
  settings.axes = read_axes(table, settings.kind);
  settings.planner_blocks =
      whole_number(table, "planner_blocks", 2, 1000, "blocks", defaults.planner_blocks);
  settings.rx_buffer_bytes =
      whole_number(table, "rx_buffer", defaults.min_rx_buffer_bytes, defaults.max_rx_buffer_bytes,
                   "bytes", defaults.rx_buffer_bytes);
  settings.baud = whole_number(table, "baud", 300, 10000000, "bit/s", 115200);
  if (table.has("junction_deviation")) {
    // grbl takes any deviation from 0 (a stop at every corner); beyond 10 mm it is a typo.
    constexpr double kMaxDeviation_mm = 10.0;
    settings.junction_deviation = table.length("junction_deviation");
    if (!(settings.junction_deviation >= 0.0 && settings.junction_deviation <= kMaxDeviation_mm)) {
      table.fail(
          "junction_deviation",
          "must be between 0 and " +
              kinematics::formatted_number("%g", kMaxDeviation_mm / table.mm_per_file_unit()) +
              " " + (table.mm_per_file_unit() == 1.0 ? "mm" : "in") + ", not " +
              kinematics::formatted_number("%g",
                                           settings.junction_deviation / table.mm_per_file_unit()));
    }
  }
  check_joints(table, settings, joints, joint_tables);
  return settings;
}

}  // namespace pkm::machine
