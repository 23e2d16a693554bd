// `pkm export rrf` and `pkm import rrf` (docs/firmware-rrf.md), proven against an independent
// RepRapFirmware linear delta (firmware_reference/rrf.hpp) reading the exported config.g lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "firmware_reference/rrf.hpp"
#include "pkm/firmware/firmware_machine.hpp"
#include "pkm/firmware/target.hpp"
#include "pkm/machine/imported_machine.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

namespace reference = test::rrf_reference;

const firmware::Target& rrf() {
  return firmware::target("rrf");
}

std::string export_text(const machine::Machine& machine) {
  const firmware::FirmwareMachine held =
      firmware::firmware_machine(machine, rrf().forms, rrf().name, false);
  return rrf().write(held, firmware::ExportContext{"test", machine.source()}).text;
}

std::string export_example(const std::string& file_name) {
  return export_text(test::load_example(file_name));
}

// The worst difference (mm) over the machine's workspace between each carriage's distance below
// its endstop as the reference RRF computes it from `text`, and as pkmkit's joints say it: the
// endstop at the joint's home switch, else its max; the joint `text` names for each drive.
double worst_carriage_error_mm(const machine::Machine& machine, const std::string& text,
                               int& samples) {
  const reference::LinearDelta delta = reference::parse(text);
  double worst = 0.0;
  samples = 0;
  kinematics::JointVector joints(machine.kinematics().joint_count());
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    if (!machine.inverse(pose, joints).ok()) continue;
    ++samples;
    const Eigen::Vector3d& p = pose.position_mm;
    for (int drive = 0; drive < 3; ++drive) {
      const int joint = delta.joint_of_drive[static_cast<std::size_t>(drive)];
      const double rrf_below = reference::homed_carriage_height(delta, drive) -
                               reference::motor_position(delta, drive, p.x(), p.y(), p.z());
      const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(joint)];
      const double endstop = spec.home_switch ? spec.home_switch->position : spec.max;
      const double pkm_below = endstop - joints[joint];
      worst = std::max(worst, std::abs(rrf_below - pkm_below));
    }
  }
  return worst;
}

// The number after `key` ("M665 B") in the exported text.
std::string rrf_number_of(const std::string& text, const std::string& key) {
  const std::size_t line = text.find("\n" + key.substr(0, key.find(' ')) + " ");
  const std::size_t at = text.find(" " + key.substr(key.find(' ') + 1), line);
  const std::size_t end = text.find_first_of(" \n", at + 2);
  return text.substr(at + 2, end - at - 2);
}

class RrfLinearDeltaExample : public ::testing::TestWithParam<std::string> {};

TEST_P(RrfLinearDeltaExample, ReferenceRrfMovesEveryCarriageAsPkmkitOverTheWorkspace) {
  const machine::Machine machine = test::load_example(GetParam());
  const std::string text = export_text(machine);
  const reference::LinearDelta delta = reference::parse(text);
  for (int drive = 0; drive < 3; ++drive) {
    ASSERT_GE(delta.joint_of_drive[static_cast<std::size_t>(drive)], 0) << text;
  }
  int samples = 0;
  const double worst = worst_carriage_error_mm(machine, text, samples);
  EXPECT_GT(samples, 100);
  EXPECT_LT(worst, 1e-3) << text;
  char worst_text[32];
  std::snprintf(worst_text, sizeof worst_text, "%.3g", worst);
  RecordProperty("worst_carriage_error_mm", worst_text);
  RecordProperty("samples", samples);
  // Speeds and accelerations are the effector's, per axis.
  for (const char* drive : {"X", "Y", "Z"}) {
    EXPECT_EQ(delta.settings.at(std::string("M203 ") + drive),
              machine.cartesian().max_feed_mm_per_min);
    EXPECT_EQ(delta.settings.at(std::string("M201 ") + drive),
              machine.cartesian().max_acceleration_mm_per_s2);
  }
  EXPECT_EQ(delta.x_tilt, 0.0);
  EXPECT_EQ(delta.y_tilt, 0.0);
}

// Import, then export: the same lines (but for the header, which names the file it came from,
// and the drive comments, which number the joints of the file the export read).
std::vector<std::string> settings_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  std::string line;
  while (std::getline(stream, line)) {
    if (line.rfind("; Written by pkmkit", 0) == 0 || line.rfind("; drive ", 0) == 0) continue;
    lines.push_back(line);
  }
  return lines;
}

