// Hand-computed cases for every model, and differential checks between models that must agree.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

using test::load_example;

TEST(CablePlotter, SourceDocumentWorkedExample) {
  // d = 100, x = 34, y = -40 gives a = 52.498, b = 77.175 (the Mach3 document's CAD check).
  const machine::Machine hektor = load_example("hektor.toml");
  kinematics::JointVector joints;
  ASSERT_TRUE(hektor.inverse(geometry::Pose::from_mm_deg(34, -40, 0), joints).ok());
  EXPECT_NEAR(joints[0], 52.498, 5e-4);
  EXPECT_NEAR(joints[1], 77.175, 5e-4);
  EXPECT_DOUBLE_EQ(joints[0], std::sqrt(34.0 * 34.0 + 40.0 * 40.0));
  EXPECT_DOUBLE_EQ(joints[1], std::sqrt(66.0 * 66.0 + 40.0 * 40.0));
}

TEST(CablePlotter, ForwardTakesTheLowerIntersection) {
  // 60 and 80 from anchors 100 apart: a 3-4-5 triangle, the pen at (36, -48), not (36, +48).
  const kinematics::CablePlotterKinematics plotter(
      kinematics::CablePlotterGeometry::level(100.0, 0.0, 0.0));
  kinematics::JointVector joints(2);
  joints << 60.0, 80.0;
  geometry::Pose pose;
  ASSERT_TRUE(plotter.forward(joints, pose).ok());
  EXPECT_DOUBLE_EQ(pose.position_mm.x(), 36.0);
  EXPECT_DOUBLE_EQ(pose.position_mm.y(), -48.0);
}

TEST(CablePlotter, CableOffsetsShiftTheJointReadings) {
  const kinematics::CablePlotterKinematics plotter(
      kinematics::CablePlotterGeometry::level(100.0, 2.5, -1.0));
  kinematics::JointVector joints;
  ASSERT_TRUE(plotter.inverse(geometry::Pose::from_mm_deg(36, -48, 0), joints).ok());
  EXPECT_DOUBLE_EQ(joints[0], 62.5);
  EXPECT_DOUBLE_EQ(joints[1], 79.0);
}

TEST(CablePlotter, APenOutsideItsAnchorsIsUnreachable) {
  // A cable only pulls: left of the left anchor the right cable would have to push, right of the
  // right anchor the left one. Below the anchors and between them the pen hangs.
  const kinematics::CablePlotterKinematics plotter(
      kinematics::CablePlotterGeometry::level(1500.0, 0.0, 0.0));
  kinematics::JointVector joints;
  EXPECT_TRUE(plotter.inverse(geometry::Pose::from_mm_deg(1, -700, 0), joints).ok());
  EXPECT_TRUE(plotter.inverse(geometry::Pose::from_mm_deg(1499, -700, 0), joints).ok());
  const kinematics::Status left =
      plotter.inverse(geometry::Pose::from_mm_deg(-500, -700, 0), joints);
  EXPECT_EQ(left.code, kinematics::StatusCode::unreachable);
  EXPECT_EQ(left.joint, 1);
  const kinematics::Status right =
      plotter.inverse(geometry::Pose::from_mm_deg(2000, -700, 0), joints);
  EXPECT_EQ(right.code, kinematics::StatusCode::unreachable);
  EXPECT_EQ(right.joint, 0);
  EXPECT_EQ(plotter.why_refused(geometry::Pose::from_mm_deg(-500, -700, 0), left),
            "left of the left anchor (x <= 0) the right cable would have to push");
}

