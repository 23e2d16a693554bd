// Every malformed machine file gives an error naming file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/model_config_writer.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/post/mach3_export.hpp"
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
    machine::parse_machine(text, "case.toml");
    FAIL() << "accepted a bad file";
  } catch (const machine::MachineFileError& error) {
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
    // Cable machines as built (docs/cable-machines.md).
    {"sled_attachment_without_mass",
     "maslow-frame.toml",
     {{"effector_mass = 9.0            # kg", "# no mass"},
      {"effector_attach = [[-155.0, 139.0], [155.0, 139.0]]",
       "effector_attach = [[-155.0, 139.0], [155.0, 139.0]] # <-"}},
     "kinematics.effector_attach",
     "must be more than 0 kg: the effector's weight is needed for effector_attach"},
    {"tension_limits_reversed",
     "maslow-frame.toml",
     {{"tension_limits = [10.0, 450.0] # N", "tension_limits = [450.0, 10.0] # <-"}},
     "kinematics.tension_limits",
     "needs 0 <= min < max (N), got [450, 10]"},
    {"tension_limits_one_value",
     "maslow-frame.toml",
     {{"tension_limits = [10.0, 450.0] # N", "tension_limits = [10.0] # <-"}},
     "kinematics.tension_limits",
     "needs two values: [min, max] N"},
    {"pulley_larger_than_the_frame",
     "maslow-frame.toml",
     {{"pulley_radius = 10.275", "pulley_radius = 1500.0 # <-"}},
     "kinematics.pulley_radius",
     "less than half the anchors' distance (1489.2 mm)"},
    {"anchors_and_anchor_distance",
     "makelangelo.toml",
     {{"anchors = [[-325.0, 500.0], [325.0, 500.0]]",
       "anchors = [[-325.0, 500.0], [325.0, 500.0]] # <-\nanchor_distance = 650.0"}},
     "kinematics.anchors",
     "give anchors or anchor_distance, not both"},
    {"anchors_right_left_of_left",
     "makelangelo.toml",
     {{"anchors = [[-325.0, 500.0], [325.0, 500.0]]",
       "anchors = [[325.0, 500.0], [-325.0, 500.0]] # <-"}},
     "kinematics.anchors",
     "the right anchor is 650 mm left of the left one: list the left anchor first"},
    {"anchors_one_above_the_other",
     "makelangelo.toml",
     {{"anchors = [[-325.0, 500.0], [325.0, 500.0]]",
       "anchors = [[-325.0, 500.0], [-325.0, 800.0]] # <-"}},
     "kinematics.anchors",
     "both anchors are at x -325 mm: the cables pull along one line"},
    {"anchor_point_with_three_numbers",
     "makelangelo.toml",
     {{"anchors = [[-325.0, 500.0], [325.0, 500.0]]",
       "anchors = [[-325.0, 500.0, 0.0], [325.0, 500.0]] # <-"}},
     "kinematics.anchors",
     "each point needs 2 numbers [x, y]"},
    {"cable_stiffness_zero",
     "maslow-frame.toml",
     {{"cable_stiffness = 150000.0     # N (EA)", "cable_stiffness = 0.0 # <-"}},
     "kinematics.cable_stiffness",
     "must be a positive force (EA, N)"},
    {"negative_cable_density",
     "maslow-frame.toml",
     {{"cable_density = 0.15           # kg/m", "cable_density = -0.15 # <-"}},
     "kinematics.cable_density",
     "must be 0 kg/m or more"},
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
    // A formula that assigns moves its machine at every evaluation (issue 26: `d = d + 1e-3`
    // gave one pose two joint values, 71.02 then 87.05 mm, and ran a motor 110 mm in LinuxCNC).
    {"formula_assigns_to_its_constant",
     "mach3-formula.toml",
     {{"b = \"sqrt(((d - x)^2) + (y^2))\"",
       "b = \"d = d + 1e-3, sqrt(((d - x)^2) + (y^2))\" # <-"}},
     "kinematics.formulas.b",
     "assigns with '=' at column 3: a formula only computes its joint from the pose"},
    {"formula_assigns_to_an_axis",
     "mach3-formula.toml",
     {{"a = \"sqrt((x^2) + (y^2))\"", "a = \"sqrt(((x = x + 1)^2) + (y^2))\" # <-"}},
     "kinematics.formulas.a",
     "assigns with '=' at column 10"},
    {"formula_gives_two_values",
     "mach3-formula.toml",
     {{"a = \"sqrt((x^2) + (y^2))\"", "a = \"x, sqrt((x^2) + (y^2))\" # <-"}},
     "kinematics.formulas.a",
     "gives 2 values separated by commas"},
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
    // A misspelt key is named as unknown, at its own line, with the valid name: not the valid
    // name as "missing" at line 1.
    {"misspelt_required_key",
     "hektor.toml",
     {{"max_acceleration = 600.0  # mm/s^2\naxis = \"A\"", "max_accel = 600.0 # <-\naxis = \"A\""}},
     "joints[1].max_accel",
     "unknown key 'max_accel' (did you mean 'max_acceleration'?)"},
    {"misspelt_table",
     "hektor.toml",
     {{"[cartesian]", "[cartesan] # <-"}},
     "cartesan",
     "unknown key 'cartesan' (did you mean 'cartesian'?)"},
    {"misspelt_optional_key",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = 100.0\ncable_offset = [1.0, 2.0] # <-"}},
     "kinematics.cable_offset",
     "unknown key 'cable_offset' (did you mean 'cable_offsets'?)"},
    {"unknown_key_lists_the_tables_keys",
     "hektor.toml",
     {{"home = [50.0, -50.0]", "home = [50.0, -50.0]\nspeed = 3 # <-"}},
     "cartesian.speed",
     "(this table's keys: home, max, max_acceleration, max_feed, min;"},
    {"joint_max_beyond_a_kilometre",
     "hektor.toml",
     {{"max = 180.0", "max = 2e6 # <-"}},
     "joints[1].max",
     "must be between -1e+06 and 1e+06 mm, not 2e+06"},
    {"anchor_distance_beyond_a_kilometre",
     "hektor.toml",
     {{"anchor_distance = 100.0", "anchor_distance = 1e300 # <-"}},
     "kinematics.anchor_distance",
     "must be within a kilometre"},
    {"glide_strut_beyond_a_kilometre",
     "hexaglide.toml",
     {{"strut = 600.0", "strut = 1e9 # <-"}},
     "kinematics.rails[1].strut",
     "must be within a kilometre"},
    {"tiny_acceleration",
     "hektor.toml",
     {{"max_acceleration = 600.0  # mm/s^2", "max_acceleration = 1e-300 # <-"}},
     "joints[1].max_acceleration",
     "must be between 0.001 and 1e+09 mm/s^2"},
    {"tiny_cartesian_acceleration",
     "hektor.toml",
     {{"max_acceleration = 500.0  # mm/s^2", "max_acceleration = 1e-300 # <-"}},
     "cartesian.max_acceleration",
     "must be between 0.001 and 1e+09 mm/s^2"},
    {"infinite_feed",
     "hektor.toml",
     {{"max_feed = 2400.0", "max_feed = inf # <-"}},
     "cartesian.max_feed",
     "finite"},
    {"tool_down_below_nan",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown_below = nan # <-"}},
     "tool.down_below",
     "finite"},
    {"tool_down_below_and_down_above",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown_below = 0.0\ndown_above = 45.0 # <-"}},
     "tool.down_above",
     "down_below is given too: one height says on which side of it the pen draws"},
    {"pen_command_moving_the_joints",  // issue 26: a pen command that moves the mechanism
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown = \"M3\"\nup = \"G0 X0 Y0\" # <-"}},
     "tool.up",
     "\"G0 X0 Y0\" moves joint 'left' (its axis X): post writes every move of the joints itself"},
    {"pen_command_feeding_the_servo_axis",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown = \"G1 Z90\" # <-\nup = \"G0 Z0\""}},
     "tool.down",
     "\"G1 Z90\" holds G1: a pen command may use G0 (of axes no joint uses) and G4 only"},
    {"pen_command_switching_to_incremental",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown = \"G91 M3\" # <-"}},
     "tool.down",
     "holds G91"},
    {"pen_command_moving_an_axis_in_the_modal_motion",
     "wall-plotter.toml",
     {{"home = [750.0, -700.0]",
       "home = [750.0, -700.0]\n[tool]\nz = \"pen\"\ndown = \"Z90\" # <-"}},
     "tool.down",
     "moves axis Z without G0"},
    {"two_joints_one_letter_names_both",
     "hektor.toml",
     {{"axis = \"B\"", "axis = \"A\" # <-"}},
     "joints[2].axis",
     "letter A is used by two joints: 'left' (axis = \"A\") and 'right' (axis = \"A\")"},
    {"explicit_letter_against_a_passthrough",
     "matrix-mill.toml",
     {{"[[joints]]\nname = \"x\"", "[[joints]]\nname = \"x\""},
      {"[0.0002, 0.0,     1.0   ],\n]", "[0.0002, 0.0,     1.0   ],\n]\npassthrough = [\"c\"]"},
      {"axis = \"Z\"", "axis = \"C\""},
      {"[cartesian]",
       "[[joints]]\nname = \"c\" # <-\nmin = -360.0\nmax = 360.0\nmax_velocity = 90.0\n"
       "max_acceleration = 900.0\n\n[cartesian]"}},
     "joints[4].name",
     "letter C is used by two joints: 'z' (axis = \"C\") and 'c' (the pass-through of c)"},
    {"plotter_cannot_pass_x",
     "wall-plotter.toml",
     {{"anchor_distance = 1500.0", "anchor_distance = 1500.0\npassthrough = [\"x\"] # <-"}},
     "kinematics.passthrough",
     "'x' cannot pass through here; this model passes \"z\", \"a\", \"b\", \"c\""},
    {"hexaglide_passes_nothing",
     "hexaglide.toml",
     {{"orientation = true", "orientation = true\npassthrough = [\"z\"] # <-"}},
     "kinematics.passthrough",
     "nothing passes through"},
    {"envelope_min_without_max",
     "linear-delta.toml",
     {{"min = [-120.0, -120.0, 0.0]", "min = [-120.0, -120.0, 0.0] # <-"},
      {"max = [120.0, 120.0, 300.0]", ""}},
     "cartesian.min",
     "give both min and max"},
    {"envelope_wrong_count",
     "linear-delta.toml",
     {{"min = [-120.0, -120.0, 0.0]", "min = [-120.0, -120.0] # <-"}},
     "cartesian.min",
     "needs 3 numbers, one per coordinate of home"},
    {"envelope_min_above_max",
     "linear-delta.toml",
     {{"max = [120.0, 120.0, 300.0]", "max = [120.0, -200.0, 300.0] # <-"}},
     "cartesian.max",
     "y: must be greater than min"},
    {"envelope_leaves_out_home",
     "linear-delta.toml",
     {{"home = [0.0, 0.0, 100.0]", "home = [0.0, 0.0, 100.0] # <-"},
      {"min = [-120.0, -120.0, 0.0]", "min = [-120.0, -120.0, 150.0]"}},
     "cartesian.home",
     "z lies outside the work envelope"},
    {"envelope_not_finite",
     "linear-delta.toml",
     {{"max = [120.0, 120.0, 300.0]", "max = [120.0, 120.0, inf] # <-"}},
     "cartesian.max",
     "finite"},
    {"fractional_iterations",
     "hexapod-bit.toml",
     {{"tool_length = 30.0", "tool_length = 30.0\nforward_max_iterations = 2.5 # <-"}},
     "kinematics.forward_max_iterations",
     "whole number"},
    {"hexapod_with_parallel_legs",
     "hexapod-bit.toml",
     // Base and platform joints on one circle: every leg vertical, turning about z moves none.
     {{"base_radius = 500.0\nplatform_radius = 400.0\nside_ratio = 0.365",
       "base = [[500, 0, 0], [250, 433.013, 0], [-250, 433.013, 0], [-500, 0, 0], "
       "[-250, -433.013, 0], [250, -433.013, 0]]\nplatform = [[500, 0, 0], [250, 433.013, 0], "
       "[-250, 433.013, 0], [-500, 0, 0], [-250, -433.013, 0], [250, -433.013, 0]]"},
      {"home = [0.0, 0.0, 1000.0, 0.0, 0.0, 0.0]",
       "home = [0.0, 0.0, 1000.0, 0.0, 0.0, 0.0] # <-"}},
     "cartesian.home",
     "the machine is singular at home: the relative smallest singular value of its jacobian is "
     "0, below 1e-06; the tool's motion c 1.000 (mm, deg) moves no joint"},
    {"delta_with_its_towers_in_one_place",
     "linear-delta.toml",
     // The three carriages on one rail: the tool swings about it.
     {{"origin = [-173.20508075688772, -100.0, 0.0]", "origin = [0.0, 200.0, 0.0]"},
      {"attach = [-34.64101615137755, -20.0, 0.0]", "attach = [0.0, 40.0, 0.0]"},
      {"origin = [173.20508075688772, -100.0, 0.0]", "origin = [0.0, 200.0, 0.0]"},
      {"attach = [34.64101615137755, -20.0, 0.0]", "attach = [0.0, 40.0, 0.0]"},
      {"home = [0.0, 0.0, 100.0]", "home = [0.0, 0.0, 100.0] # <-"}},
     "cartesian.home",
     "singular at home: the relative smallest singular value of its jacobian is 0, below 1e-06; "
     "the tool's motion x 1.000 (mm, deg) moves no joint"},
    {"formula_with_both_cables_from_one_anchor",
     "mach3-formula.toml",
     {{"b = \"sqrt(((d - x)^2) + (y^2))\"", "b = \"sqrt((x^2) + (y^2))\""},
      {"home = [50.0, -50.0]", "home = [50.0, -50.0] # <-"}},
     "cartesian.home",
     "singular at home: the relative smallest singular value of its jacobian is 0, below 1e-06; "
     "the tool's motion x 0.707 y 0.707 (mm, deg) moves no joint"},
};

