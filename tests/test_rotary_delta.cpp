// The rotary (Clavel) delta: hand-computed poses, round trips, the Jacobian, refusals naming the
// arm, and LinuxCNC's rotarydeltakins written out independently from its published description
// (a convention that differs from it fails here).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "pkm/kinematics/rotary_delta.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

// Pivots 200 mm out, arms 100, forearms 400, platform joints 60 mm from the tool point: with the
// arms horizontal each elbow is 200 + 100 - 60 = 240 mm out from its platform joint, a 3-4-5
// triangle with the 400 mm forearm.
kinematics::RotaryDeltaKinematics hand_delta() {
  return kinematics::RotaryDeltaKinematics({200.0, 100.0, 400.0, 60.0});
}

kinematics::JointVector angles_deg(double a, double b, double c) {
  kinematics::JointVector joints(3);
  joints << geometry::degrees_to_radians(a), geometry::degrees_to_radians(b),
      geometry::degrees_to_radians(c);
  return joints;
}

TEST(RotaryDelta, ArmsHorizontalHangTheToolStraightBelowTheCentre) {
  // Elbows at 300 mm from the centre, z 0; platform joints 60 mm from the tool: 240 mm across,
  // so the forearm drops sqrt(400^2 - 240^2) = 320 mm. Joint 0 (zero) is arm horizontal outward.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  kinematics::JointVector joints;
  ASSERT_TRUE(delta.inverse(geometry::Pose::from_mm_deg(0, 0, -320), joints).ok());
  ASSERT_EQ(joints.size(), 3);
  for (int arm = 0; arm < 3; ++arm) EXPECT_NEAR(joints[arm], 0.0, 1e-15) << "arm " << arm;
  geometry::Pose pose = geometry::Pose::from_mm_deg(5, -5, -300);
  ASSERT_TRUE(delta.forward(angles_deg(0, 0, 0), pose).ok());
  EXPECT_NEAR(pose.position_mm.x(), 0.0, 1e-12);
  EXPECT_NEAR(pose.position_mm.y(), 0.0, 1e-12);
  EXPECT_NEAR(pose.position_mm.z(), -320.0, 1e-12);
}

TEST(RotaryDelta, PositiveAnglesPutTheElbowsDown) {
  // Arms straight down (90 deg): elbows 200 mm out at z -100, 140 mm across from the platform
  // joints: the tool at -100 - sqrt(400^2 - 140^2) = -474.7077 mm, lower than at 0 deg.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  const double z = -100.0 - std::sqrt(400.0 * 400.0 - 140.0 * 140.0);
  kinematics::JointVector joints;
  ASSERT_TRUE(delta.inverse(geometry::Pose::from_mm_deg(0, 0, z), joints).ok());
  for (int arm = 0; arm < 3; ++arm) EXPECT_NEAR(joints[arm], M_PI / 2, 1e-12) << "arm " << arm;
  geometry::Pose pose;
  ASSERT_TRUE(delta.forward(angles_deg(90, 90, 90), pose).ok());
  EXPECT_NEAR(pose.position_mm.z(), z, 1e-12);
  EXPECT_NEAR(pose.position_mm.head<2>().norm(), 0.0, 1e-12);
}