TEST(CablePlotter, PassThroughZFollowsTheProgram) {
  // A pen on a real Z axis: the third joint is the program's Z, the cables as without it.
  const kinematics::CablePlotterKinematics plotter(
      kinematics::CablePlotterGeometry::level(100.0, 0.0, 0.0),
      kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy()));
  EXPECT_EQ(plotter.joint_count(), 3);
  EXPECT_TRUE(plotter.dof().controls(2));
  EXPECT_EQ(plotter.passthrough_axis(2), 2);
  EXPECT_EQ(plotter.passthrough_axis(0), -1);
  EXPECT_EQ(plotter.joint_kind(2), kinematics::JointKind::linear);
  kinematics::JointVector joints;
  ASSERT_TRUE(plotter.inverse(geometry::Pose::from_mm_deg(36, -48, 2.5), joints).ok());
  ASSERT_EQ(joints.size(), 3);
  EXPECT_DOUBLE_EQ(joints[0], 60.0);
  EXPECT_DOUBLE_EQ(joints[1], 80.0);
  EXPECT_DOUBLE_EQ(joints[2], 2.5);
  geometry::Pose pose;
  joints[2] = -1.25;
  ASSERT_TRUE(plotter.forward(joints, pose).ok());
  EXPECT_DOUBLE_EQ(pose.position_mm.x(), 36.0);
  EXPECT_DOUBLE_EQ(pose.position_mm.y(), -48.0);
  EXPECT_DOUBLE_EQ(pose.position_mm.z(), -1.25);
  kinematics::JointJacobian jacobian;
  ASSERT_TRUE(plotter.jacobian(geometry::Pose::from_mm_deg(36, -48, 0), jacobian).ok());
  EXPECT_EQ(jacobian(2, 2), 1.0);
  EXPECT_EQ(jacobian(2, 0), 0.0);
  EXPECT_DOUBLE_EQ(jacobian(0, 0), 36.0 / 60.0);
}

TEST(Glide, BiglidePassThroughZRoundTrip) {
  std::vector<kinematics::GlideRail> rails(2);
  rails[0] = {{0, 0, 0}, {1, 0, 0}, 200.0, {-20, 0, 0}, -1};
  rails[1] = {{0, 0, 0}, {1, 0, 0}, 200.0, {20, 0, 0}, 1};
  const kinematics::GlideKinematics biglide(
      rails, geometry::Dof::planar_xy(),
      kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy()));
  EXPECT_EQ(biglide.joint_count(), 3);
  EXPECT_EQ(biglide.rail_dof(), geometry::Dof::planar_xy());
  kinematics::JointVector joints;
  ASSERT_TRUE(biglide.inverse(geometry::Pose::from_mm_deg(30, -120, 4), joints).ok());
  EXPECT_NEAR(joints[0], 10.0 - 160.0, 1e-12);
  EXPECT_NEAR(joints[1], 50.0 + 160.0, 1e-12);
  EXPECT_EQ(joints[2], 4.0);
  geometry::Pose pose = geometry::Pose::from_mm_deg(0, -100, 0);
  ASSERT_TRUE(biglide.forward(joints, pose).ok());
  EXPECT_NEAR(pose.position_mm.x(), 30.0, 1e-12);
  EXPECT_NEAR(pose.position_mm.y(), -120.0, 1e-12);
  EXPECT_EQ(pose.position_mm.z(), 4.0);
  EXPECT_THROW(kinematics::GlideKinematics(rails, geometry::Dof::planar_xy(),
                                           kinematics::PassThroughAxes({1}, geometry::Dof::all())),
               std::invalid_argument);  // the rails move y themselves
}

TEST(Glide, AnOverflowingPoseIsUnreachableNotNaN) {
  // Far enough away the squares overflow to inf - inf = NaN, which compares false with 0.
  const machine::Machine delta = load_example("linear-delta.toml");
  kinematics::JointVector joints;
  const kinematics::Status raw =
      delta.kinematics().inverse(geometry::Pose::from_mm_deg(1e200, 0, 1e200), joints);
  EXPECT_EQ(raw.code, kinematics::StatusCode::unreachable);
  const kinematics::Status status =
      delta.inverse(geometry::Pose::from_mm_deg(1e200, 0, 1e200), joints);
  EXPECT_FALSE(status.ok());
}

