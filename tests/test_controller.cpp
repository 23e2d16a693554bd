// The machine file's [controller] table and steps_per_unit (read, defaults, located refusals,
// kept through calibration's rewrite), `pkm export grbl|grblhal`'s $ settings against values
// worked out by hand, and `pkm home --dialect grblhal`.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "pkm/machine/machine_writer.hpp"
#include "pkm/post/grbl_settings.hpp"
#include "pkm/post/homing_program.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

std::string example_text(const std::string& file) {
  std::ifstream in(test::example_machine_path(file));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `text` with `find` (which must occur) replaced by `replace`.
std::string edited(std::string text, const std::string& find, const std::string& replace) {
  const auto at = text.find(find);
  if (at == std::string::npos) throw std::logic_error("not in the text: " + find);
  return text.replace(at, find.size(), replace);
}

// Anchors 100 mm apart, cords 5..180 mm at 80 steps/mm, 60 mm/s, 600 mm/s^2.
const std::string kPlotter = R"(name = "Small plotter"
[kinematics]
type = "cable_plotter"
anchor_distance = 100.0

[[joints]]
name = "left"
min = 5.0
max = 180.0
max_velocity = 60.0
max_acceleration = 600.0
axis = "X"
steps_per_unit = 80.0

[[joints]]
name = "right"
min = 5.0
max = 180.0
max_velocity = 60.0
max_acceleration = 600.0
axis = "Y"
steps_per_unit = 80.0

[cartesian]
max_feed = 2400.0
max_acceleration = 500.0
home = [50.0, -50.0]

[controller]
kind = "grbl"
)";

machine::Machine plotter(const std::string& text = kPlotter) {
  return machine::parse_machine(text, "plotter.toml");
}

// The error parse_machine gives for `text`, as file:line:key: message.
std::string refusal(const std::string& text) {
  try {
    machine::parse_machine(text, "plotter.toml");
  } catch (const machine::MachineFileError& error) {
    return error.what();
  }
  return "accepted";
}

TEST(ControllerTable, DefaultsOfEachKind) {
  const machine::Machine grbl = plotter();
  ASSERT_TRUE(grbl.controller());
  EXPECT_EQ(grbl.controller()->kind, machine::ControllerKind::grbl);
  EXPECT_EQ(grbl.controller()->axes, 3);
  EXPECT_EQ(grbl.controller()->planner_blocks, 16);
  EXPECT_EQ(grbl.controller()->rx_buffer_bytes, 128);
  EXPECT_EQ(grbl.controller()->baud, 115200);
  EXPECT_DOUBLE_EQ(grbl.controller()->junction_deviation, 0.01);
  EXPECT_DOUBLE_EQ(*grbl.joints()[0].steps_per_unit, 80.0);

  const machine::Machine hal = plotter(edited(kPlotter, "kind = \"grbl\"", "kind = \"grblhal\""));
  EXPECT_EQ(hal.controller()->kind, machine::ControllerKind::grblhal);
  EXPECT_EQ(hal.controller()->axes, 3);
  EXPECT_EQ(hal.controller()->planner_blocks, 35);
  EXPECT_EQ(hal.controller()->rx_buffer_bytes, 1024);

  const machine::Machine none = plotter(kPlotter.substr(0, kPlotter.find("[controller]")));
  EXPECT_FALSE(none.controller());
  EXPECT_DOUBLE_EQ(*none.joints()[1].steps_per_unit, 80.0);  // steps without a controller: kept
}

TEST(ControllerTable, EveryKeyRead) {
  const machine::Machine machine =
      plotter(kPlotter +
              "axes = 3\nplanner_blocks = 15\nrx_buffer = 254\nbaud = 250000\n"
              "junction_deviation = 0.02\n");
  EXPECT_EQ(machine.controller()->planner_blocks, 15);
  EXPECT_EQ(machine.controller()->rx_buffer_bytes, 254);
  EXPECT_EQ(machine.controller()->baud, 250000);
  EXPECT_DOUBLE_EQ(machine.controller()->junction_deviation, 0.02);
}

