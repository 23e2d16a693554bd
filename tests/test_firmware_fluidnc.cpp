// The fluidnc target (docs/firmware-fluidnc.md) proven against FluidNC's own WallPlotter
// kinematics, rewritten from its source in tests/firmware_reference/fluidnc.*: the motor
// positions the exported config.yaml makes FluidNC command are pkmkit's joints over each example
// machine's workspace; import then export gives the same text; approximations cost what they say.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "firmware_reference/fluidnc.hpp"
#include "firmware_reference/maslow.hpp"
#include "pkm/firmware/fluidnc.hpp"
#include "pkm/firmware/target.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

namespace ref = test::fluidnc_reference;

const firmware::ExportContext kContext{"test", "machine.toml"};

firmware::FirmwareMachine fluidnc_machine(const machine::Machine& machine, bool approximate) {
  const firmware::Target& target = firmware::target("fluidnc");
  return firmware::firmware_machine(machine, target.forms, target.name, approximate);
}

std::string export_text(const firmware::FirmwareMachine& machine) {
  return firmware::target("fluidnc").write(machine, kContext).text;
}

kinematics::JointVector joints_at(const machine::Machine& machine, const geometry::Pose& pose) {
  kinematics::JointVector joints(machine.kinematics().joint_count());
  EXPECT_TRUE(machine.inverse(pose, joints).ok());
  return joints;
}

// The largest difference (mm) between FluidNC's motor positions for the exported text and
// pkmkit's joints, as the doc maps them: each reading less its reading at home, the left cord's
// negated (FluidNC's left motor runs backward).
double worst_motor_error_mm(const machine::Machine& machine, const std::string& text,
                            int* compared) {
  const ref::WallPlotter plotter = ref::wall_plotter(ref::read_config(text));
  const kinematics::JointVector at_home = joints_at(machine, machine.home());
  double worst = 0.0;
  *compared = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    const kinematics::JointVector joints = joints_at(machine, pose);
    const std::array<double, 3> motors = ref::motors(plotter, pose.position_mm);
    worst = std::max(worst, std::abs(motors[0] - (at_home[0] - joints[0])));
    worst = std::max(worst, std::abs(motors[1] - (joints[1] - at_home[1])));
    if (plotter.has_z) worst = std::max(worst, std::abs(motors[2] - (joints[2] - at_home[2])));
    ++*compared;
  }
  return worst;
}

class firmware_fluidnc_exact : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_fluidnc_exact, FirmwareMotorsAreThePkmkitJointsOverTheWorkspace) {
  const machine::Machine machine = test::load_example(GetParam());
  const std::string text = export_text(fluidnc_machine(machine, false));
  int compared = 0;
  const double worst = worst_motor_error_mm(machine, text, &compared);
  EXPECT_GT(compared, 100);
  EXPECT_LT(worst, 1e-3) << text;
  RecordProperty("worst_motor_error_mm", std::to_string(worst));
  // FluidNC itself computes in 32-bit floats: what that costs here, for the doc.
  const ref::WallPlotter plotter = ref::wall_plotter(ref::read_config(text));
  double float_worst = 0.0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    const std::array<double, 3> exact = ref::motors(plotter, pose.position_mm);
    const std::array<double, 3> single = ref::motors_float(plotter, pose.position_mm);
    for (int k = 0; k < 3; ++k) float_worst = std::max(float_worst, std::abs(exact[k] - single[k]));
  }
  std::printf("  FluidNC's float arithmetic: worst %.2g mm\n", float_worst);
  EXPECT_LT(float_worst, 1e-3);
  std::printf("%s: %d poses, worst motor error %.3g mm\n", GetParam().c_str(), compared, worst);
}

