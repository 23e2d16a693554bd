// The marlin target (docs/firmware-marlin.md): the exported Configuration.h block read by an
// independent implementation of Marlin's own inverse kinematics (firmware_reference/marlin.*)
// against pkmkit's over each example machine's workspace; import then export; the
// approximations' stated cost; refusals and bad input with their lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "firmware_reference/marlin.hpp"
#include "pkm/firmware/target.hpp"
#include "pkm/machine/imported_machine.hpp"
#include "pkm/machine/machine.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

using firmware::FirmwareMachine;
namespace ref = test::marlin_reference;

const firmware::Target& marlin() {
  return firmware::target("marlin");
}
const firmware::ExportContext kContext{"test", "examples/machines/X.toml"};

FirmwareMachine exported(const machine::Machine& m, bool approximate = false) {
  return firmware::firmware_machine(m, marlin().forms, "marlin", approximate);
}

// What the machine's joint j reads for Marlin's stepper position (docs: reading = Marlin's
// position + the form's offset of that joint).
double joint_offset(const FirmwareMachine& fm, int joint) {
  if (const auto* delta = std::get_if<kinematics::LinearDeltaForm>(&fm.form.geometry)) {
    return joint < 3 ? delta->towers[joint].carriage_offset_mm : 0.0;
  }
  const auto& plotter = std::get<kinematics::WallPlotterForm>(fm.form.geometry);
  return joint < 2 ? plotter.cable_offsets_mm[joint] : 0.0;
}

// Largest |pkmkit joint - Marlin's stepper position - offset| over the workspace samples (mm).
double round_trip_error(const FirmwareMachine& fm, const std::string& text) {
  const ref::Config config = ref::parse(text);
  const machine::Machine& m = fm.machine;
  kinematics::JointVector joints(m.kinematics().joint_count());
  double worst = 0.0;
  int compared = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(m)) {
    if (!m.inverse(pose, joints).ok()) continue;
    const std::array<double, 3> marlin_mm = ref::stepper_positions(config, pose.position_mm);
    for (int k = 0; k < 3; ++k) {
      const int j = config.joint_of_stepper[k];
      if (j < 0) continue;
      worst = std::max(worst, std::abs(joints[j] - marlin_mm[k] - joint_offset(fm, j)));
      ++compared;
    }
  }
  EXPECT_GT(compared, 50);
  return worst;
}

class MarlinExact : public ::testing::TestWithParam<std::string> {};

TEST_P(MarlinExact, ReferenceIkMatchesPkmkitOverTheWorkspace) {
  const FirmwareMachine fm = exported(test::load_example(GetParam()));
  ASSERT_FALSE(fm.cost.has_value());
  const firmware::ExportedFile file = marlin().write(fm, kContext);
  const double worst = round_trip_error(fm, file.text);
  std::printf("[marlin] %s: round trip max error %.3g mm\n", GetParam().c_str(), worst);
  EXPECT_LT(worst, 1e-3);
}

TEST_P(MarlinExact, ImportThenExportGivesTheSameText) {
  const FirmwareMachine fm = exported(test::load_example(GetParam()));
  const std::string text = marlin().write(fm, kContext).text;
  const machine::ImportedMachine imported = marlin().read(text, "Configuration.h");
  const std::string toml = machine::machine_file_text(imported, "imported.toml");
  const machine::Machine again = machine::parse_machine(toml, "imported.toml");
  EXPECT_EQ(marlin().write(exported(again), kContext).text, text) << toml;
}

INSTANTIATE_TEST_SUITE_P(firmware_marlin, MarlinExact,
                         ::testing::Values("linear-delta.toml", "linuxcnc-ldelta.toml",
                                           "wall-plotter.toml", "hektor.toml", "pen-plotter.toml",
                                           "maslow.toml", "linuxcnc-polargraph-2366.toml"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return test::test_name(param.param);
                         });

class MarlinApproximate : public ::testing::TestWithParam<std::string> {};

