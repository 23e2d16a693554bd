// The cable robot's swivelling pulleys (kinematics/cable_robot_pulley.cpp): lengths by hand
// (planar and spatial), inverse-forward round trips, the Jacobian against finite differences, the
// Hessian bound over balls, the machine file's keys and errors, the firmware loss.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm {
namespace {

using kinematics::CableRobotGeometry;
using kinematics::CableRobotKinematics;
using kinematics::JointVector;
using kinematics::RobotCable;

RobotCable cable(const Eigen::Vector3d& anchor, double pulley_radius = 0.0,
                 const Eigen::Vector3d& axis = Eigen::Vector3d::Zero()) {
  RobotCable c;
  c.anchor_mm = anchor;
  c.pulley_radius_mm = pulley_radius;
  c.pulley_axis = axis;
  return c;
}

geometry::Pose pose_at(double x, double y, double z) {
  geometry::Pose pose;
  pose.position_mm = {x, y, z};
  return pose;
}

// The hand case: a pulley of radius 10 whose cable arrives along -w at the anchor, the tie point
// 36 mm from the anchor across the axis (26 from the pulley's centre, level with it). The tangent
// from 26 mm: a span of sqrt(26^2 - 10^2) = 24 leaving at acos(10 / 26) before the level; the
// cable turns pi - acos(5 / 13) on the pulley; the span's direction 12/13 across, 5/13 along w.
constexpr double kHandLength_mm = 10.0 * (std::numbers::pi - 1.1760052070951352) + 24.0;

TEST(CableRobotPulley, PlanarLengthByHand) {
  CableRobotGeometry g;
  g.planar = true;
  g.cables = {cable({0.0, 1000.0, 0.0}, 10.0, {0.0, 1.0, 0.0}), cable({1000.0, 1000.0, 0.0}),
              cable({500.0, -1000.0, 0.0})};
  const CableRobotKinematics model(g);
  JointVector joints;
  ASSERT_TRUE(model.inverse(pose_at(36.0, 1000.0, 0.0), joints).ok());
  EXPECT_NEAR(joints[0], kHandLength_mm, 1e-12);
  EXPECT_NEAR(joints[0], 43.655874464946, 1e-9);
  EXPECT_NEAR(joints[1], 964.0, 1e-12);  // a straight cable unchanged
  kinematics::JointJacobian jacobian;
  ASSERT_TRUE(model.jacobian(pose_at(36.0, 1000.0, 0.0), jacobian).ok());
  EXPECT_NEAR(jacobian(0, 0), 12.0 / 13.0, 1e-12);
  EXPECT_NEAR(jacobian(0, 1), 5.0 / 13.0, 1e-12);
  // Straight below the anchor the cable does not touch the pulley: the length is the distance.
  ASSERT_TRUE(model.inverse(pose_at(1e-3, 500.0, 0.0), joints).ok());
  EXPECT_NEAR(joints[0], 500.0, 1e-6);
}

TEST(CableRobotPulley, SpatialLengthByHand) {
  // The same pulley swivelled: axis z (the cable comes down from a winch above the anchor), the
  // tie point 36 mm across it along (0.6, 0.8, 0): the pulley turns to face it.
  CableRobotGeometry g;
  g.cables = {cable({0.0, 0.0, 2000.0}, 10.0, {0.0, 0.0, 1.0}), cable({1000.0, 0.0, 2000.0}),
              cable({0.0, 1000.0, 2000.0}), cable({0.0, 0.0, -1000.0})};
  const CableRobotKinematics model(g);
  const geometry::Pose pose = pose_at(21.6, 28.8, 2000.0);
  JointVector joints;
  ASSERT_TRUE(model.inverse(pose, joints).ok());
  EXPECT_NEAR(joints[0], kHandLength_mm, 1e-12);
  kinematics::JointJacobian jacobian;
  ASSERT_TRUE(model.jacobian(pose, jacobian).ok());
  EXPECT_NEAR(jacobian(0, 0), 12.0 / 13.0 * 0.6, 1e-12);
  EXPECT_NEAR(jacobian(0, 1), 12.0 / 13.0 * 0.8, 1e-12);
  EXPECT_NEAR(jacobian(0, 2), 5.0 / 13.0, 1e-12);
  // The tie point on the swivel axis or within the pulley: refused, and said why.
  EXPECT_EQ(model.inverse(pose_at(0.0, 0.0, 1500.0), joints).code,
            kinematics::StatusCode::unreachable);
  const kinematics::Status within = model.inverse(pose_at(12.0, 0.0, 2000.0), joints);
  EXPECT_EQ(within.code, kinematics::StatusCode::unreachable);
  EXPECT_NE(model.why_refused(pose_at(12.0, 0.0, 2000.0), within).find("within its pulley_radius"),
            std::string::npos);
}

// Four ceiling pulleys, two fed from above and two from the frame's corners, and a fifth cable
// pulling down.
CableRobotKinematics ceiling_robot() {
  CableRobotGeometry g;
  g.cables = {cable({-800.0, -800.0, 2000.0}, 18.85, {0.0, 0.0, 1.0}),
              cable({800.0, -800.0, 2000.0}, 18.85, {1.0, -1.0, 0.0}),
              cable({800.0, 800.0, 2000.0}, 18.85, {0.0, 0.0, 1.0}),
              cable({-800.0, 800.0, 2000.0}, 18.85, {-1.0, 1.0, 0.0}),
              cable({0.0, 0.0, -200.0}, 18.85, {0.0, 1.0, 0.0})};
  g.cables[1].attach_mm = {30.0, -30.0, 50.0};
  return CableRobotKinematics(g);
}

TEST(CableRobotPulley, InverseForwardRoundTripAndJacobian) {
  const CableRobotKinematics model = ceiling_robot();
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> across(-500.0, 500.0), height(100.0, 1500.0);
  double worst_round_trip = 0.0, worst_jacobian = 0.0;
  for (int sample = 0; sample < 300; ++sample) {
    const geometry::Pose pose = pose_at(across(rng), across(rng), height(rng));
    JointVector joints;
    ASSERT_TRUE(model.inverse(pose, joints).ok());
    geometry::Pose found = pose_at(0.0, 0.0, 800.0);
    ASSERT_TRUE(model.forward(joints, found).ok());
    worst_round_trip = std::max(worst_round_trip, (found.position_mm - pose.position_mm).norm());
    kinematics::JointJacobian jacobian;
    ASSERT_TRUE(model.jacobian(pose, jacobian).ok());
    for (int axis = 0; axis < 3; ++axis) {
      const double h = 1e-4;
      geometry::Pose plus = pose, minus = pose;
      plus.position_mm[axis] += h;
      minus.position_mm[axis] -= h;
      JointVector q_plus, q_minus;
      ASSERT_TRUE(model.inverse(plus, q_plus).ok() && model.inverse(minus, q_minus).ok());
      for (int i = 0; i < model.cable_count(); ++i) {
        const double difference = (q_plus[i] - q_minus[i]) / (2.0 * h);
        worst_jacobian = std::max(worst_jacobian, std::abs(difference - jacobian(i, axis)));
      }
    }
  }
  EXPECT_LT(worst_round_trip, 1e-9);
  EXPECT_LT(worst_jacobian, 1e-7);
  RecordProperty("worst_round_trip_mm", std::to_string(worst_round_trip));
  std::printf("pulley round trip worst %.3g mm, Jacobian worst %.3g\n", worst_round_trip,
              worst_jacobian);
}

TEST(CableRobotPulley, PlanarRouterOverPulleysRoundTrips) {
  // A four-belt router on a 2,400 x 1,200 mm sheet, each belt over a 12 mm pulley at a corner,
  // fed along the frame's top and bottom edges.
  CableRobotGeometry g;
  g.planar = true;
  g.cables = {cable({0.0, 1200.0, 0.0}, 12.0, {-1.0, 0.0, 0.0}),
              cable({2400.0, 1200.0, 0.0}, 12.0, {1.0, 0.0, 0.0}),
              cable({2400.0, 0.0, 0.0}, 12.0, {1.0, 0.0, 0.0}),
              cable({0.0, 0.0, 0.0}, 12.0, {-1.0, 0.0, 0.0})};
  const CableRobotKinematics model(g);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> x(200.0, 2200.0), y(200.0, 1000.0);
  double worst = 0.0;
  for (int sample = 0; sample < 300; ++sample) {
    const geometry::Pose pose = pose_at(x(rng), y(rng), 0.0);
    JointVector joints;
    ASSERT_TRUE(model.inverse(pose, joints).ok());
    geometry::Pose found = pose_at(1200.0, 600.0, 0.0);
    ASSERT_TRUE(model.forward(joints, found).ok());
    worst = std::max(worst, (found.position_mm - pose.position_mm).norm());
  }
  EXPECT_LT(worst, 1e-9);
  std::printf("planar pulley round trip worst %.3g mm\n", worst);
}

TEST(CableRobotPulley, HessianBoundHoldsOverRandomBalls) {
  const CableRobotKinematics model = ceiling_robot();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0), across(-500.0, 500.0),
      height(100.0, 1500.0);
  double ratio_sum = 0.0;
  int counted = 0, bounded = 0;
  for (int ball = 0; ball < 60; ++ball) {
    const geometry::Pose centre = pose_at(across(rng), across(rng), height(rng));
    const double radius = 1.0 + 150.0 * share(rng);
    kinematics::Chord chord;
    chord.position = radius * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    const auto bounds = model.own_hessian_bounds(centre.as_vector(), radius, 100.0, chord);
    ASSERT_TRUE(bounds);
    std::vector<double> largest(static_cast<std::size_t>(model.cable_count()), 0.0);
    for (int sample = 0; sample < 60; ++sample) {
      Eigen::Vector3d direction(unit(rng), unit(rng), unit(rng));
      const bool along_chord = sample % 3 == 0;
      if (along_chord) direction = chord.position;
      const double h = 1e-2, spare = radius - h * direction.norm();
      if (spare <= 0.0) continue;
      geometry::Pose p = centre, plus, minus;
      p.position_mm +=
          spare * share(rng) * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      plus = p;
      minus = p;
      plus.position_mm += h * direction;
      minus.position_mm -= h * direction;
      JointVector q0, q_plus, q_minus;
      ASSERT_TRUE(model.inverse(p, q0).ok() && model.inverse(plus, q_plus).ok() &&
                  model.inverse(minus, q_minus).ok());
      for (int i = 0; i < model.cable_count(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double second = std::abs(q_plus[i] - 2.0 * q0[i] + q_minus[i]) / (h * h);
        const double bound =
            along_chord ? bounds->along[k] : bounds->norm[k] * direction.squaredNorm();
        EXPECT_LE(second, bound * (1.0 + 1e-6) + 4e-16 * 4.0e3 / (h * h)) << "cable " << i + 1;
        if (!along_chord && std::isfinite(bound)) largest[k] = std::max(largest[k], second / bound);
      }
    }
    for (std::size_t k = 0; k < largest.size(); ++k) {
      if (!std::isfinite(bounds->norm[k])) continue;
      ++bounded;
      ratio_sum += largest[k];
      ++counted;
    }
  }
  // Every ball here is clear of the pulleys and within a half turn: each cable bounded.
  EXPECT_EQ(bounded, 60 * model.cable_count());
  const double ratio = ratio_sum / counted;
  std::printf("pulley Hessian bound: mean largest second difference / bound %.3f\n", ratio);
  EXPECT_GT(ratio, 0.3);
}

std::string pulley_machine(const std::string& first_cable) {
  std::string text =
      "name = \"pulleys\"\nunits = \"mm\"\n[kinematics]\ntype = \"cable_robot\"\nplanar = false\n"
      "[[kinematics.cables]]\nanchor = [-800.0, -800.0, 2000.0]\n" +
      first_cable +
      "[[kinematics.cables]]\nanchor = [800.0, -800.0, 2000.0]\n"
      "[[kinematics.cables]]\nanchor = [0.0, 800.0, 2000.0]\n"
      "[[kinematics.cables]]\nanchor = [0.0, 0.0, -200.0]\n"
      "[cartesian]\nmax_feed = 100.0\nmax_acceleration = 100.0\nhome = [0.0, 0.0, 800.0]\n";
  for (int j = 0; j < 4; ++j) {
    text += "[[joints]]\nname = \"c" + std::to_string(j + 1) +
            "\"\nmin = 1.0\nmax = 5000.0\nmax_velocity = 100.0\nmax_acceleration = 1000.0\n";
  }
  return text;
}

TEST(CableRobotPulley, MachineFileKeysRoundTripAndCalibrationSeesTheRadius) {
  const std::string text = pulley_machine("pulley_radius = 18.85\npulley_axis = [0.0, 0.0, 1.0]\n");
  const machine::Machine m = machine::parse_machine(text, "p.toml");
  const auto& model = dynamic_cast<const CableRobotKinematics&>(m.kinematics());
  EXPECT_EQ(model.geometry().cables[0].pulley_radius_mm, 18.85);
  const machine::Machine again = machine::parse_machine(
      machine::replace_kinematics_section(text, "p.toml", m.kinematics(), m.units()), "w.toml");
  const auto& reread = dynamic_cast<const CableRobotKinematics&>(again.kinematics());
  EXPECT_EQ(reread.geometry().cables[0].pulley_radius_mm, 18.85);
  EXPECT_EQ(reread.geometry().cables[0].pulley_axis, Eigen::Vector3d(0.0, 0.0, 1.0));
  const auto parameters = model.parameters();
  ASSERT_EQ(parameters.size(), 4u * 7u + 1u);
  EXPECT_EQ(parameters[7].name, "cable1.pulley_radius");
  std::vector<double> values;
  for (const auto& p : parameters) values.push_back(p.value);
  values[7] = 20.0;
  CableRobotKinematics changed = model;
  changed.set_parameters(values);
  EXPECT_EQ(changed.geometry().cables[0].pulley_radius_mm, 20.0);
  EXPECT_EQ(changed.geometry().cables[1].anchor_mm, model.geometry().cables[1].anchor_mm);
  values[7] = 0.0;
  EXPECT_THROW(changed.set_parameters(values), std::invalid_argument);
  EXPECT_EQ(changed.geometry().cables[0].pulley_radius_mm, 20.0);
  const auto form = model.firmware_form();
  ASSERT_TRUE(form);
  ASSERT_FALSE(form->losses.empty());
  EXPECT_NE(form->losses.front().find("pulley_radius 18.850 mm"), std::string::npos)
      << form->losses.front();
}

void expect_error(const std::string& first_cable, const std::string& wanted) {
  try {
    machine::parse_machine(pulley_machine(first_cable), "bad.toml");
    ADD_FAILURE() << "accepted: " << first_cable;
  } catch (const machine::MachineFileError& error) {
    EXPECT_NE(std::string(error.what()).find(wanted), std::string::npos) << error.what();
  }
}

TEST(CableRobotPulley, NoPulleysWithFlexCompensation) {
  CableRobotGeometry g;
  g.cables = {cable({0.0, 0.0, 2000.0}, 10.0, {0.0, 0.0, 1.0}), cable({1000.0, 0.0, 2000.0}),
              cable({0.0, 1000.0, 2000.0}), cable({0.0, 0.0, -1000.0})};
  g.flex_compensation = true;
  g.tension_limited = true;
  g.tension_max_N = 70.0;
  g.effector_mass_kg = 1.0;
  try {
    const CableRobotKinematics model(g);
    ADD_FAILURE() << "flex compensation over a pulley";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()).rfind("flex_compensation: not with pulleys", 0), 0u)
        << error.what();
  }
}

