// A joint's max_jerk: read from the machine file in its units, refused when not a positive
// finite number, kept when a calibration rewrites the file, and held by the jerk-limited planner
// in every sample's third difference.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/motion/planner.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

std::string example_text(const std::string& file) {
  std::ifstream in(test::example_machine_path(file));
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// `text` with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
    text.replace(at, from.size(), to);
    at += to.size();
  }
  return text;
}

int line_of(const std::string& text, const std::string& what) {
  const std::size_t at = text.find(what);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

TEST(JerkMachineFile, MaxJerkIsReadInTheJointsUnits) {
  // mm/s^3 on a linear joint; in/s^3 in an inch file (25.4 mm each); deg/s^3 on a rotary joint.
  const machine::Machine delta =
      test::load_example_changed("linear-delta.toml", "max_acceleration = 3000.0\n",
                                 "max_acceleration = 3000.0\nmax_jerk = 20000.0\n");
  for (const machine::JointSpec& joint : delta.joints()) EXPECT_EQ(joint.max_jerk, 20000.0);
  const machine::Machine hexapod = test::load_example_changed(
      "linuxcnc-hexapod-sim.toml", "name = \"leg0\"\n", "name = \"leg0\"\nmax_jerk = 4000.0\n");
  EXPECT_DOUBLE_EQ(hexapod.joints()[0].max_jerk, 4000.0 * 25.4);
  EXPECT_EQ(hexapod.joints()[1].max_jerk, 0.0);  // only leg0 has one
  const machine::Machine rotary =
      test::load_example_changed("linuxcnc-rdelta.toml", "max_acceleration = 50.0     # deg/s^2\n",
                                 "max_acceleration = 50.0\nmax_jerk = 900.0\n");
  EXPECT_DOUBLE_EQ(rotary.joints()[0].max_jerk, 900.0 * std::numbers::pi / 180.0);
  EXPECT_EQ(test::load_example("linear-delta.toml").joints()[0].max_jerk, 0.0);
}

TEST(JerkMachineFile, MaxJerkMustBeAPositiveFiniteNumber) {
  const std::string original = example_text("linear-delta.toml");
  const std::string anchor = "max_acceleration = 3000.0\naxis = \"Y\"\n";
  for (const std::string value : {"0.0", "-5000.0", "nan", "inf", "1e13", "\"fast\""}) {
    const std::string text = replaced(
        original, anchor, "max_acceleration = 3000.0\nmax_jerk = " + value + "\naxis = \"Y\"\n");
    const std::string where =
        "linear-delta.toml:" + std::to_string(line_of(text, "max_jerk")) + ":joints[2].max_jerk: ";
    try {
      machine::parse_machine(text, "linear-delta.toml");
      ADD_FAILURE() << "max_jerk = " << value << " was accepted";
    } catch (const machine::MachineFileError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.substr(0, where.size()), where) << message;
      if (value == "0.0" || value == "-5000.0" || value == "1e13") {
        EXPECT_NE(message.find("must be between 0.001 and 1e+12 mm/s^3"), std::string::npos)
            << message;
      }
    }
  }
}

TEST(JerkMachineFile, RewritingTheKinematicsKeepsMaxJerk) {
  // A calibration writes the [kinematics] section back and keeps the joints as written.
  const std::string text =
      replaced(example_text("linuxcnc-rdelta.toml"), "max_acceleration = 50.0     # deg/s^2\n",
               "max_acceleration = 50.0     # deg/s^2\nmax_jerk = 900.0\n");
  const machine::Machine machine = machine::parse_machine(text, "rdelta.toml");
  const std::string rewritten = machine::replace_kinematics_section(
      text, "rdelta.toml", machine.kinematics(), machine.units());
  const machine::Machine reread = machine::parse_machine(rewritten, "rdelta.toml");
  ASSERT_EQ(reread.joints().size(), machine.joints().size());
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    EXPECT_EQ(reread.joints()[i].max_jerk, machine.joints()[i].max_jerk) << i;
  }
  EXPECT_DOUBLE_EQ(reread.joints()[0].max_jerk, 900.0 * std::numbers::pi / 180.0);
}

