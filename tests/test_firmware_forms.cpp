// The forms firmwares' kinematics take (kinematics/firmware_form.hpp) and the machine a target
// holds (firmware/firmware_machine.hpp): which example machines are which form, that a form's
// model computes the machine's own joints, refusals, and what an approximation costs.
#include <gtest/gtest.h>

#include <cmath>

#include "pkm/firmware/firmware_machine.hpp"
#include "pkm/firmware/target.hpp"
#include "test_support.hpp"

namespace pkm::test {
namespace {

using firmware::FormKind;

const std::vector<FormKind> kEveryForm = {FormKind::wall_plotter, FormKind::linear_delta,
                                          FormKind::rotary_delta};

std::optional<kinematics::FirmwareForm> form_of(const std::string& file) {
  return load_example(file).kinematics().firmware_form();
}

TEST(FirmwareForms, ExampleMachinesAnswerTheirForm) {
  for (const char* file : {"wall-plotter.toml", "hektor.toml", "pen-plotter.toml", "maslow.toml",
                           "linuxcnc-polargraph-2366.toml"}) {
    const auto form = form_of(file);
    ASSERT_TRUE(form) << file;
    EXPECT_EQ(firmware::form_kind(form->geometry), FormKind::wall_plotter) << file;
    EXPECT_TRUE(form->losses.empty()) << file << ": " << form->losses.front();
  }
  for (const char* file : {"linear-delta.toml", "linuxcnc-ldelta.toml"}) {
    const auto form = form_of(file);
    ASSERT_TRUE(form) << file;
    EXPECT_EQ(firmware::form_kind(form->geometry), FormKind::linear_delta) << file;
    EXPECT_TRUE(form->losses.empty()) << file;
  }
  const auto rotary = form_of("linuxcnc-rdelta.toml");
  ASSERT_TRUE(rotary);
  EXPECT_EQ(firmware::form_kind(rotary->geometry), FormKind::rotary_delta);
  // 10 in: lengths are mm inside.
  EXPECT_DOUBLE_EQ(std::get<kinematics::RotaryDeltaForm>(rotary->geometry).base_radius_mm, 254.0);
  for (const char* file : {"hexapod-bit.toml", "matrix-mill.toml", "triaglide.toml",
                           "triaglide-fanned.toml", "hexaglide.toml", "mach3-formula.toml"}) {
    EXPECT_FALSE(form_of(file)) << file;
  }
}

TEST(FirmwareForms, LinearDeltaTowersFoldTheEffectorOffsetIntoTheColumn) {
  // linear-delta.toml: rail 1 at (0, 200, 0), its rod's effector end at (0, 40, 0) from the tool.
  const auto form = form_of("linear-delta.toml");
  const auto& delta = std::get<kinematics::LinearDeltaForm>(form->geometry);
  EXPECT_NEAR(delta.towers[0].column_mm.x(), 0.0, 1e-12);
  EXPECT_NEAR(delta.towers[0].column_mm.y(), 160.0, 1e-12);
  EXPECT_DOUBLE_EQ(delta.towers[0].rod_mm, 300.0);
  EXPECT_DOUBLE_EQ(delta.towers[0].carriage_offset_mm, 0.0);
  // At the centre, z = 100: reading = 100 + sqrt(300^2 - 160^2) = 353.7758...
  const machine::Machine machine = load_example("linear-delta.toml");
  kinematics::JointVector joints(3);
  ASSERT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(0.0, 0.0, 100.0), joints).ok());
  EXPECT_NEAR(joints[0], 100.0 + std::sqrt(300.0 * 300.0 - 160.0 * 160.0), 1e-9);
}

TEST(FirmwareForms, WallPlotterLossesNameTheirNumbers) {
  const auto form = form_of("maslow-frame.toml");
  ASSERT_TRUE(form);
  ASSERT_EQ(form->losses.size(), 4u);  // pulley, attach, sag, stretch
  EXPECT_NE(form->losses[0].find("pulley_radius 10.275 mm"), std::string::npos);
  EXPECT_NE(form->losses[1].find("310.000 mm apart"), std::string::npos);
  EXPECT_NE(form->losses[2].find("cable_density 0.1500 kg/m"), std::string::npos);
  EXPECT_NE(form->losses[3].find("cable_stiffness 150000 N"), std::string::npos);
  ASSERT_EQ(form->unchecked.size(), 1u);
  EXPECT_NE(form->unchecked[0].find("tension_limits [10.000, 450.000] N"), std::string::npos);
}