INSTANTIATE_TEST_SUITE_P(Cases, BadMachineFile, ::testing::ValuesIn(kCases),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(JointSpec, InterfaceUnitsAreMillimetresAndDegrees) {
  machine::JointSpec rotary;
  rotary.kind = kinematics::JointKind::rotary;
  EXPECT_NEAR(rotary.to_interface(std::numbers::pi / 4.0), 45.0, 1e-12);
  EXPECT_NEAR(rotary.from_interface(-90.0), -std::numbers::pi / 2.0, 1e-15);
  EXPECT_STREQ(rotary.interface_unit(), "deg");
  machine::JointSpec linear;
  linear.kind = kinematics::JointKind::linear;
  EXPECT_EQ(linear.to_interface(12.5), 12.5);
  EXPECT_EQ(linear.from_interface(-3.25), -3.25);
  EXPECT_STREQ(linear.interface_unit(), "mm");
}

TEST(MachineFile, InchFilesAreConvertedToMillimetres) {
  std::string text = read_example("hektor.toml");
  text.replace(text.find("units = \"mm\""), 12, "units = \"inch\"");
  const machine::Machine inch = machine::parse_machine(text, "inch.toml");
  const auto parameters = inch.kinematics().parameters();
  EXPECT_EQ(parameters[2].name, "anchor_right_x");
  EXPECT_DOUBLE_EQ(parameters[2].value, 2540.0);
  EXPECT_DOUBLE_EQ(inch.joints()[0].max, 180.0 * 25.4);
  EXPECT_DOUBLE_EQ(inch.home().position_mm.y(), -50.0 * 25.4);
}

TEST(MachineFile, EveryExampleLoads) {
  for (const std::string& file : test::example_machine_files()) {
    EXPECT_NO_THROW(test::load_example(file)) << file;
  }
  EXPECT_EQ(test::example_machine_files().size(), 23u);
  const machine::Machine pen =
      test::load_example("pen-plotter.toml");  // the servo pen's [tool] table
  EXPECT_EQ(pen.tool().z, machine::ToolZ::pen);
  EXPECT_EQ(pen.tool().down_command, "M280 P0 S30");
  EXPECT_EQ(pen.tool().up_command, "M280 P0 S90");
  EXPECT_DOUBLE_EQ(pen.tool().delay_s, 0.15);
}

TEST(MachineFile, PenThatDrawsAboveItsHeight) {
  // A LinuxCNC polargraph's drawings draw at Z90 and travel at Z0: down_above = 45; its servo
  // on the controller's Z, an axis no joint uses, is switched with G0 (and G4 may wait).
  const std::string text =
      read_example("wall-plotter.toml") +
      "\n[tool]\nz = \"pen\"\ndown_above = 45.0\ndown = \"G0 Z90 (pen) G4 P0.2\"\n"
      "up = \"G0 Z0\"\n";
  const machine::Machine machine = machine::parse_machine(text, "pen.toml");
  EXPECT_TRUE(machine.tool().down_above);
  EXPECT_DOUBLE_EQ(machine.tool().pen_height_mm, 45.0);
  EXPECT_TRUE(machine.tool().pen_down(90.0));
  EXPECT_FALSE(machine.tool().pen_down(45.0));
  EXPECT_FALSE(machine.tool().pen_down(0.0));
  EXPECT_EQ(machine.tool().down_command, "G0 Z90 (pen) G4 P0.2");
}

TEST(MachineFile, ToolChannelOfAPenPlotter) {
  // A servo pen (M280) is for a controller that has the command: not the wall plotter's grbl.
  std::string plotter = read_example("wall-plotter.toml");
  plotter.replace(plotter.find("[controller]\nkind = \"grbl\"\n"), 27, "");
  const std::string text = plotter +
                           "\n[tool]\nz = \"pen\"\ndown_below = 0.5\ndown = \"M280 P0 S30\"\n"
                           "up = \"M280 P0 S90\"\ndelay = 0.15\n";
  const machine::Machine machine = machine::parse_machine(text, "pen.toml");
  EXPECT_EQ(machine.tool().z, machine::ToolZ::pen);
  EXPECT_DOUBLE_EQ(machine.tool().pen_height_mm, 0.5);
  EXPECT_FALSE(machine.tool().down_above);
  EXPECT_EQ(machine.tool().down_command, "M280 P0 S30");
  EXPECT_EQ(machine.tool().up_command, "M280 P0 S90");
  EXPECT_DOUBLE_EQ(machine.tool().delay_s, 0.15);
  EXPECT_TRUE(machine.tool().pen_down(0.49));
  EXPECT_FALSE(machine.tool().pen_down(0.5));
  const machine::Machine copy = machine;  // NOLINT(performance-unnecessary-copy-initialization)
  EXPECT_EQ(copy.tool().z, machine::ToolZ::pen);
  EXPECT_EQ(machine::load_machine(test::example_machine_path("wall-plotter.toml")).tool().z,
            machine::ToolZ::none);
}

TEST(MachineFile, FilesThatCannotBeOpenedSayWhy) {
  const auto message = [](const std::filesystem::path& path) {
    try {
      machine::load_machine(path);
    } catch (const machine::MachineFileError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("/nonexistent/machine.toml"),
            "/nonexistent/machine.toml: cannot open (No such file or directory)");
  const std::filesystem::path directory = std::filesystem::temp_directory_path();
  EXPECT_EQ(message(directory), directory.string() + ": cannot open (it is a directory)");
}

// A third joint on the wall plotter: a pen on a real Z axis, following the program's Z.
std::string plotter_with_pen_axis() {
  std::string text = read_example("wall-plotter.toml");
  text.replace(text.find("anchor_distance = 1500.0"), 24,
               "anchor_distance = 1500.0\npassthrough = [\"z\"]");
  text.replace(text.find("axis = \"X\"\n"), 11, "");
  text.replace(text.find("axis = \"Y\"\n"), 11, "");
  text.replace(text.find("[cartesian]"), 11,
               "[[joints]]\nname = \"pen\"\nmin = -5.0\nmax = 20.0\nmax_velocity = 50.0\n"
               "max_acceleration = 500.0\nsteps_per_unit = 80.0\n\n[cartesian]");
  text.replace(text.find("home = [750.0, -700.0]"), 22, "home = [750.0, -700.0, 5.0]");
  return text;
}

TEST(AxisLetters, PassThroughJointsTakeTheirOwnLetter) {
  // A matrix mill passing A and C: the C joint is C, not B (the fifth letter).
  std::string text = read_example("matrix-mill.toml");
  text.replace(text.find("  [0.0002, 0.0,     1.0   ],\n]"), 30,
               "  [0.0002, 0.0,     1.0   ],\n]\npassthrough = [\"a\", \"c\"]");
  const std::string rotary =
      "min = -360.0\nmax = 360.0\nmax_velocity = 90.0\nmax_acceleration = 900.0\n";
  text.replace(text.find("[cartesian]"), 11,
               "[[joints]]\nname = \"tilt\"\n" + rotary + "\n[[joints]]\nname = \"turn\"\n" +
                   rotary + "\n[cartesian]");
  text.replace(text.find("home = [300.0, 200.0, -100.0]"), 29,
               "home = [300.0, 200.0, -100.0, 0.0, 0.0, 0.0]");
  const machine::Machine mill = machine::parse_machine(text, "mill5.toml");
  std::string letters;
  for (const machine::JointSpec& joint : mill.joints()) letters += joint.axis_letter;
  EXPECT_EQ(letters, "XYZAC");
}

TEST(AxisLetters, JointsWithoutALetterTakeTheLettersLeft) {
  const machine::Machine plotter = machine::parse_machine(plotter_with_pen_axis(), "pen-axis.toml");
  std::string letters;
  for (const machine::JointSpec& joint : plotter.joints()) letters += joint.axis_letter;
  EXPECT_EQ(letters, "XYZ");
  // The left cable on Y: the right one takes the first letter left, X; the pen is Z.
  std::string text = plotter_with_pen_axis();
  text.replace(text.find("name = \"left\""), 13, "name = \"left\"\naxis = \"Y\"");
  const machine::Machine swapped = machine::parse_machine(text, "swapped.toml");
  letters.clear();
  for (const machine::JointSpec& joint : swapped.joints()) letters += joint.axis_letter;
  EXPECT_EQ(letters, "YXZ");
}

TEST(PassThroughZ, APenOnARealZAxisIsAJoint) {
  const machine::Machine plotter = machine::parse_machine(plotter_with_pen_axis(), "pen-axis.toml");
  EXPECT_TRUE(plotter.kinematics().dof().controls(2));
  kinematics::JointVector joints;
  ASSERT_TRUE(plotter.inverse(geometry::Pose::from_mm_deg(600, -800, -1.5), joints).ok());
  EXPECT_DOUBLE_EQ(joints[0], 1000.0);  // 600-800-1000
  EXPECT_DOUBLE_EQ(joints[1], std::hypot(900.0, 800.0));
  EXPECT_DOUBLE_EQ(joints[2], -1.5);
  EXPECT_EQ(plotter.inverse(geometry::Pose::from_mm_deg(600, -800, 25), joints).code,
            kinematics::StatusCode::joint_limit);  // the pen axis has limits of its own
  // The machine file written back keeps the pass-through.
  EXPECT_NE(machine::kinematics_toml(plotter.kinematics(), machine::LengthUnit::mm)
                .find("passthrough = [\"z\"]"),
            std::string::npos);
  // Its Z is a joint: a [tool] channel for Z is refused.
  EXPECT_THROW(
      machine::parse_machine(plotter_with_pen_axis() + "\n[tool]\nz = \"pen\"\n", "both.toml"),
      machine::MachineFileError);
}

TEST(PassThroughZ, ABiglideCarriesAPenAxisToo) {
  std::string text = read_example("triaglide.toml");
  const machine::Machine triaglide = machine::parse_machine(text, "t.toml");
  ASSERT_EQ(triaglide.kinematics().joint_count(), 3);
  // Two rails in x z with y passing through stand for the same arithmetic as the plotter's z.
  std::vector<kinematics::GlideRail> rails(2);
  rails[0] = {{0, 0, 0}, {1, 0, 0}, 200.0, {-20, 0, 0}, -1};
  rails[1] = {{0, 0, 0}, {1, 0, 0}, 200.0, {20, 0, 0}, 1};
  const kinematics::GlideKinematics biglide(
      rails, geometry::Dof::planar_xy(),
      kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy()));
  EXPECT_EQ(
      machine::kinematics_toml(biglide, machine::LengthUnit::mm).find("passthrough = [\"z\"]") !=
          std::string::npos,
      true);
}

TEST(JointLimits, NanFailsTheCheck) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  kinematics::JointVector joints(2);
  joints << 50.0, std::nan("");
  const kinematics::Status status = hektor.check_joint_limits(joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_limit);
  EXPECT_EQ(status.joint, 1);
}

