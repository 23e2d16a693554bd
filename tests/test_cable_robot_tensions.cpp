// The cable robot's tension distribution (kinematics/cable_robot_tensions.cpp): the load by hand,
// the Hangprinter v4's tensions at home checked by the balance and the optimality they must
// satisfy, a pose on the plane of three anchors refused with the fourth cable's tension worked
// out by hand, continuity along a line, a planar robot on a vertical and a tilted sheet, and the
// machine file's keys.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm {
namespace {

using kinematics::CableRobotKinematics;
using kinematics::formatted_number;
using kinematics::JointVector;
using kinematics::StatusCode;
using kinematics::TensionDistribution;

constexpr double kWeightOf1kg_N = 9.80665;

std::string hangprinter_text() {
  std::ifstream in(std::string(PKM_SOURCE_DIR) + "/examples/machines/hangprinter-v4.toml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string replaced(std::string text, const std::string& find, const std::string& by) {
  const auto at = text.find(find);
  if (at == std::string::npos) throw std::logic_error("not in the file: " + find);
  return text.replace(at, find.size(), by);
}

const CableRobotKinematics& robot(const machine::Machine& m) {
  const auto* model = dynamic_cast<const CableRobotKinematics*>(&m.kinematics());
  if (model == nullptr) throw std::logic_error("not a cable robot");
  return *model;
}

geometry::Pose at(const machine::Machine& m, const Eigen::Vector3d& position_mm) {
  geometry::Pose pose = m.home();
  pose.position_mm = position_mm;
  return pose;
}

// The Hangprinter's anchors A B C D (examples/machines/hangprinter-v4.toml).
const Eigen::Vector3d kA(0.0, -1610.98, -131.53);
const Eigen::Vector3d kB(1314.22, 1268.14, -121.28);
const Eigen::Vector3d kC(-1415.73, 707.61, -121.82);
const Eigen::Vector3d kD(0.0, 0.01, 2299.83);
// A point of the plane through A, B and D, inside the envelope: 0.35 A + 0.35 B + 0.3 D.
const Eigen::Vector3d kOnPlaneABD(459.977, -119.991, 601.4655);

TEST(CableRobotTensions, HangprinterHoldsItsWeightAtHome) {
  const machine::Machine m = machine::parse_machine(hangprinter_text(), "hangprinter-v4.toml");
  const CableRobotKinematics& model = robot(m);
  // 1 kg (M666 W1.0) under g along -z: 9.80665 N down, the load the cables balance.
  const Eigen::VectorXd w = model.wrench_N(Eigen::Vector3d::Zero());
  ASSERT_EQ(w.size(), 3);
  EXPECT_EQ(w[0], 0.0);
  EXPECT_EQ(w[1], 0.0);
  EXPECT_DOUBLE_EQ(w[2], -kWeightOf1kg_N);

  const std::optional<TensionDistribution> d = model.tensions(m.home());
  ASSERT_TRUE(d.has_value());
  ASSERT_TRUE(d->held()) << kinematics::describe_refusal(*d);
  // The balance, from the anchors themselves (each cable pulls towards its anchor).
  Eigen::Vector3d pull = Eigen::Vector3d::Zero();
  const Eigen::Vector3d anchors[4] = {kA, kB, kC, kD};
  for (int i = 0; i < 4; ++i) {
    EXPECT_GE(d->tension_N[i], 0.0);
    EXPECT_LE(d->tension_N[i], 70.0);
    pull += d->tension_N[i] * anchors[i].normalized();  // home is the origin
  }
  EXPECT_LT((pull - Eigen::Vector3d(0.0, 0.0, kWeightOf1kg_N)).norm(), 1e-9);
  // The nearest to the preferred 35 N (the middle of [0, 70]) with no cable at a limit: t - 35
  // lies in the row space of A (t = 35 + A^T lambda), the optimality the projection satisfies.
  const Eigen::MatrixXd a = model.structure_matrix(m.home());
  const Eigen::VectorXd off = d->tension_N - Eigen::VectorXd::Constant(4, 35.0);
  const Eigen::VectorXd lambda = a.transpose().colPivHouseholderQr().solve(off);
  EXPECT_LT((a.transpose() * lambda - off).norm(), 1e-9);
  // The four tensions, for the docs (D carries the weight and pulls the others up).
  for (int i = 0; i < 4; ++i) {
    RecordProperty("tension_" + std::string(1, static_cast<char>('A' + i)),
                   formatted_number("%.6f", d->tension_N[i]));
  }
  JointVector joints;
  EXPECT_TRUE(m.inverse(m.home(), joints).ok());
}

TEST(CableRobotTensions, RefusesAPoseOnThePlaneOfThreeAnchorsNamingTheFourth) {
  const machine::Machine m = machine::parse_machine(hangprinter_text(), "hangprinter-v4.toml");
  const geometry::Pose pose = at(m, kOnPlaneABD);
  // On the plane of A, B and D their cables pull within it: across it (its normal n) only C's
  // can balance the weight, t_C (u_C . n) = -(w . n), whatever the others.
  const Eigen::Vector3d n = (kB - kA).cross(kD - kA);
  const Eigen::Vector3d u_c = (kC - kOnPlaneABD).normalized();
  const Eigen::Vector3d w(0.0, 0.0, -kWeightOf1kg_N);
  const double t_c = -w.dot(n) / u_c.dot(n);
  ASSERT_LT(t_c, -1.0);  // C would have to push

  JointVector joints;
  const kinematics::Status status = m.kinematics().inverse(pose, joints);
  EXPECT_EQ(status.code, StatusCode::tension);
  EXPECT_EQ(status.joint, 2);
  const std::optional<TensionDistribution> d = robot(m).tensions(pose);
  ASSERT_TRUE(d.has_value());
  ASSERT_EQ(d->violations.size(), 1u);
  EXPECT_NEAR(d->violations[0].tension_N, t_c, 1e-9);
  EXPECT_LT(d->equilibrium_residual_N, 1e-9);
  EXPECT_EQ(m.kinematics().why_refused(pose, status),
            "no tensions within tension_limits [0.000, 70.000] N hold the 1.000 kg effector "
            "here: cable 3 would need " +
                formatted_number("%.3f", t_c) + " N (its min 0.000 N)");
  RecordProperty("t_C_N", formatted_number("%.6f", t_c));
  // The machine says it with the pose (pkm ik's words).
  const kinematics::Status refused = m.inverse(pose, joints);
  EXPECT_EQ(refused.code, StatusCode::tension);
  EXPECT_NE(m.explain(pose, refused).find("tension: no tensions within tension_limits"),
            std::string::npos)
      << m.explain(pose, refused);
}

// The largest change of any tension between neighbours along home -> kOnPlaneABD while held, and
// how many times the line passes from held to refused.
struct AlongTheLine {
  double largest_step_N = 0.0;
  int held = 0;
  int changes = 0;
};

AlongTheLine walk(const machine::Machine& m, int steps) {
  AlongTheLine result;
  Eigen::VectorXd previous;
  bool was_held = true;
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector3d p = (static_cast<double>(k) / steps) * kOnPlaneABD;
    const std::optional<TensionDistribution> d = robot(m).tensions(at(m, p));
    if (!d) throw std::logic_error("no tensions");
    if (d->held() != was_held) ++result.changes;
    was_held = d->held();
    if (!d->held()) continue;
    ++result.held;
    if (previous.size() > 0) {
      result.largest_step_N =
          std::max(result.largest_step_N, (d->tension_N - previous).lpNorm<Eigen::Infinity>());
    }
    previous = d->tension_N;
  }
  return result;
}

TEST(CableRobotTensions, ContinuousAlongALineUntilRefused) {
  const machine::Machine m = machine::parse_machine(hangprinter_text(), "hangprinter-v4.toml");
  const AlongTheLine coarse = walk(m, 400);
  const AlongTheLine fine = walk(m, 800);
  // Held from home, refused once before the plane of A, B and D, and never held again.
  EXPECT_EQ(coarse.changes, 1);
  EXPECT_EQ(fine.changes, 1);
  EXPECT_GT(coarse.held, 100);
  // Continuous: halving the step halves the largest change (a jump would stay). The steepest
  // part is the last 27 mm before the refusal, where C is held at its min 0 N and the others'
  // pretension rises towards 70 N to keep it there: 2.26 N/mm (steps of 1.96 mm here).
  const double step_mm = kOnPlaneABD.norm() / 400.0;
  EXPECT_LT(coarse.largest_step_N / step_mm, 2.5);
  EXPECT_NEAR(fine.largest_step_N / coarse.largest_step_N, 0.5, 0.05);
  // The last held pose: 96.25 % of the way (29 mm before the plane).
  EXPECT_EQ(coarse.held, 386);
  RecordProperty("largest_step_N", formatted_number("%.6f", coarse.largest_step_N));
  RecordProperty("held_of_401", coarse.held);
}

// inverse() decides first by the projection of the preferred tensions (no allocation), then by
// the full distribution: it refuses exactly the poses the distribution does not hold.
TEST(CableRobotTensions, InverseRefusesExactlyWhereTheDistributionIsNotHeld) {
  const machine::Machine m = machine::parse_machine(hangprinter_text(), "hangprinter-v4.toml");
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> across(-1000.0, 1000.0), up(-10.0, 2000.0);
  int refused = 0, at_a_limit = 0;
  for (int k = 0; k < 3000; ++k) {
    const geometry::Pose pose = at(m, {across(rng), across(rng), up(rng)});
    JointVector joints;
    const kinematics::Status status = m.kinematics().inverse(pose, joints);
    const std::optional<TensionDistribution> d = robot(m).tensions(pose);
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(status.code == StatusCode::tension, !d->held()) << pose.position_mm.transpose();
    if (!d->held()) {
      ++refused;
      EXPECT_EQ(status.joint, d->violations.at(0).cable);
    } else if ((d->tension_N.array() <= 1e-9).any() ||
               (d->tension_N.array() >= 70.0 - 1e-9).any()) {
      ++at_a_limit;  // held only with a cable at its limit: the full method's answer
    }
  }
  // Both kinds occur in the envelope (the wrench-feasible part is a prism over A B C, narrower
  // up near D).
  EXPECT_GT(refused, 300);
  EXPECT_GT(at_a_limit, 10);
  RecordProperty("refused_of_3000", refused);
  RecordProperty("held_at_a_limit", at_a_limit);
}

TEST(CableRobotTensions, AnAccelerationChangesTheLoad) {
  const machine::Machine m = machine::parse_machine(hangprinter_text(), "hangprinter-v4.toml");
  const CableRobotKinematics& model = robot(m);
  // Falling freely the effector weighs nothing; pushed along x at 1000 mm/s^2 the cables must
  // also pull it 1 N along x: w = m (g - a) = (-1, 0, -9.80665) N.
  EXPECT_LT(model.wrench_N({0.0, 0.0, -9806.65}).norm(), 1e-12);
  const Eigen::Vector3d a(1000.0, 0.0, 0.0);
  const Eigen::VectorXd w = model.wrench_N(a);
  EXPECT_NEAR(w[0], -1.0, 1e-12);
  EXPECT_NEAR(w[2], -kWeightOf1kg_N, 1e-12);
  const std::optional<TensionDistribution> d = model.tensions(m.home(), a);
  ASSERT_TRUE(d.has_value() && d->held());
  EXPECT_LT((model.structure_matrix(m.home()) * d->tension_N + w).norm(), 1e-9);
}

TEST(CableRobotTensions, WithoutTensionLimitsNothingIsRefusedForTensions) {
  const machine::Machine m = machine::parse_machine(
      replaced(hangprinter_text(), "tension_limits = [0.0, 70.0]", ""), "no-limits.toml");
  JointVector joints;
  EXPECT_TRUE(m.kinematics().inverse(at(m, kOnPlaneABD), joints).ok());
  EXPECT_TRUE(m.kinematics().inverse(at(m, 1.2 * kOnPlaneABD), joints).ok());
  // The tensions are still there to see: [0, inf), nearest 0; on the plane C would push.
  const std::optional<TensionDistribution> d = robot(m).tensions(at(m, kOnPlaneABD));
  ASSERT_TRUE(d.has_value());
  EXPECT_FALSE(d->held());
  EXPECT_EQ(d->violations.at(0).cable, 2);
}

TEST(CableRobotTensions, PreferredTensionMovesTheDistribution) {
  const machine::Machine m =
      machine::parse_machine(replaced(hangprinter_text(), "tension_limits = [0.0, 70.0]",
                                      "tension_limits = [0.0, 70.0]\npreferred_tension = 10.0"),
                             "preferred.toml");
  const CableRobotKinematics& model = robot(m);
  const std::optional<TensionDistribution> d = model.tensions(m.home());
  ASSERT_TRUE(d.has_value() && d->held());
  const Eigen::MatrixXd a = model.structure_matrix(m.home());
  EXPECT_LT((a * d->tension_N + model.wrench_N(Eigen::Vector3d::Zero())).norm(), 1e-9);
  const Eigen::VectorXd off = d->tension_N - Eigen::VectorXd::Constant(4, 10.0);
  const Eigen::VectorXd lambda = a.transpose().colPivHouseholderQr().solve(off);
  EXPECT_LT((a.transpose() * lambda - off).norm(), 1e-9);
  // Written back as read.
  const std::string toml = machine::kinematics_toml(m.kinematics(), m.units());
  EXPECT_NE(toml.find("preferred_tension = 10"), std::string::npos) << toml;
}

// Four cables to the corners of a 1000 mm square, 2 kg at its centre, limits [5, 100] N.
std::string square_robot(const std::string& gravity) {
  std::string text =
      "name = \"square\"\nunits = \"mm\"\n[kinematics]\ntype = \"cable_robot\"\nplanar = true\n"
      "effector_mass = 2.0\ntension_limits = [5.0, 100.0]\n" +
      gravity +
      "[[kinematics.cables]]\nanchor = [0.0, 1000.0, 0.0]\n"
      "[[kinematics.cables]]\nanchor = [1000.0, 1000.0, 0.0]\n"
      "[[kinematics.cables]]\nanchor = [0.0, 0.0, 0.0]\n"
      "[[kinematics.cables]]\nanchor = [1000.0, 0.0, 0.0]\n";
  for (int j = 0; j < 4; ++j) {
    text += "[[joints]]\nname = \"c" + std::to_string(j + 1) +
            "\"\nmin = 1.0\nmax = 5000.0\nmax_velocity = 100.0\nmax_acceleration = 1000.0\n";
  }
  return text + "[cartesian]\nmax_feed = 100.0\nmax_acceleration = 100.0\nhome = [500.0, 500.0]\n";
}

TEST(CableRobotTensions, PlanarRobotOnAVerticalAndATiltedSheet) {
  // Each cable at 45 degrees; the preferred 52.5 N balances nothing (the pulls cancel), so the
  // projection adds A^T lambda with A A^T = 2 I: lambda = (0, m g / 2), each cable
  // 52.5 +- (m g / 2) / sqrt(2), the upper ones more.
  for (const auto& [gravity, share] :
       {std::pair<std::string, double>{"gravity = [0, -1, 0]\n", 1.0},
        {"gravity = [0, -0.5, -0.8660254037844386]\n", 0.5}}) {
    const machine::Machine m = machine::parse_machine(square_robot(gravity), "square.toml");
    const std::optional<TensionDistribution> d = robot(m).tensions(m.home());
    ASSERT_TRUE(d.has_value() && d->held()) << gravity;
    const double change = share * 2.0 * kWeightOf1kg_N / 2.0 / std::sqrt(2.0);
    EXPECT_NEAR(d->tension_N[0], 52.5 + change, 1e-9) << gravity;
    EXPECT_NEAR(d->tension_N[1], 52.5 + change, 1e-9) << gravity;
    EXPECT_NEAR(d->tension_N[2], 52.5 - change, 1e-9) << gravity;
    EXPECT_NEAR(d->tension_N[3], 52.5 - change, 1e-9) << gravity;
  }
  // Level: the sheet takes the weight, the cables only pull against each other.
  const machine::Machine level =
      machine::parse_machine(square_robot("gravity = [0, 0, -1]\n"), "level.toml");
  const std::optional<TensionDistribution> d = robot(level).tensions(level.home());
  ASSERT_TRUE(d.has_value() && d->held());
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(d->tension_N[i], 52.5, 1e-9);
  // `gravity` is written back as read.
  const machine::Machine tilted = machine::parse_machine(
      square_robot("gravity = [0, -0.5, -0.8660254037844386]\n"), "tilted.toml");
  const std::string toml = machine::kinematics_toml(tilted.kinematics(), tilted.units());
  EXPECT_NE(toml.find("gravity = [0"), std::string::npos) << toml;
  const machine::Machine again =
      machine::parse_machine(machine::replace_kinematics_section(
                                 square_robot("gravity = [0, -0.5, -0.8660254037844386]\n"),
                                 "tilted.toml", tilted.kinematics(), tilted.units()),
                             "again.toml");
  EXPECT_EQ(robot(again).geometry().gravity_direction, robot(tilted).geometry().gravity_direction);
  EXPECT_TRUE(robot(again).geometry().gravity_given);
}

struct BadLoad {
  std::string name;
  std::string text;
  std::string key;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const BadLoad& c) {
  return out << c.name;
}

class CableRobotBadLoad : public ::testing::TestWithParam<BadLoad> {};

TEST_P(CableRobotBadLoad, NamesTheKey) {
  try {
    machine::parse_machine(GetParam().text, "case.toml");
    FAIL() << "accepted";
  } catch (const machine::MachineFileError& error) {
    EXPECT_EQ(error.key(), GetParam().key) << error.what();
    EXPECT_GT(error.line(), 0) << error.what();
    EXPECT_NE(std::string(error.what()).find(GetParam().message), std::string::npos)
        << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CableRobotBadLoad,
    ::testing::Values(BadLoad{"planar_weight_without_gravity", square_robot(""),
                              "kinematics.effector_mass", "needs `gravity = [gx, gy, gz]`"},
                      BadLoad{"gravity_zero", square_robot("gravity = [0, 0, 0]\n"),
                              "kinematics.gravity", "not zero"},
                      BadLoad{"gravity_off_the_sheet", square_robot("gravity = [0, -1, 0.1]\n"),
                              "kinematics.gravity", "z must be 0 or less"},
                      BadLoad{"preferred_above_the_max",
                              replaced(hangprinter_text(), "tension_limits = [0.0, 70.0]",
                                       "tension_limits = [0.0, 70.0]\npreferred_tension = 80.0"),
                              "kinematics.preferred_tension", "must be within tension_limits"}),
    [](const auto& test_info) { return test_info.param.name; });

}  // namespace
}  // namespace pkm