TEST_P(RrfLinearDeltaExample, ImportThenExportGivesTheSameLines) {
  const std::string first = export_example(GetParam());
  const machine::ImportedMachine imported = rrf().read(first, "config.g");
  const std::string file = machine::machine_file_text(imported, "imported.toml");
  const machine::Machine again = machine::parse_machine(file, "imported.toml");
  const std::string second = export_text(again);
  EXPECT_EQ(settings_lines(first), settings_lines(second)) << first << "\n----\n" << second;
  // The imported machine's joints are RRF's motor positions themselves.
  const reference::LinearDelta delta = reference::parse(first);
  kinematics::JointVector joints(3);
  double worst = 0.0;
  for (const geometry::Pose& pose : firmware::workspace_samples(again)) {
    if (!again.inverse(pose, joints).ok()) continue;
    const Eigen::Vector3d& p = pose.position_mm;
    for (int drive = 0; drive < 3; ++drive) {
      worst = std::max(
          worst,
          std::abs(reference::motor_position(delta, drive, p.x(), p.y(), p.z()) - joints[drive]));
    }
  }
  EXPECT_LT(worst, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(firmware_rrf, RrfLinearDeltaExample,
                         ::testing::Values("linear-delta.toml", "linuxcnc-ldelta.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

// linear-delta.toml by hand. Its columns (rail origin less the effector's joint offset) are
// (0, 160), (-138.564, -80), (138.564, -80): radius 160 at 90, 210 and 330 deg, RRF's towers C,
// A, B with no correction: drive X = joint 2, Y = joint 3, Z = joint 1. Rods 300, the endstops
// at the joints' max 700: H = 700 - sqrt(300^2 - 160^2) = 700 - 253.771551 = 446.228449.
// The bed circle: the envelope's +-120 box holds a circle of 120 about the centre.
// At x 30 y 40 z 10 tower C's carriage is 10 + sqrt(300^2 - (30^2 + 120^2)) = 10 +
// sqrt(74700) = 283.313007 mm, which is joint 1's reading (its carriage offset is 0).
TEST(firmware_rrf_export, LinearDeltaByHand) {
  const std::string text = export_example("linear-delta.toml");
  EXPECT_NE(text.find("\nM669 K3 ; linear delta kinematics\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM665 L300:300:300 R160 H446.228449 B120 X0 Y0 Z0 ;"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\nM666 X0 Y0 Z0 A0 B0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM203 X9000 Y9000 Z9000 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM201 X2000 Y2000 Z2000 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM208 S1 Z0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("; drive X = tower A = joint 2 \"tower_b\""), std::string::npos) << text;
  EXPECT_NE(text.find("; drive Z = tower C = joint 1 \"tower_a\""), std::string::npos) << text;
  EXPECT_EQ(text.rfind("; Written by pkmkit test from ", 0), 0u) << text;

  const reference::LinearDelta delta = reference::parse(text);
  EXPECT_NEAR(reference::motor_position(delta, 2, 30.0, 40.0, 10.0), 283.313007, 1e-6);
  const machine::Machine machine = test::load_example("linear-delta.toml");
  kinematics::JointVector joints(3);
  ASSERT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(30.0, 40.0, 10.0), joints).ok());
  EXPECT_NEAR(joints[0], 283.313007, 1e-6);
}

// A Kossel Pro-shaped config.g as Duet users write it (the settings of a Kossel Pro MK3
// config.g on a Duet WiFi found on GitHub, in a file written here): comments, the drives'
// directions and currents, the extruder's steps in a second M92, a Z probe, tools, a macro call
// and M501, which loads the calibration M500 saved (warned: it is another file).
constexpr const char* kKosselConfig = R"(; Main configuration file
M550 P"Kossel Pro" ; name
M111 S0 ; Debug off
G21 ; Work in millimetres
G90
M83
M569 P0 S0 ; Drive 0 goes backwards
M569 P1 S0
M569 P2 S0
M574 X2 Y2 Z2 S1 ; endstops at the high end
M665 L300.000 R153 H270 B135.0 X0 Y0 Z0 ; delta radius, rods, printable radius, homed height
M666 X0.3 Y-0.1 Z-0.2 A0.00 B0.00 ; endstop adjustments
M350 X16 Y16 E16 I1
M92 X80 Y80 Z80 ; Set axis steps/mm
M906 X1000 Y1000 Z1000 E800 I60
M201 X9000 Y9000 Z9000 E5000 ; Accelerations (mm/s^2)
M203 X30000 Y30000 Z30000 E7200 ; Maximum speeds (mm/min)
M566 X600 Y600 Z600 E150
M563 P0 D0 H1
M92 E92.6 ; extruder steps per mm
M558 P5 I1 X0 Y0 Z0
G31 X0 Y0 Z0.25 P500
M208 S1 Z-0.2 ; set minimum Z
if exists(param.X)
  echo "meta commands are not read"
T0
M98 P"local.g"
M501 ; config-override.g
)";

TEST(firmware_rrf_import, KosselConfigGivesTheMachineRrfRuns) {
  const machine::ImportedMachine imported = rrf().read(kKosselConfig, "config.g");
  EXPECT_EQ(imported.name, "Kossel Pro");
  ASSERT_EQ(imported.joints.size(), 3u);
  // The endstops: H + sqrt(300^2 - 153^2) + M666 = 270 + 258.049608 + 0.3 for tower A.
  const double rise = std::sqrt(300.0 * 300.0 - 153.0 * 153.0);
  EXPECT_NEAR(imported.joints[0].max, 270.0 + rise + 0.3, 1e-9);
  EXPECT_NEAR(imported.joints[1].max, 270.0 + rise - 0.1, 1e-9);
  EXPECT_NEAR(imported.joints[2].max, 270.0 + rise - 0.2, 1e-9);
  EXPECT_EQ(imported.joints[0].steps_per_unit, 80.0);
  EXPECT_DOUBLE_EQ(imported.max_feed_per_min, 30000.0);
  EXPECT_DOUBLE_EQ(imported.max_acceleration, 9000.0);
  ASSERT_TRUE(imported.envelope_min && imported.envelope_max);
  EXPECT_EQ(*imported.envelope_min, (std::vector<double>{-135.0, -135.0, -0.2}));
  std::string notes;
  for (const std::string& note : imported.notes) notes += note + "\n";
  EXPECT_NE(notes.find("M569 (lines 7 8 9)"), std::string::npos) << notes;
  EXPECT_NE(notes.find("M92 E (line 20)"), std::string::npos) << notes;
  EXPECT_NE(notes.find("line 24: if exists(param.X)"), std::string::npos) << notes;
  ASSERT_EQ(imported.warnings.size(), 2u);
  EXPECT_EQ(imported.warnings[0], "line 27: M98 runs \"local.g\", whose settings were not read");
  EXPECT_EQ(imported.warnings[1].rfind("line 28: M501 loads config-override.g", 0), 0u);

  // The machine file loads, and exporting it gives the file's settings back (the endstop
  // corrections already average to 0, so H stays 270).
  const machine::Machine machine =
      machine::parse_machine(machine::machine_file_text(imported, "kossel.toml"), "kossel.toml");
  const std::string text = export_text(machine);
  EXPECT_NE(text.find("\nM665 L300:300:300 R153 H270 B135 X0 Y0 Z0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM666 X0.3 Y-0.1 Z-0.2 A0 B0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM92 X80 Y80 Z80 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM208 S1 Z-0.2 ;"), std::string::npos) << text;
  int samples = 0;
  EXPECT_LT(worst_carriage_error_mm(machine, text, samples), 1e-3);
  EXPECT_GT(samples, 100);
}

std::string import_error(const std::string& text) {
  try {
    (void)rrf().read(text, "config.g");
  } catch (const firmware::FirmwareFileError& error) {
    return error.what();
  }
  return "no error";
}

TEST(firmware_rrf_import, BadInputSaysWhereAndWhy) {
  const std::string speeds = "M203 X9000 Y9000 Z9000\nM201 X1000 Y1000 Z1000\n";
  EXPECT_EQ(import_error("M665 L300 H400\n" + speeds),
            "config.g:1: M665 R: not set (the delta radius, mm)");
  EXPECT_EQ(import_error("; delta\nM665 L3x0 R150 H400\n" + speeds),
            "config.g:2: M665 L: '3x0' is not a number");
  EXPECT_EQ(import_error("M665 L300:301:302:303 R150 H400\n" + speeds)
                .rfind("config.g:1: M665 L: 4 "
                       "diagonals",
                       0),
            0u);
  EXPECT_EQ(import_error("M665 L300 R150 H400\nM201 X1000 Y1000 Z1000\n"),
            "config.g:2: M203 X: not set (the maximum speed, mm/min): no M203 sets it before the "
            "end of the file");
  EXPECT_EQ(import_error("M665 L300 R150 H400\nM666 A0.11\n" + speeds)
                .rfind("config.g:2: M666 A: "
                       "a bed tilt",
                       0),
            0u);
  EXPECT_EQ(import_error("M669 K4\n"),
            "config.g:1: M669 K: kinematics 4: pkmkit imports RRF's linear delta (K3), rotary "
            "delta (K10) and Hangprinter (K6)");
  EXPECT_EQ(import_error("M92 X80\n"),
            "config.g:1: M665: no delta in this file: RRF's linear delta is M665 L R H (and M669 "
            "K3), its rotary delta M669 K10 U L R");
  EXPECT_EQ(import_error("M665 L300 R150 H400 B{global.radius}\n" + speeds),
            "config.g:1: M665 B: '{global.radius}' is not a number");
}

// The rotary delta: RRF's arm angle (deg, up positive) is minus pkmkit's reading; each arm's
// endstop is at its joint's min (the arm at its highest). Returns the worst difference over the
// workspace between RRF's angle below the endstop and pkmkit's, as the distance (mm) the elbow
// moves by it; `absolute` the worst of RRF's angle against minus the reading, likewise.
double worst_arm_error_mm(const machine::Machine& machine, const std::string& text, int& samples,
                          double& absolute) {
  const reference::RotaryDelta delta = reference::parse_rotary(text);
  const auto deg = [](double rad) { return rad * 180.0 / 3.14159265358979323846; };
  double worst_deg = 0.0, worst_absolute_deg = 0.0;
  samples = 0;
  kinematics::JointVector joints(3);
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    if (!machine.inverse(pose, joints).ok()) continue;
    ++samples;
    const Eigen::Vector3d& p = pose.position_mm;
    for (int drive = 0; drive < 3; ++drive) {
      const int joint = delta.joint_of_drive[static_cast<std::size_t>(drive)];
      const double rrf = reference::arm_angle_deg(delta, drive, p.x(), p.y(), p.z());
      const double rrf_below = reference::homed_arm_angle_deg(delta, drive) - rrf;
      const double pkm_below =
          deg(joints[joint]) - deg(machine.joints()[static_cast<std::size_t>(joint)].min);
      worst_deg = std::max(worst_deg, std::abs(rrf_below - pkm_below));
      worst_absolute_deg = std::max(worst_absolute_deg, std::abs(rrf + deg(joints[joint])));
    }
  }
  const double arm_mm = delta.arms[0];
  absolute = worst_absolute_deg * 3.14159265358979323846 / 180.0 * arm_mm;
  return worst_deg * 3.14159265358979323846 / 180.0 * arm_mm;
}

TEST(firmware_rrf_rotary, ReferenceRrfTurnsEveryArmAsPkmkitOverTheWorkspace) {
  const machine::Machine machine = test::load_example("linuxcnc-rdelta.toml");
  const std::string text = export_text(machine);
  int samples = 0;
  double absolute = 0.0;
  const double worst = worst_arm_error_mm(machine, text, samples, absolute);
  EXPECT_GT(samples, 100);
  EXPECT_LT(worst, 1e-3) << text;
  EXPECT_LT(absolute, 1e-3) << text;
  char worst_text[32];
  std::snprintf(worst_text, sizeof worst_text, "%.3g", worst);
  RecordProperty("worst_elbow_error_mm", worst_text);
  RecordProperty("samples", samples);
}

// linuxcnc-rdelta.toml by hand, in mm: pivots at 10 in = 254 mm, effector joints at 5 in: RRF's
// R = 127 mm; arms 254, rods 457.2. pkmkit's arms point at -90, 30, 150 deg, RRF's at -150, -30,
// 90 plus corrections: +60 each, drive X = joint 1. Joints -45..90 deg, positive down: RRF's
// arm angles -90..45, the endstops (the arms at their highest, -45 deg) at A's max 45. The
// envelope, +-4 in and z -18..-10 in: B 101.6, Z -457.2..-254. 600 in/min = 15240 mm/min,
// 100 in/s^2 = 2540 mm/s^2.
// At x 0 y 0 z -350 every arm, in its own frame: a = 2 U R = 64516, b = 2 U (0 - z) = 177800,
// c = L^2 - U^2 - (z^2 + R^2) = 209031.84 - 64516 - (122500 + 16129) = 5886.84;
// sin t = (b c - a sqrt(a^2 + b^2 - c^2)) / (a^2 + b^2) = -0.311632, t = -18.160119 deg: the
// arm 18.160119 deg below horizontal, pkmkit's reading.
TEST(firmware_rrf_rotary, LinuxcncRdeltaByHand) {
  const std::string text = export_example("linuxcnc-rdelta.toml");
  EXPECT_NE(text.find("\nM669 K10 U254:254:254 L457.2:457.2:457.2 H0:0:0 A-90:45 R127 B101.6 "
                      "X60 Y60 Z60 ;"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\nM666 X0 Y0 Z0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM203 X15240 Y15240 Z15240 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM201 X2540 Y2540 Z2540 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM208 Z-457.2:-254 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("; drive X = arm A = joint 1 \"joint0\": towards -90 deg"), std::string::npos)
      << text;
  const reference::RotaryDelta delta = reference::parse_rotary(text);
  for (int drive = 0; drive < 3; ++drive) {
    EXPECT_NEAR(reference::arm_angle_deg(delta, drive, 0.0, 0.0, -350.0), -18.160119, 1e-6);
  }
  const machine::Machine machine = test::load_example("linuxcnc-rdelta.toml");
  kinematics::JointVector joints(3);
  ASSERT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(0.0, 0.0, -350.0), joints).ok());
  EXPECT_NEAR(joints[0] * 180.0 / 3.14159265358979323846, 18.160119, 1e-6);
}

