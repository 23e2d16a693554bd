// The klipper target (docs/firmware-klipper.md), proven against an independent reading of
// Klipper's delta (firmware_reference/klipper.hpp): the exported printer.cfg moves every carriage,
// from its endstop, as far as pkmkit's inverse kinematics moves the machine's joint from its
// endstop reading, over the machine's workspace; import then export gives the same settings.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "firmware_reference/klipper.hpp"
#include "pkm/firmware/klipper.hpp"
#include "pkm/firmware/klipper_import.hpp"
#include "pkm/firmware/one_circle_delta.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

namespace reference = test::klipper_reference;

const firmware::Target& klipper() {
  return firmware::target("klipper");
}

firmware::ExportedFile export_machine(const machine::Machine& machine) {
  const firmware::FirmwareMachine held =
      firmware::firmware_machine(machine, klipper().forms, "klipper", false);
  return klipper().write(held, firmware::ExportContext{"test", machine.source()});
}

// The worst difference (mm) over the workspace between Klipper's carriage travel from its
// endstop and pkmkit's joint travel from the joint's endstop reading (its home switch, else its
// max).
double worst_joint_error_mm(const machine::Machine& machine, const std::string& exported) {
  const reference::Delta delta = reference::delta(reference::parse(exported));
  const std::vector<geometry::Pose> samples = firmware::workspace_samples(machine);
  EXPECT_GT(samples.size(), 100U);
  double worst = 0.0;
  kinematics::JointVector joints(3);
  for (const geometry::Pose& pose : samples) {
    EXPECT_TRUE(machine.inverse(pose, joints).ok());
    const Eigen::Vector3d& p = pose.position_mm;
    const std::array<double, 3> klipper =
        reference::stepper_coordinates(delta, p.x(), p.y(), p.z());
    for (int i = 0; i < 3; ++i) {
      const double klipper_travel = klipper[i] - delta.abs_endstop[i];
      const machine::JointSpec& joint = machine.joints()[i];
      const double endstop = joint.home_switch ? joint.home_switch->position : joint.max;
      const double pkmkit_travel = joints[i] - endstop;
      worst = std::max(worst, std::abs(klipper_travel - pkmkit_travel));
    }
  }
  return worst;
}

std::string export_refusal(const machine::Machine& machine);

// The settings after the header (the header names the source, which an import changes).
std::string settings(const std::string& text) {
  return text.substr(text.find("[printer]"));
}

class firmware_klipper_examples : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_klipper_examples, CarriagesFollowPkmkitsJointsOverTheWorkspace) {
  const machine::Machine machine = test::load_example(GetParam());
  const firmware::ExportedFile file = export_machine(machine);
  const double worst = worst_joint_error_mm(machine, file.text);
  std::printf("klipper %s: worst carriage error %.3g mm over the workspace\n", GetParam().c_str(),
              worst);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst, 1e-6);  // the settings are exact: their rounding (1e-9) only
}