// Marlin following the fitted export moves the true machine's tool within the stated worst error.
TEST_P(MarlinApproximate, TheStatedWorstErrorBoundsTheTrueMachine) {
  const machine::Machine truth = test::load_example(GetParam());
  EXPECT_THROW(exported(truth), firmware::ExportRefused);
  const FirmwareMachine fm = exported(truth, true);
  ASSERT_TRUE(fm.cost.has_value());
  const std::string text = marlin().write(fm, kContext).text;
  EXPECT_NE(text.find("APPROXIMATED"), std::string::npos);
  const ref::Config config = ref::parse(text);
  double worst = 0.0;
  for (const geometry::Pose& pose : firmware::workspace_samples(truth)) {
    const std::array<double, 3> marlin_mm = ref::stepper_positions(config, pose.position_mm);
    kinematics::JointVector joints(truth.kinematics().joint_count());
    if (!truth.inverse(pose, joints).ok()) continue;
    for (int k = 0; k < 3; ++k) {
      const int j = config.joint_of_stepper[k];
      if (j >= 0) joints[j] = marlin_mm[k] + joint_offset(fm, j);
    }
    geometry::Pose reached = pose;
    if (!truth.kinematics().forward(joints, reached).ok()) continue;
    worst = std::max(worst, (reached.position_mm - pose.position_mm).norm());
  }
  std::printf("[marlin] %s: approximation worst %.4f mm (stated %.4f, before fit %.4f)\n",
              GetParam().c_str(), worst, fm.cost->worst_tool_error_mm,
              fm.cost->worst_before_fit_mm);
  // The defines carry 6 decimals; near hektor-pulleys' anchor line a micrometre of anchor moves
  // the pen a hundred times that.
  EXPECT_LE(worst, fm.cost->worst_tool_error_mm + 1e-3);
  EXPECT_GT(fm.cost->worst_tool_error_mm, 0.0);
}

INSTANTIATE_TEST_SUITE_P(firmware_marlin, MarlinApproximate,
                         ::testing::Values("makelangelo.toml", "maslow-frame.toml",
                                           "hektor-pulleys.toml"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return test::test_name(param.param);
                         });

// Worked by hand: LinuxCNC's ldelta (R 130.25, L 269), towers at 90 (joint 1), 210 (joint 2) and
// 330 deg (joint 3) go to Marlin's C, A and B with no trims. At the tool (10, 20, 5) tower C's
// column is (0, 130.25): horizontal distance^2 = 10^2 + 110.25^2 = 12255.0625, and
// 5 + sqrt(269^2 - 12255.0625) = 5 + sqrt(60105.9375) = 250.165123 mm on the Z stepper.
TEST(firmware_marlin_HandComputed, LinuxcncDeltaTowerCAtOnePose) {
  const FirmwareMachine fm = exported(test::load_example("linuxcnc-ldelta.toml"));
  const std::string text = marlin().write(fm, kContext).text;
  EXPECT_NE(text.find("#define DELTA_RADIUS 130.25"), std::string::npos) << text;
  EXPECT_NE(text.find("#define DELTA_DIAGONAL_ROD 269"), std::string::npos);
  EXPECT_NE(text.find("#define DELTA_TOWER_ANGLE_TRIM { 0, 0, 0 }"), std::string::npos);
  EXPECT_NE(text.find("X = joint 2 joint1, Y = joint 3 joint2, Z = joint 1 joint0"),
            std::string::npos);
  const ref::Config config = ref::parse(text);
  EXPECT_NEAR(ref::stepper_positions(config, {10, 20, 5})[2], 250.165123, 1e-6);
  kinematics::JointVector joints(3);
  ASSERT_TRUE(fm.machine.kinematics().inverse(geometry::Pose::from_mm_deg(10, 20, 5), joints).ok());
  EXPECT_NEAR(joints[0], 250.165123, 1e-6);
}

// Worked by hand: the 1500 mm wall plotter's pen at its home (750, -700): each belt is
// sqrt(750^2 + 700^2) = sqrt(1052500) = 1025.914226 mm from its motor at y 0.
TEST(firmware_marlin_HandComputed, WallPlotterBeltsAtHome) {
  const FirmwareMachine fm = exported(test::load_example("wall-plotter.toml"));
  const std::string text = marlin().write(fm, kContext).text;
  EXPECT_NE(text.find("#define X_MIN_POS 0"), std::string::npos) << text;
  EXPECT_NE(text.find("#define X_MAX_POS 1500"), std::string::npos);
  EXPECT_NE(text.find("#define Y_MAX_POS 0"), std::string::npos);
  EXPECT_NE(text.find("#define DEFAULT_AXIS_STEPS_PER_UNIT { 80, 80, 400 }"), std::string::npos);
  const std::array<double, 3> belts = ref::stepper_positions(ref::parse(text), {750, -700, 0});
  EXPECT_NEAR(belts[0], 1025.914226, 1e-6);
  EXPECT_NEAR(belts[1], 1025.914226, 1e-6);
}