// The example delta has a work envelope: min = [-120, -120, 0], max = [120, 120, 300].
std::string delta_with_envelope() {
  const std::string text = read_example("linear-delta.toml");
  EXPECT_NE(text.find("\nmin = [-120.0, -120.0, 0.0]"), std::string::npos);
  return text;
}

TEST(Envelope, ADeltaJobBelowItsBedFails) {
  const machine::Machine delta = machine::parse_machine(delta_with_envelope(), "delta.toml");
  kinematics::JointVector joints;
  const geometry::Pose below = geometry::Pose::from_mm_deg(0, 0, -150);
  const kinematics::Status status = delta.inverse(below, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::outside_envelope);
  EXPECT_EQ(status.axis, 2);
  // The extent `check` reports is clipped by the envelope.
  for (const machine::AxisExtent& extent : machine::reachable_extent(delta)) {
    EXPECT_GE(extent.min, delta.cartesian().envelope_min[extent.axis]);
    EXPECT_LE(extent.max, delta.cartesian().envelope_max[extent.axis]);
  }
  EXPECT_NEAR(machine::reachable_extent(delta)[2].min, 0.0, 1e-5);
}

// The explanation of a refused pose: pose, joint, value, limit, in the machine file's units.
struct ExplainCase {
  std::string name;
  std::string machine;  // example file, or "inch:" + example, "envelope:delta"
  geometry::Pose pose;
  std::string expected;
};

