// Cable machines as built (issue 12): hand-computed cases for the pulley wrap, the tilting
// effector, the tensions and the sagging, stretching cable, and round trips on the examples.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/elastic_catenary.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.80665;  // m/s^2: a kilogram weighs 9.80665 N

kinematics::CablePlotterGeometry level_anchors(double distance_mm) {
  return kinematics::CablePlotterGeometry::level(distance_mm);
}

kinematics::JointVector inverse(const kinematics::CablePlotterKinematics& model, double x,
                                double y) {
  kinematics::JointVector joints;
  const kinematics::Status status = model.inverse(geometry::Pose::from_mm_deg(x, y, 0), joints);
  EXPECT_TRUE(status.ok()) << kinematics::describe(status) << " at " << x << ", " << y;
  return joints;
}

TEST(CableWrap, PenStraightBelowThePulleysSideWrapsAQuarterTurn) {
  // Pulley of radius 10 at (0, 0): a pen at (10, -500) hangs from the pulley's right-hand point,
  // a quarter turn from its top: 10 pi / 2 of arc, then 500 mm straight down. (There the right
  // cable carries nothing: the edge of what IK accepts, so the balance is asked directly.)
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.pulley_radius_mm = 10.0;
  kinematics::CableBalance balance;
  ASSERT_TRUE(kinematics::solve_cable_balance(g, {10.0, -500.0}, {0.0, -1.0}, balance).ok());
  EXPECT_NEAR(kinematics::cable_joint(g, kinematics::cable_past_top(g, balance, 0), 0),
              5.0 * kPi + 500.0, 1e-9);
  // A pen further right: the right cable, from (1000, 0), leaves the left of its pulley.
  const kinematics::CablePlotterKinematics model(g);
  const kinematics::JointVector joints = inverse(model, 300.0, -500.0);
  const double distance = std::hypot(700.0, 500.0);
  const double span = std::sqrt(distance * distance - 100.0);
  const double wrap = kPi / 2.0 - (std::atan2(700.0, 500.0) - std::asin(10.0 / distance));
  EXPECT_NEAR(joints[1], 10.0 * wrap + span, 1e-9);
}

TEST(CableWrap, PenOnThePulleysHorizontalWrapsAsinROverD) {
  // A pen level with the pulleys' centres, 300 mm right of the left one: the cable leaves at
  // asin(r / D) past the top, then sqrt(D^2 - r^2) straight.
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.pulley_radius_mm = 10.0;
  const kinematics::CablePlotterKinematics model(g);
  const kinematics::JointVector joints = inverse(model, 300.0, 0.0);
  EXPECT_NEAR(joints[0], 10.0 * std::asin(10.0 / 300.0) + std::sqrt(300.0 * 300.0 - 100.0), 1e-9);
  EXPECT_NEAR(joints[1], 10.0 * std::asin(10.0 / 700.0) + std::sqrt(700.0 * 700.0 - 100.0), 1e-9);
}

TEST(SpoolBuildup, TheJointIsTheDrumsTurnAndTheRadiusFollowsTheCable) {
  // A cord on a drum of 10 mm with nothing paid out, 0.5 mm of radius per metre wound. For a pen
  // at (300, -900) the drum's radius r and the cable past its top l = r phi + s agree when
  // r = 10 - 0.0005 l (found here by iterating the closed forms of the wrap); the joint is the
  // drum's turn times 10 mm: -(10 / 0.0005) ln(1 - 0.0005 l / 10).
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.pulley_radius_mm = 10.0;
  g.spool_buildup_mm_per_m = 0.5;
  const kinematics::CablePlotterKinematics model(g);
  const kinematics::JointVector joints = inverse(model, 300.0, -900.0);
  const auto past_top = [](double r, double dx, double dy) {  // pen dx right, dy below the drum
    const double distance = std::hypot(dx, dy);
    const double wrap = kPi / 2.0 - (std::atan2(dx, dy) - std::asin(r / distance));
    return r * wrap + std::sqrt(distance * distance - r * r);
  };
  for (int cable = 0; cable < 2; ++cable) {
    const double dx = cable == 0 ? 300.0 : 700.0;
    double r = 10.0, length = 0.0;
    for (int round = 0; round < 50; ++round) {
      length = past_top(r, dx, 900.0);
      r = 10.0 - 0.0005 * length;
    }
    EXPECT_NEAR(joints[cable], -(10.0 / 0.0005) * std::log(1.0 - 0.0005 * length / 10.0), 1e-9)
        << cable;
    EXPECT_GT(joints[cable], length + 1.0) << "a thinner drum turns further per mm";
  }
  // FK finds the pen again.
  geometry::Pose pose;
  ASSERT_TRUE(model.forward(joints, pose).ok());
  EXPECT_NEAR((pose.position_mm.head<2>() - Eigen::Vector2d(300.0, -900.0)).norm(), 0.0, 1e-9);
}