// Carriage switches at different heights: after Marlin's G28 each carriage sits at its switch
// moved by DELTA_ENDSTOP_ADJ (<= 0), where Marlin declares it at the reference IK of
// (0, 0, DELTA_HEIGHT); that must be the machine's reading there less the carriage offset.
TEST(firmware_marlin_Delta, EndstopAdjustmentsPutG28OnTheMachinesScale) {
  const machine::Machine m =
      test::load_example_changed("linear-delta.toml", "axis = \"X\"",
                                 "axis = \"X\"\nhome_switch = 650.0\nhome_toward = \"max\"");
  const FirmwareMachine fm = exported(m);
  const std::string file = marlin().write(fm, kContext).text;
  const ref::Config config = ref::parse(file);
  const double height = config.values.at("DELTA_HEIGHT")[0];
  const std::vector<double>& adj = config.values.at("DELTA_ENDSTOP_ADJ");
  const std::array<double, 3> declared = ref::stepper_positions(config, {0, 0, height});
  double largest_adj = -1e9;
  for (int k = 0; k < 3; ++k) {
    const int j = config.joint_of_stepper[k];
    EXPECT_LE(adj[k], 0.0);
    largest_adj = std::max(largest_adj, adj[k]);
    // Tower a (joint 1) trips at 650; the others at the home pose's reading.
    kinematics::JointVector at_home(3);
    ASSERT_TRUE(m.kinematics().inverse(m.home(), at_home).ok());
    const double trips = j == 0 ? 650.0 : at_home[j];
    EXPECT_NEAR(declared[k] + joint_offset(fm, j), trips + adj[k], 1e-6) << "stepper " << k;
  }
  EXPECT_DOUBLE_EQ(largest_adj, 0.0);
  EXPECT_LT(*std::min_element(adj.begin(), adj.end()), -1.0) << file;
}

// A switch 0.03 mm above the home pose's reading (353.77155081 = 100 + sqrt(300^2 - 160^2) mm):
// an adjustment of -0.03 mm, under Marlin's 6 steps at 80 steps/mm (0.075 mm), is warned.
TEST(firmware_marlin_Delta, AnAdjustmentMarlinWillNotMoveIsWarned) {
  const machine::Machine m =
      test::load_example_changed("linear-delta.toml", "axis = \"X\"",
                                 "axis = \"X\"\nhome_switch = 353.80155081\nhome_toward = \"max\"");
  const firmware::ExportedFile file = marlin().write(exported(m), kContext);
  std::string all;
  for (const std::string& warning : file.warnings) all += warning + "\n";
  EXPECT_NE(
      all.find("DELTA_ENDSTOP_ADJ of tower C is -0.03 mm, within Marlin's 6 steps (0.075 mm)"),
      std::string::npos)
      << all;
}

// The M665 and M666 comment lines carry the same geometry as the defines.
TEST(firmware_marlin_Delta, TheM665LineGivesTheSameSteppers) {
  const machine::Machine m = test::load_example_changed(
      "linear-delta.toml", "origin = [0.0, 200.0, 0.0]", "origin = [3.0, 204.0, 0.0]");
  const std::string file = marlin().write(exported(m), kContext).text;
  const ref::Config from_defines = ref::parse(file);
  ref::Config from_gcode = from_defines;
  const std::size_t at = file.find("M665 ");
  ASSERT_NE(at, std::string::npos) << file;
  std::istringstream words(file.substr(at + 5, file.find('\n', at) - at - 5));
  std::string word;
  std::map<char, double> letters;
  while (words >> word) letters[word[0]] = std::stod(word.substr(1));
  from_gcode.values["DELTA_DIAGONAL_ROD"] = {letters.at('L')};
  from_gcode.values["DELTA_RADIUS"] = {letters.at('R')};
  from_gcode.values["DELTA_TOWER_ANGLE_TRIM"] = {letters.at('X'), letters.at('Y'), letters.at('Z')};
  from_gcode.values["DELTA_DIAGONAL_ROD_TRIM_TOWER"] = {letters.at('A'), letters.at('B'),
                                                        letters.at('C')};
  EXPECT_NE(file.find("DELTA_RADIUS_TRIM_TOWER has no G-code"), std::string::npos);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 50), Eigen::Vector3d(60, -40, 10)}) {
    const auto a = ref::stepper_positions(from_defines, p),
               b = ref::stepper_positions(from_gcode, p);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-5);
  }
  EXPECT_DOUBLE_EQ(letters.at('H'), from_defines.values.at("DELTA_HEIGHT")[0]);
}