TEST(firmware_rrf_rotary, ImportThenExportGivesTheSameLines) {
  const std::string first = export_example("linuxcnc-rdelta.toml");
  const machine::ImportedMachine imported = rrf().read(first, "config.g");
  const machine::Machine again = machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml");
  const std::string second = export_text(again);
  EXPECT_EQ(settings_lines(first), settings_lines(second)) << first << "\n----\n" << second;
  int samples = 0;
  double absolute = 0.0;
  EXPECT_LT(worst_arm_error_mm(again, first, samples, absolute), 1e-3);
  EXPECT_LT(absolute, 1e-3);
  EXPECT_GT(samples, 100);
}

TEST(firmware_rrf_import, RotaryDeltaPkmkitCannotHoldIsRefusedAtItsSetting) {
  const std::string speeds = "M203 X9000 Y9000 Z9000\nM201 X1000 Y1000 Z1000\n";
  EXPECT_EQ(import_error("M669 K10 U100 L200 R50 H250 X0 Y0 Z0\n" + speeds),
            "config.g:1: M669 H: pivots at heights 250:250:250 mm: pkmkit's rotary delta has "
            "them at z 0, and RRF's Z would be another (set H0:0:0 and Z from the pivots' plane)");
  EXPECT_EQ(import_error("M669 K10 U100 L200 R50 H0\n" + speeds),
            "config.g:1: M669 X: the arms point at -150, -30, 90 deg: pkmkit's rotary delta has "
            "them at -90, 30 and 150 deg (X60 Y60 Z60), and RRF cannot turn its frame");
  EXPECT_EQ(import_error("M669 K10 U100:100:101 L200 R50 H0 X60 Y60 Z60\n" + speeds),
            "config.g:1: M669 U: arms of 100:100:101 mm: pkmkit's rotary delta has one for every "
            "arm");
  EXPECT_EQ(import_error("M669 K10 U100 L200 R50 H0 X60 Y60 Z60 A-40:30\nM666 Y-75\n" + speeds),
            "config.g:1: M669 A: arm B's endstop at -45 deg is not above A's min -40 deg");
}