// An inch file: 2032 steps/in are 80 steps/mm; 0.0004 in of junction deviation is 0.01016 mm.
TEST(ControllerTable, InchFileIsConverted) {
  std::string text = edited(kPlotter, "[kinematics]", "units = \"inch\"\n[kinematics]");
  text = edited(edited(text, "steps_per_unit = 80.0", "steps_per_unit = 2032.0"),
                "steps_per_unit = 80.0", "steps_per_unit = 2032.0");
  const machine::Machine machine = plotter(text + "junction_deviation = 0.0004\n");
  EXPECT_DOUBLE_EQ(*machine.joints()[0].steps_per_unit, 80.0);
  EXPECT_DOUBLE_EQ(machine.controller()->junction_deviation, 0.0004 * 25.4);
}

struct Refusal {
  std::string name;
  std::string text;
  std::string message;  // the whole error, file:line:key: message
};

std::ostream& operator<<(std::ostream& out, const Refusal& r) {
  return out << r.name;
}

class ControllerRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(ControllerRefusal, LocatedWithTheNumbers) {
  EXPECT_EQ(refusal(GetParam().text), GetParam().message);
}

// Line numbers of kPlotter: 12 the first joint's axis, 13 its steps_per_unit, 15 the second
// joint's table, 29 [controller], 30 its kind, 31 a key added after it.
INSTANTIATE_TEST_SUITE_P(
    Table, ControllerRefusal,
    ::testing::Values(
        Refusal{"baud_zero", kPlotter + "baud = 0\n",
                "plotter.toml:31:controller.baud: must be between 300 and 10000000 bit/s, not 0"},
        Refusal{"baud_negative", kPlotter + "baud = -9600\n",
                "plotter.toml:31:controller.baud: must be between 300 and 10000000 bit/s, not "
                "-9600"},
        Refusal{"baud_fraction", kPlotter + "baud = 115200.5\n",
                "plotter.toml:31:controller.baud: must be a whole number of bit/s, not 115200"},
        Refusal{"baud_text", kPlotter + "baud = \"fast\"\n",
                "plotter.toml:31:controller.baud: must be a number"},
        Refusal{
            "unknown_key", kPlotter + "buad = 9600\n",
            "plotter.toml:31:controller.buad: unknown key 'buad' (this table's keys: axes, baud, "
            "junction_deviation, kind, planner_blocks, rx_buffer; see docs/machine-file.md)"},
        Refusal{"kind", edited(kPlotter, "kind = \"grbl\"", "kind = \"marlin\""),
                "plotter.toml:30:controller.kind: must be \"grbl\" or \"grblhal\", not "
                "\"marlin\""},
        Refusal{"kind_missing", edited(kPlotter, "kind = \"grbl\"", "baud = 9600"),
                "plotter.toml:29:controller.kind: missing (required)"},
        Refusal{"steps_missing",
                edited(kPlotter, "axis = \"Y\"\nsteps_per_unit = 80.0\n", "axis = \"Y\"\n"),
                "plotter.toml:15:joints[2].steps_per_unit: joint 'right' has no steps_per_unit, "
                "and the [controller] table needs every joint's (steps per mm, or per deg for a "
                "rotary joint)"},
        Refusal{"steps_zero", edited(kPlotter, "steps_per_unit = 80.0", "steps_per_unit = 0.0"),
                "plotter.toml:13:joints[1].steps_per_unit: must be greater than 0 and at most "
                "1e+06 steps/mm, not 0"},
        Refusal{"letter_a_on_grbl", edited(kPlotter, "axis = \"X\"", "axis = \"A\""),
                "plotter.toml:12:joints[1].axis: joint 'left' is on axis A, which grbl with 3 "
                "axes lacks (it has X Y Z)"},
        Refusal{"letter_a_on_grblhal_of_3_axes",
                edited(edited(kPlotter, "axis = \"X\"", "axis = \"A\""), "kind = \"grbl\"",
                       "kind = \"grblhal\""),
                "plotter.toml:12:joints[1].axis: joint 'left' is on axis A, which grblhal with 3 "
                "axes lacks (it has X Y Z)"},
        Refusal{"grbl_with_4_axes", kPlotter + "axes = 4\n",
                "plotter.toml:31:controller.axes: grbl 1.1 has 3 axes (X Y Z), not 4; a build "
                "with more axes is kind = \"grblhal\""},
        Refusal{"rx_buffer_below_a_line", kPlotter + "rx_buffer = 64\n",
                "plotter.toml:31:controller.rx_buffer: must be between 81 and 254 bytes, not 64"},
        Refusal{"planner_blocks_one", kPlotter + "planner_blocks = 1\n",
                "plotter.toml:31:controller.planner_blocks: must be between 2 and 1000 blocks, "
                "not 1"},
        Refusal{"junction_deviation_negative", kPlotter + "junction_deviation = -0.01\n",
                "plotter.toml:31:controller.junction_deviation: must be between 0 and 10 mm, not "
                "-0.01"},
        Refusal{"pen_m280_on_grbl", kPlotter + "\n[tool]\nz = \"pen\"\ndown = \"M280 P0 S30\"\n",
                "plotter.toml:34:tool.down: \"M280 P0 S30\" holds M280, which grbl 1.1 does not "
                "take for a pen (M3 M4 M5 switch its spindle output, M8 M9 its coolant output): "
                "e.g. down = \"M3 S1000\", up = \"M5\""}),
    [](const ::testing::TestParamInfo<Refusal>& param_info) { return param_info.param.name; });