TEST(RotaryDelta, JointZeroSwingsInTheYzPlaneAtNegativeY) {
  // Arm 0 horizontal: its elbow at (0, -300, 0). The tool at y = -80 puts arm 0's platform joint
  // at (0, -140): 160 mm across, so z = -sqrt(400^2 - 160^2) keeps that arm at 0 deg. Arms 1 and
  // 2 (at 30 and 150 deg) mirror each other across the YZ plane, so they read the same.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  kinematics::JointVector joints;
  const geometry::Pose pose =
      geometry::Pose::from_mm_deg(0, -80, -std::sqrt(400.0 * 400.0 - 160.0 * 160.0));
  ASSERT_TRUE(delta.inverse(pose, joints).ok());
  EXPECT_NEAR(joints[0], 0.0, 1e-15);
  EXPECT_NEAR(joints[1], joints[2], 1e-12);
  EXPECT_GT(joints[1], 0.5);  // the two far arms reach down towards it
  EXPECT_TRUE(
      kinematics::RotaryDeltaKinematics::arm_direction(0).isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_NEAR(std::atan2(kinematics::RotaryDeltaKinematics::arm_direction(1).y(),
                         kinematics::RotaryDeltaKinematics::arm_direction(1).x()),
              geometry::degrees_to_radians(30.0), 1e-15);
  EXPECT_NEAR(std::atan2(kinematics::RotaryDeltaKinematics::arm_direction(2).y(),
                         kinematics::RotaryDeltaKinematics::arm_direction(2).x()),
              geometry::degrees_to_radians(150.0), 1e-15);
}

TEST(RotaryDelta, TurningThePoseBy120DegreesTurnsTheJoints) {
  // Arm i+1 is arm i turned by +120 deg about z: the pose turned so reads arm i's angle there.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(2 * M_PI / 3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  geometry::Pose pose = geometry::Pose::from_mm_deg(37, -21, -350);
  geometry::Pose turned = pose;
  turned.position_mm = turn * pose.position_mm;
  kinematics::JointVector original, after;
  ASSERT_TRUE(delta.inverse(pose, original).ok());
  ASSERT_TRUE(delta.inverse(turned, after).ok());
  for (int arm = 0; arm < 3; ++arm) EXPECT_NEAR(after[(arm + 1) % 3], original[arm], 1e-12);
}

// Poses of the hand delta in its working mode, away from its singular fringe.
std::vector<geometry::Pose> working_poses(const kinematics::RotaryDeltaKinematics& delta, int count,
                                          std::mt19937_64& rng) {
  std::uniform_real_distribution<double> across(-250.0, 250.0), down(-650.0, -150.0);
  std::vector<geometry::Pose> poses;
  kinematics::JointVector joints;
  while (static_cast<int>(poses.size()) < count) {
    const geometry::Pose pose = geometry::Pose::from_mm_deg(across(rng), across(rng), down(rng));
    if (!delta.inverse(pose, joints).ok() || delta.assembly_mode(pose) != 1) continue;
    if (test::dexterity(delta, pose) < 0.02) continue;
    poses.push_back(pose);
  }
  return poses;
}

TEST(RotaryDelta, InverseThenForwardOverTheWorkspace) {
  // FK's seed carries no information for this closed form: a seed 100 mm off gives the pose too.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  std::mt19937_64 rng(11);
  double worst = 0.0;
  for (const geometry::Pose& pose : working_poses(delta, 5000, rng)) {
    kinematics::JointVector joints;
    ASSERT_TRUE(delta.inverse(pose, joints).ok());
    geometry::Pose solved = geometry::Pose::from_mm_deg(100, -100, -200);
    const kinematics::Status status = delta.forward(joints, solved);
    ASSERT_TRUE(status.ok()) << kinematics::describe(status) << " at "
                             << pose.as_vector().transpose();
    worst = std::max(worst, (solved.position_mm - pose.position_mm).norm());
  }
  EXPECT_LE(worst, 1e-9) << "mm";
}

TEST(RotaryDelta, JacobianMatchesFiniteDifferences) {
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  std::mt19937_64 rng(12);
  for (const geometry::Pose& pose : working_poses(delta, 300, rng)) {
    kinematics::JointJacobian analytic;
    ASSERT_TRUE(delta.jacobian(pose, analytic).ok());
    for (int axis = 0; axis < 3; ++axis) {
      // Richardson-extrapolated central differences: error O(h^4).
      const auto difference = [&](double h) {
        geometry::Pose plus = pose, minus = pose;
        plus.position_mm[axis] += h;
        minus.position_mm[axis] -= h;
        kinematics::JointVector at_plus, at_minus;
        EXPECT_TRUE(delta.inverse(plus, at_plus).ok());
        EXPECT_TRUE(delta.inverse(minus, at_minus).ok());
        return kinematics::JointVector((at_plus - at_minus) / (2 * h));
      };
      const kinematics::JointVector numeric =
          (4.0 * difference(5e-3) - difference(1e-2)) / 3.0;  // rad/mm
      // Relative: near the fringe (an arm 0.3 rad/mm from singular) the differences' own
      // truncation error reaches a few millionths.
      const double scale = analytic.col(axis).cwiseAbs().maxCoeff();
      EXPECT_LT((numeric - analytic.col(axis)).cwiseAbs().maxCoeff(), 1e-5 * scale)
          << "axis " << axis << " at " << pose.as_vector().transpose();
    }
    EXPECT_EQ(analytic.rightCols<3>().cwiseAbs().maxCoeff(), 0.0);  // a b c move no arm
  }
}

TEST(RotaryDelta, AnUnreachablePoseNamesTheArm) {
  // 300 mm out towards -30 deg (away from arm 2, at 150 deg): arms 0 and 1 still reach, arm 2
  // cannot: its platform joint is 300 + 200 - 60 = 440 mm from its pivot across the centre and
  // 350 down, sqrt(440^2 + 350^2) = 562 mm, more than the 100 + 400 mm of arm and forearm.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  const geometry::Pose pose = geometry::Pose::from_mm_deg(300 * std::sqrt(3.0) / 2, -150, -350);
  kinematics::JointVector joints;
  const kinematics::Status status = delta.inverse(pose, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::unreachable);
  EXPECT_EQ(status.joint, 2);
  EXPECT_EQ(delta.why_refused(pose, status),
            "arm 3 cannot reach it: the platform joint is farther than the forearm's length from "
            "every point of the elbow's circle");
  // Straight up the forearms are too long to come so near: arm 0 is named, being the first.
  const geometry::Pose above = geometry::Pose::from_mm_deg(0, 0, 0);
  const kinematics::Status too_near = delta.inverse(above, joints);
  EXPECT_EQ(too_near.code, kinematics::StatusCode::unreachable);
  EXPECT_EQ(too_near.joint, 0);
  EXPECT_NE(delta.why_refused(above, too_near).find("is nearer than"), std::string::npos);
  // Far enough away the squares overflow: still a status, never a NaN.
  EXPECT_EQ(delta.inverse(geometry::Pose::from_mm_deg(1e200, 0, -1e200), joints).code,
            kinematics::StatusCode::unreachable);
  EXPECT_EQ(delta.inverse(geometry::Pose::from_mm_deg(std::nan(""), 0, -300), joints).code,
            kinematics::StatusCode::invalid_input);
}

TEST(RotaryDelta, AStretchedArmIsSingular) {
  // Arm 0 at 30 deg with its forearm continuing its line: elbow (0, -200 - 100 cos 30, -50),
  // platform joint 400 mm further along (cos 30, -sin 30) outward and down.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  // 2e-11 mm short of fully stretched, so that rounding cannot put it out of reach.
  const double c30 = std::cos(M_PI / 6), along = 500 - 2e-11;
  const geometry::Pose pose = geometry::Pose::from_mm_deg(0, -(200 + along * c30) + 60, -along / 2);
  kinematics::JointVector joints;
  const kinematics::Status status = delta.inverse(pose, joints);
  EXPECT_EQ(status.code, kinematics::StatusCode::singular);
  EXPECT_EQ(status.joint, 0);
  EXPECT_NE(delta.why_refused(pose, status).find("arm 1 and its forearm are in line"),
            std::string::npos);
  kinematics::JointJacobian jacobian;
  EXPECT_EQ(delta.jacobian(pose, jacobian).code, kinematics::StatusCode::singular);
}

TEST(RotaryDelta, ForwardRefusesAnInwardElbow) {
  // At (0, 0, -320) the arms are horizontal; arm 0's other elbow reaching the same platform joint
  // is its mirror in the pivot-to-joint line, at 2 atan2(320, -140) = 227.26 deg = -132.74 deg.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  const double inward = 2 * std::atan2(320.0, -140.0) - 2 * M_PI;
  kinematics::JointVector joints(3);
  joints << inward, 0.0, 0.0;
  geometry::Pose pose;
  const kinematics::Status status = delta.forward(joints, pose);
  EXPECT_EQ(status.code, kinematics::StatusCode::other_assembly);
  EXPECT_EQ(status.joint, 0);
  // Joints a whole turn away are the same arms.
  joints << 2 * M_PI, -2 * M_PI, 4 * M_PI;
  ASSERT_TRUE(delta.forward(joints, pose).ok());
  EXPECT_NEAR(pose.position_mm.z(), -320.0, 1e-12);
  joints << 0.0, std::nan(""), 0.0;
  EXPECT_EQ(delta.forward(joints, pose).code, kinematics::StatusCode::invalid_input);
}

TEST(RotaryDelta, AssemblyModeIsTheSideForwardKinematicsReturns) {
  // Arms at 0 deg: the forearm spheres' centres (elbows moved in by 60 mm) lie at z 0, 240 mm out,
  // so the spheres also meet at z +320. There each arm's elbow is on the other side of its
  // pivot-to-joint line: inverse kinematics reads 360 - 2 atan2(320, -140) = 132.74 deg, the
  // forearms' determinant changes sign, and FK of those joints never returns there.
  const kinematics::RotaryDeltaKinematics delta = hand_delta();
  EXPECT_EQ(delta.assembly_mode(geometry::Pose::from_mm_deg(0, 0, -320)), 1);
  const geometry::Pose upper = geometry::Pose::from_mm_deg(0, 0, 320);
  EXPECT_EQ(delta.assembly_mode(upper), -1);
  kinematics::JointVector joints;
  ASSERT_TRUE(delta.inverse(upper, joints).ok());
  for (int arm = 0; arm < 3; ++arm) {
    EXPECT_NEAR(joints[arm], 2 * M_PI - 2 * std::atan2(320.0, -140.0), 1e-12);
  }
  geometry::Pose pose = upper;
  EXPECT_EQ(delta.forward(joints, pose).code, kinematics::StatusCode::other_assembly);
}

TEST(RotaryDelta, PassThroughCFollowsTheArms) {
  const kinematics::RotaryDeltaKinematics delta(
      {200.0, 100.0, 400.0, 60.0}, kinematics::PassThroughAxes({5}, geometry::Dof::translation()));
  EXPECT_EQ(delta.joint_count(), 4);
  EXPECT_EQ(delta.joint_kind(0), kinematics::JointKind::rotary);
  EXPECT_EQ(delta.joint_kind(3), kinematics::JointKind::rotary);
  EXPECT_EQ(delta.passthrough_axis(3), 5);
  kinematics::JointVector joints;
  ASSERT_TRUE(delta.inverse(geometry::Pose::from_mm_deg(0, 0, -320, 0, 0, 45), joints).ok());
  EXPECT_DOUBLE_EQ(joints[3], M_PI / 4);
  geometry::Pose pose;
  ASSERT_TRUE(delta.forward(joints, pose).ok());
  EXPECT_DOUBLE_EQ(pose.orientation_rad.z(), M_PI / 4);
  EXPECT_NEAR(pose.position_mm.z(), -320.0, 1e-12);
  EXPECT_THROW(
      kinematics::RotaryDeltaKinematics(
          {200, 100, 400, 60}, kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy())),
      std::invalid_argument);  // the arms move z themselves
}