std::string export_refusal(const machine::Machine& machine) {
  try {
    (void)export_text(machine);
  } catch (const firmware::ExportRefused& error) {
    return error.what();
  }
  return "no refusal";
}

TEST(firmware_rrf_export, RefusesWhatRrfCannotHold) {
  // Another form: the message names the one rrf has.
  const std::string hexapod = export_refusal(test::load_example("hexapod-bit.toml"));
  EXPECT_NE(hexapod.find("rrf has kinematics for a linear delta"), std::string::npos) << hexapod;
  // A column off the common circle (tower_a's rail 1 mm farther out).
  const std::string moved = export_refusal(test::load_example_changed(
      "linear-delta.toml", "origin = [0.0, 200.0, 0.0]", "origin = [0.0, 201.0, 0.0]"));
  EXPECT_NE(moved.find("one circle about x 0 y 0 (M665 R), and this machine's columns stand at "
                       "161 mm, 160 mm and 160 mm"),
            std::string::npos)
      << moved;
  // A leaning rail: refused exactly; the core's --approximate fits the nearest linear delta
  // (columns free), whose columns are then off one circle: without --approximate reaching the
  // target that is refused, with it the nearest delta on one circle is written, its cost
  // measured on the leaning machine as built.
  const machine::Machine leaning = test::load_example_changed(
      "linear-delta.toml", "direction = [0.0, 0.0, 1.0]\nstrut = 300.0\nattach = [0.0, 40.0, 0.0]",
      "direction = [0.0, 0.01, 1.0]\nstrut = 300.0\nattach = [0.0, 40.0, 0.0]");
  const std::string lean = export_refusal(leaning);
  EXPECT_NE(lean.find("rail 1 leans 0.5729 deg from vertical"), std::string::npos) << lean;
  const firmware::FirmwareMachine nearest =
      firmware::firmware_machine(leaning, rrf().forms, rrf().name, true);
  ASSERT_TRUE(nearest.cost);
  try {
    (void)rrf().write(nearest, firmware::ExportContext{"test", "linear-delta.toml"});
    ADD_FAILURE() << "the fitted columns off one circle were written";
  } catch (const firmware::ExportRefused& error) {
    EXPECT_NE(
        std::string(error.what()).find("--approximate writes the nearest delta on one circle"),
        std::string::npos)
        << error.what();
  }
  const firmware::ExportedFile on_circle =
      rrf().write(nearest, firmware::ExportContext{"test", "linear-delta.toml", true});
  ASSERT_TRUE(on_circle.cost);
  EXPECT_NE(on_circle.text.find("APPROXIMATED"), std::string::npos);
  EXPECT_NE(on_circle.text.find("columns at different radii"), std::string::npos);
  // Measured on the machine as built: more than the first fit's (the circle costs something),
  // and a real number (a leaning rail of 0.57 deg over a 700 mm rail).
  EXPECT_GE(on_circle.cost->worst_tool_error_mm, nearest.cost->worst_tool_error_mm - 1e-9);
  EXPECT_GT(on_circle.cost->worst_tool_error_mm, 0.01);
  EXPECT_LT(on_circle.cost->worst_tool_error_mm, 20.0);
  std::printf("rrf leaning rail: first fit %.4f mm, on one circle %.4f mm worst\n",
              nearest.cost->worst_tool_error_mm, on_circle.cost->worst_tool_error_mm);
}

