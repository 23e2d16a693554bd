// The certified job check: moves proven, violated at the hand-computed place, undecided where no
// bound exists; the example jobs on their machines proven; a job whose limit crossing falls
// between two of plan's samples refused at its move.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "pkm/certify/job_check.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/motion/segment.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm::certify {
namespace {

motion::Segment line(const geometry::Vector6d& start, const geometry::Vector6d& end) {
  motion::Segment segment;
  segment.start = start;
  segment.end = end;
  segment.feed_mm_per_s = 10.0;
  return segment;
}

geometry::Vector6d pose(double x, double y, double z, double a = 0, double b = 0, double c = 0) {
  return geometry::Pose::from_mm_deg(x, y, z, a, b, c).as_vector();
}

// Leg 1 of the paper's hexapod joins base joint a and platform joint b (tool tip at 30 mm):
// with the platform level, its length is the distance from the tip to a - b - (0, 0, 30) =
// (200.3644, 153.8868, -30). Straight above that point the leg is z + 30 long: 600 (its min) at
// z = 570.
constexpr double kLegX = 200.3643704832, kLegY = 153.8868015505;

TEST(CertifyMove, AVerticalLinePastALegsMinIsViolatedWhereComputedByHand) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const MoveProver prover(machine);
  // z from 1000 down to 500: leg 1 reaches 600 mm at z = 570, u = 430 / 500 = 0.86.
  const MoveProof proof = prover.prove(line(pose(kLegX, kLegY, 1000), pose(kLegX, kLegY, 500)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  const Finding& finding = *proof.finding;
  EXPECT_EQ(finding.quantity, Quantity::joint);
  EXPECT_EQ(finding.index, 0);
  EXPECT_NEAR(finding.u0, 0.86, 1e-9);
  EXPECT_NEAR(finding.pose[2], 570.0, 1e-6);
  EXPECT_EQ(finding.limit, 600.0);
  EXPECT_LT(finding.value, 600.0);
  EXPECT_NE(finding.text.find("joint 'leg1' = "), std::string::npos) << finding.text;
}

TEST(CertifyMove, TheSameLineStoppingShortIsProven) {
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const MoveProver prover(machine);
  const MoveProof proof = prover.prove(line(pose(kLegX, kLegY, 1000), pose(kLegX, kLegY, 571)));
  EXPECT_EQ(proof.verdict, Verdict::proven);
  EXPECT_GT(proof.pieces, 1);
  EXPECT_FALSE(proof.finding.has_value());
}

TEST(CertifyMove, ALegsMinimumBetweenSamplesIsFound) {
  // Along x at y = kLegY, z = 570 - 1e-8, leg 1 is shortest above the point: 600 - 1e-8 mm, below
  // 600 only within 3.5 um of x = kLegX (sqrt(2 * 600 * 1e-8)); the ends are 600.09 mm.
  const machine::Machine machine = test::load_example("hexapod-bit.toml");
  const MoveProver prover(machine);
  const double z = 570.0 - 1e-8;
  const MoveProof proof =
      prover.prove(line(pose(kLegX - 10.25, kLegY, z), pose(kLegX + 9.75, kLegY, z)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->index, 0);
  EXPECT_NEAR(proof.finding->u0, 10.25 / 20.0, 0.0036 / 20.0);
  EXPECT_NEAR(proof.finding->worst_value, 600.0 - 1e-8, 1e-9);
  EXPECT_NEAR(proof.finding->worst_u, 10.25 / 20.0, 0.0036 / 20.0);
  // 2e-8 deeper than the limit is needed nowhere on a line 2e-8 higher: proven.
  const MoveProof clear =
      prover.prove(line(pose(kLegX - 10.25, kLegY, z + 2e-8), pose(kLegX + 9.75, kLegY, z + 2e-8)));
  EXPECT_EQ(clear.verdict, Verdict::proven);
}

TEST(CertifyMove, AnArcBulgingPastTheEnvelopeIsViolatedWhereItCrosses) {
  // The linear delta's envelope ends at x = 120. A ccw arc about (0, 0) from (110, -50) to
  // (110, 50) has radius 120.830 and bulges to x = 120.830 at its middle; it crosses x = 120 at
  // the angle -acos(120 / 120.830) = -6.7305 deg of its -24.444 .. 24.444 deg sweep.
  const machine::Machine machine = test::load_example("linear-delta.toml");
  const MoveProver prover(machine);
  motion::Segment arc = line(pose(110, -50, 100), pose(110, 50, 100));
  arc.kind = motion::SegmentKind::arc;
  arc.centre = Eigen::Vector3d(0, 0, 100);
  const double half_sweep = std::atan2(50.0, 110.0);
  arc.sweep_rad = 2.0 * half_sweep;
  const MoveProof proof = prover.prove(arc);
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->quantity, Quantity::envelope);
  EXPECT_EQ(proof.finding->index, 0);
  const double crossing = -std::acos(120.0 / std::hypot(110.0, 50.0));
  EXPECT_NEAR(proof.finding->u0, (crossing + half_sweep) / (2.0 * half_sweep), 1e-9);
  EXPECT_NEAR(proof.finding->worst_value, std::hypot(110.0, 50.0), 1e-3);
  // The arc through (110, -40) .. (110, 40) stays within x <= 116.3: proven.
  motion::Segment inside = line(pose(110, -40, 100), pose(110, 40, 100));
  inside.kind = motion::SegmentKind::arc;
  inside.centre = Eigen::Vector3d(0, 0, 100);
  inside.sweep_rad = 2.0 * std::atan2(40.0, 110.0);
  EXPECT_EQ(prover.prove(inside).verdict, Verdict::proven);
}

// The vertical-legs hexapod of test_leg_limits.cpp with max_joint_angle = 30: leg 5's platform
// end reaches 30 deg at a tilt of a = 25.4958 deg (computed there by hand).
machine::Machine tilting_hexapod(const std::string& keys) {
  return test::parallel_leg_hexapod(test::hexagon_points(), keys);
}

TEST(CertifyMove, ATiltPastTheJointAngleIsViolatedAtTheHandComputedAngle) {
  const machine::Machine machine = tilting_hexapod("max_joint_angle = 30");
  const MoveProver prover(machine);
  const MoveProof proof = prover.prove(line(pose(0, 0, 500), pose(0, 0, 500, 28)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->quantity, Quantity::joint_angle);
  EXPECT_EQ(proof.finding->index, 4);
  EXPECT_EQ(proof.finding->other, 1);  // the platform end
  EXPECT_NEAR(proof.finding->u0, 25.495825673868385 / 28.0, 1e-9);
  EXPECT_NE(proof.finding->text.find("max_joint_angle is 30.000 deg"), std::string::npos);
  EXPECT_EQ(prover.prove(line(pose(0, 0, 500), pose(0, 0, 500, 25))).verdict, Verdict::proven);
}

TEST(CertifyMove, LegsBroughtTogetherAreViolatedWhereTheyTouch) {
  // test_leg_limits.cpp's pair: legs 1 and 2, 60 mm apart, touch 40 mm legs at x = 559.017.
  const machine::Machine machine =
      test::parallel_leg_hexapod(test::close_pair_points(), "leg_diameter = 40");
  const MoveProver prover(machine);
  const MoveProof proof = prover.prove(line(pose(0, 0, 500), pose(600, 0, 500)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->quantity, Quantity::clearance);
  EXPECT_EQ(proof.finding->index, 0);
  EXPECT_EQ(proof.finding->other, 1);
  EXPECT_NEAR(proof.finding->u0, 500.0 * std::sqrt(1.25) / 600.0, 1e-9);
  EXPECT_EQ(prover.prove(line(pose(0, 0, 500), pose(550, 0, 500))).verdict, Verdict::proven);
}

TEST(CertifyMove, AModelWithoutDerivativeBoundsIsUndecided) {
  const machine::Machine machine = test::load_example("mach3-formula.toml");
  const MoveProver prover(machine);
  EXPECT_NE(prover.unavailable().find("no bound on the derivatives"), std::string::npos);
  const geometry::Vector6d home = machine.home().as_vector();
  geometry::Vector6d next = home;
  next[0] += 1.0;
  const MoveProof proof = prover.prove(line(home, next));
  EXPECT_EQ(proof.verdict, Verdict::undecided);
  EXPECT_EQ(proof.finding->text, prover.unavailable());
}

TEST(CertifyJob, TheExampleJobsAreProvenOnTheirMachines) {
  const auto job = [](const char* name) {
    return std::filesystem::path(PKM_SOURCE_DIR) / "examples" / "jobs" / name;
  };
  const JobCheck sphere = check_job(test::load_example("hexapod-bit.toml"), job("sphere.ngc"), {});
  EXPECT_TRUE(sphere.certified());
  EXPECT_GT(sphere.moves, 10);
  EXPECT_EQ(sphere.violated + sphere.undecided, 0);
  const JobCheck hyperboloid =
      check_job(test::load_example("hexapod-bit-200.toml"), job("hyperboloid.ngc"), {});
  EXPECT_TRUE(hyperboloid.certified());
  EXPECT_GT(hyperboloid.moves, 10);
}

TEST(CertifyJob, TheFirstFailingMoveIsNamedByItsLine) {
  const test::TempProgram program(
      "G21 G90 G61\n"
      "G1 F3000 X200.3644 Y153.8868 Z900\n"
      "G1 Z500\n"  // line 3: leg 1 below 600 mm from z = 570
      "G1 Z400\n"  // line 4: refused too, counted
      "M2\n");
  const JobCheck check = check_job(test::load_example("hexapod-bit.toml"), program.path(), {});
  EXPECT_FALSE(check.certified());
  EXPECT_EQ(check.moves, 3);
  EXPECT_EQ(check.proven, 1);
  EXPECT_EQ(check.violated, 2);
  ASSERT_TRUE(check.first_failure.has_value());
  EXPECT_EQ(check.first_failure->line, 3);
  EXPECT_EQ(check.first_failure->index, 1);
  EXPECT_NEAR(check.first_failure->finding.pose[2], 570.0, 1e-3);
}

TEST(CertifyJob, APenThatNeverGoesDownIsAWarning) {
  // A LinuxCNC polargraph's drawing (Z90 draws, Z0 travels) on examples/machines/pen-plotter.toml
  // (down below 0): every move keeps the limits, and the pen never goes down.
  const test::TempProgram program(
      "G21 G90\nG0 X1 Y0\nG0 Z90\nG1 X5 Y20 F400\nG1 X10\nG0 Z0\nG0 X18\nG0 Z90\n"
      "G1 X21 Y15\nG0 Z0\nM2\n");
  JobCheckOptions options;
  options.origin = pose(750, -700, 0);
  const JobCheck check = check_job(test::load_example("pen-plotter.toml"), program.path(), options);
  EXPECT_TRUE(check.certified());
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_EQ(check.warnings[0].line, 2);
  EXPECT_NE(check.warnings[0].message.find("[tool] down_above = 45 would draw at Z 90"),
            std::string::npos)
      << check.warnings[0].message;
}

// LinuxCNC's hexapod sample as `pkm import linuxcnc` writes it, legs 20..40 in (tests/data):
// home 20 in above the base plane z = 0; tool_length 0, so the platform joints are at the tip's
// height. The same leg lengths hold the platform's mirror image below the base.
machine::Machine linuxcnc_sample_hexapod() {
  return machine::load_machine(std::filesystem::path(PKM_SOURCE_DIR) / "tests" / "data" /
                               "linuxcnc-hexapod-sample-legs-20-40.toml");
}

TEST(CertifyMove, AHexapodThroughItsBasePlaneIsViolatedWhereThePlatformMeetsIt) {
  // Level, down the axis from z = 1 in to z = -1 in: every platform joint meets the base plane at
  // z = 0 (u = 0.5), each leg lying flat there, 22.02 in long (within 20..40 in); below it the
  // legs hold the mirror image. The joints alone never leave their limits on this line.
  const machine::Machine machine = linuxcnc_sample_hexapod();
  const MoveProver prover(machine);
  const MoveProof proof = prover.prove(line(pose(0, 0, 25.4), pose(0, 0, -25.4)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  const Finding& finding = *proof.finding;
  EXPECT_EQ(finding.quantity, Quantity::assembly_mode);
  EXPECT_NEAR(finding.u0, 0.5, 1e-9);
  EXPECT_NEAR(finding.pose[2], 0.0, 1e-6);
  EXPECT_NE(finding.text.find("past the base joints' plane"), std::string::npos) << finding.text;
  // The same line stopping 0.001 in above the plane is proven.
  EXPECT_EQ(prover.prove(line(pose(0, 0, 25.4), pose(0, 0, 0.0254))).verdict, Verdict::proven);
  // A tilt that takes one platform joint through the plane: level at z = 0.1 in, the joints of
  // legs 1 and 2 at y = 11.5 in go down by 11.5 sin(a) for a tilt a about x, through the plane
  // at sin(a) = 0.1 / 11.5 (a = 0.498 deg); 1 deg is past it.
  const MoveProof tilt = prover.prove(line(pose(0, 0, 2.54), pose(0, 0, 2.54, -1.0)));
  ASSERT_EQ(tilt.verdict, Verdict::violated);
  EXPECT_EQ(tilt.finding->quantity, Quantity::assembly_mode);
  EXPECT_NEAR(geometry::radians_to_degrees(-tilt.finding->pose[3]), 0.4982, 1e-3);
}

TEST(CertifyJob, ARealJobThroughTheHexapodsBasePlaneIsRefusedAtItsLine) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  // pcb2gcode's drill.ngc without --origin on LinuxCNC's hexapod sample: line 24's drilling cycle
  // plunges from Z0.08 to Z-0.063 in, through the base plane (post refused it there, with "no
  // block, however short", while check certified every move).
  const JobCheck check =
      check_job(linuxcnc_sample_hexapod(), test::real_corpus() / "cam/pcb2gcode/drill.ngc", {});
  EXPECT_FALSE(check.certified());
  ASSERT_TRUE(check.first_failure.has_value());
  EXPECT_EQ(check.first_failure->line, 24);
  EXPECT_EQ(check.first_failure->finding.quantity, Quantity::assembly_mode);
  EXPECT_NEAR(check.first_failure->finding.pose[2], 0.0, 1e-6);
  EXPECT_NEAR(check.first_failure->finding.pose[0], 0.9 * 25.4, 1e-9);
}

}  // namespace
}  // namespace pkm::certify

namespace pkm::certify {
namespace {

// Soundness, as a property: random moves (lines between random poses of the reachable box,
// some reaching past it) on machines of each kind; every move proven must pass 4001 samples, and
// every violation found must be a pose the machine refuses.
// The property for one machine: returns the numbers of proven and violated moves.
std::pair<int, int> check_soundness(const machine::Machine& machine, int trials) {
  const MoveProver prover(machine);
  std::mt19937_64 rng(13);
  const machine::PoseBox box = machine::reach_box(machine);
  std::uniform_real_distribution<double> share(-0.1, 1.1);
  const auto random_pose = [&] {
    geometry::Vector6d p = machine.home().as_vector();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!box.axes.controls(axis)) continue;
      const double span = box.max[axis] - box.min[axis];
      const double limited = axis >= 3 ? std::min(span, geometry::degrees_to_radians(30.0)) : span;
      const double low = axis >= 3 ? p[axis] - 0.5 * limited : box.min[axis];
      p[axis] = low + share(rng) * limited;
    }
    return p;
  };
  int proven = 0, violated = 0;
  kinematics::JointVector joints;
  for (int trial = 0; trial < trials; ++trial) {
    const motion::Segment segment = line(random_pose(), random_pose());
    const MoveProof proof = prover.prove(segment);
    if (proof.verdict == Verdict::proven) {
      ++proven;
      for (int k = 0; k <= 4000; ++k) {
        const geometry::Pose at = geometry::Pose::from_vector(segment.at(k / 4000.0));
        const kinematics::Status status = machine.inverse(at, joints);
        EXPECT_TRUE(status.ok()) << "trial " << trial << " sample " << k << ": "
                                 << machine.explain(at, status);
        if (!status.ok()) break;
      }
    } else if (proof.verdict == Verdict::violated) {
      ++violated;
      EXPECT_FALSE(machine.inverse(geometry::Pose::from_vector(proof.finding->pose), joints).ok());
    }
  }
  return {proven, violated};
}

class CertifyEveryKind : public ::testing::TestWithParam<std::string> {};

TEST_P(CertifyEveryKind, ProvenMovesPassDenseSamplesAndViolationsAreRefusedPoses) {
  const auto [proven, violated] = check_soundness(test::load_example(GetParam()), 100);
  // Both outcomes occur, so neither half of the property is empty.
  EXPECT_GT(proven, 0);
  EXPECT_GT(violated, 0);
  EXPECT_GE(proven + violated, 50);
}

TEST(CertifyLegLimits, ProvenMovesKeepJointAnglesAndClearances) {
  // The paper's hexapod with 30 deg joints and 120 mm legs: the angle and clearance bounds.
  std::ifstream file(test::example_machine_path("hexapod-bit.toml"));
  std::stringstream text;
  text << file.rdbuf();
  std::string toml = text.str();
  toml.replace(toml.find("tool_length = 30.0"), 18,
               "tool_length = 30.0\nmax_joint_angle = 30\nleg_diameter = 120");
  const machine::Machine machine = machine::parse_machine(toml, "hexapod-limited.toml");
  const auto [proven, violated] = check_soundness(machine, 150);
  EXPECT_GT(proven, 0);
  EXPECT_GT(violated, 0);
}

INSTANTIATE_TEST_SUITE_P(Examples, CertifyEveryKind,
                         ::testing::Values("hexapod-bit.toml", "hexaglide.toml",
                                           "linear-delta.toml", "triaglide.toml",
                                           "wall-plotter.toml", "hektor.toml", "matrix-mill.toml",
                                           "linuxcnc-rdelta.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

TEST(CertifySoundness, TheLinuxcncSampleHexapodsMovesAcrossItsBasePlane) {
  // Random lines near the base plane (z from -1 to 3 in, tilts within 3 deg, x and y within 1 in,
  // where the legs stay within 20..40 in): a proven move keeps every platform joint above the plane
  // at 4001 samples; a violated one is refused for the assembly mode at a pose the machine refuses;
  // both occur.
  const machine::Machine machine = linuxcnc_sample_hexapod();
  const MoveProver prover(machine);
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<double> across(-1.0, 1.0), height(-1.0, 3.0), tilt(-3.0, 3.0);
  const auto random_pose = [&] {
    return pose(25.4 * across(rng), 25.4 * across(rng), 25.4 * height(rng), tilt(rng), tilt(rng),
                tilt(rng));
  };
  const auto& hexapod = dynamic_cast<const kinematics::HexapodKinematics&>(machine.kinematics());
  int proven = 0, crossing = 0;
  kinematics::JointVector joints;
  for (int trial = 0; trial < 200; ++trial) {
    const motion::Segment segment = line(random_pose(), random_pose());
    const MoveProof proof = prover.prove(segment);
    if (proof.verdict == Verdict::proven) {
      ++proven;
      for (int k = 0; k <= 4000; ++k) {
        const geometry::Pose at = geometry::Pose::from_vector(segment.at(k / 4000.0));
        ASSERT_GT(hexapod.base_side(at).margin_mm, 0.0) << "trial " << trial << " sample " << k;
      }
    } else if (proof.verdict == Verdict::violated &&
               proof.finding->quantity == Quantity::assembly_mode) {
      ++crossing;
      EXPECT_EQ(machine.inverse(geometry::Pose::from_vector(proof.finding->pose), joints).code,
                kinematics::StatusCode::other_assembly);
    }
  }
  EXPECT_GT(proven, 10);
  EXPECT_GT(crossing, 10);
}

}  // namespace
}  // namespace pkm::certify

namespace pkm::certify {
namespace {

TEST(CertifyCables, ABeltCrossingItsPulleysOuterTangentIsViolatedWhereComputedByHand) {
  // hektor-pulleys.toml: the left belt hangs straight down from its pulley's rightmost point at
  // x = r = 6.366 mm; left of it the right belt would push. Along y = -50 from x = 10 to 3 that
  // is u = (10 - 6.366) / 7.
  const machine::Machine machine = test::load_example("hektor-pulleys.toml");
  const MoveProver prover(machine);
  EXPECT_TRUE(prover.unavailable().empty()) << prover.unavailable();
  const MoveProof proof = prover.prove(line(pose(10, -50, 0), pose(3, -50, 0)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->quantity, Quantity::pull);
  EXPECT_EQ(proof.finding->index, 1);
  EXPECT_NEAR(proof.finding->u0, (10.0 - 6.366) / 7.0, 1e-9);
  const MoveProof clear = prover.prove(line(pose(10, -50, 0), pose(6.4, -50, 0)));
  EXPECT_EQ(clear.verdict, Verdict::proven);
}

machine::Machine straight_makelangelo() {
  return machine::load_machine(std::string(PKM_SOURCE_DIR) +
                               "/tests/data/makelangelo-straight.toml");
}

// The line of tests/data/tension-between-samples.ngc: the left cable's tension least (0.5 N -
// 1e-8 N, below tension_limits' min) 10.1 mm along its 19.8 mm, below the min from u = 0.504378
// to 0.515825 (found by 2 million samples).
const Eigen::Vector2d kDipStart(238.673597626, 10.064767823), kDipEnd(237.021219713, -9.666163407);

TEST(CertifyCables, ATensionDipBelowTheMinBetweenSamplesIsViolatedWhereItStarts) {
  const machine::Machine machine = straight_makelangelo();
  const MoveProver prover(machine);
  EXPECT_TRUE(prover.unavailable().empty()) << prover.unavailable();
  const MoveProof proof =
      prover.prove(line(pose(kDipStart.x(), kDipStart.y(), 0), pose(kDipEnd.x(), kDipEnd.y(), 0)));
  ASSERT_EQ(proof.verdict, Verdict::violated);
  EXPECT_EQ(proof.finding->quantity, Quantity::tension);
  EXPECT_EQ(proof.finding->index, 0);
  EXPECT_EQ(proof.finding->limit, 0.5);
  EXPECT_NEAR(proof.finding->u0, 0.504378, 1e-6);
  EXPECT_NEAR(proof.finding->worst_value, 0.5 - 1e-8, 1e-10);
  EXPECT_NE(proof.finding->text.find("left cable would go slack"), std::string::npos);
  // 3.06e-6 mm up the tension's gradient (0.0065 N/mm), the line's least tension is 0.5 + 1e-8:
  // proven.
  const Eigen::Vector2d up = Eigen::Vector2d(-0.99651, 0.08345) * 3.06e-6;
  const MoveProof clear = prover.prove(line(pose(kDipStart.x() + up.x(), kDipStart.y() + up.y(), 0),
                                            pose(kDipEnd.x() + up.x(), kDipEnd.y() + up.y(), 0)));
  EXPECT_EQ(clear.verdict, Verdict::proven);
}

TEST(CertifyCables, SaggingCablesAreUndecidedSayingWhy) {
  const machine::Machine machine = test::load_example("makelangelo.toml");
  const MoveProver prover(machine);
  EXPECT_NE(prover.unavailable().find("cables that sag (cable_density > 0)"), std::string::npos);
  EXPECT_EQ(prover.prove(line(pose(0, 0, 0), pose(10, 0, 0))).verdict, Verdict::undecided);
}

// Random lines over a weighed, tilting, straight-cable gondola: every proven move passes 401
// samples of the machine's inverse; every violation found is a pose the machine refuses.
TEST(CertifyCables, ProvenMovesOfAWeighedGondolaPassEverySample) {
  const machine::Machine machine = straight_makelangelo();
  const MoveProver prover(machine);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> x(-350.0, 350.0), y(-700.0, 480.0);
  int proven = 0, violated = 0;
  kinematics::JointVector joints;
  for (int n = 0; n < 60; ++n) {
    const motion::Segment segment = line(pose(x(rng), y(rng), 0), pose(x(rng), y(rng), 0));
    const MoveProof proof = prover.prove(segment);
    if (proof.verdict == Verdict::proven) {
      ++proven;
      for (int k = 0; k <= 400; ++k) {
        ASSERT_TRUE(
            machine.inverse(geometry::Pose::from_vector(segment.at(k / 400.0)), joints).ok());
      }
    } else if (proof.verdict == Verdict::violated) {
      ++violated;
      ASSERT_FALSE(machine.inverse(geometry::Pose::from_vector(proof.finding->pose), joints).ok());
    }
  }
  EXPECT_GT(proven, 10);
  EXPECT_GT(violated, 10);
}

}  // namespace
}  // namespace pkm::certify
