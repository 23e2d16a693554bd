// The N-cable robot (kinematics/cable_robot.hpp): inverse kinematics by hand, forward kinematics'
// least squares (round trips, a mismeasured cable), the Jacobian, the machine file's keys and
// the writer, on a Hangprinter v4 and a Maslow 4 (tests/data).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <utility>
#include <vector>

#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm {
namespace {

using kinematics::CableFit;
using kinematics::CableRobotKinematics;
using kinematics::JointVector;
using kinematics::StatusCode;

std::string example_text(const std::string& file) {
  std::ifstream in(std::string(PKM_SOURCE_DIR) + "/examples/machines/" + file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

machine::Machine example_machine(const std::string& file) {
  return machine::parse_machine(example_text(file), file);
}

const CableRobotKinematics& robot(const machine::Machine& m) {
  const auto* model = dynamic_cast<const CableRobotKinematics*>(&m.kinematics());
  if (model == nullptr) throw std::logic_error("not a cable robot");
  return *model;
}

// A machine file with its kinematics section's cables given as TOML text.
std::string robot_text(const std::string& kinematics, int joints) {
  std::string text =
      "name = \"test\"\nunits = \"mm\"\n[kinematics]\ntype = \"cable_robot\"\n" + kinematics;
  for (int j = 0; j < joints; ++j) {
    text += "[[joints]]\nname = \"c" + std::to_string(j + 1) +
            "\"\nmin = 1.0\nmax = 5000.0\nmax_velocity = 100.0\nmax_acceleration = 1000.0\n";
  }
  return text;
}

TEST(CableRobot, InverseByHand) {
  // Spatial: cable 1 from (0, 0, 1000) to a tie point 10 mm along x from the tool, offset 5 mm.
  const machine::Machine m = machine::parse_machine(
      robot_text("planar = false\n"
                 "[[kinematics.cables]]\nanchor = [0.0, 0.0, 1000.0]\nattach = [10.0, 0.0, 0.0]\n"
                 "offset = 5.0\n"
                 "[[kinematics.cables]]\nanchor = [1000.0, 0.0, 0.0]\n"
                 "[[kinematics.cables]]\nanchor = [0.0, 1000.0, 0.0]\n"
                 "[[kinematics.cables]]\nanchor = [-1000.0, -1000.0, 0.0]\n"
                 "[cartesian]\nmax_feed = 100.0\nmax_acceleration = 100.0\n"
                 "home = [100.0, 200.0, 300.0]\n",
                 4),
      "hand.toml");
  JointVector joints;
  ASSERT_TRUE(m.kinematics().inverse(m.home(), joints).ok());
  // (0, 0, 1000) - (110, 200, 300) = (-110, -200, 700): 12100 + 40000 + 490000 = 542100.
  EXPECT_NEAR(joints[0], std::sqrt(542100.0) + 5.0, 1e-12);
  // (1000, 0, 0) - (100, 200, 300) = (900, -200, -300): 810000 + 40000 + 90000 = 940000.
  EXPECT_NEAR(joints[1], std::sqrt(940000.0), 1e-12);
  EXPECT_NEAR(joints[3], std::sqrt(1100.0 * 1100.0 + 1200.0 * 1200.0 + 300.0 * 300.0), 1e-12);

  // Planar, a swivel arm of 150 mm and the anchor 120 mm above the sled's plane: at (300, 600) the
  // anchor (0, 1000) is 500 mm away in plan, the arm's end 350: the belt sqrt(350^2 + 120^2) = 370.
  const machine::Machine planar = machine::parse_machine(
      robot_text("planar = true\n"
                 "[[kinematics.cables]]\nanchor = [0.0, 1000.0, 120.0]\nswivel_arm = 150.0\n"
                 "[[kinematics.cables]]\nanchor = [1000.0, 1000.0, 0.0]\n"
                 "[[kinematics.cables]]\nanchor = [500.0, 0.0, 0.0]\n"
                 "[cartesian]\nmax_feed = 100.0\nmax_acceleration = 100.0\n"
                 "home = [300.0, 600.0]\n",
                 3),
      "planar.toml");
  ASSERT_TRUE(planar.kinematics().inverse(planar.home(), joints).ok());
  EXPECT_NEAR(joints[0], 370.0, 1e-12);
  EXPECT_NEAR(joints[1], std::sqrt(700.0 * 700.0 + 400.0 * 400.0), 1e-12);
  EXPECT_NEAR(joints[2], std::sqrt(200.0 * 200.0 + 600.0 * 600.0), 1e-12);
}

// Uniform poses in the machine's envelope that its IK and joint limits accept.
std::vector<geometry::Pose> envelope_poses(const machine::Machine& m, int count,
                                           std::mt19937_64& rng) {
  const auto& envelope = m.cartesian();
  std::vector<geometry::Pose> poses;
  while (static_cast<int>(poses.size()) < count) {
    geometry::Pose pose = m.home();
    for (int axis = 0; axis < 3; ++axis) {
      if (!m.kinematics().dof().controls(axis)) continue;
      std::uniform_real_distribution<double> along(envelope.envelope_min[axis],
                                                   envelope.envelope_max[axis]);
      pose.position_mm[axis] = along(rng);
    }
    JointVector joints;
    if (m.inverse(pose, joints).ok()) poses.push_back(pose);
  }
  return poses;
}

class CableRobotExample : public ::testing::TestWithParam<std::string> {};

TEST_P(CableRobotExample, InverseForwardRoundTrip) {
  const machine::Machine m = example_machine(GetParam());
  std::mt19937_64 rng(31);
  double worst_mm = 0.0;
  int most_iterations = 0;
  geometry::Pose previous = m.home();
  for (const geometry::Pose& pose : envelope_poses(m, 2000, rng)) {
    JointVector joints;
    ASSERT_TRUE(m.inverse(pose, joints).ok());
    for (const geometry::Pose& seed : {m.home(), previous}) {
      geometry::Pose solved = seed;
      const kinematics::Status status = m.forward(joints, solved);
      ASSERT_TRUE(status.ok()) << kinematics::describe(status);
      worst_mm = std::max(worst_mm, (solved.position_mm - pose.position_mm).norm());
      most_iterations = std::max(most_iterations, status.iterations);
    }
    previous = pose;
  }
  EXPECT_LE(worst_mm, 1e-9);
  // With flex, Gauss-Newton's Jacobian leaves out the stretch's (a ten-thousandth): a step more.
  EXPECT_LE(most_iterations, GetParam() == "hangprinter-v4-flex.toml" ? 16 : 12);
  std::ostringstream worst;
  worst << worst_mm;
  RecordProperty("worst_mm", worst.str());
  RecordProperty("most_iterations", most_iterations);
}

TEST_P(CableRobotExample, JacobianMatchesFiniteDifferences) {
  const machine::Machine m = example_machine(GetParam());
  std::mt19937_64 rng(7);
  const double h = 1e-3;
  for (const geometry::Pose& pose : envelope_poses(m, 200, rng)) {
    kinematics::JointJacobian jacobian;
    ASSERT_TRUE(m.kinematics().jacobian(pose, jacobian).ok());
    for (int axis = 0; axis < 3; ++axis) {
      geometry::Pose up = pose;
      geometry::Pose down = pose;
      up.position_mm[axis] += h;
      down.position_mm[axis] -= h;
      JointVector joints_up;
      JointVector joints_down;
      ASSERT_TRUE(m.kinematics().inverse(up, joints_up).ok());
      ASSERT_TRUE(m.kinematics().inverse(down, joints_down).ok());
      for (int j = 0; j < m.kinematics().joint_count(); ++j) {
        EXPECT_NEAR(jacobian(j, axis), (joints_up[j] - joints_down[j]) / (2 * h), 1e-8)
            << "joint " << j << " axis " << axis;
      }
    }
  }
}

TEST_P(CableRobotExample, ReachBoxHoldsEveryPoseWithinTheJointLimits) {
  const machine::Machine m = example_machine(GetParam());
  JointVector joint_min(m.kinematics().joint_count());
  JointVector joint_max(m.kinematics().joint_count());
  for (int j = 0; j < joint_min.size(); ++j) {
    joint_min[j] = m.joints()[j].min;
    joint_max[j] = m.joints()[j].max;
  }
  const auto box = m.kinematics().tool_position_box(joint_min, joint_max);
  ASSERT_TRUE(box.has_value());
  std::mt19937_64 rng(5);
  for (const geometry::Pose& pose : envelope_poses(m, 500, rng)) {
    EXPECT_TRUE(box->contains(pose.position_mm)) << pose.position_mm.transpose();
  }
  // A cable's max length less its offset about its centre: the Hangprinter's D line reaches
  // 3500 mm down from 2299.83 mm; the Maslow's z is its Z joint's range.
  if (GetParam() == "hangprinter-v4.toml") {
    EXPECT_DOUBLE_EQ(box->min().z(), 2299.83 - 3500.0);
  } else if (GetParam() == "hangprinter-v4-flex.toml") {
    // Stretched at most 70 N x 3500 mm x 4 strands / (4 x (20000 - 70) N): 12.2930 mm more.
    EXPECT_NEAR(box->min().z(), 2299.83 - 3500.0 - 70.0 * 3500.0 / (20000.0 - 70.0), 1e-9);
  } else {
    EXPECT_EQ(box->min().z(), -40.0);
    EXPECT_EQ(box->max().z(), 20.0);
    EXPECT_DOUBLE_EQ(box->max().x(), -27.6 + 3300.0 + 153.4);  // the top left belt
  }
}

TEST_P(CableRobotExample, WriterReadsBack) {
  const std::string text = example_text(GetParam());
  const machine::Machine m = machine::parse_machine(text, GetParam());
  const std::string written =
      machine::replace_kinematics_section(text, GetParam(), m.kinematics(), m.units());
  const machine::Machine again = machine::parse_machine(written, "written.toml");
  const auto before = m.kinematics().parameters();
  const auto after = again.kinematics().parameters();
  ASSERT_EQ(before.size(), after.size());
  for (std::size_t k = 0; k < before.size(); ++k) {
    EXPECT_EQ(before[k].name, after[k].name);
    EXPECT_EQ(before[k].value, after[k].value) << before[k].name;
  }
  const auto& g = robot(m).geometry();
  const auto& h = robot(again).geometry();
  EXPECT_EQ(g.planar, h.planar);
  EXPECT_EQ(g.effector_mass_kg, h.effector_mass_kg);
  EXPECT_EQ(g.tension_limited, h.tension_limited);
  EXPECT_EQ(g.tension_max_N, h.tension_max_N);
  for (std::size_t i = 0; i < g.cables.size(); ++i) {
    EXPECT_EQ(g.cables[i].swivel_arm_mm, h.cables[i].swivel_arm_mm);
  }
  EXPECT_EQ(m.kinematics().joint_count(), again.kinematics().joint_count());
  EXPECT_EQ(machine::kinematics_toml(again.kinematics(), again.units()),
            machine::kinematics_toml(m.kinematics(), m.units()));
}

INSTANTIATE_TEST_SUITE_P(Data, CableRobotExample,
                         ::testing::Values("hangprinter-v4.toml", "hangprinter-v4-flex.toml",
                                           "maslow4.toml"),
                         [](const auto& test_info) {
                           std::string name = test_info.param;
                           name = name.substr(0, name.find('.'));
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// The joints of `pose` with `cable` read `excess_mm` long.
JointVector joints_with_excess(const machine::Machine& m, const geometry::Pose& pose, int cable,
                               double excess_mm) {
  JointVector joints;
  if (!m.kinematics().inverse(pose, joints).ok()) throw std::logic_error("pose out of reach");
  joints[cable] += excess_mm;
  return joints;
}

// Maslow 4's belt length as its firmware computes it (MaslowKinematics::computeTL and its
// siblings), in its own coordinates about the frame's centre, written here from its equation.
double maslow_belt(double corner_x, double corner_y, double corner_z, double x, double y,
                   double z) {
  constexpr double kCentreX = 1461.9000902928362;  // the frame's diagonals' crossing
  constexpr double kCentreY = 1033.0733975960557;
  constexpr double kArmAndBeltEnd = 123.4 + 30.0;
  const double a = corner_x - (x + kCentreX);
  const double b = corner_y - (y + kCentreY);
  const double c = 0.0 - (z + corner_z);
  const double in_plan = std::sqrt(a * a + b * b) - kArmAndBeltEnd;
  return std::sqrt(in_plan * in_plan + c * c);
}

TEST(CableRobot, MaslowBeltsAsItsFirmwareComputesThem) {
  const machine::Machine m = example_machine("maslow4.toml");
  const double corners[4][3] = {
      {-27.6, 2064.9, 100.0}, {2924.3, 2066.5, 56.0}, {0.0, 0.0, 34.0}, {2953.2, 0.0, 78.0}};
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> across(-1200.0, 1200.0);
  std::uniform_real_distribution<double> up_down(-600.0, 600.0);
  std::uniform_real_distribution<double> plunge(-40.0, 20.0);
  double worst = 0.0;
  for (int sample = 0; sample < 1000; ++sample) {
    const double x = across(rng);
    const double y = up_down(rng);
    const double z = plunge(rng);
    geometry::Pose pose = m.home();
    pose.position_mm = {x + 1461.9000902928362, y + 1033.0733975960557, z};
    JointVector joints;
    ASSERT_TRUE(m.kinematics().inverse(pose, joints).ok());
    for (int belt = 0; belt < 4; ++belt) {
      const double theirs =
          maslow_belt(corners[belt][0], corners[belt][1], corners[belt][2], x, y, z);
      worst = std::max(worst, std::abs(joints[belt] - theirs));
    }
    EXPECT_EQ(joints[4], z);
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(CableRobot, MaslowNamesTheMismeasuredBelt) {
  // Four belts in a plane: two more than coordinates, so one belt's error shows as its own.
  const machine::Machine m = example_machine("maslow4.toml");
  const CableRobotKinematics& model = robot(m);
  geometry::Pose pose = m.home();
  pose.position_mm = {900.0, 700.0, -5.0};
  for (int cable = 0; cable < 4; ++cable) {
    const JointVector joints = joints_with_excess(m, pose, cable, 1.0);
    geometry::Pose solved = m.home();
    const kinematics::Status status = m.forward(joints, solved);
    EXPECT_EQ(status.code, StatusCode::unreachable);
    EXPECT_EQ(status.joint, cable);
    const CableFit fit = model.fit(joints, m.home());
    ASSERT_TRUE(fit.status.ok());
    EXPECT_EQ(fit.culprit, cable);
    EXPECT_NEAR(fit.alone_excess_mm[cable], 1.0, 1e-3);
    EXPECT_GT(fit.worst_mm, 0.1);
    const std::string text = model.explain_misfit(fit, m.joint_names());
    EXPECT_NE(
        text.find("cable '" + m.joint_names()[cable] + "' alone explains it: it reads 1.000 mm"),
        std::string::npos)
        << text;
  }
}

TEST(CableRobot, HangprinterRefusesAMismeasuredLineAndSaysAnyCouldBeIt) {
  // Four lines in space, one more than coordinates: any one line's error fits the misfit.
  const machine::Machine m = example_machine("hangprinter-v4.toml");
  const CableRobotKinematics& model = robot(m);
  geometry::Pose pose = m.home();
  pose.position_mm = {150.0, -100.0, 400.0};
  const JointVector joints = joints_with_excess(m, pose, 1, 1.0);
  geometry::Pose solved = m.home();
  const kinematics::Status status = m.forward(joints, solved);
  ASSERT_EQ(status.code, StatusCode::unreachable);
  const CableFit fit = model.fit(joints, m.home());
  ASSERT_TRUE(fit.status.ok());
  EXPECT_EQ(status.joint, fit.worst_cable);
  EXPECT_EQ(fit.culprit, -1);
  EXPECT_NEAR(fit.alone_excess_mm[1], 1.0, 1e-3);
  for (int cable = 0; cable < 4; ++cable) EXPECT_LE(fit.alone_worst_mm[cable], 0.01);
  const std::string text = model.explain_misfit(fit, m.joint_names());
  EXPECT_NE(text.find("'B' by +1.000 mm"), std::string::npos) << text;
  EXPECT_NE(text.find("cannot tell which"), std::string::npos) << text;

  // A misfit within the tolerance (a joint program's rounding, a few micrometres) is a pose.
  const JointVector close = joints_with_excess(m, pose, 1, 0.004);
  geometry::Pose near = m.home();
  ASSERT_TRUE(m.forward(close, near).ok());
  EXPECT_LT((near.position_mm - pose.position_mm).norm(), 0.01);
  EXPECT_GT(model.fit(close, m.home()).worst_mm, 1e-4);
}

TEST(CableRobot, ForwardFromAFarSeedFindsTheJointsPose) {
  const machine::Machine m = example_machine("hangprinter-v4.toml");
  geometry::Pose pose = m.home();
  pose.position_mm = {-300.0, 200.0, 1200.0};
  JointVector joints;
  ASSERT_TRUE(m.inverse(pose, joints).ok());
  // The mirror image of the pose across the plane of A, B and C, and a seed beyond the frame.
  for (const Eigen::Vector3d& start :
       {Eigen::Vector3d(-300.0, 200.0, -1450.0), Eigen::Vector3d(5000.0, -5000.0, 9000.0)}) {
    geometry::Pose solved = m.home();
    solved.position_mm = start;
    ASSERT_TRUE(m.kinematics().forward(joints, solved).ok());
    EXPECT_LT((solved.position_mm - pose.position_mm).norm(), 1e-9);
  }
}

// Flex compensation (hangprinter-v4-flex.toml): forward kinematics inverts the unstretched
// lengths, stretch and all, to 1e-9 mm over a grid of the workspace and from a far seed; the
// stretch is D's alone at home (A B C at their 0 N minimum), and grows towards the frame's edge.
TEST(CableRobot, FlexCompensationRoundTripsAndStretchesTheLines) {
  const machine::Machine flex = example_machine("hangprinter-v4-flex.toml");
  const machine::Machine straight = example_machine("hangprinter-v4.toml");
  double worst = 0.0, most_stretch = 0.0;
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  int poses = 0;
  for (double x = -900.0; x <= 900.0; x += 300.0) {
    for (double y = -900.0; y <= 900.0; y += 300.0) {
      for (double z = 0.0; z <= 1800.0; z += 300.0) {
        const geometry::Pose pose = geometry::Pose::from_mm_deg(x, y, z);
        JointVector joints, lengths;
        if (!flex.inverse(pose, joints).ok()) continue;
        ASSERT_TRUE(straight.inverse(pose, lengths).ok());
        if ((lengths - joints).maxCoeff() > most_stretch) {
          most_stretch = (lengths - joints).maxCoeff();
          where = pose.position_mm;
        }
        EXPECT_GE((lengths - joints).minCoeff(), 0.0);
        geometry::Pose solved = flex.home();
        solved.position_mm = {5000.0, -5000.0, 9000.0};
        ASSERT_TRUE(flex.kinematics().forward(joints, solved).ok()) << x << " " << y << " " << z;
        worst = std::max(worst, (solved.position_mm - pose.position_mm).norm());
        ++poses;
      }
    }
  }
  std::printf("flex: %d poses, worst FK error %.3g mm, largest stretch %.4f mm at %g %g %g\n",
              poses, worst, most_stretch, where.x(), where.y(), where.z());
  EXPECT_GT(poses, 90);
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(most_stretch, 1.127);
  JointVector home, lengths;
  ASSERT_TRUE(flex.inverse(flex.home(), home).ok());
  ASSERT_TRUE(straight.inverse(straight.home(), lengths).ok());
  EXPECT_NEAR(lengths[3] - home[3], 9.81 / 1.001 * 2299.83 / 20000.0, 1e-6);
  EXPECT_EQ(lengths[0] - home[0], 0.0);
}

TEST(CableRobot, FlexCompensationNeedsTensionLimits) {
  std::string text = example_text("hangprinter-v4-flex.toml");
  const std::string limits = "tension_limits = [0.0, 70.0]    # N (M666 I0.0, X70.0)\n";
  text.erase(text.find(limits), limits.size());
  try {
    machine::parse_machine(text, "flex.toml");
    ADD_FAILURE() << "flex without tension_limits";
  } catch (const machine::MachineFileError& error) {
    EXPECT_NE(std::string(error.what()).find("flex_compensation: needs tension_limits"),
              std::string::npos)
        << error.what();
  }
}

TEST(CableRobot, RefusesAnAnchorWithinItsArmAndSaysWhy) {
  const machine::Machine m = example_machine("maslow4.toml");
  geometry::Pose pose = m.home();
  pose.position_mm = {30.0, 40.0, 0.0};  // 50 mm from the bottom left corner, its arm 153.4
  JointVector joints;
  const kinematics::Status status = m.kinematics().inverse(pose, joints);
  EXPECT_EQ(status.code, StatusCode::unreachable);
  EXPECT_EQ(status.joint, 2);
  EXPECT_EQ(m.kinematics().why_refused(pose, status),
            "cable 3's anchor is 50.000 mm from its arm's pivot in plan view, within the swivel "
            "arm's 153.400 mm");
}

TEST(CableRobot, SketchDrawsEachCableFromItsAnchor) {
  const machine::Machine m = example_machine("maslow4.toml");
  const kinematics::MechanismSketch* sketch = m.kinematics().sketch();
  ASSERT_NE(sketch, nullptr);
  JointVector joints;
  ASSERT_TRUE(m.kinematics().inverse(m.home(), joints).ok());
  std::vector<kinematics::SketchLine> lines;
  sketch->moving_parts(m.home(), joints, lines);
  int cables = 0;
  for (const kinematics::SketchLine& line : lines) {
    if (line.part != kinematics::SketchPart::link) continue;
    // Each belt runs from its anchor to its arm's end, as long as its joint says.
    EXPECT_NEAR((line.to - line.from).norm(), joints[cables], 1e-9);
    ++cables;
  }
  EXPECT_EQ(cables, 4);
}

struct BadKey {
  std::string name;
  std::string file;
  std::vector<std::pair<std::string, std::string>> edits;  // each first occurrence replaced
  std::string key;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const BadKey& c) {
  return out << c.name;
}

class CableRobotBadKey : public ::testing::TestWithParam<BadKey> {};

int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return -1;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
}

TEST_P(CableRobotBadKey, NamesFileLineAndKey) {
  const BadKey& c = GetParam();
  std::string text = example_text(c.file);
  for (const auto& [find, replace] : c.edits) {
    const auto at = text.find(find);
    ASSERT_NE(at, std::string::npos) << find;
    text.replace(at, find.size(), replace);
  }
  try {
    machine::parse_machine(text, "case.toml");
    FAIL() << "accepted";
  } catch (const machine::MachineFileError& error) {
    EXPECT_EQ(error.line(), line_of(text, "# <-")) << error.what();
    EXPECT_EQ(error.key(), c.key) << error.what();
    EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
  }
}

const std::string kFirstCable = "[[kinematics.cables]]           # A\n";
const std::string kDCable =
    "[[kinematics.cables]]           # D\nanchor = [0.0, 0.01, 2299.83]\nattach = [0.0, 0.0, "
    "0.0]\nspool_radius = 75.192          # mm (M666 R)\nmechanical_advantage = 4        # M666 "
    "U\n";
const std::string kTwoBelts =
    "[[kinematics.cables]]           # top right\nanchor = [2924.3, 2066.5, 0.0]\n"
    "attach = [0.0, 0.0, 56.0]\nswivel_arm = 153.4\n\n"
    "[[kinematics.cables]]           # bottom left\nanchor = [0.0, 0.0, 0.0]\n"
    "attach = [0.0, 0.0, 34.0]\nswivel_arm = 153.4\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, CableRobotBadKey,
    ::testing::Values(
        BadKey{"three_cables_in_space",
               "hangprinter-v4.toml",
               {{kDCable, ""}, {kFirstCable, "[[kinematics.cables]] # <-\n"}},
               "kinematics.cables",
               "a spatial cable robot needs at least 4 cables"},
        BadKey{"half_a_strand",
               "hangprinter-v4.toml",
               {{"mechanical_advantage = 4        # M666 U", "mechanical_advantage = 2.5 # <-"}},
               "kinematics.cables[4].mechanical_advantage",
               "must be a whole number from 1 to 100000, got 2.5"},
        BadKey{"shared_spool_key_without_a_radius",
               "hangprinter-v4.toml",
               {{"spool_radius = 75.192          # mm (M666 R)\nmechanical_advantage = 4        # "
                 "M666 U\n",
                 ""},
                {"lines_per_spool = 1             # M666 O, for every cable",
                 "lines_per_spool = 1 # <-"}},
               "kinematics.lines_per_spool",
               "cable 4 has no spool_radius"},
        BadKey{"two_belts_in_a_plane",
               "maslow4.toml",
               {{kTwoBelts, ""}, {"# top left\n", "# <-\n"}},
               "kinematics.cables",
               "a planar cable robot needs at least 3 cables"},
        BadKey{
            "anchor_not_a_number",
            "hangprinter-v4.toml",
            {{"anchor = [1314.22, 1268.14, -121.28]", "anchor = [1314.22, \"x\", -121.28] # <-"}},
            "kinematics.cables[2].anchor",
            "must be a number"},
        BadKey{"pulley_without_its_axis",
               "hangprinter-v4.toml",
               {{"attach = [0.0, 0.0, 0.0]\n",
                 "attach = [0.0, 0.0, 0.0]\npulley_radius = 10.0 # <-\n"}},
               "kinematics.cables[1].pulley_radius",
               "needs pulley_axis = [x, y, z]"},
        BadKey{"negative_swivel_arm",
               "maslow4.toml",
               {{"swivel_arm = 153.4", "swivel_arm = -1.0 # <-"}},
               "kinematics.cables[1].swivel_arm",
               "must be a length of 0 or more"},
        BadKey{"follow_z_without_a_z_joint",
               "maslow4.toml",
               {{"passthrough = [\"z\"]\n", ""},
                {"cables_follow_z = true", "cables_follow_z = true # <-"},
                {"[[joints]]\nname = \"z\"", "[[no_joints]]\nname = \"z\""}},
               "kinematics.cables_follow_z",
               "needs the tool's z as a pass-through joint"},
        BadKey{"tension_limits_backwards",
               "hangprinter-v4.toml",
               {{"tension_limits = [0.0, 70.0]", "tension_limits = [70.0, 0.0] # <-"}},
               "kinematics.tension_limits",
               "0 <= min < max"},
        BadKey{"unknown_key",
               "hangprinter-v4.toml",
               {{"attach = [0.0, 0.0, 0.0]\n", "atach = [0.0, 0.0, 0.0] # <-\n"}},
               "kinematics.cables[1].atach",
               "unknown key"}),
    [](const auto& test_info) { return test_info.param.name; });

}  // namespace
}  // namespace pkm