TEST_P(firmware_fluidnc_exact, ImportThenExportGivesTheSameText) {
  const machine::Machine machine = test::load_example(GetParam());
  const std::string text = export_text(fluidnc_machine(machine, false));
  const machine::ImportedMachine imported = firmware::read_fluidnc(text, "config.yaml");
  const std::string machine_text = machine::machine_file_text(imported, "imported.toml");
  const machine::Machine back = machine::parse_machine(machine_text, "imported.toml");
  // The header names the source; the settings below it must be the same.
  auto settings = [](const std::string& all) { return all.substr(all.find("kinematics:")); };
  EXPECT_EQ(settings(export_text(fluidnc_machine(back, false))), settings(text)) << machine_text;
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_fluidnc_exact,
                         ::testing::Values("wall-plotter.toml", "hektor.toml", "pen-plotter.toml",
                                           "maslow.toml", "linuxcnc-polargraph-2366.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

// wall-plotter.toml: anchors (0, 0) and (1500, 0), home (750, -700). FluidNC's frame is the
// machine's less home: anchors (-750, 700) and (750, 700); at FluidNC's (0, 0) each cord is
// hypot(750, 700) = 1025.914226 mm. The pen at machine (300, -1000) is FluidNC's (-450, -300):
// left cord hypot(300, 1000) = 1044.030651, motor -(1044.030651 - 1025.914226) = -18.116424 mm;
// right cord hypot(1200, 1000) = 1562.049935, motor 1562.049935 - 1025.914226 = 536.135709 mm.
TEST(firmware_fluidnc_wall_plotter, HandComputedPose) {
  const machine::Machine machine = test::load_example("wall-plotter.toml");
  const std::string text = export_text(fluidnc_machine(machine, false));
  EXPECT_NE(text.find("    left_anchor_x: -750.000000\n    left_anchor_y: 700.000000\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("    right_anchor_x: 750.000000\n    right_anchor_y: 700.000000\n"),
            std::string::npos);
  EXPECT_NE(text.find("startup_line0: G10 L2 P1 X-750.000000 Y700.000000\n"), std::string::npos);
  EXPECT_NE(text.find("    steps_per_mm: 80.000000\n    max_rate_mm_per_min: 9000.000\n"
                      "    acceleration_mm_per_sec2: 1000.000\n"),
            std::string::npos);
  const std::array<double, 3> motors =
      ref::motors(ref::wall_plotter(ref::read_config(text)), Eigen::Vector3d(300.0, -1000.0, 0.0));
  EXPECT_NEAR(motors[0], -18.116424, 1e-6);
  EXPECT_NEAR(motors[1], 536.135709, 1e-6);
  const kinematics::JointVector joints =
      joints_at(machine, geometry::Pose::from_mm_deg(300.0, -1000.0, 0.0));
  EXPECT_NEAR(joints[0], 1044.030651, 1e-6);
  EXPECT_NEAR(joints[1], 1562.049935, 1e-6);
}

TEST(firmware_fluidnc_wall_plotter, MaslowZIsTheThirdAxis) {
  const machine::Machine machine = test::load_example("maslow.toml");
  const std::string text = export_text(fluidnc_machine(machine, false));
  const auto config = ref::read_config(text);
  ASSERT_EQ(config.count("axes.z.max_rate_mm_per_min"), 1u) << text;
  EXPECT_EQ(config.at("axes.z.max_rate_mm_per_min"), "300.000");
  EXPECT_EQ(config.at("macros.startup_line0"), "G10 L2 P1 X-1489.200000 Y1072.600000 Z-5.000000");
}

// A calibrated plotter's anchors are rarely level: FluidNC's forward kinematics, which take them
// level, would report (and resume from) another place than its inverse kinematics went to.
TEST(firmware_fluidnc_wall_plotter, UnlevelAnchorsRefusedWithTheError) {
  const machine::Machine machine = test::load_example_changed(
      "wall-plotter.toml", "anchor_distance = 1500.0", "anchors = [[0.0, 0.0], [1500.0, 5.0]]");
  try {
    (void)export_text(fluidnc_machine(machine, false));
    FAIL() << "not refused";
  } catch (const firmware::ExportRefused& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("would be off by up to "), std::string::npos) << what;
    std::printf("%s\n", what.c_str());
    EXPECT_NE(what.find("(anchors' y 0.0000 and 5.0000 mm)"), std::string::npos) << what;
  }
}

TEST(firmware_fluidnc_wall_plotter, SettingOutsideFluidncsRangeRefused) {
  const machine::Machine machine = test::load_example_changed(
      "wall-plotter.toml", "steps_per_unit = 80.0", "steps_per_unit = 200000.0");
  try {
    (void)export_text(fluidnc_machine(machine, false));
    FAIL() << "not refused";
  } catch (const firmware::ExportRefused& error) {
    EXPECT_NE(std::string(error.what())
                  .find("fluidnc: axis x steps_per_mm 200000.000 (mm) is outside FluidNC's "
                        "0.001..100000"),
              std::string::npos)
        << error.what();
  }
}

class firmware_fluidnc_refused : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_fluidnc_refused, NamesTheFormsItHas) {
  const machine::Machine machine = test::load_example(GetParam());
  try {
    (void)fluidnc_machine(machine, true);
    FAIL() << "not refused";
  } catch (const firmware::ExportRefused& error) {
    EXPECT_NE(std::string(error.what())
                  .find("a two-cable wall plotter, a rotary delta or a cable robot on swivel arms "
                        "(Maslow 4)"),
              std::string::npos)
        << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_fluidnc_refused,
                         ::testing::Values("linear-delta.toml", "hexapod-bit.toml",
                                           "matrix-mill.toml", "triaglide.toml",
                                           "mach3-formula.toml", "hangprinter-v4.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

TEST(firmware_fluidnc_rotary_delta, RefusedWithFluidncsRanges) {
  const machine::Machine machine = test::load_example("linuxcnc-rdelta.toml");
  try {
    (void)export_text(fluidnc_machine(machine, false));
    FAIL() << "not refused";
  } catch (const firmware::ExportRefused& error) {
    // base_radius 10 in = 254 mm: a base triangle of side 2 sqrt(3) 254 = 879.882 mm.
    EXPECT_NE(std::string(error.what()).find("base_triangle_mm 879.882 (FluidNC takes 20..500 mm)"),
              std::string::npos)
        << error.what();
  }
}

// A rotary delta inside FluidNC's ranges: pivots 60 mm from the centre, arms 80 mm, forearms
// 200 mm, effector joints 25 mm from the tool. With the arms horizontal the tool is at
// z = -sqrt(200^2 - (60 + 80 - 25)^2) = -sqrt(26775) = -163.630682 mm.
machine::Machine small_rotary_delta() {
  std::string text =
      "name = \"small rotary delta\"\nunits = \"mm\"\n[kinematics]\ntype = \"rotary_delta\"\n"
      "base_radius = 60.0\narm_length = 80.0\nforearm_length = 200.0\nplatform_radius = 25.0\n";
  for (int arm = 0; arm < 3; ++arm) {
    text += "[[joints]]\nname = \"arm" + std::to_string(arm) +
            "\"\nmin = -40.0\nmax = 80.0\nmax_velocity = 100.0\nmax_acceleration = 500.0\n"
            "steps_per_unit = 50.0\naxis = \"" +
            std::string(1, "XYZ"[arm]) + "\"\n";
  }
  text +=
      "[cartesian]\nmax_feed = 3000.0\nmax_acceleration = 1000.0\n"
      "home = [0.0, 0.0, -163.630682]\n";
  return machine::parse_machine(text, "small-rotary-delta.toml");
}

TEST(firmware_fluidnc_rotary_delta, FirmwareArmsAreThePkmkitJointsOverTheWorkspace) {
  const machine::Machine machine = small_rotary_delta();
  const std::string text = export_text(fluidnc_machine(machine, false));
  EXPECT_NE(text.find("    base_triangle_mm: 207.846097\n"), std::string::npos) << text;
  EXPECT_NE(text.find("    end_effector_triangle_mm: 86.602540\n"), std::string::npos);
  EXPECT_NE(text.find("    up_degrees: -40.000\n"), std::string::npos);
  if (std::getenv("PKM_SHOW_FLUIDNC")) std::printf("%s", text.c_str());
  const ref::ParallelDelta delta = ref::parallel_delta(ref::read_config(text));
  // Hand case: the arms horizontal put the tool at (0, 0, -163.630682): every arm at 0 deg.
  std::array<double, 3> degrees{};
  ASSERT_TRUE(ref::arm_degrees(delta, Eigen::Vector3d(0.0, 0.0, -163.630682), degrees));
  for (const double arm : degrees) EXPECT_NEAR(arm, 0.0, 1e-5);
  // 1 um at the end of an 80 mm arm.
  const double tolerance_deg = geometry::radians_to_degrees(1e-3 / 80.0);
  double worst = 0.0;
  int compared = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
    const kinematics::JointVector joints = joints_at(machine, pose);
    ASSERT_TRUE(ref::arm_degrees(delta, pose.position_mm, degrees)) << pose.position_mm.transpose();
    for (int arm = 0; arm < 3; ++arm) {
      worst = std::max(worst, std::abs(degrees[arm] - geometry::radians_to_degrees(joints[arm])));
    }
    ++compared;
  }
  std::printf("small rotary delta: %d poses, worst arm error %.3g deg\n", compared, worst);
  EXPECT_GT(compared, 100);
  EXPECT_LT(worst, tolerance_deg);
}

TEST(firmware_fluidnc_rotary_delta, ImportThenExportGivesTheSameText) {
  const std::string text = export_text(fluidnc_machine(small_rotary_delta(), false));
  const machine::ImportedMachine imported = firmware::read_fluidnc(text, "config.yaml");
  const machine::Machine back =
      machine::parse_machine(machine::machine_file_text(imported, "back.toml"), "back.toml");
  auto settings = [](const std::string& all) { return all.substr(all.find("kinematics:")); };
  EXPECT_EQ(settings(export_text(fluidnc_machine(back, false))), settings(text));
}

// The approximation's cost, followed as FluidNC does: the reference's motor positions for each
// sample, added to the true machine's joints at home (the pen parked there at power-on), through
// the true machine's forward kinematics.
std::optional<double> fluidnc_tool_error_mm(const machine::Machine& truth, const std::string& text,
                                            const geometry::Pose& pose) {
  const ref::WallPlotter plotter = ref::wall_plotter(ref::read_config(text));
  const kinematics::JointVector at_home = joints_at(truth, truth.home());
  const std::array<double, 3> motors = ref::motors(plotter, pose.position_mm);
  kinematics::JointVector joints = at_home;
  joints[0] = at_home[0] - motors[0];
  joints[1] = at_home[1] + motors[1];
  if (plotter.has_z) joints[2] = at_home[2] + motors[2];
  geometry::Pose reached = pose;
  if (!truth.kinematics().forward(joints, reached).ok()) return std::nullopt;
  return (reached.position_mm - pose.position_mm).norm();
}

// FluidNC's nearest wall plotter: the core's (anchors fitted, each cord zeroed at home as
// FluidNC's motors count from home), with the workspace poses where the true machine cannot take
// the form's cords.
struct Nearest {
  firmware::FirmwareMachine machine;
  int lost = 0;
};

Nearest nearest_wall_plotter(const machine::Machine& truth) {
  firmware::FirmwareMachine held =
      firmware::firmware_machine(truth, firmware::fluidnc_target().forms, "fluidnc", true);
  const int lost = held.cost->unreached;
  return Nearest{std::move(held), lost};
}

class firmware_fluidnc_approximated : public ::testing::TestWithParam<std::string> {};

TEST_P(firmware_fluidnc_approximated, LandsWithinTheStatedCost) {
  const machine::Machine truth = test::load_example(GetParam());
  EXPECT_THROW((void)fluidnc_machine(truth, false), firmware::ExportRefused);
  const Nearest nearest = nearest_wall_plotter(truth);
  ASSERT_TRUE(nearest.machine.cost.has_value());
  const firmware::ApproximationCost& cost = *nearest.machine.cost;
  std::printf(
      "%s: worst %.4f mm at x %.1f y %.1f, rms %.4f mm over %d poses (before fit %.4f), "
      "%d poses lost\n",
      GetParam().c_str(), cost.worst_tool_error_mm, cost.worst_at.position_mm.x(),
      cost.worst_at.position_mm.y(), cost.rms_tool_error_mm, cost.samples, cost.worst_before_fit_mm,
      nearest.lost);
  EXPECT_GT(cost.worst_tool_error_mm, 0.0);
  EXPECT_LE(cost.worst_tool_error_mm, cost.worst_before_fit_mm);
  const std::string text = export_text(nearest.machine);
  EXPECT_NE(text.find("APPROXIMATED"), std::string::npos);
  double worst = 0.0;
  int lost = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(truth)) {
    const std::optional<double> error = fluidnc_tool_error_mm(truth, text, pose);
    if (error) {
      worst = std::max(worst, *error);
    } else {
      ++lost;  // no pose of the true machine: the header counts these
    }
  }
  EXPECT_EQ(lost, nearest.lost);
  std::printf("  FluidNC's motors on the true machine: worst %.6f mm\n", worst);
  // The text's anchors are rounded to 1e-6 mm (FluidNC reads them as 32-bit floats anyway).
  EXPECT_LE(worst, cost.worst_tool_error_mm + 1e-4) << text;
}

INSTANTIATE_TEST_SUITE_P(Examples, firmware_fluidnc_approximated,
                         ::testing::Values("makelangelo.toml", "maslow-frame.toml",
                                           "hektor-pulleys.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

TEST(firmware_fluidnc_import, MissingAnchorNamesItsLine) {
  const std::string text =
      "name: \"plotter\"\nboard: MKS\nkinematics:\n  WallPlotter:\n    left_anchor_x: -100\n"
      "    right_anchor_x: 100\n    right_anchor_y: 100\naxes:\n  x:\n    steps_per_mm: 80\n"
      "  y:\n    steps_per_mm: 80\n";
  try {
    (void)firmware::read_fluidnc(text, "config.yaml");
    FAIL() << "accepted";
  } catch (const firmware::FirmwareFileError& error) {
    EXPECT_STREQ(error.what(), "config.yaml:4: left_anchor_y: missing in WallPlotter:");
  }
}

TEST(firmware_fluidnc_import, NotANumberNamesItsLine) {
  const std::string text =
      "kinematics:\n  WallPlotter:\n    left_anchor_x: -100\n    left_anchor_y: 1OO\n"
      "    right_anchor_x: 100\n    right_anchor_y: 100\naxes:\n  x:\n  y:\n";
  try {
    (void)firmware::read_fluidnc(text, "config.yaml");
    FAIL() << "accepted";
  } catch (const firmware::FirmwareFileError& error) {
    EXPECT_STREQ(error.what(), "config.yaml:4: left_anchor_y: '1OO' is not a number");
  }
}

TEST(firmware_fluidnc_import, ParallelDeltaMissingSettingNamesItsLine) {
  const std::string text =
      "kinematics:\n  parallel_delta:\n    crank_mm: 70\n    base_triangle_mm: 179.437\n"
      "    end_effector_triangle_mm: 86.603\naxes:\n  x:\n  y:\n  z:\n";
  try {
    (void)firmware::read_fluidnc(text, "config.yaml");
    FAIL() << "accepted";
  } catch (const firmware::FirmwareFileError& error) {
    EXPECT_STREQ(error.what(), "config.yaml:2: linkage_mm: missing in parallel_delta:");
  }
}

TEST(firmware_fluidnc_import, OtherKinematicsRefusedAtItsLine) {
  try {
    (void)firmware::read_fluidnc("axes:\n  x:\nkinematics:\n  CoreXY:\n", "config.yaml");
    FAIL() << "accepted";
  } catch (const firmware::FirmwareFileError& error) {
    EXPECT_STREQ(error.what(),
                 "config.yaml:3: kinematics: CoreXY: pkmkit imports FluidNC's WallPlotter, "
                 "parallel_delta and Maslow's MaslowKinematics only");
  }
}

// A user's file: other sections, comments, CRLF, FluidNC's defaults for what is left out.
TEST(firmware_fluidnc_import, UsersFileWithOtherSections) {
  const std::string text =
      "board: MKS DLC32\r\nname: my plotter\r\n# a comment\r\nstepping:\r\n  engine: RMT\r\n"
      "kinematics:\r\n  WallPlotter:\r\n    left_anchor_x: -400\r\n    left_anchor_y: 300\r\n"
      "    right_anchor_x: 400\r\n    right_anchor_y: 300\r\n    segment_length: 5\r\n"
      "axes:\r\n  x:\r\n    steps_per_mm: \"100\"  # quoted, then a comment\r\n    "
      "max_rate_mm_per_min: 3000\r\n"
      "    motor0:\r\n      standard_stepper:\r\n        step_pin: gpio.12\r\n"
      "  y:\r\n    steps_per_mm: 100\r\n    max_rate_mm_per_min: 3000\r\n"
      "spindle:\r\n  PWM:\r\n    pwm_hz: 5000\r\n";
  const machine::ImportedMachine imported = firmware::read_fluidnc(text, "config.yaml");
  EXPECT_EQ(imported.name, "my plotter");
  ASSERT_EQ(imported.joints.size(), 2u);
  EXPECT_DOUBLE_EQ(imported.joints[0].max_velocity, 50.0);
  EXPECT_DOUBLE_EQ(imported.joints[0].max_acceleration, 25.0);  // FluidNC's default
  EXPECT_DOUBLE_EQ(*imported.joints[0].steps_per_unit, 100.0);  // quoted, with a comment
  EXPECT_DOUBLE_EQ(*imported.joints[1].steps_per_unit, 100.0);
  bool noted = false;
  for (const std::string& note : imported.notes) {
    noted |= note == "not imported (not kinematics): board, stepping, spindle";
  }
  EXPECT_TRUE(noted);
  const machine::Machine machine =
      machine::parse_machine(machine::machine_file_text(imported, "m.toml"), "m.toml");
  // Home at FluidNC's origin: each cord hypot(400, 300) = 500 mm.
  const kinematics::JointVector home = joints_at(machine, machine.home());
  EXPECT_NEAR(home[0], 500.0, 1e-9);
  EXPECT_NEAR(home[1], 500.0, 1e-9);
}

}  // namespace
}  // namespace pkm

namespace pkm {
namespace {

// Maslow 4's belts: the lengths its firmware computes from the exported keys (the reference) are
// pkmkit's joints over maslow4.toml's workspace, Maslow's x y counted from the frame's centre.
TEST(firmware_fluidnc_maslow, FirmwareBeltsAreThePkmkitJointsOverTheWorkspace) {
  const machine::Machine m = test::load_example("maslow4.toml");
  const std::string text = export_text(fluidnc_machine(m, false));
  const test::maslow_reference::Frame frame = test::maslow_reference::read_frame(text);
  EXPECT_NEAR(frame.centre_x, 1461.9, 1e-3);
  EXPECT_NEAR(frame.centre_y, 1033.073, 1e-3);
  EXPECT_DOUBLE_EQ(frame.z[0], 100.0);
  EXPECT_DOUBLE_EQ(frame.arm_length + frame.belt_end_extension, 153.4);
  double worst = 0.0, worst_float = 0.0;
  int poses = 0;
  for (const geometry::Pose& pose : firmware::workspace_samples(m, 15)) {
    const kinematics::JointVector joints = joints_at(m, pose);
    const Eigen::Vector3d& p = pose.position_mm;
    const std::array<double, 4> belts =
        test::maslow_reference::belts(frame, p.x() - frame.centre_x, p.y() - frame.centre_y, p.z());
    const std::array<double, 4> in_float = test::maslow_reference::belts_float(
        frame, p.x() - frame.centre_x, p.y() - frame.centre_y, p.z());
    for (int k = 0; k < 4; ++k) {
      worst = std::max(worst, std::abs(belts[k] - joints[k]));
      worst_float = std::max(worst_float, std::abs(in_float[k] - joints[k]));
    }
    EXPECT_NEAR(joints[4], p.z(), 1e-12);
    ++poses;
  }
  EXPECT_GT(poses, 100);
  EXPECT_LT(worst, 1e-3);
  // The firmware's floats: a few ulp of a 3 m belt (2.4e-4 mm each).
  EXPECT_LT(worst_float, 5e-3);
  std::printf(
      "maslow4: worst |reference belt - pkmkit joint| %.3g mm (in the firmware's floats %.3g mm) "
      "over %d poses\n",
      worst, worst_float, poses);
}

TEST(firmware_fluidnc_maslow, ImportThenExportGivesTheSameText) {
  const std::string text = export_text(fluidnc_machine(test::load_example("maslow4.toml"), false));
  const machine::ImportedMachine imported = firmware::read_fluidnc(text, "maslow.yaml");
  const machine::Machine back =
      machine::parse_machine(machine::machine_file_text(imported, "back.toml"), "back.toml");
  EXPECT_EQ(export_text(fluidnc_machine(back, false)).substr(text.find('\n')),
            text.substr(text.find('\n')));
}

// The form is maslow4.toml exactly: no losses, and its model gives the machine's joints.
TEST(firmware_fluidnc_maslow, FormIsExactForMaslow4) {
  const machine::Machine m = test::load_example("maslow4.toml");
  const std::optional<kinematics::FirmwareForm> form = m.kinematics().firmware_form();
  ASSERT_TRUE(form);
  EXPECT_TRUE(form->losses.empty());
  EXPECT_STREQ(kinematics::form_name(form->geometry), "cable robot on swivel arms");
  const auto model = kinematics::make_form_kinematics(form->geometry, form->passthrough);
  const geometry::Pose pose = geometry::Pose::from_vector(
      (geometry::Vector6d() << 500.0, 1600.0, -12.0, 0.0, 0.0, 0.0).finished());
  kinematics::JointVector from_form(model->joint_count());
  ASSERT_TRUE(model->inverse(pose, from_form).ok());
  const kinematics::JointVector joints = joints_at(m, pose);
  for (Eigen::Index k = 0; k < joints.size(); ++k) EXPECT_NEAR(from_form[k], joints[k], 1e-9);
  // By hand, the tl belt: corner (-27.6, 2064.9), its tie point 100 mm up at z -12.
  const double plan = std::hypot(-27.6 - 500.0, 2064.9 - 1600.0) - 153.4;
  EXPECT_NEAR(joints[0], std::hypot(plan, 100.0 - 12.0), 1e-9);
}

TEST(firmware_fluidnc_maslow, ArmsOfDifferentLengthsRefused) {
  const machine::Machine m =
      test::load_example_changed("maslow4.toml", "attach = [0.0, 0.0, 56.0]\nswivel_arm = 153.4",
                                 "attach = [0.0, 0.0, 56.0]\nswivel_arm = 150.0");
  try {
    (void)export_text(fluidnc_machine(m, false));
    FAIL() << "exported";
  } catch (const firmware::ExportRefused& error) {
    EXPECT_NE(std::string(error.what())
                  .find("one armLength for all four belts; cable 1's swivel_arm is 150.000 mm, "
                        "cable 0's 153.400 mm"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace pkm