// A delta as calibration leaves one, each tower its own: columns on a 150 mm circle at 91, 209.5
// and 330.2 deg (RRF's C, A, B, corrections +1, -0.5, +0.2), rods 290, 290.4, 289.7, the second
// carriage 1.5 mm above its effector joint, the endstops at 600, 601 and a switch at 590.
// Carriage heights at the endstops in RRF's terms (endstop less offset less sqrt(L^2 - R^2)):
// A 601 - 1.5 - 249.060733 = 350.839267, B 590 - 247.842874 = 342.157126, C 600 - 248.193473 =
// 351.806527; H their mean 348.267640, M666 the rest: 2.571627, -6.110514, 3.538887.
constexpr const char* kCalibratedDelta = R"(name = "calibrated delta"
units = "mm"
[kinematics]
type = "glide"
[[kinematics.rails]]
origin = [-2.6178609655925213, 149.9771542734587, 0.0]
direction = [0.0, 0.0, 1.0]
strut = 290.0
attach = [0.0, 0.0, 0.0]
[[kinematics.rails]]
origin = [-130.55335439098496, -73.86353401552005, 0.0]
direction = [0.0, 0.0, 1.0]
strut = 290.4
attach = [0.0, 0.0, 1.5]
[[kinematics.rails]]
origin = [130.1648180053392, -74.5460941541334, 0.0]
direction = [0.0, 0.0, 1.0]
strut = 289.7
attach = [0.0, 0.0, 0.0]
[[joints]]
name = "c"
min = 0.0
max = 600.0
max_velocity = 200.0
max_acceleration = 3000.0
steps_per_unit = 80.0
[[joints]]
name = "a"
min = 0.0
max = 601.0
max_velocity = 200.0
max_acceleration = 3000.0
steps_per_unit = 80.5
[[joints]]
name = "b"
min = 0.0
max = 600.0
max_velocity = 200.0
max_acceleration = 3000.0
steps_per_unit = 79.5
home_switch = 590.0
home_toward = "max"
[cartesian]
max_feed = 6000.0
max_acceleration = 1500.0
home = [0.0, 0.0, 100.0]
min = [-100.0, -110.0, 0.5]
max = [105.0, 100.0, 200.0]
)";

