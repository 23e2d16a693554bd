// Every failing pose says why: unreachable, joint limit, singular, not converged, branch, NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pkm/kinematics/cable_plotter.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

using test::load_example;

TEST(Status, CablePlotterAboveTheAnchorsIsUnreachable) {
  const machine::Machine hektor = load_example("hektor.toml");
  kinematics::JointVector joints;
  EXPECT_EQ(hektor.inverse(geometry::Pose::from_mm_deg(34, 40, 0), joints).code,
            kinematics::StatusCode::unreachable);
  EXPECT_EQ(hektor.inverse(geometry::Pose::from_mm_deg(34, 0, 0), joints).code,
            kinematics::StatusCode::singular);
}

TEST(Status, JointLimitNamesTheJoint) {
  const machine::Machine hektor = load_example("hektor.toml");
  kinematics::JointVector joints;
  // At (10, -170) the left cable is 170.3 mm (fine), the right one 192.4 mm (> 180).
  const kinematics::Status status =
      hektor.inverse(geometry::Pose::from_mm_deg(10, -170, 0), joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_limit);
  EXPECT_EQ(status.joint, 1);
  EXPECT_EQ(hektor.describe(status), "joint limit (joint 'right')");
}

TEST(Status, NanIsRefusedNotPropagated) {
  for (const std::string& file : test::example_machine_files()) {
    const machine::Machine machine = load_example(file);
    kinematics::JointVector joints;
    geometry::Pose pose = machine.home();
    pose.position_mm.x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(machine.inverse(pose, joints).code, kinematics::StatusCode::invalid_input) << file;
    ASSERT_TRUE(machine.inverse(machine.home(), joints).ok());
    joints[0] = std::numeric_limits<double>::infinity();
    geometry::Pose seed = machine.home();
    EXPECT_EQ(machine.forward(joints, seed).code, kinematics::StatusCode::invalid_input) << file;
  }
}

TEST(Status, CablesThatCannotMeetAreUnreachable) {
  const kinematics::CablePlotterKinematics plotter(
      kinematics::CablePlotterGeometry::level(100.0, 0.0, 0.0));
  kinematics::JointVector joints(2);
  joints << 30.0, 40.0;  // 30 + 40 < 100: the circles do not meet
  geometry::Pose pose;
  EXPECT_EQ(plotter.forward(joints, pose).code, kinematics::StatusCode::unreachable);
  joints << 50.0, 50.0;  // they meet on the anchor line: no depth, no tension
  EXPECT_EQ(plotter.forward(joints, pose).code, kinematics::StatusCode::singular);
}

TEST(Status, GlideStrutTooShortNamesTheRail) {
  const machine::Machine delta = load_example("linear-delta.toml");
  kinematics::JointVector joints;
  // 300 mm struts from towers on a 200 mm circle: 500 mm out from the centre is out of reach of
  // the tower on the far side... and of tower A, which is nearest to -y.
  const kinematics::Status status =
      delta.kinematics().inverse(geometry::Pose::from_mm_deg(0, -400, 100), joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::unreachable);
  EXPECT_EQ(status.joint, 0);
}

TEST(Status, HexapodLegLimits) {
  const machine::Machine hexapod = load_example("hexapod-bit.toml");
  kinematics::JointVector joints;
  EXPECT_EQ(hexapod.inverse(geometry::Pose::from_mm_deg(0, 0, 1600), joints).code,
            kinematics::StatusCode::joint_limit);
  EXPECT_EQ(hexapod.inverse(geometry::Pose::from_mm_deg(0, 0, 400), joints).code,
            kinematics::StatusCode::joint_limit);
  kinematics::JointVector too_short(6);
  too_short.setConstant(500.0);
  geometry::Pose pose = hexapod.home();
  const kinematics::Status status = hexapod.forward(too_short, pose);
  EXPECT_EQ(status.code, kinematics::StatusCode::joint_limit);
  EXPECT_EQ(status.joint, 0);
}

TEST(Status, HexapodImpossibleLegsDoNotConverge) {
  const machine::Machine hexapod = load_example("hexapod-bit.toml");
  kinematics::JointVector legs(6);
  legs << 600, 1500, 600, 1500, 600, 1500;  // no pose stretches alternate legs this far
  legs[0] = 100;
  geometry::Pose pose = hexapod.home();
  const geometry::Pose seed = pose;
  const kinematics::Status status = hexapod.kinematics().forward(legs, pose);
  EXPECT_FALSE(status.ok());
  EXPECT_TRUE(status.code == kinematics::StatusCode::not_converged ||
              status.code == kinematics::StatusCode::branch_changed);
  EXPECT_EQ(pose.position_mm, seed.position_mm) << "a failed FK leaves the seed untouched";
}

TEST(Status, ForwardNeverCrossesToTheMirrorBranch) {
  // The formula machine has no gravity: (36, -48) and (36, +48) give the same cables. Seeded
  // below the anchors, Newton must either land below them or report the jump.
  const machine::Machine formula = load_example("mach3-formula.toml");
  kinematics::JointVector joints(2);
  joints << 60.0, 80.0;
  for (const double seed_y : {-0.01, -0.1, -1.0, -10.0, -100.0}) {
    for (const double seed_x : {-50.0, 0.0, 36.0, 90.0, 150.0}) {
      geometry::Pose pose = geometry::Pose::from_mm_deg(seed_x, seed_y, 0);
      const kinematics::Status status = formula.kinematics().forward(joints, pose);
      if (status.ok()) {
        EXPECT_NEAR(pose.position_mm.y(), -48.0, 1e-9) << seed_x << " " << seed_y;
      } else {
        EXPECT_TRUE(status.code == kinematics::StatusCode::branch_changed ||
                    status.code == kinematics::StatusCode::not_converged);
      }
    }
  }
}

}  // namespace
}  // namespace pkm