TEST(SpoolBuildup, HasNoDeviationBound) {
  // Pulleys alone keep post's bound (the wrap adds no curvature beyond the span's); a drum whose
  // radius follows the cable and whose joint is its turn does not, so post samples it.
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.pulley_radius_mm = 10.0;
  const geometry::Vector6d centre = geometry::Pose::from_mm_deg(300.0, -900.0, 0.0).as_vector();
  EXPECT_TRUE(bounds::inverse_hessian_bounds(kinematics::CablePlotterKinematics(g), centre, 1.0,
                                             100.0, {}));
  g.spool_buildup_mm_per_m = 0.5;
  EXPECT_FALSE(bounds::inverse_hessian_bounds(kinematics::CablePlotterKinematics(g), centre, 1.0,
                                              100.0, {}));
}

TEST(CableTension, ASymmetricVByHand) {
  // 2 kg at (500, -375) below anchors 1000 apart: each cable at 3-4-5, sin = 0.6 upwards, so
  // 2 t 0.6 = 2 g: t = g / 0.6 = 16.3444 N.
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.effector_mass_kg = 2.0;
  const kinematics::CablePlotterKinematics model(g);
  kinematics::CableStatics statics;
  ASSERT_TRUE(model.statics(geometry::Pose::from_mm_deg(500, -375, 0), {0.0, 0.0}, statics).ok());
  EXPECT_NEAR(statics.tension_N[0], kG / 0.6, 1e-12);
  EXPECT_NEAR(statics.tension_N[1], kG / 0.6, 1e-12);
  // Accelerating up at 1 m/s^2 the cables carry m (g + a).
  ASSERT_TRUE(
      model.statics(geometry::Pose::from_mm_deg(500, -375, 0), {0.0, 1000.0}, statics).ok());
  EXPECT_NEAR(statics.tension_N[0], (kG + 1.0) / 0.6, 1e-12);
  // Accelerating right at 1 m/s^2: the right cable pulls more. Horizontal: 0.8 (t1 - t0) = 2;
  // vertical: 0.6 (t0 + t1) = 2 g.
  ASSERT_TRUE(
      model.statics(geometry::Pose::from_mm_deg(500, -375, 0), {1000.0, 0.0}, statics).ok());
  EXPECT_NEAR(statics.tension_N[1] - statics.tension_N[0], 2.0 / 0.8, 1e-12);
  EXPECT_NEAR(statics.tension_N[1] + statics.tension_N[0], 2.0 * kG / 0.6, 1e-12);
}

TEST(CableTension, LimitsRefuseWithTheirOwnStatusNamingTheCable) {
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.effector_mass_kg = 2.0;
  g.tension_limited = true;
  g.tension_min_N = 5.0;
  g.tension_max_N = 40.0;
  const kinematics::CablePlotterKinematics model(g);
  kinematics::JointVector joints;
  EXPECT_TRUE(
      model.inverse(geometry::Pose::from_mm_deg(500, -375, 0), joints).ok());  // 16.3 N each
  // Near the anchor line the tensions pass 40 N; near the right side the left cable goes slack.
  const kinematics::Status high = model.inverse(geometry::Pose::from_mm_deg(500, -100, 0), joints);
  EXPECT_EQ(high.code, kinematics::StatusCode::tension);
  const kinematics::Status slack = model.inverse(geometry::Pose::from_mm_deg(990, -900, 0), joints);
  EXPECT_EQ(slack.code, kinematics::StatusCode::tension);
  EXPECT_EQ(slack.joint, 0);
  EXPECT_NE(model.why_refused(geometry::Pose::from_mm_deg(990, -900, 0), slack)
                .find("the left cable would go slack: 0.292 N, below tension_limits' min 5 N"),
            std::string::npos)
      << model.why_refused(geometry::Pose::from_mm_deg(990, -900, 0), slack);
}