TEST(RotaryDelta, RdeltaSampleGivesRotarydeltakinsNumbers) {
  // rotarydeltakins' forward kinematics on the rdelta sample's geometry (10, 10, 18, 5 in),
  // evaluated in double precision from its source's formulas: joints (10, 20, 30) deg put the tool
  // at (1.0945539334, -1.7969670819, -14.0843750284) in, (45, -10, 60) deg at (8.0225060140,
  // 2.0891761176, -14.7604689012) in, and (0, 0, 0) at z = -sqrt(18^2 - 15^2) = -sqrt(99) in.
  const machine::Machine rdelta = test::load_example("linuxcnc-rdelta.toml");
  const struct {
    double joints_deg[3];
    double tool_in[3];
  } cases[] = {{{10, 20, 30}, {1.0945539334082581, -1.7969670819032801, -14.084375028364294}},
               {{45, -10, 60}, {8.022506013970009, 2.089176117628809, -14.760468901224469}},
               {{0, 0, 0}, {0.0, 0.0, -std::sqrt(99.0)}}};
  for (const auto& c : cases) {
    const kinematics::JointVector joints =
        angles_deg(c.joints_deg[0], c.joints_deg[1], c.joints_deg[2]);
    geometry::Pose pose = rdelta.home();
    ASSERT_TRUE(rdelta.kinematics().forward(joints, pose).ok());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pose.position_mm[k] / 25.4, c.tool_in[k], 1e-12);
    kinematics::JointVector back;
    ASSERT_TRUE(rdelta.kinematics().inverse(pose, back).ok());
    EXPECT_LT((back - joints).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// LinuxCNC's rotarydeltakins from its published description (the comment of
// rotarydeltakins-common.h, after Zsombor-Murray's descriptive geometry of Clavel's delta), in
// the description's own terms and method, independent of the model above:
// - the origin is the centre of the plane of the three hip joints, Z up;
// - the thigh of joint 0 swings in the YZ plane, hip at (0, -platformradius, 0); the others are
//   joint 0 turned by 120 and 240 deg about Z;
// - zero degrees is the thigh straight out (knee at Z = 0); positive is knee downward;
// - thighs point outward; the controlled point is the lower of the two solutions.
struct PublishedRotaryDelta {
  double platformradius, thighlength, shinlength, footradius;  // mm

  static Eigen::Vector3d turned(const Eigen::Vector3d& p, double angle) {
    return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * p;
  }

  // Joint 0 at controlled point (x, y, z): in the YZ plane the knee lies on the thigh's circle
  // about the hip and on the circle the shin's sphere (about the ankle (x, y - footradius, z))
  // cuts from that plane; of the two meeting points the outer one (smaller y).
  double joint0(const Eigen::Vector3d& p) const {
    const Eigen::Vector2d hip(-platformradius, 0.0);
    const Eigen::Vector2d ankle(p.y() - footradius, p.z());
    const double section = std::sqrt(shinlength * shinlength - p.x() * p.x());
    const Eigen::Vector2d axis = ankle - hip;
    const double d = axis.norm();
    const double along = (thighlength * thighlength - section * section + d * d) / (2 * d);
    const double across = std::sqrt(thighlength * thighlength - along * along);
    const Eigen::Vector2d middle = hip + along * axis / d;
    const Eigen::Vector2d normal(-axis.y() / d, axis.x() / d);
    const Eigen::Vector2d a = middle + across * normal, b = middle - across * normal;
    const Eigen::Vector2d knee = a.x() < b.x() ? a : b;  // (y, z): the smaller y is outward
    return std::atan2(-knee.y(), -(knee.x() - hip.x()));
  }

  Eigen::Vector3d joints(const Eigen::Vector3d& p) const {
    // Joint i's thigh is joint 0's turned by 120 i deg: turn the point back by as much.
    return {joint0(p), joint0(turned(p, -2 * M_PI / 3)), joint0(turned(p, 2 * M_PI / 3))};
  }

  // The controlled point where the three shin spheres about the knees, moved in by footradius,
  // meet: subtracting sphere 0 from spheres 1 and 2 leaves two planes, x and y linear in z; sphere
  // 0 then gives a quadratic in z, of which the lower root.
  Eigen::Vector3d point(const Eigen::Vector3d& joints) const {
    std::array<Eigen::Vector3d, 3> c;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d in_yz(
          0.0, -(platformradius - footradius + thighlength * std::cos(joints[i])),
          -thighlength * std::sin(joints[i]));
      c[i] = turned(in_yz, 2 * M_PI / 3 * i);
    }
    // 2 (c_i - c_0) . p = |c_i|^2 - |c_0|^2, i = 1, 2: [x y] = A^-1 (w - z g).
    Eigen::Matrix2d a;
    Eigen::Vector2d w, g;
    for (int i = 1; i < 3; ++i) {
      const Eigen::Vector3d n = 2 * (c[i] - c[0]);
      a.row(i - 1) << n.x(), n.y();
      w[i - 1] = c[i].squaredNorm() - c[0].squaredNorm();
      g[i - 1] = n.z();
    }
    const Eigen::Vector2d offset = a.inverse() * w, slope = -(a.inverse() * g);
    // |(offset + slope z, z) - c0|^2 = shin^2.
    const Eigen::Vector2d base = offset - c[0].head<2>();
    const double qa = slope.squaredNorm() + 1.0;
    const double qb = 2 * (base.dot(slope) - c[0].z());
    const double qc = base.squaredNorm() + c[0].z() * c[0].z() - shinlength * shinlength;
    const double z = (-qb - std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
    return {offset.x() + slope.x() * z, offset.y() + slope.y() * z, z};
  }
};

TEST(RotaryDelta, AgreesWithRotarydeltakinsPublishedEquations) {
  // The example from LinuxCNC's rdelta sample config over its workspace: the same joints for the
  // same pose, the same pose for the same joints.
  const machine::Machine rdelta = test::load_example("linuxcnc-rdelta.toml");
  const auto& model = dynamic_cast<const kinematics::RotaryDeltaKinematics&>(rdelta.kinematics());
  const kinematics::RotaryDeltaGeometry& g = model.geometry();
  EXPECT_DOUBLE_EQ(g.base_radius_mm, 254.0);  // 10 in
  EXPECT_DOUBLE_EQ(g.forearm_length_mm, 457.2);
  const PublishedRotaryDelta published{g.base_radius_mm, g.arm_length_mm, g.forearm_length_mm,
                                       g.platform_radius_mm};
  std::mt19937_64 rng(13);
  int compared = 0;
  for (const geometry::Pose& pose : test::sample_reachable_poses(rdelta, 3000, rng)) {
    kinematics::JointVector joints;
    ASSERT_TRUE(rdelta.inverse(pose, joints).ok());
    const Eigen::Vector3d expected = published.joints(pose.position_mm);
    EXPECT_LT((joints.head<3>() - expected).cwiseAbs().maxCoeff(), 1e-12)
        << pose.as_vector().transpose();
    geometry::Pose solved = rdelta.home();
    ASSERT_TRUE(rdelta.forward(joints, solved).ok());
    EXPECT_LT((published.point(joints.head<3>()) - solved.position_mm).norm(), 1e-9);
    ++compared;
  }
  EXPECT_EQ(compared, 3000);
  // And joints anywhere in the arms' limits (-45..90 deg), not only where IK led.
  std::uniform_real_distribution<double> angle(geometry::degrees_to_radians(-45),
                                               geometry::degrees_to_radians(90));
  int solved_count = 0;
  for (int k = 0; k < 3000; ++k) {
    kinematics::JointVector joints(3);
    joints << angle(rng), angle(rng), angle(rng);
    geometry::Pose solved = rdelta.home();
    if (!model.forward(joints, solved).ok()) continue;
    EXPECT_LT((published.point(joints) - solved.position_mm).norm(), 1e-9);
    EXPECT_LT((published.joints(solved.position_mm) - joints).cwiseAbs().maxCoeff(), 1e-9);
    ++solved_count;
  }
  EXPECT_GT(solved_count, 2000);  // most triples within the limits are a pose
}

// The example file with `find` replaced by `replace`: the error it gives (empty when none).
std::string error_of_edited_example(const std::string& find, const std::string& replace) {
  std::ifstream in(test::example_machine_path("linuxcnc-rdelta.toml"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  const auto at = text.find(find);
  if (at == std::string::npos) return "test text not found: " + find;
  text.replace(at, find.size(), replace);
  try {
    machine::parse_machine(text, "rdelta.toml");
  } catch (const machine::MachineFileError& error) {
    return error.what();
  }
  return "";
}

TEST(RotaryDelta, MachineFileErrorsNameLineAndKey) {
  // Line 25 is `base_radius = 10.0` in the example, 26 arm_length, 27 forearm_length.
  EXPECT_EQ(error_of_edited_example("forearm_length = 18.0", "forearm_length = -18.0"),
            "rdelta.toml:27:kinematics.forearm_length: must be a positive length");
  EXPECT_EQ(error_of_edited_example("base_radius = 10.0", "base_radius = -1.0"),
            "rdelta.toml:25:kinematics.base_radius: must be a length >= 0");
  EXPECT_NE(error_of_edited_example("arm_length = 10.0 ", "# no arm ")
                .find("kinematics.arm_length: missing"),
            std::string::npos);
  EXPECT_NE(error_of_edited_example("platform_radius = 5.0",
                                    "platform_radius = 5.0\npassthrough = [\"z\"]")
                .find("kinematics.passthrough: 'z' cannot pass through here"),
            std::string::npos);
  // Forearms too long to come up to home: the home line names the arm.
  EXPECT_EQ(error_of_edited_example("forearm_length = 18.0", "forearm_length = 28.0"),
            "rdelta.toml:57:cartesian.home: is not a usable pose: pose x 0.0000 y 0.0000 z "
            "-10.1267 in: unreachable: arm 1 cannot reach it: the platform joint is nearer than "
            "the forearm's length to every point of the elbow's circle");
  EXPECT_EQ(error_of_edited_example("", ""), "");
}

}  // namespace
}  // namespace pkm