// An inch machine's lengths go to Marlin in mm: the same delta 25.4 times larger.
TEST(firmware_marlin_Delta, AnInchMachineIsWrittenInMillimetres) {
  const machine::Machine inch =
      test::load_example_changed("linear-delta.toml", "units = \"mm\"", "units = \"inch\"");
  const FirmwareMachine fm = exported(inch);
  const std::string text = marlin().write(fm, kContext).text;
  EXPECT_NE(text.find("#define DELTA_RADIUS 4064  "), std::string::npos) << text;  // 160 in
  EXPECT_NE(text.find("#define DELTA_DIAGONAL_ROD 7620  "), std::string::npos);    // 300 in
  EXPECT_LT(round_trip_error(fm, text), 1e-3);
}

// Marlin clamps a polargraph to the rectangle between and below its motors: a machine whose
// envelope reaches past them is exported with a warning giving both ranges.
TEST(firmware_marlin_Polargraph, TheClampIsWarnedWithItsNumbers) {
  const machine::Machine wide = test::load_example_changed(
      "pen-plotter.toml", "home = [750.0, -700.0]",
      "home = [750.0, -700.0]\nmin = [-100.0, -1800.0]\nmax = [1600.0, -150.0]");
  const firmware::ExportedFile file = marlin().write(exported(wide), kContext);
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_NE(file.warnings[0].find("Marlin clamps X to 0..1500"), std::string::npos)
      << file.warnings[0];
  EXPECT_NE(file.warnings[0].find("the machine reaches X -100..1600"), std::string::npos)
      << file.warnings[0];
  EXPECT_NE(file.text.find("#define Y_MIN_POS -1800  "), std::string::npos) << file.text;
}

TEST(firmware_marlin_Refuses, MachinesOfAnotherFormNameTheForms) {
  try {
    (void)exported(test::load_example("hexapod-bit.toml"));
    FAIL() << "exported a hexapod";
  } catch (const firmware::ExportRefused& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("two-cable wall plotter"), std::string::npos) << message;
    EXPECT_NE(message.find("linear delta"), std::string::npos) << message;
  }
}

TEST(firmware_marlin_Refuses, TiltedAnchors) {
  const machine::Machine tilted = test::load_example_changed(
      "wall-plotter.toml", "anchor_distance = 1500.0", "anchors = [[0.0, 0.0], [1500.0, 20.0]]");
  const FirmwareMachine fm = exported(tilted);
  try {
    (void)marlin().write(fm, kContext);
    FAIL() << "wrote tilted anchors";
  } catch (const firmware::ExportRefused& error) {
    EXPECT_NE(std::string(error.what()).find("Y_MAX_POS"), std::string::npos) << error.what();
  }
}

std::string read_error(const std::string& text) {
  try {
    (void)marlin().read(text, "Configuration.h");
  } catch (const firmware::FirmwareFileError& error) {
    return error.what();
  }
  return "(no error)";
}

const char* kDelta =
    "// a user's delta\n"
    "#define DELTA\n"
    "#define DELTA_DIAGONAL_ROD (200 + 50.0f)  // mm\n"
    "#define DELTA_RADIUS 124.0\n"
    "#define DELTA_HEIGHT 250.00\n"
    "//#define DELTA_ENDSTOP_ADJ { 9, 9, 9 }\n"
    "#define PRINTABLE_RADIUS 140.0\n"
    "#define X_MIN_POS -(PRINTABLE_RADIUS)\n"
    "#define BED_CENTER_AT_0_0\n"
    "#define STEPS_PER_TURN 200\n"
    "#define MICROSTEPS 16\n"
    "#define XYZ_STEPS ((STEPS_PER_TURN) * (MICROSTEPS) / double(2 * 20))\n"
    "#define DEFAULT_AXIS_STEPS_PER_UNIT { XYZ_STEPS, XYZ_STEPS, XYZ_STEPS, 760*1.1 }\n"
    "#define DEFAULT_MAX_FEEDRATE { 500, 500, 500, 25 }\n"
    "#define DEFAULT_MAX_ACCELERATION { 9000, 9000, 9000, 9000 }\n"
    "#define BAUDRATE 250000\n";