// An exact form's model computes the machine's own joints everywhere in its workspace.
TEST(FirmwareForms, ExactFormModelsGiveTheMachinesJoints) {
  for (const char* file : {"wall-plotter.toml", "maslow.toml", "linuxcnc-polargraph-2366.toml",
                           "linear-delta.toml", "linuxcnc-ldelta.toml", "linuxcnc-rdelta.toml"}) {
    const machine::Machine machine = load_example(file);
    const firmware::FirmwareMachine held =
        firmware::firmware_machine(machine, kEveryForm, "test", false);
    EXPECT_FALSE(held.cost) << file;
    const auto model = kinematics::make_form_kinematics(held.form.geometry, held.form.passthrough);
    const std::vector<geometry::Pose> samples = firmware::workspace_samples(machine);
    ASSERT_GT(samples.size(), 100u) << file;
    double worst = 0.0;
    kinematics::JointVector expected(machine.kinematics().joint_count());
    kinematics::JointVector got(model->joint_count());
    for (const geometry::Pose& pose : samples) {
      ASSERT_TRUE(machine.inverse(pose, expected).ok());
      ASSERT_TRUE(model->inverse(pose, got).ok()) << file;
      worst = std::max(worst, (got - expected).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-9) << file;
  }
}

TEST(FirmwareForms, AnotherFormIsRefusedNamingTheTargetsForms) {
  try {
    (void)firmware::firmware_machine(load_example("hexapod-bit.toml"),
                                     {FormKind::wall_plotter, FormKind::rotary_delta}, "fluidnc",
                                     true);
    FAIL() << "a hexapod went to a wall-plotter firmware";
  } catch (const firmware::ExportRefused& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("fluidnc has kinematics for a two-cable wall plotter or a rotary "
                           "delta; this machine's model is hexapod"),
              std::string::npos)
        << message;
  }
}

TEST(FirmwareForms, LossesAreRefusedUnlessApproximated) {
  const machine::Machine machine = load_example("makelangelo.toml");
  try {
    (void)firmware::firmware_machine(machine, {FormKind::wall_plotter}, "fluidnc", false);
    FAIL() << "a gondola on pulleys went to a point-anchor plotter silently";
  } catch (const firmware::ExportRefused& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("pulley_radius 6.366 mm"), std::string::npos) << message;
    EXPECT_NE(message.find("--approximate"), std::string::npos) << message;
  }
}

// The approximation's stated worst error bounds every sample's, and the fit does better than the
// form's nearest geometry read off the machine file.
TEST(FirmwareForms, ApproximationStatesTheWorstToolError) {
  for (const char* file : {"makelangelo.toml", "maslow-frame.toml", "hektor-pulleys.toml"}) {
    const machine::Machine machine = load_example(file);
    const firmware::FirmwareMachine held =
        firmware::firmware_machine(machine, {FormKind::wall_plotter}, "test", true);
    ASSERT_TRUE(held.cost) << file;
    const firmware::ApproximationCost& cost = *held.cost;
    EXPECT_GT(cost.samples, 100) << file;
    EXPECT_GT(cost.worst_tool_error_mm, 0.0) << file;
    EXPECT_LT(cost.worst_tool_error_mm, cost.worst_before_fit_mm) << file;
    EXPECT_LE(cost.rms_tool_error_mm, cost.worst_tool_error_mm) << file;
    EXPECT_TRUE(held.machine.kinematics().firmware_form()->losses.empty()) << file;
    // Each sample's error, measured here on its own: the firmware's joints (the fitted model's
    // IK) driven on the machine as built (its FK).
    for (const geometry::Pose& pose : firmware::workspace_samples(machine)) {
      kinematics::JointVector joints(held.machine.kinematics().joint_count());
      if (!held.machine.kinematics().inverse(pose, joints).ok()) continue;
      geometry::Pose reached = pose;
      if (!machine.kinematics().forward(joints, reached).ok()) continue;
      EXPECT_LE((reached.position_mm - pose.position_mm).norm(), cost.worst_tool_error_mm + 1e-9)
          << file;
    }
    std::printf("%s: worst %.4f mm (before the fit %.4f), rms %.4f mm over %d poses\n", file,
                cost.worst_tool_error_mm, cost.worst_before_fit_mm, cost.rms_tool_error_mm,
                cost.samples);
  }
}

}  // namespace
}  // namespace pkm::test