TEST(EffectorTilt, SymmetricAttachmentHangsLevel) {
  // Cables tied 50 mm either side of the pen, the weight 30 mm below it, the pen on the centre
  // line: level, each cable from (450, -600) to (0, 0): 750 mm, sin 0.8 upwards.
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.attach_mm = {Eigen::Vector2d(-50.0, 0.0), Eigen::Vector2d(50.0, 0.0)};
  g.center_of_mass_mm = {0.0, -30.0};
  g.effector_mass_kg = 1.0;
  const kinematics::CablePlotterKinematics model(g);
  kinematics::CableStatics statics;
  ASSERT_TRUE(model.statics(geometry::Pose::from_mm_deg(500, -600, 0), {0.0, 0.0}, statics).ok());
  EXPECT_NEAR(statics.tilt_rad, 0.0, 1e-12);
  EXPECT_NEAR(statics.tension_N[0], kG / 1.6, 1e-12);
  const kinematics::JointVector joints = inverse(model, 500.0, -600.0);
  EXPECT_NEAR(joints[0], 750.0, 1e-9);
  EXPECT_NEAR(joints[1], 750.0, 1e-9);
}

TEST(EffectorTilt, CablesTiedAtOnePointOffTheSideHangTheWeightBelowTheKnot) {
  // Both cables tied at (30, 40) from the pen, the weight at the pen: the weight hangs straight
  // below the knot, so the effector turns by atan(30 / 40) and the knot is 50 mm above the pen,
  // wherever the pen is. The cables run to the knot.
  kinematics::CablePlotterGeometry g = level_anchors(1000.0);
  g.attach_mm = {Eigen::Vector2d(30.0, 40.0), Eigen::Vector2d(30.0, 40.0)};
  g.effector_mass_kg = 1.0;
  const kinematics::CablePlotterKinematics model(g);
  for (const Eigen::Vector2d& pen : {Eigen::Vector2d(500, -600), Eigen::Vector2d(200, -800)}) {
    kinematics::CableStatics statics;
    ASSERT_TRUE(
        model.statics(geometry::Pose::from_mm_deg(pen.x(), pen.y(), 0), {0, 0}, statics).ok());
    EXPECT_NEAR(statics.tilt_rad, std::atan2(30.0, 40.0), 1e-12);
    const kinematics::JointVector joints = inverse(model, pen.x(), pen.y());
    const Eigen::Vector2d knot = pen + Eigen::Vector2d(0.0, 50.0);
    EXPECT_NEAR(joints[0], knot.norm(), 1e-9);
    EXPECT_NEAR(joints[1], (knot - Eigen::Vector2d(1000.0, 0.0)).norm(), 1e-9);
  }
}

