// The grblhal target (docs/firmware-grblhal.md), proven against an independent reading of
// grblHAL's WallPlotter (firmware_reference/grblhal.*): the exported `$` settings, through the
// firmware's own inverse kinematics, give pkmkit's joints over the workspace; approximations land
// within their stated cost; import then export gives the same settings; bad files fail at their
// line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "firmware_reference/grblhal.hpp"
#include "pkm/firmware/grblhal.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

namespace reference = test::grblhal_reference;

const firmware::ExportContext kContext{"test", "machine.toml"};

firmware::FirmwareMachine wall_plotter(const machine::Machine& machine, bool approximate) {
  return firmware::firmware_machine(machine, firmware::grblhal_target().forms, "grblhal",
                                    approximate);
}

std::string turned_export(const firmware::FirmwareMachine& machine) {
  return firmware::grblhal_write(machine, kContext, firmware::GrblhalFrameTurn::allow).text;
}

// The documented mapping: G54 x y = the machine's -x -y (z as is); motor A = the right cord less
// its offset, motor B = the left cord less its offset, Z = the pass-through joint.
Eigen::Vector3d g54_of(const geometry::Pose& pose) {
  return {-pose.position_mm.x(), -pose.position_mm.y(), pose.position_mm.z()};
}

Eigen::Vector3d motors_of(const kinematics::JointVector& joints,
                          const kinematics::WallPlotterForm& form) {
  return {joints[1] - form.cable_offsets_mm[1], joints[0] - form.cable_offsets_mm[0],
          joints.size() > 2 ? joints[2] : 0.0};
}

kinematics::JointVector joints_of(const Eigen::Vector3d& motors,
                                  const kinematics::WallPlotterForm& form, int count) {
  kinematics::JointVector joints(count);
  joints[0] = motors.y() + form.cable_offsets_mm[0];
  joints[1] = motors.x() + form.cable_offsets_mm[1];
  if (count > 2) joints[2] = motors.z();
  return joints;
}

const kinematics::WallPlotterForm& form_of(const firmware::FirmwareMachine& machine) {
  return std::get<kinematics::WallPlotterForm>(machine.form.geometry);
}

struct RoundTrip {
  int samples = 0;
  double worst_joint_mm = 0.0;     // firmware motors vs pkmkit's joints (double precision)
  double worst_float_mm = 0.0;     // the same with the firmware's single precision
  double worst_position_mm = 0.0;  // the firmware's forward kinematics back to its position
};

RoundTrip round_trip(const firmware::FirmwareMachine& machine, const std::string& text) {
  const reference::WallPlotterFile file = reference::parse(text);
  const kinematics::WallPlotterForm& form = form_of(machine);
  RoundTrip result;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine.machine)) {
    kinematics::JointVector joints(machine.machine.kinematics().joint_count());
    if (!machine.machine.inverse(pose, joints).ok()) continue;
    const Eigen::Vector3d expected = motors_of(joints, form);
    const Eigen::Vector3d motors = reference::motors_mm(file, g54_of(pose));
    const Eigen::Vector3d motors_float = reference::motors_mm_float(file, g54_of(pose));
    const Eigen::Vector3d back = reference::machine_position_mm(file, motors) - file.g54;
    ++result.samples;
    result.worst_joint_mm =
        std::max(result.worst_joint_mm, (motors - expected).cwiseAbs().maxCoeff());
    result.worst_float_mm =
        std::max(result.worst_float_mm, (motors_float - expected).cwiseAbs().maxCoeff());
    result.worst_position_mm =
        std::max(result.worst_position_mm, (back - g54_of(pose)).cwiseAbs().maxCoeff());
  }
  return result;
}

class firmware_grblhal_exact : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_grblhal_exact, FirmwareJointsMatchPkmkitOverTheWorkspace) {
  const machine::Machine machine = test::load_example(GetParam());
  const firmware::FirmwareMachine exact = wall_plotter(machine, false);
  ASSERT_FALSE(exact.cost);
  const RoundTrip trip = round_trip(exact, turned_export(exact));
  std::printf(
      "[ grblhal ] %s: %d poses, worst motor error %.3g mm (float firmware %.3g mm), "
      "forward kinematics back %.3g mm\n",
      GetParam().c_str(), trip.samples, trip.worst_joint_mm, trip.worst_float_mm,
      trip.worst_position_mm);
  EXPECT_GT(trip.samples, 50);
  EXPECT_LT(trip.worst_joint_mm, 1e-6);
  // The pen on grblHAL's y >= 0 side; its radical-line forward kinematics loses digits near the
  // motor line (2e-5 mm on the Maslow in double).
  EXPECT_LT(trip.worst_position_mm, 1e-3);
  EXPECT_LT(trip.worst_float_mm, 1e-3);
}