TEST(CableRobotPulley, MachineFileErrorsAtTheirKey) {
  expect_error("pulley_radius = 18.85\n",
               "bad.toml:8:kinematics.cables[1].pulley_radius: needs pulley_axis");
  expect_error("pulley_radius = -1.0\npulley_axis = [0.0, 0.0, 1.0]\n",
               "bad.toml:8:kinematics.cables[1].pulley_radius: must be a length of 0 or more");
  expect_error("pulley_radius = 5.0\npulley_axis = [0.0, 0.0, 0.0]\n",
               "bad.toml:9:kinematics.cables[1].pulley_axis: must be a non-zero direction");
  expect_error("pulley_radius = 5.0\npulley_axis = [0.0, 0.0, 1.0]\nswivel_arm = 20.0\n",
               "bad.toml:8:kinematics.cables[1].pulley_radius: not with a swivel_arm");
}

}  // namespace
}  // namespace pkm

namespace pkm {
namespace {

TEST(CableRobotPulley, ASpoolCountsTheLineFromItsLengthOverThePulleyAtTheOrigin) {
  CableRobotGeometry g;
  g.cables = {cable({0.0, 0.0, 2000.0}, 10.0, {0.0, 0.0, 1.0}), cable({1000.0, 0.0, 2000.0}),
              cable({0.0, 1000.0, 2000.0}), cable({0.0, 0.0, -1000.0})};
  g.cables[0].attach_mm = {21.6, 28.8, 2000.0};  // at the origin, the hand case's tie point
  g.cables[0].spool = kinematics::CableSpool{};
  g.cables[0].spool->radius_mm = 10.0;
  const CableRobotKinematics model(g);
  const std::optional<double> at_origin = model.motor_full_steps(0, kHandLength_mm);
  ASSERT_TRUE(at_origin);
  EXPECT_NEAR(*at_origin, 0.0, 1e-9);
  // 1 mm more line: 200 full steps per turn of a 10 mm spool.
  EXPECT_NEAR(*model.motor_full_steps(0, kHandLength_mm + 1.0), 200.0 / (20.0 * std::numbers::pi),
              1e-9);
  // Hangprinter's motor degrees become lines by the inverse, from the same origin over the
  // pulley (it once counted from the straight distance, 36 mm: 7.66 mm off here).
  EXPECT_NEAR(*model.joint_from_motor_full_steps(0, 0.0), kHandLength_mm, 1e-9);
  for (const double joint : {kHandLength_mm - 20.0, kHandLength_mm + 350.0}) {
    EXPECT_NEAR(*model.joint_from_motor_full_steps(0, *model.motor_full_steps(0, joint)), joint,
                1e-9);
  }
}

TEST(CableRobotPulley, SketchDrawsThePulleyFacingTheTiePointAndTheSpan) {
  CableRobotGeometry g;
  g.cables = {cable({0.0, 0.0, 2000.0}, 10.0, {0.0, 0.0, 1.0}), cable({1000.0, 0.0, 2000.0}),
              cable({0.0, 1000.0, 2000.0}), cable({0.0, 0.0, -1000.0})};
  const CableRobotKinematics model(g);
  JointVector joints;
  std::vector<kinematics::SketchLine> lines;
  model.moving_parts(pose_at(21.6, 28.8, 2000.0), joints, lines);
  // The pulley's circle (its centre 10 mm from the anchor towards the tie point), then the span.
  const Eigen::Vector3d centre(6.0, 8.0, 2000.0);
  std::size_t span = 0;
  while (span < lines.size() && (lines[span].to - lines[span].from).norm() < 5.0) {
    EXPECT_NEAR((lines[span].from - centre).norm(), 10.0, 1e-9);
    ++span;
  }
  ASSERT_GT(span, 8u);
  ASSERT_LT(span, lines.size());
  EXPECT_NEAR((lines[span].to - lines[span].from).norm(), 24.0, 1e-9);
  EXPECT_NEAR((lines[span].from - centre).norm(), 10.0, 1e-9);
  EXPECT_NEAR((lines[span].to - Eigen::Vector3d(21.6, 28.8, 2000.0)).norm(), 0.0, 1e-9);
}

TEST(CableRobotPulley, ClearanceBracketsTheRefusedPoses) {
  // Near the first pulley (its axis z through (-800, -800, 2000), radius 18.85): a cell whose
  // margin is proven positive holds no refused pose; a refused pose's cell is not proven.
  const CableRobotKinematics model = ceiling_robot();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> near(-60.0, 60.0), unit(-1.0, 1.0);
  int proven = 0, refused = 0;
  for (int cell = 0; cell < 400; ++cell) {
    const geometry::Pose centre =
        pose_at(-800.0 + near(rng), -800.0 + near(rng), 2000.0 + near(rng));
    const double radius = 5.0;
    std::array<double, 2> margins[6];
    model.reach_over_cell(centre.as_vector(), radius, radius, 100.0, margins);
    JointVector joints;
    for (int sample = 0; sample < 20; ++sample) {
      geometry::Pose p = centre;
      p.position_mm +=
          radius * unit(rng) * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      const bool ok = model.inverse(p, joints).ok();
      if (margins[0][0] > 0.0) {
        EXPECT_TRUE(ok) << p.position_mm.transpose();
      }
      if (!ok && model.inverse(p, joints).joint == 0) {
        ++refused;
        EXPECT_LE(margins[0][0], 0.0);
      }
    }
    if (margins[0][0] > 0.0) ++proven;
  }
  EXPECT_GT(proven, 50);
  EXPECT_GT(refused, 20);
}

}  // namespace
}  // namespace pkm