TEST(Hexapod, AnUpsideDownPlatformIsAnotherAssemblyMode) {
  // The legs have lengths at B = 180, but FK from the machine's side never returns there.
  const machine::Machine hexapod = load_example("hexapod-bit.toml");
  const auto& model = hexapod.kinematics();
  EXPECT_EQ(model.assembly_mode(geometry::Pose::from_mm_deg(0, 0, 1000, 0, 0, 0)), 1);
  EXPECT_EQ(model.assembly_mode(geometry::Pose::from_mm_deg(0, 0, 1000, 0, 89, 0)), 1);
  EXPECT_EQ(model.assembly_mode(geometry::Pose::from_mm_deg(0, 0, 1000, 0, 180, 0)), -1);
  EXPECT_EQ(model.assembly_mode(geometry::Pose::from_mm_deg(0, 0, 1000, 91, 0, 0)), -1);
  kinematics::JointVector joints;
  EXPECT_TRUE(model.inverse(geometry::Pose::from_mm_deg(0, 0, 1000, 0, 180, 0), joints).ok());
  EXPECT_EQ(hexapod.inverse(geometry::Pose::from_mm_deg(0, 0, 1000, 0, 180, 0), joints).code,
            kinematics::StatusCode::other_assembly);
}

TEST(Formula, Mach3FormulasAgreeWithTheCablePlotterModel) {
  const machine::Machine formula = load_example("mach3-formula.toml");
  const machine::Machine plotter = load_example("hektor.toml");
  std::mt19937_64 rng(11);
  for (const geometry::Pose& pose : test::sample_reachable_poses(plotter, 2000, rng)) {
    kinematics::JointVector from_formula, from_model;
    ASSERT_TRUE(formula.inverse(pose, from_formula).ok());
    ASSERT_TRUE(plotter.inverse(pose, from_model).ok());
    EXPECT_NEAR(from_formula[0], from_model[0], 1e-12);
    EXPECT_NEAR(from_formula[1], from_model[1], 1e-12);
  }
}

TEST(Formula, ComparisonsAreNotAssignmentsAndAFormulaGivesOneValueEveryTime) {
  // '<=', '>=', '==' and '!=' hold an '=' and are comparisons, accepted; the joint's value at a
  // pose is the same at every evaluation (an assignment would have moved it).
  kinematics::FormulaDefinition definition;
  definition.axes = {0, 1};
  definition.constants = {{"d", 100.0}};
  definition.formulas = {{"a", "y <= 0 && x >= 0 && x != 1e9 ? sqrt(x^2 + y^2) : 0"},
                         {"b", "(d == 100) * sqrt((d - x)^2 + y^2)"}};
  const kinematics::FormulaKinematics model(definition);
  const geometry::Pose pose = geometry::Pose::from_mm_deg(30.0, -40.0, 0.0);
  kinematics::JointVector first, again;
  ASSERT_TRUE(model.inverse(pose, first).ok());
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(model.inverse(pose, again).ok());
  EXPECT_DOUBLE_EQ(first[0], 50.0);
  EXPECT_DOUBLE_EQ(first[1], std::sqrt(70.0 * 70.0 + 40.0 * 40.0));
  EXPECT_EQ(first, again);
}