TEST(EffectorTilt, AsymmetricAttachmentBalancesForcesAndMoment) {
  // Tied at (-40, 20) and (70, 5), the weight at (5, -25), off the centre line: check the
  // solution against the balance, recomputed here from the tilt and the tensions alone.
  kinematics::CablePlotterGeometry g = level_anchors(1200.0);
  g.attach_mm = {Eigen::Vector2d(-40.0, 20.0), Eigen::Vector2d(70.0, 5.0)};
  g.center_of_mass_mm = {5.0, -25.0};
  g.effector_mass_kg = 3.0;
  const kinematics::CablePlotterKinematics model(g);
  const Eigen::Vector2d pen(380.0, -700.0);
  kinematics::CableStatics statics;
  ASSERT_TRUE(
      model.statics(geometry::Pose::from_mm_deg(pen.x(), pen.y(), 0), {0, 0}, statics).ok());
  EXPECT_GT(std::abs(statics.tilt_rad), 0.01);
  const Eigen::Rotation2Dd turn(statics.tilt_rad);
  const Eigen::Vector2d weight(0.0, -3.0 * kG);
  Eigen::Vector2d force = weight;
  double moment = 0.0;
  const kinematics::JointVector joints = inverse(model, pen.x(), pen.y());
  for (int cable = 0; cable < 2; ++cable) {
    const Eigen::Vector2d arm = turn * g.attach_mm[cable];
    const Eigen::Vector2d to_anchor = g.anchors_mm[cable] - (pen + arm);
    EXPECT_NEAR(joints[cable], to_anchor.norm(), 1e-9);
    const Eigen::Vector2d pull = statics.tension_N[cable] * to_anchor.normalized();
    force += pull;
    moment += arm.x() * pull.y() - arm.y() * pull.x();
  }
  const Eigen::Vector2d com = turn * g.center_of_mass_mm;
  moment += com.x() * weight.y() - com.y() * weight.x();
  EXPECT_NEAR(force.norm(), 0.0, 1e-10);
  EXPECT_NEAR(moment, 0.0, 1e-8);
}

TEST(Catenary, MatchesTheClosedFormOfAUniformInextensibleChain) {
  // y = a cosh(x / a): from the vertex to x the arc is a sinh(x / a), the rise a (cosh - 1).
  const double a = 1000.0, w = 0.0015;  // mm; N/mm
  const double h = w * a;
  kinematics::CatenarySpan span = kinematics::catenary_span(h, 0.0, a * std::sinh(0.8), w, 0.0);
  EXPECT_NEAR(span.across_mm, 800.0, 1e-9);
  EXPECT_NEAR(span.rise_mm, a * (std::cosh(0.8) - 1.0), 1e-9);
  // From x = -300 (the chain dips first: the end is pulled down, V = H sinh(-0.3)) to x = 800.
  span = kinematics::catenary_span(h, h * std::sinh(-0.3), a * (std::sinh(0.8) - std::sinh(-0.3)),
                                   w, 0.0);
  EXPECT_NEAR(span.across_mm, 1100.0, 1e-9);
  EXPECT_NEAR(span.rise_mm, a * (std::cosh(0.8) - std::cosh(0.3)), 1e-9);
}

TEST(Catenary, ElasticSpanMatchesAnIntegrationOfTheCable) {
  // Irvine's elastic catenary against the cable's own equations integrated along it: each
  // unstretched element ds becomes (1 + T / EA) ds along the tension's direction.
  const double h = 80.0, v = -12.0, length = 2500.0, w = 0.15 * kG * 1e-3, compliance = 1e-4;
  const kinematics::CatenarySpan span = kinematics::catenary_span(h, v, length, w, compliance);
  const int steps = 20000;
  const double ds = length / steps;
  double x = 0.0, y = 0.0;
  const auto slope = [&](double s, double& dx, double& dy) {
    const double vertical = v + w * s, tension = std::hypot(h, vertical);
    dx = h / tension * (1.0 + compliance * tension);
    dy = vertical / tension * (1.0 + compliance * tension);
  };
  for (int k = 0; k < steps; ++k) {  // Simpson's rule on each step
    double x0, y0, x1, y1, x2, y2;
    slope(k * ds, x0, y0);
    slope((k + 0.5) * ds, x1, y1);
    slope((k + 1) * ds, x2, y2);
    x += ds / 6.0 * (x0 + 4.0 * x1 + x2);
    y += ds / 6.0 * (y0 + 4.0 * y1 + y2);
  }
  EXPECT_NEAR(span.across_mm, x, 1e-8);
  EXPECT_NEAR(span.rise_mm, y, 1e-8);
  // Without weight: a straight cable stretched by its tension.
  const kinematics::CatenarySpan straight =
      kinematics::catenary_span(30.0, 40.0, 1000.0, 0.0, 1e-4);
  EXPECT_NEAR(std::hypot(straight.across_mm, straight.rise_mm), 1000.0 * (1.0 + 50.0 * 1e-4), 1e-9);
}