TEST_P(firmware_klipper_examples, ImportThenExportGivesTheSameSettings) {
  const machine::Machine machine = test::load_example(GetParam());
  const std::string first = export_machine(machine).text;
  const machine::ImportedMachine imported = firmware::read_klipper(first, "printer.cfg");
  const std::string machine_text = machine::machine_file_text(imported, "imported.toml");
  const machine::Machine back = machine::parse_machine(machine_text, "imported.toml");
  const std::string second = export_machine(back).text;
  EXPECT_EQ(settings(first), settings(second));
  // And the imported machine is the same machine: its joints from Klipper's settings.
  EXPECT_LT(worst_joint_error_mm(back, first), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_klipper_examples,
                         ::testing::Values("linear-delta.toml", "linuxcnc-ldelta.toml"),
                         [](const ::testing::TestParamInfo<std::string>& example) {
                           return test::test_name(example.param);
                         });

// By hand, linuxcnc-ldelta (R 130.25, L 269, every joint's max 375 mm, its endstop
// reading): sqrt(269^2 - 130.25^2) = 235.3634158062803, so position_endstop = 375 - 235.3634158 =
// 139.6365841937197 on every tower. Tool at (30, 0, 5): tower a at angle 90, (0, 130.25):
// d^2 = 30^2 + 130.25^2 = 17865.0625, carriage 5 + sqrt(72361 - 17865.0625) = 238.4436495174;
// tower b at 210, (-112.7998088, -65.125): d^2 = 142.7998088^2 + 65.125^2 = 24633.0510306,
// carriage 5 + sqrt(72361 - 24633.0510306) = 223.4672720785; tower c at 330 (112.7998088,
// -65.125): d^2 = 82.7998088^2 + 65.125^2 = 11097.0739694, carriage 5 + 247.5155066467 =
// 252.5155066467.
TEST(firmware_klipper, HandComputedPose) {
  const machine::Machine machine = test::load_example("linuxcnc-ldelta.toml");
  const std::string text = export_machine(machine).text;
  EXPECT_NE(text.find("[stepper_a]  # the machine's first joint\nangle: 90  #"), std::string::npos)
      << text;
  EXPECT_NE(text.find("[stepper_b]  # the machine's second joint\nangle: 210  #"),
            std::string::npos);
  EXPECT_NE(text.find("[stepper_c]  # the machine's third joint\nangle: 330  #"),
            std::string::npos);
  EXPECT_NE(text.find("delta_radius: 130.25  #"), std::string::npos);
  EXPECT_NE(text.find("arm_length: 269  #"), std::string::npos);
  EXPECT_NE(text.find("position_endstop: 139.63658419"), std::string::npos);
  EXPECT_NE(text.find("print_radius: 95  #"), std::string::npos);
  EXPECT_NE(text.find("minimum_z_position: -5  #"), std::string::npos);
  EXPECT_NE(text.find("max_velocity: 300  #"), std::string::npos);
  const reference::Delta delta = reference::delta(reference::parse(text));
  const std::array<double, 3> carriages = reference::stepper_coordinates(delta, 30.0, 0.0, 5.0);
  EXPECT_NEAR(carriages[0], 238.4436495174, 1e-9);
  EXPECT_NEAR(carriages[1], 223.4672720785, 1e-9);
  EXPECT_NEAR(carriages[2], 252.5155066467, 1e-9);
  kinematics::JointVector joints(3);
  ASSERT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(30.0, 0.0, 5.0), joints).ok());
  EXPECT_NEAR(joints[0], 238.4436495174, 1e-9);
  EXPECT_NEAR(joints[1], 223.4672720785, 1e-9);
  EXPECT_NEAR(joints[2], 252.5155066467, 1e-9);
}

// linear-delta: the effector's 40 mm joint offset folds into delta_radius 160; a carriage reading
// 700 at its endstop puts the tool at 700 - sqrt(64400) = 446.2284492...; steps carried.
TEST(firmware_klipper, EffectorOffsetAndStepsPerMm) {
  const machine::Machine machine = test::load_example_changed(
      "linear-delta.toml", "axis = \"X\"", "axis = \"X\"\nsteps_per_unit = 80.0");
  const firmware::ExportedFile file = export_machine(machine);
  EXPECT_NE(file.text.find("delta_radius: 160  #"), std::string::npos) << file.text;
  EXPECT_NE(file.text.find("position_endstop: 446.228449"), std::string::npos);
  const reference::Delta delta = reference::delta(reference::parse(file.text));
  EXPECT_NEAR(delta.abs_endstop[0], 700.0, 1e-9);
  EXPECT_DOUBLE_EQ(delta.steps_per_mm[0], 80.0);  // rotation_distance 40 at 16 x 200
  EXPECT_EQ(delta.steps_per_mm[1], 0.0);          // not given: left for the user, with a warning
  ASSERT_EQ(file.warnings.size(), 2U);
  EXPECT_NE(file.warnings[0].find("stepper_b"), std::string::npos);
}

// A carriage whose rod leaves it 12 mm above its reading's zero (attach z): Klipper's stepper
// coordinate is the reading less 12 mm, so that tower's position_endstop is 12 mm lower.
TEST(firmware_klipper, CarriageOffsetMovesItsEndstop) {
  const machine::Machine machine = test::load_example_changed(
      "linear-delta.toml", "attach = [0.0, 40.0, 0.0]", "attach = [0.0, 40.0, 12.0]");
  const firmware::ExportedFile file = export_machine(machine);
  EXPECT_NE(file.text.find("position_endstop: 434.228449"), std::string::npos) << file.text;
  EXPECT_LT(worst_joint_error_mm(machine, file.text), 1e-6);
}