TEST(Formula, OneModelFromSeveralThreadsAtOnceGivesOneThreadsJoints) {
  // The workspace's threads share one constant model (docs/kinematics.md): each call's pose must
  // stay its own while another thread evaluates the same formulas at another pose.
  const machine::Machine machine = load_example("mach3-formula.toml");
  const kinematics::Kinematics& model = machine.kinematics();
  std::vector<geometry::Pose> poses;
  for (int i = 0; i < 400; ++i) {
    poses.push_back(geometry::Pose::from_mm_deg(10.0 + 0.2 * i, -20.0 - 0.3 * (i % 97), 0.0));
  }
  std::vector<kinematics::JointVector> alone(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k)
    ASSERT_TRUE(model.inverse(poses[k], alone[k]).ok());
  constexpr int kThreads = 4;
  constexpr int kRounds = 400;  // enough for the threads to overlap: 640k calls, 0.04 s
  std::vector<int> mismatches(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      kinematics::JointVector joints;
      for (int round = 0; round < kRounds; ++round) {
        for (std::size_t n = 0; n < poses.size(); ++n) {
          const std::size_t k = (n * static_cast<std::size_t>(t + 1) + 37 * t) % poses.size();
          const bool ok = model.inverse(poses[k], joints).ok();
          if (!ok || joints != alone[k]) ++mismatches[static_cast<std::size_t>(t)];
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(mismatches[static_cast<std::size_t>(t)], 0) << t;
  EXPECT_DOUBLE_EQ(alone[0][0], std::hypot(10.0, 20.0));
  EXPECT_DOUBLE_EQ(alone[0][1], std::hypot(90.0, 20.0));
}

TEST(Formula, AnAssignmentIsRefusedWithItsColumn) {
  kinematics::FormulaDefinition definition;
  definition.axes = {0, 1};
  definition.constants = {{"d", 100.0}};
  definition.formulas = {{"a", "sqrt(x^2 + y^2)"}, {"b", "d = d + 1e-3, sqrt((d - x)^2 + y^2)"}};
  try {
    const kinematics::FormulaKinematics model(definition);
    FAIL() << "a formula that assigns to its constant was accepted";
  } catch (const kinematics::FormulaError& error) {
    EXPECT_EQ(error.joint(), "b");
    EXPECT_NE(std::string(error.what()).find("assigns with '=' at column 3"), std::string::npos)
        << error.what();
  }
}

TEST(Matrix, JointIsMatrixTimesAxis) {
  const machine::Machine mill = load_example("matrix-mill.toml");
  kinematics::JointVector joints;
  ASSERT_TRUE(mill.inverse(geometry::Pose::from_mm_deg(100, 50, -20), joints).ok());
  EXPECT_NEAR(joints[0], 100.0 + 0.0003 * 50 - 0.0001 * -20, 1e-12);  // 100.017
  EXPECT_NEAR(joints[1], 50.0, 1e-12);
  EXPECT_NEAR(joints[2], 0.0002 * 100 - 20.0, 1e-12);  // -19.98
  geometry::Pose back = mill.home();
  ASSERT_TRUE(mill.forward(joints, back).ok());
  EXPECT_LT((back.position_mm - Eigen::Vector3d(100, 50, -20)).norm(), 1e-12);
}

TEST(Matrix, ExtraAxesPassThrough) {
  Eigen::Matrix3d skew = Eigen::Matrix3d::Identity();
  skew(0, 1) = 0.01;
  const kinematics::MatrixKinematics model(skew, {3});  // x y z plus a rotary A joint
  kinematics::JointVector joints;
  ASSERT_TRUE(model.inverse(geometry::Pose::from_mm_deg(10, 20, 30, 45), joints).ok());
  ASSERT_EQ(joints.size(), 4);
  EXPECT_DOUBLE_EQ(joints[0], 10.2);
  EXPECT_DOUBLE_EQ(joints[3], M_PI / 4);
  EXPECT_EQ(model.joint_kind(3), kinematics::JointKind::rotary);
  EXPECT_EQ(model.passthrough_axis(3), 3);
  EXPECT_EQ(model.passthrough_axis(2), -1);
}

TEST(Matrix, SingularMatrixIsRefused) {
  Eigen::Matrix3d singular;
  singular << 1, 2, 3, 2, 4, 6, 0, 0, 1;
  EXPECT_THROW(kinematics::MatrixKinematics(singular, {}), std::invalid_argument);
}

TEST(Glide, LinearDeltaHandComputed) {
  // Tip at (0, 0, 100): every effector joint is 200 - 40 = 160 mm from its tower, so each
  // carriage sits at 100 + sqrt(300^2 - 160^2) = 353.7716 mm.
  const machine::Machine delta = load_example("linear-delta.toml");
  kinematics::JointVector joints;
  ASSERT_TRUE(delta.inverse(delta.home(), joints).ok());
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(joints[i], 100.0 + std::sqrt(64400.0), 1e-12);
}

TEST(Glide, ParallelTriaglideHandComputed) {
  // Home tip (0, 0, 200). Rail 2 at (y, z) = (0, 700): strut foot 450 mm below, carriage at
  // sqrt(500^2 - 450^2). Rail 1 at (-350, 600), joint (0, -60, 250): offsets (290, -350).
  const machine::Machine triaglide = load_example("triaglide.toml");
  kinematics::JointVector joints;
  ASSERT_TRUE(triaglide.inverse(triaglide.home(), joints).ok());
  EXPECT_NEAR(joints[1], std::sqrt(500.0 * 500.0 - 450.0 * 450.0), 1e-12);
  EXPECT_NEAR(joints[0], std::sqrt(500.0 * 500.0 - 290.0 * 290.0 - 350.0 * 350.0), 1e-12);
  EXPECT_NEAR(joints[2], joints[0], 1e-12);
}

TEST(Glide, BiglideRoundTripAndBranches) {
  // Two rails on the X axis; the left carriage behind its strut (branch -1), the right ahead.
  std::vector<kinematics::GlideRail> rails(2);
  rails[0] = {{0, 0, 0}, {1, 0, 0}, 200.0, {-20, 0, 0}, -1};
  rails[1] = {{0, 0, 0}, {1, 0, 0}, 200.0, {20, 0, 0}, 1};
  const kinematics::GlideKinematics biglide(rails, geometry::Dof::planar_xy());
  kinematics::JointVector joints;
  ASSERT_TRUE(biglide.inverse(geometry::Pose::from_mm_deg(30, -120, 0), joints).ok());
  EXPECT_NEAR(joints[0], 10.0 - 160.0, 1e-12);  // 30 - 20 - sqrt(200^2 - 120^2)
  EXPECT_NEAR(joints[1], 50.0 + 160.0, 1e-12);
  geometry::Pose pose = geometry::Pose::from_mm_deg(0, -100, 0);
  ASSERT_TRUE(biglide.forward(joints, pose).ok());
  EXPECT_NEAR(pose.position_mm.x(), 30.0, 1e-12);
  EXPECT_NEAR(pose.position_mm.y(), -120.0, 1e-12);
  // Seeded above the rails, FK finds the mirror pose: both satisfy the struts and branches.
  pose = geometry::Pose::from_mm_deg(0, 100, 0);
  ASSERT_TRUE(biglide.forward(joints, pose).ok());
  EXPECT_NEAR(pose.position_mm.y(), 120.0, 1e-12);
}

TEST(Hexapod, SemiRegularHexagonsHaveThePapersShape) {
  const kinematics::HexapodGeometry geometry =
      kinematics::HexapodGeometry::semi_regular(500, 400, 0.365, 30);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(geometry.base_mm[i].norm(), 500.0, 1e-12);
    EXPECT_NEAR(geometry.platform_mm[i].norm(), 400.0, 1e-12);
  }
  const double base_short = (geometry.base_mm[0] - geometry.base_mm[1]).norm();
  const double base_long = (geometry.base_mm[1] - geometry.base_mm[2]).norm();
  EXPECT_NEAR(base_short / base_long, 0.365, 1e-12);
  // Platform pairs are legs (1, 6), (2, 3), (4, 5): rotated 60 deg against the base pairs.
  const double platform_short = (geometry.platform_mm[1] - geometry.platform_mm[2]).norm();
  const double platform_long = (geometry.platform_mm[0] - geometry.platform_mm[1]).norm();
  EXPECT_NEAR(platform_short / platform_long, 0.365, 1e-12);
}

TEST(Hexapod, HomeLegLengthsByLawOfCosines) {
  const machine::Machine hexapod = load_example("hexapod-bit.toml");
  kinematics::JointVector joints;
  ASSERT_TRUE(hexapod.inverse(hexapod.home(), joints).ok());
  // Leg 1 joins base joint at -h to platform joint at -60 deg + h, platform 1030 mm up.
  const double h = std::atan(std::sqrt(3.0) * 0.365 / 2.365);
  const double angle = M_PI / 3 - 2 * h;
  const double expected = std::sqrt(500.0 * 500.0 + 400.0 * 400.0 -
                                    2 * 500.0 * 400.0 * std::cos(angle) + 1030.0 * 1030.0);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(joints[i], expected, 1e-9) << "leg " << i + 1;
}

TEST(Hexapod, ThreeFoldSymmetry) {
  // Turning the whole machine state by 120 deg about Z (position T*p, attitude T*R*T^-1) maps
  // leg i onto leg i+2.
  const machine::Machine hexapod = load_example("hexapod-bit.toml");
  std::mt19937_64 rng(3);
  for (const geometry::Pose& pose : test::sample_reachable_poses(hexapod, 200, rng, 10.0)) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(2 * M_PI / 3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Matrix3d rotated =
        turn * geometry::rotation_from_abc(pose.orientation_rad) * turn.transpose();
    geometry::Pose turned;
    turned.position_mm = turn * pose.position_mm;
    const Eigen::Vector3d zyx = rotated.eulerAngles(2, 1, 0);
    turned.orientation_rad = {zyx[2], zyx[1], zyx[0]};
    kinematics::JointVector original, after;
    ASSERT_TRUE(hexapod.kinematics().inverse(pose, original).ok());
    ASSERT_TRUE(hexapod.kinematics().inverse(turned, after).ok());
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(after[(i + 2) % 6], original[i], 1e-9);
  }
}

TEST(Batch, InverseBatchEqualsSingleCalls) {
  // Varying and fixed attitude (the hexapod batch reuses its rotation), and a NaN in the middle.
  for (const std::string& file : test::example_machine_files()) {
    const machine::Machine machine = load_example(file);
    std::mt19937_64 rng(17);
    std::vector<geometry::Pose> poses = test::sample_reachable_poses(machine, 300, rng, 15.0);
    for (std::size_t i = 100; i < 200; ++i) poses[i].orientation_rad = poses[99].orientation_rad;
    poses[150].position_mm.y() = std::nan("");
    std::vector<kinematics::JointVector> batch(poses.size());
    std::vector<kinematics::Status> statuses(poses.size());
    machine.kinematics().inverse_batch(poses, batch, statuses);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      kinematics::JointVector single;
      const kinematics::Status status = machine.kinematics().inverse(poses[i], single);
      ASSERT_EQ(statuses[i].code, status.code) << file << " pose " << i;
      if (status.ok()) {
        EXPECT_LT((batch[i] - single).cwiseAbs().maxCoeff(), 1e-12) << file;
      }
    }
    EXPECT_EQ(statuses[150].code, kinematics::StatusCode::invalid_input) << file;
  }
}

TEST(Parameters, RoundTripThroughSetParameters) {
  for (const std::string& file : test::example_machine_files()) {
    machine::Machine machine = load_example(file);
    const std::vector<kinematics::Parameter> parameters = machine.kinematics().parameters();
    std::vector<double> values;
    for (const kinematics::Parameter& p : parameters) values.push_back(p.value);
    kinematics::JointVector before, after;
    ASSERT_TRUE(machine.kinematics().inverse(machine.home(), before).ok()) << file;
    machine.kinematics().set_parameters(values);
    ASSERT_TRUE(machine.kinematics().inverse(machine.home(), after).ok()) << file;
    EXPECT_LT((before - after).cwiseAbs().maxCoeff(), 1e-12) << file;
  }
}

}  // namespace
}  // namespace pkm