// The settings only (from the first `$` line): the header names the source file.
std::string settings_part(const std::string& text) {
  return text.substr(text.find("\n$") + 1);
}

TEST_P(firmware_grblhal_exact, ImportThenExportGivesTheSameSettings) {
  const machine::Machine machine = test::load_example(GetParam());
  const std::string text = turned_export(wall_plotter(machine, false));
  const machine::ImportedMachine imported = firmware::grblhal_read(text, "exported.txt");
  const machine::Machine again = machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml");
  EXPECT_EQ(settings_part(turned_export(wall_plotter(again, false))), settings_part(text));
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_grblhal_exact,
                         ::testing::Values("wall-plotter.toml", "hektor.toml", "pen-plotter.toml",
                                           "maslow.toml", "linuxcnc-polargraph-2366.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

TEST(firmware_grblhal_export, TheTargetRefusesTheTurnedFrameNamingIt) {
  const machine::Machine machine = test::load_example("wall-plotter.toml");
  try {
    (void)firmware::grblhal_target().write(wall_plotter(machine, false), kContext);
    FAIL() << "expected a refusal";
  } catch (const firmware::ExportRefused& refused) {
    EXPECT_NE(std::string(refused.what()).find("turned 180 deg about z"), std::string::npos)
        << refused.what();
  }
}

TEST(firmware_grblhal_export, HandComputedPose) {
  // wall-plotter.toml: anchors (0, 0) and (1500, 0). The pen at machine (300, -400) is G54
  // (-300, 400); the G54 offset is the right anchor (1500, 0), so grblHAL's position is
  // (1200, 400): motor A = sqrt(1200^2 + 400^2) = sqrt(1600000) = 1264.911064 mm (the right
  // cord), motor B = sqrt((1500 - 1200)^2 + 400^2) = 500 mm (the left cord).
  const firmware::FirmwareMachine exact =
      wall_plotter(test::load_example("wall-plotter.toml"), false);
  const std::string text = turned_export(exact);
  EXPECT_NE(text.find("\n$130=1500.000 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\nG10 L2 P1 X1500.000 Y0.000 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$100=80.000 (X = motor A: the right cord 'right': steps/mm)"),
            std::string::npos)
      << text;
  const Eigen::Vector3d motors =
      reference::motors_mm(reference::parse(text), Eigen::Vector3d(-300.0, 400.0, 0.0));
  EXPECT_NEAR(motors.x(), 1264.911064, 1e-6);
  EXPECT_NEAR(motors.y(), 500.0, 1e-9);
  kinematics::JointVector joints(2);
  ASSERT_TRUE(exact.machine.inverse(geometry::Pose::from_mm_deg(300.0, -400.0, 0.0), joints).ok());
  EXPECT_NEAR(joints[0], 500.0, 1e-9);
  EXPECT_NEAR(joints[1], 1264.911064, 1e-6);
}

TEST(firmware_grblhal_export, OtherFormsAreRefusedNamingTheWallPlotter) {
  for (const char* name : {"linear-delta.toml", "linuxcnc-ldelta.toml", "hexapod-bit.toml",
                           "matrix-mill.toml", "triaglide.toml", "mach3-formula.toml"}) {
    try {
      (void)wall_plotter(test::load_example(name), true);
      ADD_FAILURE() << name << ": expected a refusal";
    } catch (const firmware::ExportRefused& refused) {
      EXPECT_NE(std::string(refused.what()).find("a two-cable wall plotter or a rotary delta"),
                std::string::npos)
          << name << ": " << refused.what();
    }
  }
}

firmware::FirmwareMachine approximated(const machine::Machine& machine) {
  return firmware::firmware_machine(machine, firmware::grblhal_target().forms, "grblhal", true);
}

class firmware_grblhal_approximated : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_grblhal_approximated, TheTrueMachineLandsWithinTheStatedCost) {
  const machine::Machine machine = test::load_example(GetParam());
  EXPECT_THROW((void)wall_plotter(machine, false), firmware::ExportRefused);
  const firmware::FirmwareMachine fitted = approximated(machine);
  ASSERT_TRUE(fitted.cost);
  const std::string text = turned_export(fitted);
  EXPECT_NE(text.find("APPROXIMATED"), std::string::npos);
  const reference::WallPlotterFile file = reference::parse(text);
  const kinematics::WallPlotterForm& form = form_of(fitted);
  double worst = 0.0;
  int samples = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    const kinematics::JointVector joints = joints_of(reference::motors_mm(file, g54_of(pose)), form,
                                                     machine.kinematics().joint_count());
    geometry::Pose reached = pose;
    if (!machine.kinematics().forward(joints, reached).ok()) continue;  // as the cost skips it
    worst = std::max(worst, (reached.position_mm - pose.position_mm).norm());
    ++samples;
  }
  const Eigen::Vector3d& at = fitted.cost->worst_at.position_mm;
  std::printf(
      "[ grblhal ] %s: anchors (%.4f, %.4f) (%.4f, %.4f), offsets %.4f %.4f mm; stated worst "
      "%.4f mm at (%.1f, %.1f), rms %.4f (before the fit %.4f mm); measured %.4f mm over %d "
      "poses\n",
      GetParam().c_str(), form.anchors_mm[0].x(), form.anchors_mm[0].y(), form.anchors_mm[1].x(),
      form.anchors_mm[1].y(), form.cable_offsets_mm[0], form.cable_offsets_mm[1],
      fitted.cost->worst_tool_error_mm, at.x(), at.y(), fitted.cost->rms_tool_error_mm,
      fitted.cost->worst_before_fit_mm, worst, samples);
  EXPECT_GT(samples, 50);
  EXPECT_GT(worst, 1e-3);  // the losses are real
  EXPECT_LE(worst, fitted.cost->worst_tool_error_mm + 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_grblhal_approximated,
                         ::testing::Values("makelangelo.toml", "maslow-frame.toml",
                                           "hektor-pulleys.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

std::string failure_of(const std::string& text) {
  try {
    (void)firmware::grblhal_read(text, "plotter.txt");
  } catch (const firmware::FirmwareFileError& error) {
    return error.what();
  }
  return "(no error)";
}

const char* kSettings =
    "$100=80 (steps)\n"
    "$101=80\n"
    "$110=9000\n"
    "$111=9000\n"
    "$120=1000\n"
    "$121=1000\n"
    "$130=1500\n"
    "$131=2100\n";

TEST(firmware_grblhal_import, ReadsARealShapedDumpNotingWhatItLeaves) {
  const std::string text = std::string("; a $$ dump\n$0=5.0\n$22=0\n$70=mynet\n$H\n") + kSettings +
                           "G10 L2 P1 X1500 Y0 ; G54\nG21\n";
  const machine::ImportedMachine imported = firmware::grblhal_read(text, "plotter.txt");
  ASSERT_EQ(imported.joints.size(), 2u);
  EXPECT_EQ(imported.joints[0].name, "left");
  EXPECT_DOUBLE_EQ(imported.joints[0].max_velocity, 150.0);
  EXPECT_DOUBLE_EQ(imported.joints[1].max, 2100.0);
  EXPECT_NE(imported.kinematics_section.find("anchor_distance = 1500.0"), std::string::npos)
      << imported.kinematics_section;
  std::string notes;
  for (const std::string& note : imported.notes) notes += note + "\n";
  EXPECT_NE(notes.find("$0, $22, $70"), std::string::npos) << notes;
  EXPECT_NE(notes.find("line 5: $H"), std::string::npos) << notes;
  EXPECT_NE(notes.find("line 15: G21"), std::string::npos) << notes;
  const machine::Machine machine =
      machine::parse_machine(machine::machine_file_text(imported, "out.toml"), "out.toml");
  EXPECT_EQ(machine.joints().size(), 2u);
  // The G54 offset X1500 is the right anchor: anchors (0, 0) and (1500, 0). The pen at (300,
  // -400) is G54 (-300, 400), grblHAL's (1200, 400): motor B (the left cord) sqrt(300^2 + 400^2)
  // = 500, motor A (the right) sqrt(1200^2 + 400^2) = 1264.911064 mm.
  kinematics::JointVector joints(2);
  ASSERT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(300.0, -400.0, 0.0), joints).ok());
  EXPECT_NEAR(joints[0], 500.0, 1e-9);
  EXPECT_NEAR(joints[1], 1264.911064, 1e-6);
}

TEST(firmware_grblhal_import, AMissingKinematicsSettingNamesItself) {
  std::string text = kSettings;
  text.replace(text.find("$130=1500\n"), 10, "");
  EXPECT_EQ(failure_of(text),
            "plotter.txt:7: $130: missing (X max travel: WallPlotter's motor A to motor B, mm)");
}

TEST(firmware_grblhal_import, ANonNumberFailsAtItsLine) {
  std::string text = kSettings;
  text.replace(text.find("$111=9000"), 9, "$111=fast");
  EXPECT_EQ(failure_of(text), "plotter.txt:4: $111: 'fast' is not a number");
  EXPECT_EQ(failure_of(std::string(kSettings) + "G10 L2 P1 X1,5 Y0\n"),
            "plotter.txt:9: G10 L2 P1 X: '1,5' is not a number");
}

// linuxcnc-rdelta.toml (inch): base_radius 10, arm 10, forearm 18, platform 5 in.
TEST(firmware_grblhal_delta, FirmwareAnglesMatchPkmkitOverTheWorkspace) {
  const firmware::FirmwareMachine exact =
      wall_plotter(test::load_example("linuxcnc-rdelta.toml"), false);
  const std::string text = firmware::grblhal_target().write(exact, kContext).text;
  const reference::WallPlotterFile file = reference::parse(text);
  double worst_rad = 0.0;
  int samples = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(exact.machine)) {
    kinematics::JointVector joints(3);
    ASSERT_TRUE(exact.machine.inverse(pose, joints).ok());
    Eigen::Vector3d angles;
    ASSERT_TRUE(reference::delta_angles_rad(file, pose.position_mm, angles));
    worst_rad = std::max(worst_rad, (angles - joints.head<3>()).cwiseAbs().maxCoeff());
    ++samples;
  }
  std::printf(
      "[ grblhal ] linuxcnc-rdelta.toml: %d poses, worst arm angle error %.3g rad (%.3g mm "
      "at the 254 mm bicep's elbow)\n",
      samples, worst_rad, worst_rad * 254.0);
  EXPECT_GT(samples, 50);
  EXPECT_LT(worst_rad * 254.0, 1e-6);
}