// A home switch at reading 650 (towards max) is tower a's endstop: 650 - sqrt(64400) =
// 396.2284492; a switch met moving down is no Klipper delta's.
TEST(firmware_klipper, HomeSwitchIsTheEndstop) {
  const machine::Machine machine = test::load_example_changed(
      "linear-delta.toml", "name = \"tower_a\"", "name = \"tower_a\"\nhome_switch = 650.0");
  const firmware::ExportedFile file = export_machine(machine);
  EXPECT_NE(file.text.find("position_endstop: 396.228449"), std::string::npos) << file.text;
  EXPECT_LT(worst_joint_error_mm(machine, file.text), 1e-6);
  const std::string refusal = export_refusal(test::load_example_changed(
      "linear-delta.toml", "name = \"tower_a\"", "name = \"tower_a\"\nhome_switch = 10.0"));
  EXPECT_NE(refusal.find("joint 'tower_a' homes downwards"), std::string::npos) << refusal;
}

// The same delta in inch: Klipper's settings are mm (130.25 in = 3308.35 mm, 300 in/s = 7620
// mm/s).
TEST(firmware_klipper, InchMachineWritesMillimetres) {
  const machine::Machine machine =
      test::load_example_changed("linuxcnc-ldelta.toml", "units = \"mm\"", "units = \"inch\"");
  const firmware::ExportedFile file = export_machine(machine);
  EXPECT_NE(file.text.find("delta_radius: 3308.35  #"), std::string::npos) << file.text;
  EXPECT_NE(file.text.find("arm_length: 6832.6  #"), std::string::npos);
  EXPECT_NE(file.text.find("max_velocity: 7620  #"), std::string::npos);
  EXPECT_LT(worst_joint_error_mm(machine, file.text), 1e-6);
}

// A Klipper user's printer.cfg: pins, other sections, comments of both kinds, a continuation
// line and DELTA_CALIBRATE's SAVE_CONFIG block, which overrides the endstops and angles above.
constexpr const char* kUserConfig = R"([stepper_a]
step_pin: PF0   ; the X socket
dir_pin: PF1
microsteps: 16
rotation_distance: 40
endstop_pin: ^PE4
homing_speed: 50
position_endstop: 297.05
arm_length: 333.0

[stepper_b]
step_pin: PF6
microsteps: 16
rotation_distance: 40

[stepper_c]
step_pin = PL3
microsteps: 32
rotation_distance: 40

[extruder]
microsteps: 16
gcode:
  G28
  G1 Z10

[mcu]
serial: /dev/ttyACM0

[printer]
kinematics: delta
max_velocity: 300
max_accel: 3000
max_z_velocity: 150
delta_radius: 174.75  # smooth rod offset less the effector's and carriage's

[delta_calibrate]
radius: 50

#*# <---------------------- SAVE_CONFIG ---------------------->
#*# DO NOT EDIT THIS BLOCK OR BELOW. The contents are auto-generated.
#*#
#*# [printer]
#*# delta_radius = 175.004
#*#
#*# [stepper_a]
#*# angle = 210.5
#*# position_endstop = 296.0
#*#
#*# [stepper_b]
#*# angle = 329.0
#*# position_endstop = 297.5
)";

// A printer.cfg of Klipper before 2019-2021: one [printer] delta_arm_length, and step_distance
// (mm per step) where Klipper now has rotation_distance and microsteps.
TEST(firmware_klipper, ImportsAnOlderKlippersKeys) {
  const machine::ImportedMachine imported = firmware::read_klipper(
      "[stepper_a]\nstep_distance: .01\nposition_endstop: 297.05\n"
      "[stepper_b]\nstep_distance: .01\n[stepper_c]\nstep_distance: .0125\n"
      "[printer]\nkinematics: delta\nmax_velocity: 300\nmax_accel: 3000\n"
      "delta_arm_length: 333.0\ndelta_radius: 174.75\n",
      "printer.cfg");
  ASSERT_EQ(imported.joints.size(), 3U);
  EXPECT_DOUBLE_EQ(*imported.joints[0].steps_per_unit, 100.0);
  EXPECT_DOUBLE_EQ(*imported.joints[2].steps_per_unit, 80.0);
  const machine::Machine machine = machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml");
  // Tower c at 90 deg on the y axis (x exactly 0, not cos 90 deg's rounding), rods of 333 mm.
  EXPECT_NE(machine::kinematics_toml(machine.kinematics(), machine::LengthUnit::mm)
                .find("origin = [0.0, 174.75, 0.0]\ndirection = [0.0, 0.0, 1.0]\nstrut = 333.0"),
            std::string::npos);
}