std::ostream& operator<<(std::ostream& out, const ExplainCase& c) {
  return out << c.name;
}

machine::Machine machine_of(const std::string& name) {
  if (name == "envelope:delta") return machine::parse_machine(delta_with_envelope(), "delta.toml");
  if (name.rfind("inch:", 0) == 0) {
    std::string text = read_example(name.substr(5));
    text.replace(text.find("units = \"mm\""), 12, "units = \"inch\"");
    return machine::parse_machine(text, "inch.toml");
  }
  return test::load_example(name);
}

class Explained : public ::testing::TestWithParam<ExplainCase> {};

TEST_P(Explained, NamesPoseJointValueAndLimit) {
  const ExplainCase& c = GetParam();
  const machine::Machine machine = machine_of(c.machine);
  kinematics::JointVector joints;
  const kinematics::Status status = machine.inverse(c.pose, joints);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(machine.explain(c.pose, status), c.expected);
}

const ExplainCase kExplainCases[] = {
    {"plotter_off_the_sheet", "wall-plotter.toml", geometry::Pose::from_mm_deg(1400, -2000, 0),
     "pose x 1400.000 y -2000.000 mm: joint 'left' = 2441.311 mm passes its max 2100.000 mm"},
    {"plotter_outside_its_anchors", "wall-plotter.toml", geometry::Pose::from_mm_deg(-500, -700, 0),
     "pose x -500.000 y -700.000 mm: unreachable: left of the left anchor (x <= 0) the right "
     "cable would have to push"},
    {"hexapod_leg_too_long", "hexapod-bit.toml", geometry::Pose::from_mm_deg(0, 0, 1600),
     "pose x 0.000 y 0.000 z 1600.000 mm a 0.000 b 0.000 c 0.000 deg: joint 'leg1' = 1649.463 "
     "mm passes its max 1500.000 mm"},
    {"hexapod_upside_down", "hexapod-bit.toml", geometry::Pose::from_mm_deg(0, 0, 1000, 0, 180, 0),
     "pose x 0.000 y 0.000 z 1000.000 mm a 0.000 b 180.000 c 0.000 deg: another assembly mode "
     "than home's, across a singularity (a platform below its carriages, a hexapod platform "
     "tilted past 90 deg)"},
    {"delta_below_its_bed", "envelope:delta", geometry::Pose::from_mm_deg(0, 0, -150),
     "pose x 0.000 y 0.000 z -150.000 mm: z = -150.000 mm passes the work envelope's min 0.000 "
     "mm ([cartesian] min)"},
    {"triaglide_strut_too_short", "triaglide.toml", geometry::Pose::from_mm_deg(0, 0, -900),
     "pose x 0.000 y 0.000 z -900.000 mm: unreachable: the strut of rail 1 is too short to "
     "reach it"},
    {"triaglide_rail_too_short", "triaglide.toml", geometry::Pose::from_mm_deg(900, 0, 200),
     "pose x 900.000 y 0.000 z 200.000 mm: joint 'rail1' = 1108.327 mm passes its max 800.000 "
     "mm"},
    {"inch_machine_speaks_inches", "inch:hektor.toml",
     geometry::Pose::from_mm_deg(10 * 25.4, -170 * 25.4, 0),
     "pose x 10.0000 y -170.0000 in: joint 'right' = 192.3538 in passes its max 180.0000 in"},
};