TEST(firmware_grblhal_delta, HandComputedHome) {
  // rdelta's home: every arm at 1 deg, the tool at z = -10 sin 1 deg - sqrt(18^2 - (10 - 5 +
  // 10 cos 1 deg)^2) = -10.126694 in = -257.218 mm on the axis. The triangle sides are 2 sqrt 3
  // times the radii: f = 3.4641016 x 254 = 879.88181 mm, e = 3.4641016 x 127 = 439.940905 mm.
  const firmware::FirmwareMachine exact =
      wall_plotter(test::load_example("linuxcnc-rdelta.toml"), false);
  const std::string text = firmware::grblhal_target().write(exact, kContext).text;
  EXPECT_NE(text.find("\n$641=457.200 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$642=254.000 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$643=879.88181 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$644=439.940905 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$646=-45.000 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$648=90.000 ("), std::string::npos) << text;
  EXPECT_NE(text.find("\n$110=104.719755 ("), std::string::npos) << text;  // 100 deg/s in rad/min
  Eigen::Vector3d angles;
  ASSERT_TRUE(reference::delta_angles_rad(
      reference::parse(text), Eigen::Vector3d(0.0, 0.0, -10.126694135940447 * 25.4), angles));
  // 1e-6 deg: the settings carry six decimals of a mm (879.88181 for 879.8818102).
  for (int arm = 0; arm < 3; ++arm) EXPECT_NEAR(angles[arm] * 180.0 / M_PI, 1.0, 1e-6);
}

TEST(firmware_grblhal_delta, ImportThenExportGivesTheSameSettings) {
  const firmware::FirmwareMachine exact =
      wall_plotter(test::load_example("linuxcnc-rdelta.toml"), false);
  const std::string text = firmware::grblhal_target().write(exact, kContext).text;
  const machine::ImportedMachine imported = firmware::grblhal_read(text, "delta.txt");
  const machine::Machine again = machine::parse_machine(
      machine::machine_file_text(imported, "imported.toml"), "imported.toml");
  EXPECT_EQ(
      settings_part(firmware::grblhal_target().write(wall_plotter(again, false), kContext).text),
      settings_part(text));
}

TEST(firmware_grblhal_delta, AMissingBicepNamesItself) {
  EXPECT_EQ(failure_of("$110=100\n$111=100\n$112=100\n$120=50\n$121=50\n$122=50\n$641=300\n"
                       "$643=75\n$644=24\n"),
            "plotter.txt:9: $642: missing (bicep length rf, mm)");
}

}  // namespace
}  // namespace pkm