TEST(Catenary, DerivativesMatchCentralDifferences) {
  // The sagging balance's Newton iteration uses these: a chain that dips first, one that does
  // not, a stretching straight cable.
  struct Case {
    double h, v, length, w, c;
  };
  for (const Case& k : {Case{80.0, -12.0, 2500.0, 0.0015, 1e-4},
                        Case{40.0, 30.0, 900.0, 0.002, 0.0}, Case{30.0, 40.0, 1000.0, 0.0, 1e-5}}) {
    const kinematics::CatenarySpanDerivatives d =
        kinematics::catenary_span_derivatives(k.h, k.v, k.length, k.w, k.c);
    const auto numeric = [&](int which, bool rise) {
      double x[3] = {k.h, k.v, k.length};
      const double step = 1e-5 * std::max(1.0, std::abs(x[which]));
      x[which] += step;
      const kinematics::CatenarySpan plus = kinematics::catenary_span(x[0], x[1], x[2], k.w, k.c);
      x[which] -= 2.0 * step;
      const kinematics::CatenarySpan minus = kinematics::catenary_span(x[0], x[1], x[2], k.w, k.c);
      return rise ? (plus.rise_mm - minus.rise_mm) / (2.0 * step)
                  : (plus.across_mm - minus.across_mm) / (2.0 * step);
    };
    EXPECT_NEAR(d.across_by_horizontal, numeric(0, false), 1e-7);
    EXPECT_NEAR(d.across_by_vertical, numeric(1, false), 1e-7);
    EXPECT_NEAR(d.across_by_length, numeric(2, false), 1e-7);
    EXPECT_NEAR(d.rise_by_horizontal, numeric(0, true), 1e-7);
    EXPECT_NEAR(d.rise_by_vertical, numeric(1, true), 1e-7);
    EXPECT_NEAR(d.rise_by_length, numeric(2, true), 1e-7);
  }
}

TEST(Catenary, ALighterChainTendsToTheStraightCable) {
  kinematics::CablePlotterGeometry g = level_anchors(2000.0);
  g.pulley_radius_mm = 10.0;
  g.effector_mass_kg = 5.0;
  const kinematics::CablePlotterKinematics straight(g);
  const kinematics::JointVector reference = inverse(straight, 700.0, -1200.0);
  double previous = INFINITY;
  for (const double density : {0.5, 0.05, 0.005, 0.0005}) {
    g.cable_density_kg_per_m = density;
    const kinematics::CablePlotterKinematics sagging(g);
    const kinematics::JointVector joints = inverse(sagging, 700.0, -1200.0);
    const double difference = std::abs(joints[0] - reference[0]);
    EXPECT_LT(difference, previous) << density;
    // A heavier chain hangs below the straight line: it takes more chain to reach.
    EXPECT_GT(joints[0], reference[0]) << density;
    previous = difference;
  }
  EXPECT_LT(previous, 1e-3);
}

class CableExampleRoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(CableExampleRoundTrip, ForwardOfInverseWithinANanometre) {
  const machine::Machine machine = test::load_example(GetParam());
  std::mt19937_64 rng(12);
  int tested = 0;
  double worst = 0.0;
  for (const geometry::Pose& pose : test::sample_reachable_poses(machine, 200, rng, 1.0, 0.0)) {
    kinematics::JointVector joints;
    if (!machine.inverse(pose, joints).ok()) continue;
    geometry::Pose found = machine.home();
    const kinematics::Status status = machine.kinematics().forward(joints, found);
    ASSERT_TRUE(status.ok()) << kinematics::describe(status) << " at "
                             << pose.position_mm.transpose();
    worst = std::max(worst, (found.position_mm - pose.position_mm).norm());
    ++tested;
  }
  EXPECT_GT(tested, 100);
  EXPECT_LE(worst, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Examples, CableExampleRoundTrip,
                         ::testing::Values("hektor-pulleys.toml", "makelangelo.toml",
                                           "maslow-frame.toml"));

}  // namespace
}  // namespace pkm