TEST(firmware_klipper, ImportsAUsersPrinterCfg) {
  const machine::ImportedMachine imported = firmware::read_klipper(kUserConfig, "printer.cfg");
  ASSERT_EQ(imported.joints.size(), 3U);
  EXPECT_EQ(imported.joints[0].name, "stepper_a");
  EXPECT_DOUBLE_EQ(*imported.joints[0].steps_per_unit, 80.0);
  EXPECT_DOUBLE_EQ(*imported.joints[2].steps_per_unit, 160.0);
  EXPECT_DOUBLE_EQ(imported.joints[0].max_velocity, 150.0);
  EXPECT_DOUBLE_EQ(imported.max_feed_per_min, 18000.0);
  const std::string notes = [&] {
    std::string all;
    for (const std::string& note : imported.notes) all += note + "\n";
    return all;
  }();
  EXPECT_NE(notes.find("[extruder] not read"), std::string::npos) << notes;
  EXPECT_NE(notes.find("[mcu] not read"), std::string::npos);
  EXPECT_NE(notes.find("[stepper_a] not read: dir_pin, endstop_pin, homing_speed, step_pin"),
            std::string::npos);
  // The machine moves its carriages as Klipper would with the saved calibration.
  const machine::Machine machine = machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml");
  const reference::Delta delta = reference::delta(reference::parse(
      std::string("[printer]\nkinematics: delta\ndelta_radius: 175.004\n"
                  "[stepper_a]\nangle: 210.5\nposition_endstop: 296\narm_length: 333\n"
                  "[stepper_b]\nangle: 329\nposition_endstop: 297.5\n")));
  kinematics::JointVector joints(3);
  double worst = 0.0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    const Eigen::Vector3d& p = pose.position_mm;
    const std::array<double, 3> carriages =
        reference::stepper_coordinates(delta, p.x(), p.y(), p.z());
    for (int i = 0; i < 3; ++i) {
      worst = std::max(worst, std::abs((carriages[i] - delta.abs_endstop[i]) -
                                       (joints[i] - machine.joints()[i].max)));
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(machine.home().position_mm.z(), 296.0, 1.0);  // every carriage at its endstop
  // Its export carries the calibration, and imports and exports to the same settings.
  const std::string first = export_machine(machine).text;
  EXPECT_NE(first.find("angle: 210.5  #"), std::string::npos) << first;
  EXPECT_NE(first.find("delta_radius: 175.004  #"), std::string::npos);
  EXPECT_NE(first.find("position_endstop: 297.5  #"), std::string::npos);
  const machine::Machine back = machine::parse_machine(
      machine::machine_file_text(firmware::read_klipper(first, "exported.cfg"), "back.toml"),
      "back.toml");
  EXPECT_EQ(settings(first), settings(export_machine(back).text));
}

// Found by fuzz/firmware_config.cpp: an export read back refused ("cartesian.home: is not a
// usable pose: ... joint 'stepper_a' = 700.000 mm passes its max 700.000 mm"). Klipper's home is
// every carriage at its endstop, each joint's max; forward kinematics to that pose and inverse
// back put a joint 1e-13 mm above its max (or 1e-9 mm, x and y that close to 0 written as 0). It
// was not the export: a calibrated delta, its endstops apart (SAVE_CONFIG's), was refused one time
// in three (the first two here, of 40 random ones; the third is the fuzzer's, endstops 1e-9 apart).
TEST(firmware_klipper, FuzzFoundAHomeAtEveryEndstopLoads) {
  struct Case {
    double radius, endstop_a, endstop_b, endstop_c;
  };
  for (const Case& c :
       {Case{179.9, 296.168, 299.543, 295.063}, Case{130.2, 299.818, 292.593, 296.447},
        Case{160.0, 446.22844919, 446.228449191, 446.228449191}}) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "[printer]\nkinematics: delta\nmax_velocity: 300\nmax_accel: 3000\n"
                  "delta_radius: %.4f\n[stepper_a]\narm_length: 300\nposition_endstop: %.9f\n"
                  "[stepper_b]\nposition_endstop: %.9f\n[stepper_c]\nposition_endstop: %.9f\n",
                  c.radius, c.endstop_a, c.endstop_b, c.endstop_c);
    const machine::ImportedMachine imported = firmware::read_klipper(text, "printer.cfg");
    const machine::Machine machine = machine::parse_machine(
        machine::machine_file_text(imported, "imported.toml"), "imported.toml");
    // Each joint's max is its endstop's reading, and home puts every carriage there (lowered by
    // 1e-9 mm steps of z where rounding put one past it: its reading moves by up to 1.4 times).
    const double rise = std::sqrt(300.0 * 300.0 - c.radius * c.radius);
    kinematics::JointVector joints(3);
    ASSERT_TRUE(machine.inverse(machine.home(), joints).ok());
    const std::array<double, 3> endstops = {c.endstop_a, c.endstop_b, c.endstop_c};
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(machine.joints()[i].max, endstops[i] + rise, 1e-9) << text;
      EXPECT_NEAR(joints[i], endstops[i] + rise, 1e-8) << text;
    }
  }
}

