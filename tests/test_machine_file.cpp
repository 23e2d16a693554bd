// Every malformed machine file gives an error naming file, line and key.
#include <gtest/gtest.h>

#include <fstream>
#include <numbers>
#include <sstream>

#include "test_support.hpp"

namespace pkm {
namespace {

std::string read_example(const std::string& file) {
  std::ifstream in(test::example_machine_path(file));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Edit {
  std::string find;     // text replaced (its first occurrence; must occur in the base)
  std::string replace;  // its replacement; "# <-" marks the line the error must name
};

struct BadFileCase {
  std::string name;
  std::string base;  // example file the case starts from
  std::vector<Edit> edits;
  std::string key;
  std::string message;  // a part of the message
  int line = 0;         // expected line when no "# <-" marker can carry it (a key that is absent)
};

std::ostream& operator<<(std::ostream& out, const BadFileCase& c) {
  return out << c.name;
}

int marked_line(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (line.find("# <-") != std::string::npos) return number;
  }
  return -1;
}

class BadMachineFile : public ::testing::TestWithParam<BadFileCase> {};

TEST_P(BadMachineFile, NamesFileLineAndKey) {
  const BadFileCase& c = GetParam();
  std::string text = read_example(c.base);
  for (const Edit& edit : c.edits) {
    const auto at = text.find(edit.find);
    ASSERT_NE(at, std::string::npos) << "case text not in " << c.base << ": " << edit.find;
    text.replace(at, edit.find.size(), edit.replace);
  }
  const int line = c.line > 0 ? c.line : marked_line(text);
  ASSERT_GT(line, 0) << "case has no # <- marker";
  try {
    parse_machine(text, "case.toml");
    FAIL() << "accepted a bad file";
  } catch (const MachineFileError& error) {
    EXPECT_EQ(error.file(), "case.toml");
    EXPECT_EQ(error.line(), line) << error.what();
    EXPECT_EQ(error.key(), c.key) << error.what();
    EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
    EXPECT_EQ(std::string(error.what()).rfind("case.toml:" + std::to_string(line) + ":" + c.key, 0),
              0u)
        << error.what();
  }
}

const std::string kThirdJoint =
    "[[joints]]\nname = \"third\"\nmin = 1.0\nmax = 2.0\nmax_velocity = 1.0\n"
    "max_acceleration = 1.0\n\n[cartesian]";

const BadFileCase kCases[] = {
    {"syntax",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = = 100.0 # <-"}},
     "(syntax)",
     ""},
    {"missing_name",
     "hektor.toml",
     {{"name = \"Hektor (source document, d = 100)\"\n", ""}},
     "name",
     "missing",
     1},
    {"unknown_top_level_key",
     "hektor.toml",
     {{"units = \"mm\"", "units = \"mm\"\ncolour = 3 # <-"}},
     "colour",
     "unknown key"},
    {"unknown_model_key",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = 100.0\npulley = 3.0 # <-"}},
     "kinematics.pulley",
     "unknown key"},
    {"unknown_joint_key",
     "hektor.toml",
     {{"axis = \"B\"", "axis = \"B\"\nsteps = 80 # <-"}},
     "joints[2].steps",
     "unknown key"},
    {"tool_z_unknown",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]", "home = [750.0, -700.0]\n[tool]\nz = \"laser\" # <-"}},
     "tool.z",
     "must be \"pen\" or \"ignore\""},
    {"tool_on_a_machine_with_z",
     "linear-delta.toml",
     {{"[cartesian]", "[tool]\nz = \"pen\" # <-\n[cartesian]"}},
     "tool.z",
     "moves in Z itself"},
    {"tool_negative_delay",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]", "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndelay = -1 # <-"}},
     "tool.delay",
     "between 0 and 60 s"},
    {"unknown_type",
     "hektor.toml",
     {{"type = \"cable_plotter\"", "type = \"scara\" # <-"}},
     "kinematics.type",
     "unknown kinematics type 'scara'"},
    {"negative_anchor_distance",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = -100.0 # <-"}},
     "kinematics.anchor_distance",
     "positive"},
    {"anchor_distance_not_a_number",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = \"100\" # <-"}},
     "kinematics.anchor_distance",
     "must be a number"},
    {"anchor_distance_nan",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = nan # <-"}},
     "kinematics.anchor_distance",
     "finite"},
    {"missing_anchor_distance",
     "hektor.toml",
     {{"[kinematics]\ntype = \"cable_plotter\"\nanchor_distance = 100.0",
       "[kinematics] # <-\ntype = \"cable_plotter\""}},
     "kinematics.anchor_distance",
     "missing"},
    {"bad_units",
     "hektor.toml",
     {{"units = \"mm\"", "units = \"feet\" # <-"}},
     "units",
     "\"mm\" or \"inch\""},
    {"min_above_max",
     "hektor.toml",
     {{"max = 180.0", "max = 4.0 # <-"}},
     "joints[1].max",
     "greater than min"},
    {"zero_velocity",
     "hektor.toml",
     {{"max_velocity = 60.0       # mm/s", "max_velocity = 0.0 # <-"}},
     "joints[1].max_velocity",
     "must be between 0.001 and 1e+06 mm/s, not 0"},
    {"duplicate_joint_name",
     "hektor.toml",
     {{"name = \"right\"", "name = \"left\" # <-"}},
     "joints[2].name",
     "named twice"},
    {"bad_axis_letter",
     "hektor.toml",
     {{"axis = \"A\"", "axis = \"Q\" # <-"}},
     "joints[1].axis",
     "one letter"},
    {"duplicate_axis_letter",
     "hektor.toml",
     {{"axis = \"B\"", "axis = \"A\" # <-"}},
     "joints[2].axis",
     "used by two joints"},
    {"joint_count_mismatch",
     "hektor.toml",
     {{"[[joints]]", "[[joints]] # <-"}, {"[cartesian]", kThirdJoint}},
     "joints",
     "has 2 joints; the file lists 3"},
    {"home_unreachable",
     "hektor.toml",
     {{"home = [50.0, -50.0]", "home = [50.0, 50.0] # <-"}},
     "cartesian.home",
     "unreachable"},
    {"home_outside_joint_limits",
     "hektor.toml",
     {{"home = [50.0, -50.0]", "home = [50.0, -175.0] # <-"}},
     "cartesian.home",
     "pose x 50.000 y -175.000 mm: joint 'left' = 182.003 mm passes its max 180.000 mm"},
    {"home_too_short",
     "hexapod-bit.toml",
     {{"home = [0.0, 0.0, 1000.0, 0.0, 0.0, 0.0]", "home = [0.0, 0.0] # <-"}},
     "cartesian.home",
     "controls z"},
    {"missing_cartesian",
     "hektor.toml",
     {{"[cartesian]\nmax_feed = 2400.0         # mm/min\n"
       "max_acceleration = 500.0  # mm/s^2\nhome = [50.0, -50.0]\n",
       ""}},
     "cartesian",
     "missing",
     1},
    {"singular_matrix",
     "matrix-mill.toml",
     {{"matrix = [\n  [1.0,    0.0003, -0.0001],\n  [0.0,    1.0,     0.0   ],",
       "matrix = [ # <-\n  [1.0,    2.0, 3.0],\n  [2.0,    4.0,     6.0   ],"}},
     "kinematics.matrix",
     "singular"},
    {"matrix_wrong_shape",
     "matrix-mill.toml",
     {{"matrix = [", "matrix = [ # <-"}, {"  [0.0002, 0.0,     1.0   ],\n]", "]"}},
     "kinematics.matrix",
     "3 rows"},
    {"hexapod_shorthand_and_points",
     "hexapod-bit.toml",
     {{"base_radius = 500.0", "base_radius = 500.0 # <-"},
      {"tool_length = 30.0", "tool_length = 30.0\nbase = [[0.0, 0.0, 0.0]]"}},
     "kinematics.base_radius",
     "not both"},
    {"hexapod_bad_side_ratio",
     "hexapod-bit.toml",
     {{"side_ratio = 0.365", "side_ratio = 1.5 # <-"}},
     "kinematics.side_ratio",
     "(0, 1]"},
    {"hexapod_missing_tool_length",
     "hexapod-bit.toml",
     {{"[kinematics]", "[kinematics] # <-"}, {"tool_length = 30.0\n", ""}},
     "kinematics.tool_length",
     "missing"},
    {"formula_syntax",
     "mach3-formula.toml",
     {{"a = \"sqrt((x^2) + (y^2))\"", "a = \"sqrt((x^2) + (y^2)\" # <-"}},
     "kinematics.formulas.a",
     "parenthes"},
    {"formula_unknown_variable",
     "mach3-formula.toml",
     {{"a = \"sqrt((x^2) + (y^2))\"", "a = \"sqrt((x^2) + (z^2))\" # <-"}},
     "kinematics.formulas.a",
     "z"},
    {"formula_missing_for_joint",
     "mach3-formula.toml",
     {{"[kinematics.formulas]", "[kinematics.formulas] # <-"},
      {"b = \"sqrt(((d - x)^2) + (y^2))\"", "bee = \"sqrt(((d - x)^2) + (y^2))\""}},
     "kinematics.formulas",
     "joint 'b' has no formula"},
    {"glide_orientation_needs_six_rails",
     "triaglide.toml",
     {{"orientation = false", "orientation = true"},
      {"[[kinematics.rails]]", "[[kinematics.rails]] # <-"}},
     "kinematics.rails",
     "exactly 6 rails"},
    {"glide_zero_direction",
     "linear-delta.toml",
     {{"direction = [0.0, 0.0, 1.0]", "direction = [0.0, 0.0, 0.0] # <-"}},
     "kinematics.rails[1].direction",
     "must not be zero"},
    {"glide_bad_branch",
     "linear-delta.toml",
     {{"attach = [0.0, 40.0, 0.0]", "attach = [0.0, 40.0, 0.0]\nbranch = 2 # <-"}},
     "kinematics.rails[1].branch",
     "1 or -1"},
    {"fractional_iterations",
     "hexapod-bit.toml",
     {{"tool_length = 30.0", "tool_length = 30.0\nforward_max_iterations = 2.5 # <-"}},
     "kinematics.forward_max_iterations",
     "whole number"},
};