INSTANTIATE_TEST_SUITE_P(Cases, Explained, ::testing::ValuesIn(kExplainCases),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(Explained, AMoveIsExplainedWhereItLeavesTheReach) {
  // From home straight out along x: leg 3 and 6 pass 1500 mm on the way; the first to cross
  // is named, where it crosses, whichever point of the move a caller found failing.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const geometry::Vector6d from = geometry::Pose::from_mm_deg(0, 0, 1000).as_vector();
  const geometry::Vector6d to = geometry::Pose::from_mm_deg(900, 900, 1000).as_vector();
  const std::string text =
      hexapod.explain_path([&](double u) -> geometry::Vector6d { return from + u * (to - from); });
  EXPECT_EQ(text.rfind("at 67.0 % of it: pose x 603.0", 0), 0u) << text;
  EXPECT_NE(text.find(": joint 'leg6' passes its max 1500.000 mm there, up to 1827.233 mm along "
                      "the move"),
            std::string::npos)
      << text;
}

TEST(Explained, OutsideReachHintSuggestsAnOrigin) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  machine::PoseBox job;
  job.axes = geometry::Dof::planar_xy();
  job.min << 0, 0, 0, 0, 0, 0;
  job.max << 15, 20, 0, 0, 0, 0;
  const std::string hint = machine::outside_reach_hint(plotter, job, geometry::Vector6d::Zero());
  const machine::PoseBox reach = machine::reach_box(plotter);
  char origin[64];
  std::snprintf(origin, sizeof origin, "--origin %.0f %.0f would centre it",
                0.5 * (reach.min[0] + reach.max[0]) - 7.5,
                0.5 * (reach.min[1] + reach.max[1]) - 10);
  EXPECT_EQ(
      hint.rfind("the job spans x 0.000..15.000 y 0.000..20.000 mm; the machine reaches x ", 0), 0u)
      << hint;
  EXPECT_NE(hint.find(origin), std::string::npos) << hint;
  geometry::Vector6d centred = geometry::Vector6d::Zero();
  centred[0] = 0.5 * (reach.min[0] + reach.max[0]) - 7.5;
  centred[1] = 0.5 * (reach.min[1] + reach.max[1]) - 10;
  EXPECT_EQ(machine::outside_reach_hint(plotter, job, centred), "");
}

