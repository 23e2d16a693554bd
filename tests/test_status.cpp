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
  const Machine hektor = load_example("hektor.toml");
  JointVector joints;
  EXPECT_EQ(hektor.inverse(Pose::from_mm_deg(34, 40, 0), joints).code, StatusCode::unreachable);
  EXPECT_EQ(hektor.inverse(Pose::from_mm_deg(34, 0, 0), joints).code, StatusCode::singular);
}

TEST(Status, JointLimitNamesTheJoint) {
  const Machine hektor = load_example("hektor.toml");
  JointVector joints;
  // At (10, -170) the left cable is 170.3 mm (fine), the right one 192.4 mm (> 180).
  const Status status = hektor.inverse(Pose::from_mm_deg(10, -170, 0), joints);
  EXPECT_EQ(status.code, StatusCode::joint_limit);
  EXPECT_EQ(status.joint, 1);
  EXPECT_EQ(hektor.describe(status), "joint limit (joint 'right')");
}

TEST(Status, NanIsRefusedNotPropagated) {
  for (const std::string& file : test::example_machine_files()) {
    const Machine machine = load_example(file);
    JointVector joints;
    Pose pose = machine.home();
    pose.position_mm.x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(machine.inverse(pose, joints).code, StatusCode::invalid_input) << file;
    ASSERT_TRUE(machine.inverse(machine.home(), joints).ok());
    joints[0] = std::numeric_limits<double>::infinity();
    Pose seed = machine.home();
    EXPECT_EQ(machine.forward(joints, seed).code, StatusCode::invalid_input) << file;
  }
}

TEST(Status, CablesThatCannotMeetAreUnreachable) {
  const CablePlotterKinematics plotter(CablePlotterGeometry::level(100.0, 0.0, 0.0));
  JointVector joints(2);
  joints << 30.0, 40.0;  // 30 + 40 < 100: the circles do not meet
  Pose pose;
  EXPECT_EQ(plotter.forward(joints, pose).code, StatusCode::unreachable);
  joints << 50.0, 50.0;  // they meet on the anchor line: no depth, no tension
  EXPECT_EQ(plotter.forward(joints, pose).code, StatusCode::singular);
}

TEST(Status, GlideStrutTooShortNamesTheRail) {
  const Machine delta = load_example("linear-delta.toml");
  JointVector joints;
  // 300 mm struts from towers on a 200 mm circle: 500 mm out from the centre is out of reach of
  // the tower on the far side... and of tower A, which is nearest to -y.
  const Status status = delta.kinematics().inverse(Pose::from_mm_deg(0, -400, 100), joints);
  EXPECT_EQ(status.code, StatusCode::unreachable);
  EXPECT_EQ(status.joint, 0);
}

TEST(Status, HexapodLegLimits) {
  const Machine hexapod = load_example("hexapod-bit.toml");
  JointVector joints;
  EXPECT_EQ(hexapod.inverse(Pose::from_mm_deg(0, 0, 1600), joints).code, StatusCode::joint_limit);
  EXPECT_EQ(hexapod.inverse(Pose::from_mm_deg(0, 0, 400), joints).code, StatusCode::joint_limit);
  JointVector too_short(6);
  too_short.setConstant(500.0);
  Pose pose = hexapod.home();
  const Status status = hexapod.forward(too_short, pose);
  EXPECT_EQ(status.code, StatusCode::joint_limit);
  EXPECT_EQ(status.joint, 0);
}

TEST(Status, HexapodImpossibleLegsDoNotConverge) {
  const Machine hexapod = load_example("hexapod-bit.toml");
  JointVector legs(6);
  legs << 600, 1500, 600, 1500, 600, 1500;  // no pose stretches alternate legs this far
  legs[0] = 100;
  Pose pose = hexapod.home();
  const Pose seed = pose;
  const Status status = hexapod.kinematics().forward(legs, pose);
  EXPECT_FALSE(status.ok());
  EXPECT_TRUE(status.code == StatusCode::not_converged ||
              status.code == StatusCode::branch_changed);
  EXPECT_EQ(pose.position_mm, seed.position_mm) << "a failed FK leaves the seed untouched";
}

TEST(Status, ForwardNeverCrossesToTheMirrorBranch) {
  // The formula machine has no gravity: (36, -48) and (36, +48) give the same cables. Seeded
  // below the anchors, Newton must either land below them or report the jump.
  const Machine formula = load_example("mach3-formula.toml");
  JointVector joints(2);
  joints << 60.0, 80.0;
  for (const double seed_y : {-0.01, -0.1, -1.0, -10.0, -100.0}) {
    for (const double seed_x : {-50.0, 0.0, 36.0, 90.0, 150.0}) {
      Pose pose = Pose::from_mm_deg(seed_x, seed_y, 0);
      const Status status = formula.kinematics().forward(joints, pose);
      if (status.ok()) {
        EXPECT_NEAR(pose.position_mm.y(), -48.0, 1e-9) << seed_x << " " << seed_y;
      } else {
        EXPECT_TRUE(status.code == StatusCode::branch_changed ||
                    status.code == StatusCode::not_converged);
      }
    }
  }
}

}  // namespace
}  // namespace pkm