TEST(firmware_rrf_export, EachTowerItsOwnRodOffsetEndstopAndAngle) {
  const machine::Machine machine = machine::parse_machine(kCalibratedDelta, "calibrated.toml");
  const std::string text = export_text(machine);
  EXPECT_NE(text.find("\nM665 L290.4:289.7:290 R150 H348.26764 B100 X-0.5 Y0.2 Z1 ;"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\nM666 X2.571627 Y-6.110514 Z3.538887 A0 B0 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM92 X80.5 Y79.5 Z80 ;"), std::string::npos) << text;
  EXPECT_NE(text.find("\nM208 S1 Z0.5 ;"), std::string::npos) << text;
  int samples = 0;
  const double worst = worst_carriage_error_mm(machine, text, samples);
  EXPECT_LT(worst, 1e-3) << text;
  EXPECT_GT(samples, 100);
  char worst_text[32];
  std::snprintf(worst_text, sizeof worst_text, "%.3g", worst);
  RecordProperty("worst_carriage_error_mm", worst_text);
  RecordProperty("samples", samples);
  // And back: the same lines again.
  const machine::Machine again = machine::parse_machine(
      machine::machine_file_text(rrf().read(text, "config.g"), "imported.toml"), "imported.toml");
  EXPECT_EQ(settings_lines(text), settings_lines(export_text(again)));
}

// Without a work envelope, B and Z min come from the reach along the axes through home.
TEST(firmware_rrf_export, WithoutAnEnvelopeTheReachBoundsB) {
  const machine::Machine machine = test::load_example_changed(
      "linear-delta.toml", "min = [-120.0, -120.0, 0.0]\nmax = [120.0, 120.0, 300.0]", "");
  ASSERT_FALSE(machine.cartesian().has_envelope());
  const std::string text = export_text(machine);
  const reference::LinearDelta delta = reference::parse(text);
  const machine::PoseBox reach = machine::reach_box(machine);
  EXPECT_DOUBLE_EQ(
      std::stod(rrf_number_of(text, "M665 B")),
      std::round(std::min({-reach.min[0], reach.max[0], -reach.min[1], reach.max[1]}) * 1e6) / 1e6);
  EXPECT_GT(delta.print_radius, 120.0);
  int samples = 0;
  EXPECT_LT(worst_carriage_error_mm(machine, text, samples), 1e-3);
}

// RRF does not ask M666 to average 0: the export moves their mean into H, every carriage's homed
// height the same (270 + 0.5 either way).
TEST(firmware_rrf_import, EndstopCorrectionsComeBackWithTheirMeanInH) {
  const machine::ImportedMachine imported = rrf().read(
      "M665 L300 R153 H270 B135\nM666 X0.5 Y0.5 Z0.5\nM203 X9000 Y9000 Z9000\n"
      "M201 X1000 Y1000 Z1000\n",
      "config.g");
  const std::string text = export_text(machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml"));
  EXPECT_NE(text.find("\nM665 L300:300:300 R153 H270.5 B135 X0 Y0 Z0 ;"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\nM666 X0 Y0 Z0 A0 B0 ;"), std::string::npos) << text;
}

// Users' own settings, drawn at random as RRF's auto-calibration leaves them (3 decimals, a few
// degrees of correction, endstop corrections of any mean): import then export moves each tower
// and each homed carriage height by less than 1e-6 mm, and the exported file drives the imported
// machine's joints as RRF would.
TEST(firmware_rrf_import, RandomSettingsComeBackAsTheSameDelta) {
  std::mt19937_64 rng(30);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto three = [](double value) { return std::round(value * 1000.0) / 1000.0; };
  for (int trial = 0; trial < 20; ++trial) {
    const double radius = three(120.0 + 60.0 * (unit(rng) + 1.0));
    std::string rods = "L";
    for (int k = 0; k < 3; ++k) {
      rods += (k > 0 ? ":" : "") + std::to_string(three(radius * 1.8 + 2.0 * unit(rng)));
    }
    std::string text =
        "M665 " + rods + " R" + std::to_string(radius) + " H" +
        std::to_string(three(300.0 + 50.0 * unit(rng))) + " B" +
        std::to_string(three(radius * 0.6)) + " X" + std::to_string(three(3.0 * unit(rng))) + " Y" +
        std::to_string(three(3.0 * unit(rng))) + " Z" + std::to_string(three(3.0 * unit(rng))) +
        "\nM666 X" + std::to_string(three(2.0 * unit(rng))) + " Y" +
        std::to_string(three(2.0 * unit(rng))) + " Z" + std::to_string(three(2.0 * unit(rng))) +
        "\nM203 X12000 Y12000 Z12000\nM201 X3000 Y3000 Z3000\nM208 S1 Z-2\n";
    SCOPED_TRACE(text);
    const machine::Machine machine = machine::parse_machine(
        machine::machine_file_text(rrf().read(text, "config.g"), "imported.toml"), "imported.toml");
    const std::string exported = export_text(machine);
    const reference::LinearDelta before = reference::parse(text);
    const reference::LinearDelta after = reference::parse(exported);
    for (int tower = 0; tower < 3; ++tower) {
      EXPECT_EQ(after.joint_of_drive[static_cast<std::size_t>(tower)], tower);
      const std::array<double, 2> was = reference::tower_position(before, tower);
      const std::array<double, 2> is = reference::tower_position(after, tower);
      EXPECT_NEAR(is[0], was[0], 1e-6);
      EXPECT_NEAR(is[1], was[1], 1e-6);
      EXPECT_NEAR(reference::homed_carriage_height(after, tower),
                  reference::homed_carriage_height(before, tower), 1e-6);
    }
    int samples = 0;
    EXPECT_LT(worst_carriage_error_mm(machine, exported, samples), 1e-3);
    EXPECT_GT(samples, 100);
  }
}

// Rotary settings pkmkit's form holds, drawn at random, their Z range above the endstops' pose:
// import then export gives each arm's homed angle back within 1e-6 deg, and the reference RRF
// follows the imported machine's joints.
TEST(firmware_rrf_import, RandomRotarySettingsComeBackAsTheSameDelta) {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto three = [](double value) {
    return std::to_string(std::round(value * 1000.0) / 1000.0);
  };
  for (int trial = 0; trial < 20; ++trial) {
    const std::string text =
        "M669 K10 U" + three(100.0 + 20.0 * unit(rng)) + " L" + three(215.0 + 30.0 * unit(rng)) +
        " H0 A" + three(-50.0 + 10.0 * unit(rng)) + ":" + three(40.0 + 10.0 * unit(rng)) + " R" +
        three(50.0 + 20.0 * unit(rng)) + " B60 X60 Y60 Z60\nM666 X" + three(2.0 * unit(rng)) +
        " Y" + three(2.0 * unit(rng)) + " Z" + three(2.0 * unit(rng)) +
        "\nM203 X6000 Y6000 Z6000\nM201 X500 Y500 Z500\nM208 Z-400:100\n";
    SCOPED_TRACE(text);
    const machine::Machine machine = machine::parse_machine(
        machine::machine_file_text(rrf().read(text, "config.g"), "imported.toml"), "imported.toml");
    const std::string exported = export_text(machine);
    const reference::RotaryDelta before = reference::parse_rotary(text);
    const reference::RotaryDelta after = reference::parse_rotary(exported);
    for (int arm = 0; arm < 3; ++arm) {
      EXPECT_NEAR(reference::homed_arm_angle_deg(after, arm),
                  reference::homed_arm_angle_deg(before, arm), 1e-6);
      EXPECT_NEAR(after.angle_corrections[static_cast<std::size_t>(arm)], 60.0, 1e-9);
    }
    EXPECT_NEAR(after.radius, before.radius, 1e-9);
    EXPECT_NEAR(after.min_arm_angle, before.min_arm_angle, 1e-9);
    int samples = 0;
    double absolute = 0.0;
    EXPECT_LT(worst_arm_error_mm(machine, exported, samples, absolute), 1e-3);
    EXPECT_LT(absolute, 1e-3);
    EXPECT_GT(samples, 100);
  }
}

}  // namespace
}  // namespace pkm
