// pkm home: the [homing] table and home_switch keys (read, checked, file:line:key errors), the
// homing program per dialect and the set-position block for readings measured by hand, against
// programs written out by hand for a small cable plotter.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "pkm/post/homing_program.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

// Hektor's size with letters X Y: anchors 100 mm apart, belts 5..180 mm, switches at 10 mm.
// Home (50, -50): both belts sqrt(5000) = 70.710678 mm. Default feed: 60 mm/s = 3600 mm/min.
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
home_switch = 10.0

[[joints]]
name = "right"
min = 5.0
max = 180.0
max_velocity = 60.0
max_acceleration = 600.0
axis = "Y"
home_switch = 10.0

[cartesian]
max_feed = 2400.0
max_acceleration = 500.0
home = [50.0, -50.0]

[homing]
sequence = ["left", "right"]
slack = 10.0
probe_feed = 120.0
backoff = 5.0
)";

// `text` with `find` (which must occur) replaced by `replace`.
std::string edited(std::string text, const std::string& find, const std::string& replace) {
  const auto at = text.find(find);
  if (at == std::string::npos) throw std::logic_error("not in the text: " + find);
  return text.replace(at, find.size(), replace);
}

machine::Machine plotter(const std::string& text = kPlotter) {
  return machine::parse_machine(text, "plotter.toml");
}

// By hand: left first. The right belt is paid out 10 mm; the left is probed towards its min over
// the farthest it can be from its switch, 180 - 10 = 170 mm, set to 10 and backed off 5 (15).
// LinuxCNC sets the reading at the probe's trip point: the switch plus how far the joint is
// from it (#5420 current X, #5061 trip X). Then the left is paid out (25 mm, within 180) and the
// right probed over 170 mm plus the 10 mm it was paid out while unknown: 180 mm.
const std::string kLinuxcncProgram =
    R"((homing program by pkmkit for Small plotter, dialect linuxcnc)
(switch of left 10.000 mm, probed towards its min)
(switch of right 10.000 mm, probed towards its min)
G21 G90 G94
G54
G92.1
(home left)
G91 G1 Y10.00000 F3600
G91 G38.2 X-170.00000 F120
G10 L20 P1 X[10.00000 + #5420 - #5061]
G91 G1 X5.00000 F3600
(home right)
G91 G1 X10.00000 F3600
G91 G38.2 Y-180.00000 F120
G10 L20 P1 Y[10.00000 + #5421 - #5062]
G91 G1 Y5.00000 F3600
(to home: x 50.000 y -50.000 mm)
G90 G1 X70.71068 Y70.71068 F3600
M2
)";

TEST(HomingProgram, LinuxcncByHand) {
  EXPECT_EQ(post::homing_program(plotter(), post::Dialect::linuxcnc), kLinuxcncProgram);
}

TEST(HomingProgram, Mach3ProbesWithG31AndSetsWithG92) {
  std::string expected = kLinuxcncProgram;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"dialect linuxcnc", "dialect mach3"},
           {"G91 G38.2 X-170.00000", "G91 G31 X-170.0000"},
           {"G91 G38.2 Y-180.00000", "G91 G31 Y-180.0000"},
           {"G10 L20 P1 X[10.00000 + #5420 - #5061]", "G92 X10.0000"},
           {"G10 L20 P1 Y[10.00000 + #5421 - #5062]", "G92 Y10.0000"},
           {"Y10.00000 F3600", "Y10.0000 F3600"},
           {"X10.00000 F3600", "X10.0000 F3600"},
           {"X5.00000", "X5.0000"},
           {"Y5.00000", "Y5.0000"},
           {"X70.71068 Y70.71068", "X70.7107 Y70.7107"}}) {
    expected = edited(expected, from, to);
  }
  EXPECT_EQ(post::homing_program(plotter(), post::Dialect::mach3), expected);
}

TEST(HomingProgram, GrblWritesThreeDecimals) {
  const std::string program = post::homing_program(plotter(), post::Dialect::grbl);
  EXPECT_NE(program.find("G91 G38.2 X-170.000 F120\nG10 L20 P1 X10.000\n"), std::string::npos)
      << program;
  EXPECT_NE(program.find("G90 G1 X70.711 Y70.711 F3600\nM2\n"), std::string::npos) << program;
}