TEST(Explained, OutsideReachHintSpeaksTheMachineFilesUnits) {
  // LinuxCNC's inch hexapod: --origin is typed in inches, so the boxes and the --origin the hint
  // suggests are in inches too (it said mm, and an --origin of mm values, on an inch machine).
  const machine::Machine hexapod = test::load_example("linuxcnc-hexapod-sim.toml");
  machine::PoseBox job;
  job.axes = geometry::Dof::all();
  job.min << 0, 0, 0, 0, 0, 0;
  job.max << 25.4, 50.8, 0, 0, 0, 0;  // 1 x 2 in at Z0
  geometry::Vector6d origin = geometry::Vector6d::Zero();
  origin[2] = 20.0;  // "--origin 0 0 20" read as mm: the job 0.787 in above the base
  const std::string hint = machine::outside_reach_hint(hexapod, job, origin);
  EXPECT_EQ(hint.rfind("the job spans x 0.000..1.000 y 0.000..2.000 z 0.787..0.787 in; the machine "
                       "reaches x -7.932..7.932 y ",
                       0),
            0u)
      << hint;
  const machine::PoseBox reach = machine::reach_box(hexapod);
  char suggestion[96];
  std::snprintf(suggestion, sizeof suggestion, "--origin %.2f %.2f %.2f would centre it",
                (0.5 * (reach.min[0] + reach.max[0]) - 12.7) / 25.4,
                (0.5 * (reach.min[1] + reach.max[1]) - 25.4) / 25.4,
                0.5 * (reach.min[2] + reach.max[2]) / 25.4);
  EXPECT_NE(hint.find(suggestion), std::string::npos) << hint;
}