// Why rotary deltas are refused, and only why: Klipper's rotary_delta turns every arm exactly as
// pkmkit's rotary delta does (shoulder_radius = base_radius - platform_radius, arms at 270, 30
// and 150 deg for joints 0, 1, 2, Klipper's angle = -pkmkit's joint) once its frame is pkmkit's
// moved up by shoulder_height, which Klipper requires above 0: the frames cannot coincide.
TEST(firmware_klipper, RotaryDeltaMatchesOnlyInAShiftedFrame) {
  const machine::Machine machine = test::load_example("linuxcnc-rdelta.toml");
  const std::optional<kinematics::FirmwareForm> held = machine.kinematics().firmware_form();
  ASSERT_TRUE(held.has_value());
  const kinematics::RotaryDeltaForm form = std::get<kinematics::RotaryDeltaForm>(held->geometry);
  const double shoulder_radius = form.base_radius_mm - form.platform_radius_mm;  // 127 mm
  const double shoulder_height = 600.0;  // any height above 0: Klipper's bed below the shoulders
  const std::array<double, 3> arm_angles_deg = {270.0, 30.0, 150.0};
  kinematics::JointVector joints(3);
  double worst_rad = 0.0, worst_unshifted_rad = 0.0;
  int unreachable_unshifted = 0;  // poses Klipper's arms cannot reach in pkmkit's own frame
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    ASSERT_TRUE(machine.inverse(pose, joints).ok());
    const Eigen::Vector3d& p = pose.position_mm;
    for (int i = 0; i < 3; ++i) {
      const auto klipper = [&](double z) {
        return reference::rotary_arm_angle(shoulder_radius, shoulder_height, arm_angles_deg[i],
                                           form.arm_length_mm, form.forearm_length_mm, p.x(), p.y(),
                                           z);
      };
      worst_rad = std::max(worst_rad, std::abs(klipper(p.z() + shoulder_height) + joints[i]));
      const double unshifted = klipper(p.z()) + joints[i];
      if (std::isnan(unshifted)) {
        ++unreachable_unshifted;
      } else {
        worst_unshifted_rad = std::max(worst_unshifted_rad, std::abs(unshifted));
      }
    }
  }
  std::printf(
      "klipper linuxcnc-rdelta: worst arm error %.3g rad with the frame shifted; without, %.3g "
      "rad and %d arm positions out of reach\n",
      worst_rad, worst_unshifted_rad, unreachable_unshifted);
  EXPECT_LT(worst_rad, 1e-9);
  // In pkmkit's own frame Klipper's arms go elsewhere, or cannot reach.
  EXPECT_TRUE(worst_unshifted_rad > 0.1 || unreachable_unshifted > 0);
}