TEST(HomingMoves, ProbeStopsPastTheSwitchByV2Over2A) {
  // 120 mm/min = 2 mm/s at 600 mm/s^2: 4 / 1200 mm.
  int probes = 0;
  for (const machine::HomingMove& move : machine::homing_moves(plotter())) {
    if (move.kind != machine::HomingMoveKind::probe) continue;
    ++probes;
    EXPECT_NEAR(move.stop_distance, 4.0 / 1200.0, 1e-15);
  }
  EXPECT_EQ(probes, 2);
}

TEST(HomingMoves, SwitchNearMaxIsReachedIncreasing) {
  // A switch at 175 (nearer max 180): probed upwards over 175 - 5 = 170, backed off downwards.
  const machine::Machine machine =
      plotter(edited(kPlotter, "home_switch = 10.0", "home_switch = 175.0"));
  const std::vector<machine::HomingMove> moves = machine::homing_moves(machine);
  ASSERT_GE(moves.size(), 4u);
  EXPECT_EQ(moves[1].kind, machine::HomingMoveKind::probe);
  EXPECT_DOUBLE_EQ(moves[1].targets[0].second, 170.0);
  EXPECT_EQ(moves[3].kind, machine::HomingMoveKind::back_off);
  EXPECT_DOUBLE_EQ(moves[3].targets[0].second, -5.0);
  // home_toward overrides the nearer end.
  const machine::Machine turned =
      plotter(edited(kPlotter, "home_switch = 10.0", "home_switch = 10.0\nhome_toward = \"max\""));
  EXPECT_TRUE(turned.joints()[0].home_switch->toward_max);
  EXPECT_FALSE(turned.joints()[1].home_switch->toward_max);
}

TEST(HomingMoves, InchFileConvertsToMm) {
  // The same numbers in inches: every distance and feed is 25.4 times larger in mm.
  const machine::Machine machine =
      plotter(edited(kPlotter, "[kinematics]", "units = \"inch\"\n[kinematics]"));
  const std::string program = post::homing_program(machine, post::Dialect::linuxcnc);
  EXPECT_NE(program.find("G91 G1 Y254.00000 F91440\nG91 G38.2 X-4318.00000 F3048\n"
                         "G10 L20 P1 X[254.00000 + #5420 - #5061]\nG91 G1 X127.00000 F91440\n"),
            std::string::npos)
      << program;
  EXPECT_NE(program.find("(switch of left 10.000 in, probed towards its min)"), std::string::npos);
}

TEST(HomingMoves, PassThroughJointIsNeitherPaidOutNorRequired) {
  const machine::Machine machine = plotter(
      edited(edited(edited(kPlotter, "anchor_distance = 100.0",
                           "anchor_distance = 100.0\npassthrough = [\"z\"]"),
                    "[cartesian]",
                    "[[joints]]\nname = \"pen\"\nmin = -5.0\nmax = 5.0\nmax_velocity = 5.0\n"
                    "max_acceleration = 50.0\n\n[cartesian]"),
             "home = [50.0, -50.0]", "home = [50.0, -50.0, 2.0]"));
  const std::string program = post::homing_program(machine, post::Dialect::linuxcnc);
  EXPECT_NE(program.find("G91 G1 Y10.00000 F3600\n"), std::string::npos) << program;
  EXPECT_NE(program.find("G90 G1 X70.71068 Y70.71068 F3600\n"), std::string::npos) << program;
  EXPECT_EQ(program.find(" Z"), std::string::npos) << program;
  EXPECT_EQ(post::measured_joint_indices(machine), (std::vector<int>{0, 1}));
}

TEST(HomingMoves, PenGoesUpFirst) {
  const machine::Machine machine =
      plotter(kPlotter + "\n[tool]\nz = \"pen\"\nup = \"M280 P0 S90\"\ndelay = 0.15\n");
  const std::string program = post::homing_program(machine, post::Dialect::linuxcnc);
  EXPECT_NE(program.find("G92.1\nM280 P0 S90\nG4 P0.150\n(home left)\n"), std::string::npos)
      << program;
}

TEST(HomingProgram, MachineNameStaysInsideItsComment) {
  const machine::Machine machine =
      plotter(edited(kPlotter, "name = \"Small plotter\"", "name = \"Small (2)\\nplotter\""));
  const std::string program = post::homing_program(machine, post::Dialect::linuxcnc);
  EXPECT_EQ(program.substr(0, program.find('\n')),
            "(homing program by pkmkit for Small [2] plotter, dialect linuxcnc)");
}