INSTANTIATE_TEST_SUITE_P(Cases, BadMachineFile, ::testing::ValuesIn(kCases),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(JointSpec, InterfaceUnitsAreMillimetresAndDegrees) {
  JointSpec rotary;
  rotary.kind = JointKind::rotary;
  EXPECT_NEAR(rotary.to_interface(std::numbers::pi / 4.0), 45.0, 1e-12);
  EXPECT_NEAR(rotary.from_interface(-90.0), -std::numbers::pi / 2.0, 1e-15);
  EXPECT_STREQ(rotary.interface_unit(), "deg");
  JointSpec linear;
  linear.kind = JointKind::linear;
  EXPECT_EQ(linear.to_interface(12.5), 12.5);
  EXPECT_EQ(linear.from_interface(-3.25), -3.25);
  EXPECT_STREQ(linear.interface_unit(), "mm");
}

TEST(MachineFile, InchFilesAreConvertedToMillimetres) {
  std::string text = read_example("hektor.toml");
  text.replace(text.find("units = \"mm\""), 12, "units = \"inch\"");
  const Machine inch = parse_machine(text, "inch.toml");
  const auto parameters = inch.kinematics().parameters();
  EXPECT_DOUBLE_EQ(parameters[0].value, 2540.0);
  EXPECT_DOUBLE_EQ(inch.joints()[0].max, 180.0 * 25.4);
  EXPECT_DOUBLE_EQ(inch.home().position_mm.y(), -50.0 * 25.4);
}

TEST(MachineFile, EveryExampleLoads) {
  for (const std::string& file : test::example_machine_files()) {
    EXPECT_NO_THROW(test::load_example(file)) << file;
  }
  EXPECT_EQ(test::example_machine_files().size(), 10u);
}

TEST(MachineFile, ToolChannelOfAPenPlotter) {
  const std::string text = read_example("wall-plotter.toml") +
                           "\n[tool]\nz = \"pen\"\ndown_below = 0.5\ndown = \"M280 P0 S30\"\n"
                           "up = \"M280 P0 S90\"\ndelay = 0.15\n";
  const Machine machine = parse_machine(text, "pen.toml");
  EXPECT_EQ(machine.tool().z, ToolZ::pen);
  EXPECT_DOUBLE_EQ(machine.tool().down_below_mm, 0.5);
  EXPECT_EQ(machine.tool().down_command, "M280 P0 S30");
  EXPECT_EQ(machine.tool().up_command, "M280 P0 S90");
  EXPECT_DOUBLE_EQ(machine.tool().delay_s, 0.15);
  EXPECT_TRUE(machine.tool().pen_down(0.49));
  EXPECT_FALSE(machine.tool().pen_down(0.5));
  const Machine copy = machine;  // NOLINT(performance-unnecessary-copy-initialization)
  EXPECT_EQ(copy.tool().z, ToolZ::pen);
  EXPECT_EQ(load_machine(test::example_machine_path("wall-plotter.toml")).tool().z, ToolZ::none);
}

TEST(MachineFile, MissingFileIsAnError) {
  EXPECT_THROW(load_machine("/nonexistent/machine.toml"), MachineFileError);
}

}  // namespace
}  // namespace pkm