TEST(Conditioning, AWellBuiltHexapodIsFarFromSingular) {
  EXPECT_GT(machine::relative_conditioning_at_home(test::load_example("hexapod-bit.toml")), 1e-2);
  EXPECT_EQ(machine::singular_at_home(test::load_example("hexapod-bit.toml")), "");
}

// Text that would make toml++ recurse without bound is refused, located, before it is parsed
// (a 62 KB `a.a.a....b = 1` overflowed the stack).
TEST(MachineFile, TextBeyondTheParsersBoundsIsALocatedError) {
  const auto error_of = [](const std::string& text) {
    try {
      (void)machine::parse_machine(text, "bounds.toml");
    } catch (const machine::MachineFileError& error) {
      return std::pair{error.line(), std::string(error.what())};
    }
    return std::pair{0, std::string("no error")};
  };
  std::string dotted = "a";
  for (int i = 0; i < 31000; ++i) dotted += ".a";
  const auto [line, message] = error_of("name = \"x\"\n" + dotted + ".b = 1\n");
  EXPECT_EQ(line, 2);
  EXPECT_NE(message.find("bounds.toml:2:(syntax): a dotted key of more than 32 parts"),
            std::string::npos)
      << message;
  const auto nested = error_of("x = " + std::string(100000, '[') + std::string(100000, ']'));
  EXPECT_EQ(nested.first, 1);
  EXPECT_NE(nested.second.find("nested deeper than 32"), std::string::npos) << nested.second;
  const auto long_line = error_of("\n\n# " + std::string(70000, 'c') + "\n");
  EXPECT_EQ(long_line.first, 3);
  EXPECT_NE(long_line.second.find("line longer than 65536 bytes"), std::string::npos);
  // Up to the bounds toml++ reads on (and the loader reports what it makes of the keys); strings
  // and numbers hold dots and brackets that are not keys or nesting.
  std::string deep = "a";
  for (int i = 0; i < 31; ++i) deep += ".a";
  EXPECT_EQ(error_of(deep + " = 1\n").second.find("dotted key"), std::string::npos);
  EXPECT_EQ(error_of("s = \"" + std::string(100, '.') + "[[[[\"\nv = [1.5, 2.5]\n")
                .second.find("(syntax)"),
            std::string::npos);
}