TEST(firmware_marlin_Reader, ReadsAUsersDeltaWithExpressionsAndIgnoresTheRest) {
  const machine::ImportedMachine imported = marlin().read(kDelta, "Configuration.h");
  ASSERT_EQ(imported.joints.size(), 3u);
  EXPECT_DOUBLE_EQ(imported.joints[0].max_velocity, 500.0);
  EXPECT_DOUBLE_EQ(*imported.joints[2].steps_per_unit, 80.0);  // 200 * 16 / double(40)
  EXPECT_DOUBLE_EQ((*imported.envelope_min)[0], -140.0);
  EXPECT_DOUBLE_EQ((*imported.home)[2], 250.0);
  EXPECT_NE(imported.kinematics_section.find("strut = 250"), std::string::npos)
      << imported.kinematics_section;
  bool noted = false;
  for (const std::string& note : imported.notes)
    noted = noted || note.find("BAUDRATE") != std::string::npos;
  EXPECT_TRUE(noted);
  // DELTA_ENDSTOP_ADJ is commented out: off, so every joint's endstop is at the same height.
  EXPECT_DOUBLE_EQ(imported.joints[0].max, imported.joints[1].max);
}

// Shaped like Marlin's own Polargraph example configuration: motors 650 mm apart at y 500, the
// pen homed where both belts are at full length (hypot(325, 982.65) = 1035.0 mm), no
// MANUAL_X_HOME_POS.
TEST(firmware_marlin_Reader, APolargraphHomedAtFullBelt) {
  const char* text =
      "#define POLARGRAPH\n"
      "#if ENABLED(POLARGRAPH)\n"
      "  #define POLARGRAPH_MAX_BELT_LEN  1035.0 // (mm)\n"
      "#endif\n"
      "#define DEFAULT_AXIS_STEPS_PER_UNIT { 80, 80, 80 }\n"
      "#define DEFAULT_MAX_FEEDRATE { 300, 300, 5 }\n"
      "#define DEFAULT_MAX_ACCELERATION { 3000, 3000, 100 }\n"
      "#define X_BED_SIZE 650\n#define Y_BED_SIZE 1000\n"
      "#define X_MIN_POS -325\n#define Y_MIN_POS -500\n#define Z_MIN_POS 0\n"
      "#define X_MAX_POS 325\n#define Y_MAX_POS 500\n#define Z_MAX_POS 100\n"
      "//#define MANUAL_X_HOME_POS 0\n"
      "#define MANUAL_Y_HOME_POS -482.65\n";
  const machine::ImportedMachine imported = marlin().read(text, "Configuration.h");
  EXPECT_NE(imported.kinematics_section.find("[-325.0, 500.0]"), std::string::npos)
      << imported.kinematics_section;
  ASSERT_EQ(imported.joints.size(), 3u);             // left, right and the pen's Z
  EXPECT_DOUBLE_EQ(imported.joints[0].max, 1036.0);  // Marlin's reach test: belt < 1035 + 1
  EXPECT_EQ(imported.warnings.size(), 1u);
  const machine::Machine m =
      machine::parse_machine(machine::machine_file_text(imported, "p.toml"), "p.toml");
  kinematics::JointVector joints(3);
  ASSERT_TRUE(m.inverse(m.home(), joints).ok());
  EXPECT_NEAR(joints[0], 1035.0, 1e-3);
}

TEST(firmware_marlin_Reader, AMissingSettingNamesItAndTheLine) {
  std::string text = kDelta;
  text.replace(text.find("#define DELTA_RADIUS 124.0\n"), 27, "");
  EXPECT_EQ(read_error(text).rfind("Configuration.h:2: DELTA_RADIUS: missing", 0), 0u)
      << read_error(text);
}