// Four joints on grbl's three axes: the hexapod's six legs.
TEST(ControllerTable, MoreJointsThanAxes) {
  const std::string hexapod =
      example_text("hexapod-bit.toml") + "\n[controller]\nkind = \"grbl\"\n";
  const std::string message = refusal(hexapod);
  EXPECT_NE(message.find(":controller.kind: this machine has 6 joints; grbl has 3 axes drives 3 "
                         "at most (grblHAL builds go to 8 axes: kind = \"grblhal\")"),
            std::string::npos)
      << message;
  const std::string hal =
      refusal(edited(hexapod, "kind = \"grbl\"", "kind = \"grblhal\"\naxes = 4"));
  EXPECT_NE(hal.find(":controller.axes: this machine has 6 joints; grblhal built with 4 axes "
                     "drives 4 at most"),
            std::string::npos)
      << hal;
}

// Calibration rewrites [kinematics] only: the steps and the [controller] table come back as they
// were.
TEST(ControllerTable, KeptThroughCalibrationsRewrite) {
  const std::string text = kPlotter + "planner_blocks = 15\nbaud = 250000\n";
  machine::Machine machine = plotter(text);
  std::vector<double> parameters;
  for (const kinematics::Parameter& parameter : machine.kinematics().parameters()) {
    parameters.push_back(parameter.value);
  }
  parameters[0] += 0.5;
  machine.kinematics().set_parameters(parameters);
  const std::string rewritten = machine::replace_kinematics_section(
      text, "plotter.toml", machine.kinematics(), machine.units());
  EXPECT_NE(rewritten, text);
  const machine::Machine again = plotter(rewritten);
  EXPECT_DOUBLE_EQ(again.kinematics().parameters()[0].value, parameters[0]);
  ASSERT_TRUE(again.controller());
  EXPECT_EQ(again.controller()->planner_blocks, 15);
  EXPECT_EQ(again.controller()->baud, 250000);
  EXPECT_DOUBLE_EQ(*again.joints()[1].steps_per_unit, 80.0);
}

// The example wall plotter by hand: 80 steps/mm; 150 mm/s = 9000 mm/min; 1000 mm/s^2; cords
// 150..2100 mm: 1950 mm of travel.
TEST(ExportGrbl, WallPlotterByHand) {
  const machine::Machine machine = test::load_example("wall-plotter.toml");
  const post::ControllerSettingsFile file =
      post::controller_settings(machine, machine::ControllerKind::grbl);
  EXPECT_EQ(file.text(),
            "$1=255 (keep the motors enabled at rest: the tool hangs on them)\n"
            "$13=0 (report positions in mm: joint programs are in mm)\n"
            "$11=0.010 (junction deviation, mm)\n"
            "$100=80.000 (X = joint left: steps/mm)\n"
            "$101=80.000 (Y = joint right: steps/mm)\n"
            "$110=9000.000 (X = joint left: max rate, mm/min)\n"
            "$111=9000.000 (Y = joint right: max rate, mm/min)\n"
            "$120=1000.000 (X = joint left: acceleration, mm/s^2)\n"
            "$121=1000.000 (Y = joint right: acceleration, mm/s^2)\n"
            "$130=1950.000 (X = joint left: max travel, mm: its max - min)\n"
            "$131=1950.000 (Y = joint right: max travel, mm: its max - min)\n");
  EXPECT_TRUE(file.warnings.empty());
}