// A model the registry does not know, as a new kind starts: x and y scaled onto two joints. It
// writes a key of every kind through the writer and answers none of the other questions.
class ScaledAxes final : public kinematics::Kinematics {
 public:
  std::string_view type() const override { return "scaled"; }
  int joint_count() const override { return 2; }
  geometry::Dof dof() const override { return geometry::Dof::planar_xy(); }
  kinematics::Status inverse(const geometry::Pose& pose,
                             kinematics::JointVector& joints) const override {
    joints.resize(2);
    joints << 2.5 * pose.position_mm.x(), pose.position_mm.y();
    return kinematics::Status::success();
  }
  kinematics::Status forward(const kinematics::JointVector& joints,
                             geometry::Pose& pose) const override {
    pose.position_mm.head<2>() << joints[0] / 2.5, joints[1];
    return kinematics::Status::success();
  }
  kinematics::Status jacobian(const geometry::Pose& pose,
                              kinematics::JointJacobian& d) const override {
    return kinematics::numerical_jacobian(*this, pose, d);
  }
  std::vector<kinematics::Parameter> parameters() const override { return {}; }
  void set_parameters(std::span<const double>) override {}
  std::unique_ptr<kinematics::Kinematics> clone() const override {
    return std::make_unique<ScaledAxes>();
  }
  void write_config(kinematics::ModelConfigWriter& out) const override {
    out.number("scale", 2.5);
    out.length("reach", 254.0);
    const std::array<Eigen::Vector2d, 2> feet = {Eigen::Vector2d(254.0, 0.0),
                                                 Eigen::Vector2d(0.0, 76.2)};
    out.length_vector2_list("feet", feet);
    const std::array<Eigen::Vector3d, 3> corners = {Eigen::Vector3d(254.0, 76.2, 63.5),
                                                    Eigen::Vector3d::Zero(),
                                                    Eigen::Vector3d(-254.0, 0.0, 0.0)};
    out.length_vector3_list("corners", corners);
    out.whole_number("teeth", 20);
    out.boolean("mirrored", false);
    out.axis_list("axes", dof());
    out.string("label", "a \"quoted\" name");
    out.number_table("constants", {{"k", 0.5}});
    out.table_list_entry("wheels").length("radius", 63.5);
    out.table_list_entry("wheels").length("radius", 76.2);
  }
};

TEST(ModelConfigWriter, AModelsKeysAreWrittenAsTomlInTheFilesUnit) {
  ScaledAxes model;
  model.set_forward_options({1e-11, 80});
  // Lengths in inch (254 mm = 10 in); keys in the order written, then each sub-table; two rows
  // of points on one line, three a row per line.
  EXPECT_EQ(machine::kinematics_toml(model, machine::LengthUnit::inch),
            "[kinematics]\n"
            "type = \"scaled\"\n"
            "forward_max_iterations = 80\n"
            "scale = 2.5\n"
            "reach = 10.0\n"
            "feet = [[10.0, 0.0], [0.0, 3.0]]\n"
            "corners = [\n"
            "  [10.0, 3.0, 2.5],\n"
            "  [0.0, 0.0, 0.0],\n"
            "  [-10.0, 0.0, 0.0],\n"
            "]\n"
            "teeth = 20\n"
            "mirrored = false\n"
            "axes = [\"x\", \"y\"]\n"
            "label = \"a \\\"quoted\\\" name\"\n"
            "\n"
            "[kinematics.constants]\n"
            "k = 0.5\n"
            "\n"
            "[[kinematics.wheels]]\n"
            "radius = 2.5\n"
            "\n"
            "[[kinematics.wheels]]\n"
            "radius = 3.0\n");
}

TEST(ModelConfigWriter, AModelWithoutAClosedFormulaIsRefusedByTheMach3Export) {
  const std::vector<machine::JointSpec> joints = test::test_model_joints_uv();
  const machine::Machine machine("scaled", "test", machine::LengthUnit::mm,
                                 std::make_unique<ScaledAxes>(), joints, {6000.0, 500.0},
                                 geometry::Pose::from_mm_deg(0.0, 0.0, 0.0));
  EXPECT_EQ(machine.kinematics().sketch(), nullptr);
  EXPECT_EQ(machine.kinematics().hanging_cables(), nullptr);
  EXPECT_EQ(machine.kinematics().leg_limit_settings(), nullptr);
  try {
    post::mach3_formulas(machine);
    FAIL() << "a model without formulas was exported";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "a scaled machine has no closed formula for Mach3's formula axes");
  }
}

}  // namespace
}  // namespace pkm