TEST(firmware_marlin_Reader, ANonNumberNamesItsLine) {
  std::string text = kDelta;
  text.replace(text.find("124.0"), 5, "12.4.0");
  EXPECT_EQ(read_error(text).rfind("Configuration.h:4: DELTA_RADIUS:", 0), 0u) << read_error(text);
  text = kDelta;
  text.replace(text.find("124.0"), 5, "RADIUS_OF_MY_BED");
  EXPECT_NE(read_error(text).find("Configuration.h:4: DELTA_RADIUS: 'RADIUS_OF_MY_BED'"),
            std::string::npos)
      << read_error(text);
}

// Found by fuzz/firmware_config.cpp: an exported delta whose pkmkit line said "X = joint 4"
// left a tower without geometry, and the model threw std::invalid_argument ("rail 2: strut must
// be positive") with no file or line. A stepper's joint out of 1..3, a joint twice, or "none" on
// a delta is now an error at the comment's line.
TEST(firmware_marlin_Reader, FuzzFoundAJointOutOfRangeIsAnErrorAtItsLine) {
  const std::string line17 = "Configuration.h:17: // pkmkit joints: stepper X = 'joint 4 tower_b'";
  std::string text = std::string(kDelta) +
                     "// pkmkit joints: X = joint 4 tower_b, Y = joint 3 tower_c, Z = joint 1 "
                     "tower_a (steps per mm: Marlin's stock values, set yours)\n";
  EXPECT_EQ(read_error(text).rfind(line17, 0), 0u) << read_error(text);
  text = std::string(kDelta) + "// pkmkit joints: X = joint 1 a, Y = joint 3 c, Z = joint 1 b\n";
  EXPECT_EQ(
      read_error(text).rfind("Configuration.h:17: // pkmkit joints: stepper Z = 'joint 1 b'", 0),
      0u)
      << read_error(text);
  text = std::string(kDelta) + "// pkmkit joints: X = joint 1 a, Y = joint 2 b, Z = none\n";
  EXPECT_EQ(read_error(text).rfind("Configuration.h:17: // pkmkit joints: stepper Z = none", 0), 0u)
      << read_error(text);
}

// Found by fuzz/firmware_config.cpp: "#define DELTA_DIAGONAL_ROD -00" made a rail of rod 0, and
// the model threw std::invalid_argument ("rail 1: strut must be positive") with no file or line.
TEST(firmware_marlin_Reader, FuzzFoundARodOfZeroIsAnErrorAtItsLine) {
  std::string text = kDelta;
  text.replace(text.find("(200 + 50.0f)"), 13, "-00");
  EXPECT_EQ(
      read_error(text).rfind("Configuration.h:3: DELTA_DIAGONAL_ROD: tower A's rod is 0 mm", 0), 0u)
      << read_error(text);
  // A trim that takes one tower's rod below 0: that tower, at the trim's line.
  text = std::string(kDelta) + "#define DELTA_DIAGONAL_ROD_TRIM_TOWER { 0, -300, 0 }\n";
  EXPECT_EQ(read_error(text).rfind(
                "Configuration.h:17: DELTA_DIAGONAL_ROD_TRIM_TOWER: tower B's rod is -50 mm", 0),
            0u)
      << read_error(text);
}

// A joint's name may hold spaces (the machine file allows them): the pkmkit line gives it back.
TEST(firmware_marlin_Reader, JointNamesWithSpacesComeBack) {
  const std::string text = std::string(kDelta) +
                           "// pkmkit joints: X = joint 2 tower b, Y = joint 3 tower c, Z = joint "
                           "1 tower a (steps per mm: Marlin's stock values, set yours)\n";
  const machine::ImportedMachine imported = marlin().read(text, "Configuration.h");
  ASSERT_EQ(imported.joints.size(), 3u);
  EXPECT_EQ(imported.joints[0].name, "tower a");
  EXPECT_EQ(imported.joints[1].name, "tower b");
  EXPECT_EQ(imported.joints[2].name, "tower c");
  EXPECT_FALSE(imported.joints[0].steps_per_unit);  // Marlin's stock steps are not the machine's
}

TEST(firmware_marlin_Reader, NeitherKinematicsIsAnError) {
  EXPECT_NE(read_error("#define X_BED_SIZE 200\n").find("Configuration.h:1: DELTA"),
            std::string::npos);
}

}  // namespace
}  // namespace pkm