// Joints in the controller's order whatever the file's; an inch file in mm (grbl's $13=0). Left
// (on Z): 2000 steps/in = 78.740157 steps/mm (8 digits: grbl reads no more), 2 in/s = 3048
// mm/min, 20 in/s^2 = 508 mm/s^2, 1..8 in = 177.8 mm of travel. Right (on Y): 80 steps/in =
// 3.149606 steps/mm, 60 in/s = 91440 mm/min, 600 in/s^2 = 15240 mm/s^2, 5..180 in = 4445 mm.
// 0.0005 in of junction deviation = 0.0127 mm.
TEST(ExportGrbl, InchFileInMillimetresInAxisOrder) {
  std::string text = edited(kPlotter, "[kinematics]", "units = \"inch\"\n[kinematics]");
  text = edited(text, "axis = \"X\"", "axis = \"Z\"");
  text = edited(text, "min = 5.0\nmax = 180.0\nmax_velocity = 60.0\nmax_acceleration = 600.0",
                "min = 1.0\nmax = 8.0\nmax_velocity = 2.0\nmax_acceleration = 20.0");
  text = edited(text, "steps_per_unit = 80.0", "steps_per_unit = 2000.0");
  text = edited(text, "anchor_distance = 100.0", "anchor_distance = 4.0");
  text = edited(text, "home = [50.0, -50.0]", "home = [1.0, -5.0]");
  text = edited(text, "max_feed = 2400.0", "max_feed = 100.0");
  const machine::Machine machine = plotter(text + "junction_deviation = 0.0005\n");
  const std::string settings =
      post::controller_settings(machine, machine::ControllerKind::grbl).text();
  EXPECT_EQ(settings,
            "$1=255 (keep the motors enabled at rest: the tool hangs on them)\n"
            "$13=0 (report positions in mm: joint programs are in mm)\n"
            "$11=0.0127 (junction deviation, mm)\n"
            "$101=3.149606 (Y = joint right: steps/mm)\n"
            "$102=78.740157 (Z = joint left: steps/mm)\n"
            "$111=91440.000 (Y = joint right: max rate, mm/min)\n"
            "$112=3048.000 (Z = joint left: max rate, mm/min)\n"
            "$121=15240.000 (Y = joint right: acceleration, mm/s^2)\n"
            "$122=508.000 (Z = joint left: acceleration, mm/s^2)\n"
            "$131=4445.000 (Y = joint right: max travel, mm: its max - min)\n"
            "$132=177.800 (Z = joint left: max travel, mm: its max - min)\n");
}

// grblHAL numbers its axes X Y Z A B C U V: a joint on A is $103.
TEST(ExportGrbl, GrblhalNumbersAxisA) {
  std::string text = edited(kPlotter, "axis = \"Y\"", "axis = \"A\"");
  text = edited(text, "kind = \"grbl\"", "kind = \"grblhal\"\naxes = 4");
  const std::string settings =
      post::controller_settings(plotter(text), machine::ControllerKind::grblhal).text();
  EXPECT_NE(settings.find("$103=80.000 (A = joint right: steps/mm)\n"), std::string::npos)
      << settings;
  EXPECT_NE(settings.find("$133=175.000 (A = joint right: max travel, mm: its max - min)\n"),
            std::string::npos)
      << settings;
}