TEST(HomingMoves, CopiedMachineKeepsItsHoming) {
  const machine::Machine original = plotter();
  const machine::Machine copy = original;  // NOLINT(performance-unnecessary-copy-initialization)
  ASSERT_TRUE(copy.homing());
  EXPECT_EQ(copy.homing()->sequence, (std::vector<int>{0, 1}));
  EXPECT_EQ(post::homing_program(copy, post::Dialect::linuxcnc), kLinuxcncProgram);
}

TEST(HomingProgram, RefusesWhatADialectCannotWrite) {
  const auto message = [](const machine::Machine& machine, post::Dialect dialect) {
    try {
      post::homing_program(machine, dialect);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  const machine::Machine letters_ab = plotter(
      edited(edited(kPlotter, "axis = \"X\"", "axis = \"A\""), "axis = \"Y\"", "axis = \"B\""));
  EXPECT_EQ(message(letters_ab, post::Dialect::mach3),
            "plotter.toml: Mach3's probe (G31) moves no rotary axis, and joint 'left' is A: use "
            "--dialect linuxcnc or grblhal, or change the joints' axis letters in the machine "
            "file");
  EXPECT_EQ(message(letters_ab, post::Dialect::grbl),
            "plotter.toml: dialect grbl has no axis A (joint 'left'): use --dialect linuxcnc or "
            "grblhal, or change the joints' axis letters in the machine file");
  EXPECT_EQ(message(letters_ab, post::Dialect::grblhal), "accepted");  // its axes A B C U V W
  const machine::Machine no_homing = plotter(kPlotter.substr(0, kPlotter.find("[homing]")));
  EXPECT_EQ(message(no_homing, post::Dialect::linuxcnc),
            "plotter.toml: the machine file has no [homing] table (docs/homing.md)");
}

// Readings 60 and 80 mm on anchors 100 mm apart: the 3-4-5 triangle, x = (60² - 80² + 100²) /
// 200 = 36, y = -sqrt(60² - 36²) = -48.
TEST(MeasuredJoints, ThreeFourFiveTriangle) {
  const machine::Machine machine = plotter();
  const post::MeasuredJoints measured = post::measured_joints(machine, {60.0, 80.0});
  EXPECT_NEAR(measured.pose.position_mm.x(), 36.0, 1e-12);
  EXPECT_NEAR(measured.pose.position_mm.y(), -48.0, 1e-12);
  EXPECT_EQ(post::set_position_program(machine, post::Dialect::linuxcnc, measured),
            "(set-position block by pkmkit for Small plotter, dialect linuxcnc)\n"
            "(measured by hand at rest: left 60.000 mm)\n"
            "(measured by hand at rest: right 80.000 mm)\n"
            "(pose x 36.000 y -48.000 mm)\n"
            "G21 G90 G94\nG54\nG92.1\n"
            "G10 L20 P1 X60.00000 Y80.00000\n"
            "M2\n");
  EXPECT_NE(post::set_position_program(machine, post::Dialect::mach3, measured)
                .find("\nG92 X60.0000 Y80.0000\nM2\n"),
            std::string::npos);
}

TEST(MeasuredJoints, WorksWithoutSwitches) {
  const machine::Machine machine = plotter(kPlotter.substr(0, kPlotter.find("[homing]")));
  EXPECT_NEAR(post::measured_joints(machine, {80.0, 60.0}).pose.position_mm.x(), 64.0, 1e-12);
}

TEST(MeasuredJoints, RefusalsSayTheNumbers) {
  const machine::Machine machine = plotter();
  const auto message = [&](const std::vector<double>& values) {
    try {
      post::measured_joints(machine, values);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({60.0}),
            "--measured takes 2 readings, one per joint of the mechanism (left right), not 1");
  EXPECT_EQ(message({60.0, 190.0}),
            "no pose has the readings left 60.000 mm, right 190.000 mm on Small plotter: joint "
            "'right' = 190.000 mm passes its max 180.000 mm; measure again, from the same point "
            "of each cable as the joint's zero");
  // 10 + 20 < 100: the two circles do not meet.
  EXPECT_NE(message({10.0, 20.0}).find("forward kinematics finds none (unreachable"),
            std::string::npos)
      << message({10.0, 20.0});
  // 30 and 120: x = (900 - 14400 + 10000) / 200 = -17.5, left of the left anchor.
  EXPECT_EQ(message({30.0, 120.0}).substr(0, 106),
            "the readings left 30.000 mm, right 120.000 mm put the machine where it cannot be: "
            "pose x -17.500 y -24.367");
}

struct BadHoming {
  std::string name;
  std::string find, replace;
  int line;
  std::string key;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const BadHoming& c) {
  return out << c.name;
}

class BadHomingFile : public ::testing::TestWithParam<BadHoming> {};

TEST_P(BadHomingFile, NamesFileLineAndKey) {
  const BadHoming& c = GetParam();
  try {
    plotter(edited(kPlotter, c.find, c.replace));
    FAIL() << "accepted a bad file";
  } catch (const machine::MachineFileError& error) {
    EXPECT_EQ(error.line(), c.line) << error.what();
    EXPECT_EQ(error.key(), c.key) << error.what();
    EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
  }
}

// Lines of kPlotter: joints[1] home_switch 13, [homing] 29, sequence 30, slack 31,
// probe_feed 32, backoff 33.
const BadHoming kBadHoming[] = {
    {"unknown_joint", "\"left\", \"right\"]", "\"left\", \"rigth\"]", 30, "homing.sequence",
     "names 'rigth', which is no joint of the machine (left, right)"},
    {"joint_twice", "\"left\", \"right\"]", "\"left\", \"left\", \"right\"]", 30, "homing.sequence",
     "names joint 'left' twice"},
    {"joint_left_out", "\"left\", \"right\"]", "\"left\"]", 30, "homing.sequence",
     "leaves out joint 'right': every joint of the mechanism must find its switch"},
    {"no_switch", "home_switch = 10.0\n", "", 29, "homing.sequence",
     "names joint 'left', whose [[joints]] table has no home_switch"},
    {"switch_not_a_number", "home_switch = 10.0", "home_switch = \"low\"", 13,
     "joints[1].home_switch", "must be a number"},
    {"switch_nan", "home_switch = 10.0", "home_switch = nan", 13, "joints[1].home_switch",
     "must be finite"},
    {"toward_without_switch", "home_switch = 10.0", "home_toward = \"min\"", 13,
     "joints[1].home_toward", "needs home_switch beside it"},
    {"toward_up", "home_switch = 10.0", "home_switch = 10.0\nhome_toward = \"up\"", 14,
     "joints[1].home_toward", "must be \"min\" or \"max\", not \"up\""},
    {"negative_slack", "slack = 10.0", "slack = -1.0", 31, "homing.slack",
     "must be at least 0 and at most 1e+06 mm, not -1"},
    {"zero_probe_feed", "probe_feed = 120.0", "probe_feed = 0", 32, "homing.probe_feed",
     "must be at least 0.001 and at most 6e+07 mm/min, not 0"},
    {"zero_backoff", "backoff = 5.0", "backoff = 0.0", 33, "homing.backoff",
     "must be greater than 0"},
    {"misspelt_key", "backoff = 5.0", "backof = 5.0", 33, "homing.backof",
     "unknown key 'backof' (did you mean 'backoff'?)"},
    {"zero_probe_travel", "backoff = 5.0", "backoff = 5.0\nprobe_travel = 0", 34,
     "homing.probe_travel", "must be greater than 0"},
    // Left at 15 after its back-off, paid out 170: 185 > 180.
    {"slack_past_max", "slack = 10.0", "slack = 170.0", 31, "homing.slack",
     "paying out joint 'left' by 170.000 mm before joint 'right' homes takes it past its max: "
     "joint 'left' = 185.000 mm passes its max 180.000 mm"},
    // A switch at -1 mm: backing off 5 leaves 4 < 5; back-offs of 6 to 181 mm would do.
    {"backoff_short_of_min", "home_switch = 10.0", "home_switch = -1.0", 33, "homing.backoff",
     "backing off 5.000 mm from the switch of joint 'left' (home_switch -1.000 mm) leaves it "
     "outside its limits: joint 'left' = 4.000 mm passes its min 5.000 mm; give a backoff "
     "between 6.000 mm and 181.000 mm"},
};

INSTANTIATE_TEST_SUITE_P(Cases, BadHomingFile, ::testing::ValuesIn(kBadHoming),
                         [](const auto& test) { return test.param.name; });

TEST(HomingFile, ExamplesCarrySwitches) {
  for (const char* file : {"wall-plotter.toml", "hektor.toml"}) {
    const machine::Machine machine = test::load_example(file);
    ASSERT_TRUE(machine.homing()) << file;
    EXPECT_EQ(machine.homing()->sequence, (std::vector<int>{0, 1})) << file;
  }
}

}  // namespace
}  // namespace pkm