std::string import_error(const std::string& text) {
  try {
    (void)firmware::read_klipper(text, "printer.cfg");
  } catch (const firmware::FirmwareFileError& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(firmware_klipper, BadInputNamesItsLine) {
  const std::string base =
      "[printer]\nkinematics: delta\nmax_velocity: 300\nmax_accel: 3000\n"
      "delta_radius: 174.75\n\n[stepper_a]\nposition_endstop: 297\n";
  EXPECT_EQ(import_error(base), "printer.cfg:7: [stepper_a] arm_length: must be given");
  EXPECT_EQ(import_error(base + "arm_length: 333 mm\n"),
            "printer.cfg:9: [stepper_a] arm_length: '333 mm' is not a number");
  EXPECT_EQ(import_error(base + "arm_length: 150\n"),
            "printer.cfg:9: [stepper_a] arm_length: 150 mm must be above delta_radius 174.75 mm");
  EXPECT_EQ(import_error("[printer]\nkinematics: delta\nmax_accel: 3000\n"),
            "printer.cfg:1: [printer] max_velocity: must be given");
  EXPECT_EQ(import_error("[printer]\nkinematics delta\n"),
            "printer.cfg:2: 'kinematics delta' is neither a [section], a 'key: value' option nor "
            "an indented continuation");
  EXPECT_NE(
      import_error("[printer]\nkinematics: rotary_delta\n")
          .find("printer.cfg:2: [printer] kinematics: rotary_delta measures z up from the bed"),
      std::string::npos);
  EXPECT_EQ(import_error("[printer]\nkinematics: deltesian\n"),
            "printer.cfg:2: [printer] kinematics: deltesian: pkmkit has no model of that form");
  EXPECT_EQ(import_error("[mcu]\nserial: /dev/ttyACM0\n"),
            "printer.cfg:1: no [printer] section: not a Klipper printer.cfg");
  EXPECT_EQ(import_error("[include delta.cfg]\n[mcu]\nserial: /dev/ttyACM0\n"),
            "printer.cfg:1: no [printer] section: not a Klipper printer.cfg (it includes "
            "delta.cfg: import the file that holds [printer])");
}

std::string export_refusal(const machine::Machine& machine) {
  try {
    (void)export_machine(machine);
  } catch (const firmware::ExportRefused& refused) {
    return refused.what();
  }
  return "(exported)";
}

TEST(firmware_klipper, RefusesWhatItCannotHold) {
  const std::string hexapod = export_refusal(test::load_example("hexapod-bit.toml"));
  EXPECT_NE(
      hexapod.find("klipper has kinematics for a linear delta, a rotary delta or a cable robot"),
      std::string::npos)
      << hexapod;
  const std::string rotary = export_refusal(test::load_example("linuxcnc-rdelta.toml"));
  EXPECT_NE(rotary.find("shifted up by the shoulder height"), std::string::npos) << rotary;
  // One tower 1 mm further out: no single delta_radius.
  const std::string radii = export_refusal(test::load_example_changed(
      "linuxcnc-ldelta.toml", "origin = [0.0, 130.25, 0.0]", "origin = [0.0, 131.25, 0.0]"));
  EXPECT_NE(radii.find("131.250000, 130.250000 and 130.250000 mm"), std::string::npos) << radii;
  EXPECT_NE(radii.find("would cost a tool error of up to"), std::string::npos) << radii;
}

// The nearest delta Klipper holds to linuxcnc-ldelta with tower a 1 mm further out: its
// printer.cfg, driven by Klipper's own equations (the reference), moves the machine as built (its
// forward kinematics) within the stated cost of every workspace pose.
TEST(firmware_klipper, NearestDeltaKeepsItsStatedCost) {
  const machine::Machine machine = test::load_example_changed(
      "linuxcnc-ldelta.toml", "origin = [0.0, 130.25, 0.0]", "origin = [0.0, 131.25, 0.0]");
  const firmware::FirmwareMachine exact =
      firmware::firmware_machine(machine, klipper().forms, "klipper", false);
  const firmware::FirmwareMachine nearest =
      firmware::nearest_delta_on_one_circle(exact, "klipper's delta_radius");
  ASSERT_TRUE(nearest.cost.has_value());
  const firmware::ApproximationCost& cost = *nearest.cost;
  std::printf(
      "klipper nearest delta to a tower 1 mm out: worst %.4f mm (before the fit %.4f), "
      "rms %.4f over %d poses\n",
      cost.worst_tool_error_mm, cost.worst_before_fit_mm, cost.rms_tool_error_mm, cost.samples);
  EXPECT_GT(cost.samples, 100);
  EXPECT_LT(cost.worst_tool_error_mm, cost.worst_before_fit_mm);
  const std::string text = klipper().write(nearest, firmware::ExportContext{"test", "m"}).text;
  EXPECT_NE(text.find("APPROXIMATED"), std::string::npos);
  const reference::Delta delta = reference::delta(reference::parse(text));
  kinematics::JointVector joints(3);
  double worst = 0.0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    const Eigen::Vector3d& p = pose.position_mm;
    const std::array<double, 3> carriages =
        reference::stepper_coordinates(delta, p.x(), p.y(), p.z());
    for (int i = 0; i < 3; ++i) {
      joints[i] = carriages[i] - delta.abs_endstop[i] + machine.joints()[i].max;
    }
    geometry::Pose reached = pose;
    ASSERT_TRUE(machine.kinematics().forward(joints, reached).ok());
    worst = std::max(worst, (reached.position_mm - p).norm());
  }
  EXPECT_LE(worst, cost.worst_tool_error_mm + 1e-6);
  EXPECT_GT(worst, 0.01);  // a real error: the tower is 1 mm out
}

}  // namespace
}  // namespace pkm