TEST(ExportGrbl, Refusals) {
  const auto message = [](const machine::Machine& machine, machine::ControllerKind kind) {
    try {
      post::controller_settings(machine, kind);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(plotter(kPlotter.substr(0, kPlotter.find("[controller]"))),
                    machine::ControllerKind::grbl),
            "plotter.toml: has no [controller] table; pkm export grbl needs one (kind = \"grbl\") "
            "and each joint's steps_per_unit (docs/machine-file.md)");
  EXPECT_EQ(message(plotter(), machine::ControllerKind::grblhal),
            "plotter.toml: its [controller] kind is \"grbl\": use pkm export grbl, or change kind "
            "in the machine file");
  // 180 - 5 = 175 mm at 2e4 steps/mm: 3.5 million steps; at 1e6 steps/mm, 175 million; a
  // kilometre-long cord at 1e4 steps/mm passes 2^31.
  std::string long_cords = edited(kPlotter, "max = 180.0", "max = 300000.0");
  long_cords = edited(long_cords, "steps_per_unit = 80.0", "steps_per_unit = 10000.0");
  EXPECT_EQ(message(plotter(long_cords), machine::ControllerKind::grbl),
            "plotter.toml: joint 'left' spans 2999950000 steps (its range times steps_per_unit), "
            "beyond grbl's step counter (2147483647)");
}

// 400 steps/mm at 150 mm/s: 60 kHz, twice what grbl manages on an AVR; 30000 / 400 = 75 mm/s.
TEST(ExportGrbl, StepRateBeyondAnAvrIsAWarning) {
  std::string text = edited(kPlotter, "steps_per_unit = 80.0", "steps_per_unit = 400.0");
  text = edited(text, "max_velocity = 60.0", "max_velocity = 150.0");
  const post::ControllerSettingsFile file =
      post::controller_settings(plotter(text), machine::ControllerKind::grbl);
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_EQ(file.warnings[0],
            "joint 'left' at its max_velocity 150.000 mm/s steps at 60000 Hz; grbl 1.1 on a 16 MHz "
            "AVR steps at about 30000 Hz at most: lower max_velocity to 75.000 mm/s");
}

// Every line fits grbl's 80 characters and holds nothing grbl's serial interrupt acts on (? ! ~,
// bytes above 0x7F), however the joints are named.
TEST(ExportGrbl, LinesAreSafeForGrbl) {
  const std::string name =
      "l\xC3\x91"
      "ft? (main) cord with a very long name that goes on and on!";
  const machine::Machine machine =
      plotter(edited(kPlotter, "name = \"left\"", "name = \"" + name + "\""));
  const std::string text = post::controller_settings(machine, machine::ControllerKind::grbl).text();
  std::istringstream lines(text);
  int count = 0;
  for (std::string line; std::getline(lines, line); ++count) {
    EXPECT_LE(line.size(), 80u) << line;
    EXPECT_EQ(line.find_first_of("?!~;"), std::string::npos) << line;
    for (const char c : line) EXPECT_TRUE(c >= 0x20 && c <= 0x7E) << line;
    EXPECT_EQ(line.find('(', line.find('(') + 1), std::string::npos) << line;  // one comment
  }
  EXPECT_EQ(count, 11);
  EXPECT_NE(text.find("$100=80.000 (X = joint l__ft_ [main] cord with a very long name th...: "
                      "steps/mm)\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(post::grbl_comment_text("a(b)c?d!e~f\xC3\x91"
                                    "g"),
            "a[b]c_d_e_f__g");
}

// grblHAL zeroes as grbl does: G10 L20 P1 with the readings, 4 decimals (its dialect's).
TEST(HomeGrblhal, SetPositionBlock) {
  const machine::Machine machine =
      plotter(edited(kPlotter, "kind = \"grbl\"", "kind = \"grblhal\""));
  const post::MeasuredJoints measured = post::measured_joints(machine, {60.0, 80.0});
  EXPECT_EQ(post::set_position_program(machine, post::Dialect::grblhal, measured),
            "(set-position block by pkmkit for Small plotter, dialect grblhal)\n"
            "(measured by hand at rest: left 60.000 mm)\n"
            "(measured by hand at rest: right 80.000 mm)\n"
            "(pose x 36.000 y -48.000 mm)\n"
            "G21 G90 G94\nG54\nG92.1\n"
            "G10 L20 P1 X60.0000 Y80.0000\n"
            "M2\n");
}

// The homing program for grblhal probes with G38.2 and sets each joint where it stopped, as grbl
// does (grblHAL evaluates no #5061 expressions unless built with NGC_EXPRESSIONS_ENABLE).
TEST(HomeGrblhal, HomingProgramProbesWithG38) {
  std::string text = edited(kPlotter, "axis = \"X\"", "axis = \"X\"\nhome_switch = 10.0");
  text = edited(text, "axis = \"Y\"", "axis = \"Y\"\nhome_switch = 10.0");
  text = edited(text, "kind = \"grbl\"", "kind = \"grblhal\"");
  const machine::Machine machine =
      plotter(text +
              "\n[homing]\nsequence = [\"left\", \"right\"]\nslack = 10.0\n"
              "probe_feed = 120.0\nbackoff = 5.0\n");
  const std::string program = post::homing_program(machine, post::Dialect::grblhal);
  // The left cord from at most 180 - 10 = 170 mm past its switch; the right one 10 mm more, paid
  // out while the left homed.
  EXPECT_NE(program.find("G91 G38.2 X-170.0000 F120\nG10 L20 P1 X10.0000\nG91 G1 X5.0000 F3600\n"
                         "(home right)\nG91 G1 X10.0000 F3600\nG91 G38.2 Y-180.0000 F120\n"
                         "G10 L20 P1 Y10.0000\n"),
            std::string::npos)
      << program;
}

}  // namespace
}  // namespace pkm