struct Collect final : motion::SampleSink {
  std::vector<motion::Sample> samples;
  void write(const motion::Sample& sample) override { samples.push_back(sample); }
};

motion::PlanReport plan(const machine::Machine& machine, const std::string& program, Collect& out,
                        const motion::PlanOptions& options = {}) {
  const auto path =
      std::filesystem::temp_directory_path() / ("pkm-jerk-" + std::to_string(::getpid()) + ".ngc");
  std::ofstream(path) << program;
  motion::PlanReport report;
  try {
    report = motion::plan_program(machine, path, {}, options, out);
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
  std::filesystem::remove(path);
  return report;
}

struct JointPeaks {
  std::vector<double> velocity, acceleration, jerk;
};

// Each joint's largest first, second and third difference of the samples over the period's
// powers, over runs of samples one period apart (the last sample lands on the job's end).
JointPeaks joint_peaks(const std::vector<motion::Sample>& samples, double period_s) {
  const std::size_t joints = static_cast<std::size_t>(samples.front().joints.size());
  JointPeaks peaks{std::vector<double>(joints), std::vector<double>(joints),
                   std::vector<double>(joints)};
  const auto even = [&](std::size_t k, std::size_t back) {
    for (std::size_t n = 0; n < back; ++n) {
      const double dt = samples[k - n].time_s - samples[k - n - 1].time_s;
      if (std::abs(dt - period_s) > 1e-9 * period_s) return false;
    }
    return true;
  };
  for (std::size_t k = 1; k < samples.size(); ++k) {
    for (std::size_t i = 0; i < joints; ++i) {
      const auto q = [&](std::size_t back) {
        return samples[k - back].joints[static_cast<int>(i)];
      };
      const double t = period_s;
      if (even(k, 1)) peaks.velocity[i] = std::max(peaks.velocity[i], std::abs(q(0) - q(1)) / t);
      if (k >= 2 && even(k, 2)) {
        const double second = q(0) - 2.0 * q(1) + q(2);
        peaks.acceleration[i] = std::max(peaks.acceleration[i], std::abs(second) / (t * t));
      }
      if (k >= 3 && even(k, 3)) {
        const double third = q(0) - 3.0 * q(1) + 3.0 * q(2) - q(3);
        peaks.jerk[i] = std::max(peaks.jerk[i], std::abs(third) / (t * t * t));
      }
    }
  }
  return peaks;
}

// Lines across the delta's reach and an arc, each to a stop (G61).
constexpr const char* kStopJob =
    "G21 G90 G61\n"
    "G1 F6000 X-100 Y-80 Z20\n"
    "G1 X40 Y50 Z40\n"
    "G2 X40 Y-50 I0 J-50\n"
    "G0 X0 Y0 Z100\n"
    "M2\n";

constexpr double kMaxJerk = 20000.0;  // mm/s^3, each tower

machine::Machine delta_with_max_jerk(double max_jerk) {
  return test::load_example_changed(
      "linear-delta.toml", "max_acceleration = 3000.0\n",
      "max_acceleration = 3000.0\nmax_jerk = " + machine::toml_number(max_jerk) + "\n");
}

// The third difference of samples one period T apart is T^3 times a weighted mean of q''' over
// the three periods (the weights, a quadratic B-spline, sum to one) wherever q is twice
// continuously differentiable, as it is along a move and at a stop, where the ramps start and end
// at zero acceleration: so the 1 ms sampling needs no tolerance of its own. What is left is the
// rounding of four joint values of some 300 mm (1e-13 mm each, 8e-13 mm in the difference, over
// T^3 = 1e-9 s^3: 1e-3 mm/s^3), far within the 1e-6 of 20,000 mm/s^3 kept here. The planner
// keeps 15 % of max_jerk: 10 % for junctions passed at speed, the rest for the sampling of q'''
// along the path every 0.5 mm (the bound it plans with is a sum of maxima: the samples reach 70 %
// of max_jerk here).
TEST(JerkPlan, MaxJerkHoldsInEverySampleAndCostsTime) {
  const machine::Machine delta = delta_with_max_jerk(kMaxJerk);
  Collect limited;
  const motion::PlanReport report = plan(delta, kStopJob, limited);
  const JointPeaks peaks = joint_peaks(limited.samples, 0.001);
  double highest = 0.0;
  for (std::size_t i = 0; i < peaks.jerk.size(); ++i) {
    const machine::JointSpec& joint = delta.joints()[i];
    EXPECT_LE(peaks.jerk[i], kMaxJerk * (1.0 + 1e-6)) << joint.name;
    EXPECT_LE(peaks.velocity[i], joint.max_velocity * (1.0 + 1e-9)) << joint.name;
    EXPECT_LE(peaks.acceleration[i], joint.max_acceleration * (1.0 + 1e-6)) << joint.name;
    highest = std::max(highest, peaks.jerk[i]);
  }
  EXPECT_GT(highest, 0.6 * kMaxJerk);  // the limit is what bounds the ramps (70 % today)
  motion::PlanOptions estimate;
  estimate.estimate_only = true;
  Collect none;
  EXPECT_EQ(plan(delta, kStopJob, none, estimate).duration_s, report.duration_s);
  Collect free;
  const motion::PlanReport unlimited =
      plan(test::load_example("linear-delta.toml"), kStopJob, free);
  const JointPeaks free_peaks = joint_peaks(free.samples, 0.001);
  EXPECT_GT(*std::max_element(free_peaks.jerk.begin(), free_peaks.jerk.end()), 10.0 * kMaxJerk);
  EXPECT_LT(unlimited.duration_s, report.duration_s - 0.05);
}

TEST(JerkPlan, MaxJerkHoldsThroughBlendsAndTangentJoins) {
  // G64: the corners are blended, the arc joins its lines tangentially; passing a junction at
  // speed the joints' velocity and acceleration change between two samples.
  const machine::Machine delta = delta_with_max_jerk(kMaxJerk);
  Collect out;
  plan(delta,
       "G21 G90 G64 P0.05\nG1 F6000 X-60 Y-40 Z30\nG1 X60 Y-40\nG3 X60 Y40 I0 J40\n"
       "G1 X-60 Y40\nG1 X-60 Y-40\nM2\n",
       out);
  const JointPeaks peaks = joint_peaks(out.samples, 0.001);
  for (std::size_t i = 0; i < peaks.jerk.size(); ++i) {
    EXPECT_LE(peaks.jerk[i], kMaxJerk * (1.0 + 1e-6)) << delta.joints()[i].name;
  }
}

TEST(JerkPlan, ToolJerkIsTheLeastOfTheOptionAndTheJoints) {
  // A --jerk far below what the joints allow is the ramps' jerk; one far above is lowered to
  // theirs: the plan then equals the plan with the joints' limit alone.
  const machine::Machine delta = delta_with_max_jerk(kMaxJerk);
  motion::PlanOptions soft, stiff;
  soft.jerk_mm_per_s3 = 1000.0;
  stiff.jerk_mm_per_s3 = 1e9;
  Collect a, b, c;
  const double joints_only = plan(delta, kStopJob, a).duration_s;
  EXPECT_EQ(plan(delta, kStopJob, b, stiff).duration_s, joints_only);
  EXPECT_GT(plan(delta, kStopJob, c, soft).duration_s, joints_only + 0.1);
}

// The linear delta with joints slower than its tool (1000 mm/s^2 against 2000): the joints'
// acceleration bounds the moves.
machine::Machine delta_with_slow_joints() {
  return test::load_example_changed("linear-delta.toml", "max_acceleration = 3000.0\n",
                                    "max_acceleration = 1000.0\n");
}

TEST(JerkPlan, SoftJerkRampsUseTheJointsWholeAcceleration) {
  // At 20,000 mm/s^3 the ramps' acceleration rises 40 mm/s^2 in two periods: a junction's
  // reserve stays free without the 80 % share along the move.
  const machine::Machine delta = delta_with_slow_joints();
  motion::PlanOptions options;
  options.jerk_mm_per_s3 = 20000.0;
  Collect out;
  // Straight down, the towers move as the tool: their acceleration is the ramps'.
  plan(delta, "G21 G90 G61\nG1 F9000 Z250\nG1 Z20\nM2\n", out, options);
  const JointPeaks peaks = joint_peaks(out.samples, 0.001);
  const double highest = *std::max_element(peaks.acceleration.begin(), peaks.acceleration.end());
  EXPECT_LE(highest, 1000.0 * (1.0 + 1e-6));
  EXPECT_GT(highest, 999.0);  // not 800: kMoveAccelerationShare of it
}

TEST(JerkPlan, JointLimitsHoldAtTangentJoinsPassedAtSpeed) {
  // A circle of 10,000 lines (0.036 deg apart: tangent joins, passed at speed) where each
  // tower's rate along the path changes at every join: the junctions' reserve and the moves'
  // whole acceleration together stay within the limit in every sample.
  const machine::Machine delta = delta_with_slow_joints();
  std::string program = "G21 G90 G64\nG1 F6000 X60 Y0 Z30\n";
  constexpr int kLines = 10000;
  for (int k = 1; k <= kLines; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kLines;
    program += "G1 X" + std::to_string(60.0 * std::cos(angle)) + " Y" +
               std::to_string(60.0 * std::sin(angle)) + "\n";
  }
  program += "M2\n";
  for (const double jerk : {20000.0, 1e6}) {
    motion::PlanOptions options;
    options.jerk_mm_per_s3 = jerk;
    Collect out;
    plan(delta, program, out, options);
    const JointPeaks peaks = joint_peaks(out.samples, 0.001);
    for (std::size_t i = 0; i < peaks.acceleration.size(); ++i) {
      const machine::JointSpec& joint = delta.joints()[i];
      EXPECT_LE(peaks.acceleration[i], joint.max_acceleration * (1.0 + 1e-6)) << jerk;
      EXPECT_LE(peaks.velocity[i], joint.max_velocity * (1.0 + 1e-9)) << jerk;
    }
  }
}

TEST(JerkPlan, JointLimitsHoldWhereAJunctionTakesItsReserve) {
  // Straight down (every tower's rate along the path 1, the tool's acceleration theirs), then
  // 10 mm on 0.9 mrad off straight (a tangent join, passed at speed), braking on both sides of
  // the join to the stop at the end; tower_c's rate jumps by 4.9e-4 there, taking up to the
  // 20 % reserve of its 150 mm/s^2. At 1e6 mm/s^3 the ramps brake at the move's whole
  // acceleration up to a period from the join: the moves must keep 80 % (with all of it the
  // samples reach 153.9 mm/s^2); at 2e4 they ease off in time and may take all.
  const machine::Machine delta = test::load_example_changed(
      "linear-delta.toml", "max_acceleration = 3000.0\n", "max_acceleration = 150.0\n");
  for (const double jerk : {20000.0, 1e6}) {
    motion::PlanOptions options;
    options.jerk_mm_per_s3 = jerk;
    Collect out;
    plan(delta, "G21 G90 G64\nG1 F9000 Z250\nG1 Z100\nG1 X0.009 Z90\nM2\n", out, options);
    const JointPeaks peaks = joint_peaks(out.samples, 0.001);
    for (std::size_t i = 0; i < peaks.acceleration.size(); ++i) {
      EXPECT_LE(peaks.acceleration[i], 150.0 * (1.0 + 1e-6)) << delta.joints()[i].name << jerk;
    }
  }
}

}  // namespace
}  // namespace pkm
