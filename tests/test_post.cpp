// Joint-space programs: checked independently of the post-processor by reading them back with the
// interpreter and running forward kinematics densely along every joint-linear block.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "pkm/geometry/distance.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/post/deviation_bound.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/mach3_export.hpp"
#include "pkm/verify/joint_path.hpp"
#include "test_support.hpp"

namespace pkm::post {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("pkm-post-" + std::to_string(::getpid()) + "-" + name);
}

// The programmed moves of a job, in machine coordinates.
std::vector<motion::Segment> programmed_moves(const Machine& machine,
                                              const std::filesystem::path& job,
                                              const Vector6d& origin = Vector6d::Zero()) {
  const Vector6d home = machine.home().as_vector();
  const gcode::InterpreterOptions options = motion::starting_at({}, home, origin);
  motion::SegmentBuilder builder(home, origin, false);
  std::vector<motion::Segment> moves;
  gcode::Interpreter(job, options).run([&](const gcode::Canon& canon) {
    const auto segment = builder.take(canon);
    if (segment && segment->kind != motion::SegmentKind::dwell) moves.push_back(*segment);
  });
  return moves;
}

// Exact distance from p to a line or to a planar arc (no motion along its normal); the positions
// the machine does not control are taken from p, so they never count.
double distance_to_move(Eigen::Vector3d p, const motion::Segment& move, Dof dof) {
  Vector6d start = move.start, end = move.end;
  for (int axis = 0; axis < 3; ++axis) {
    if (!dof.controls(axis)) start[axis] = end[axis] = p[axis];
  }
  if (move.kind == motion::SegmentKind::line) {
    return distance_to_segment(p, start.head<3>(), end.head<3>());
  }
  EXPECT_EQ(move.kind, motion::SegmentKind::arc);
  EXPECT_EQ(start[move.normal_axis], end[move.normal_axis]);
  const int a = move.first_axis, b = move.second_axis;
  const double radius = std::hypot(start[a] - move.centre[a], start[b] - move.centre[b]);
  const double start_angle = std::atan2(start[b] - move.centre[b], start[a] - move.centre[a]);
  double angle = std::atan2(p[b] - move.centre[b], p[a] - move.centre[a]) - start_angle;
  // The angle from the start in the arc's own direction, in [0, 2 pi).
  angle = std::fmod(move.sweep_rad >= 0.0 ? angle : -angle, 2.0 * M_PI);
  if (angle < 0.0) angle += 2.0 * M_PI;
  double nearest = std::min((p - start.head<3>()).norm(), (p - end.head<3>()).norm());
  if (angle <= std::abs(move.sweep_rad)) {
    const double in_plane =
        std::abs(std::hypot(p[a] - move.centre[a], p[b] - move.centre[b]) - radius);
    nearest =
        std::min(nearest, std::hypot(in_plane, p[move.normal_axis] - start[move.normal_axis]));
  }
  return nearest;
}

double distance_to_path(const Eigen::Vector3d& p, const std::vector<motion::Segment>& moves,
                        Dof dof) {
  double nearest = INFINITY;
  for (const auto& move : moves) nearest = std::min(nearest, distance_to_move(p, move, dof));
  return nearest;
}

// The joint values of every block of a joint-space program, read back by the interpreter.
std::vector<JointVector> joint_blocks(const Machine& machine, const std::filesystem::path& file) {
  std::vector<JointVector> blocks;
  JointVector home;
  EXPECT_TRUE(machine.inverse(machine.home(), home).ok());
  gcode::InterpreterOptions options;
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const JointSpec& joint = machine.joints()[i];
    const int index = static_cast<int>(std::string("XYZABCUVW").find(joint.axis_letter));
    options.start_position[index] = joint.to_interface(home[static_cast<int>(i)]);
  }
  blocks.push_back(home);
  gcode::Interpreter(file, options).run([&](const gcode::Canon& canon) {
    if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
    JointVector q(static_cast<int>(machine.joints().size()));
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const JointSpec& joint = machine.joints()[i];
      const double value = canon.end[std::string("XYZABCUVW").find(joint.axis_letter)];
      q[static_cast<int>(i)] = joint.from_interface(value);
    }
    blocks.push_back(q);
  });
  return blocks;
}

// The worst distance from the programmed path of the tool tip along every joint-linear block, by
// forward kinematics at `points` + 1 points per block.
double dense_deviation(const Machine& machine, const std::vector<JointVector>& blocks,
                       const std::vector<motion::Segment>& moves, int points = 1000) {
  double worst = 0.0;
  Pose pose = machine.home();
  for (std::size_t b = 1; b < blocks.size(); ++b) {
    for (int k = 0; k <= points; ++k) {
      const JointVector q =
          blocks[b - 1] + (k / static_cast<double>(points)) * (blocks[b] - blocks[b - 1]);
      EXPECT_TRUE(machine.forward(q, pose).ok());
      worst =
          std::max(worst, distance_to_path(pose.position_mm, moves, machine.kinematics().dof()));
    }
  }
  return worst;
}

// A small job about home in the machine's first two controlled axes, with an arc where those are
// x and y, and an attitude change on machines that control one.
std::string job_about_home(const Machine& machine) {
  const Vector6d home = machine.home().as_vector();
  const bool xy = machine.kinematics().dof().controls(0) && machine.kinematics().dof().controls(1);
  char text[512];
  std::string job = "G21 G90 F600\n";
  std::snprintf(text, sizeof text, "G1 X%.4f Y%.4f\nG1 X%.4f Y%.4f\n", home[0] + 8, home[1],
                home[0] + 8, home[1] + 8);
  job += text;
  if (xy) {
    std::snprintf(text, sizeof text, "G3 X%.4f Y%.4f I-8 J0\n", home[0] - 8, home[1] + 8);
    job += text;
  }
  if (machine.kinematics().dof().any_rotation()) job += "G1 A4 B-3\n";
  std::snprintf(text, sizeof text, "G0 X%.4f Y%.4f\nM2\n", home[0], home[1]);
  return job + text;
}

PostReport post_to_file(const Machine& machine, const std::filesystem::path& job,
                        const std::filesystem::path& output, const PostOptions& options) {
  std::ofstream out(output);
  return post_program(machine, job, {}, options,
                      [&](const std::string& line) { out << line << "\n"; });
}

class PostEveryMachine : public ::testing::TestWithParam<std::string> {};

TEST_P(PostEveryMachine, NothingAboveTheReportedBoundCheckedDensely) {
  // Forward kinematics at 1,001 points of every block, against the exact programmed lines and
  // arcs: nothing above the bound the post reports (formula machines have a sampled deviation,
  // held to the tolerance only).
  const Machine machine = test::load_example(GetParam());
  const auto job = temp_file("job.ngc");
  std::ofstream(job) << job_about_home(machine);
  const auto moves = programmed_moves(machine, job);
  for (const double tolerance : {0.1, 0.01, 0.001}) {
    const auto output = temp_file("joints.ngc");
    PostOptions options;
    options.tolerance_mm = tolerance;
    const PostReport report = post_to_file(machine, job, output, options);
    EXPECT_LE(report.max_deviation_mm, tolerance);
    const std::vector<JointVector> blocks = joint_blocks(machine, output);
    EXPECT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
    const double dense = dense_deviation(machine, blocks, moves);
    std::cout << "[ bound    ] tolerance " << tolerance << ": " << report.blocks
              << " blocks, largest found " << dense << " mm, reported " << report.max_deviation_mm
              << " mm\n";
    if (report.bounded) {
      EXPECT_LE(dense, report.max_deviation_mm) << "tolerance " << tolerance;
    } else {
      EXPECT_EQ(machine.kinematics().type(), "formula");
      EXPECT_LE(dense, tolerance * 1.02) << "tolerance " << tolerance;
    }
    std::filesystem::remove(output);
  }
  std::filesystem::remove(job);
}

INSTANTIATE_TEST_SUITE_P(Examples, PostEveryMachine,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

TEST(Verify, FlagsACoarseJointProgramAtItsLine) {
  // Each move of the job as one joint-linear block: the arc (job line 3) becomes block line 3.
  const Machine hektor = test::load_example("hektor.toml");
  const auto job = temp_file("coarse-job.ngc");
  std::ofstream(job) << "G21 G90 F600\nG1 X20 Y-60\nG2 X80 Y-60 I30 J0\nG1 X50 Y-20\nM2\n";
  const auto joints = temp_file("coarse-joints.ngc");
  {
    std::ofstream out(joints);
    out << "G21 G90 G94 F600\n";
    for (const auto& [x, y] :
         std::vector<std::pair<double, double>>{{20, -60}, {80, -60}, {50, -20}}) {
      JointVector q;
      ASSERT_TRUE(hektor.inverse(Pose::from_mm_deg(x, y, 0), q).ok());
      out << "G1 A" << q[0] << " B" << q[1] << "\n";
    }
    out << "M2\n";
  }
  const verify::VerifyReport report = verify::verify_joint_program(hektor, joints, job, {});
  std::filesystem::remove(job);
  std::filesystem::remove(joints);
  EXPECT_EQ(report.blocks, 3);
  EXPECT_GT(report.max_deviation_mm, 10.0);  // the chord of a 30 mm arc in joint space
  EXPECT_EQ(report.max_deviation_joint_line, 3);
  EXPECT_TRUE(report.violations.empty());
}

// Joints rounded as the linuxcnc dialect writes them (5 decimals of mm or deg).
JointVector rounded_as_written(const Machine& machine, const JointVector& q) {
  JointVector result = q;
  for (int i = 0; i < q.size(); ++i) {
    const JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    result[i] = joint.from_interface(std::round(joint.to_interface(q[i]) * 1e5) / 1e5);
  }
  return result;
}

// Blocks of the adaptive post, and of uniform splitting held to the same bound: per move, the
// fewest equal pieces each of whose bound is within `tolerance`.
std::pair<long, long> adaptive_and_uniform(const Machine& machine, const std::string& job_text,
                                           double tolerance) {
  const auto job = temp_file("uniform-job.ngc");
  std::ofstream(job) << job_text;
  PostOptions options;
  options.tolerance_mm = tolerance;
  const long adaptive = post_program(machine, job, {}, options, [](const std::string&) {}).blocks;
  const DeviationBound bound(machine, 10.0 * tolerance);
  long uniform = 0;
  for (const motion::Segment& move : programmed_moves(machine, job)) {
    const auto joints_at = [&](double u) {
      JointVector q;
      EXPECT_TRUE(machine.inverse(Pose::from_vector(move.at(u)), q).ok());
      return q;
    };
    const auto fits = [&](int pieces) {
      for (int k = 0; k < pieces; ++k) {
        const double u0 = static_cast<double>(k) / pieces, u1 = static_cast<double>(k + 1) / pieces;
        const JointVector q0 = joints_at(u0), q1 = joints_at(u1);
        const BlockEnds ends{rounded_as_written(machine, q0), q0, rounded_as_written(machine, q1),
                             q1};
        if (!(bound(move, u0, u1, ends) <= tolerance)) return false;
      }
      return true;
    };
    int low = 0, high = 1;
    while (!fits(high)) {
      low = high;
      high *= 2;
    }
    while (high - low > 1) {
      const int middle = (low + high) / 2;
      (fits(middle) ? high : low) = middle;
    }
    uniform += high;
  }
  std::filesystem::remove(job);
  return {adaptive, uniform};
}

TEST(Post, BlocksAgainstUniformSplittingOnEveryMachine) {
  // A square of 2 x 16 mm about home: reports the ratio per machine; adaptive is never worse.
  for (const std::string& file : test::example_machine_files()) {
    const Machine machine = test::load_example(file);
    if (!DeviationBound(machine, 0.01).available()) continue;  // formula machines: sampled
    int axes[2] = {0, 1};
    for (int axis = 0, n = 0; axis < 3 && n < 2; ++axis) {
      if (machine.kinematics().dof().controls(axis)) axes[n++] = axis;
    }
    const Vector6d home = machine.home().as_vector();
    const char letters[] = "XYZ";
    std::ostringstream job;
    job << "G21 G90 F600\n";
    for (const auto& [dx, dy] :
         std::vector<std::pair<int, int>>{{16, 0}, {16, 16}, {-16, 16}, {-16, 0}, {0, 0}}) {
      job << "G1 " << letters[axes[0]] << home[axes[0]] + dx << " " << letters[axes[1]]
          << home[axes[1]] + dy << "\n";
    }
    job << "M2\n";
    const auto [adaptive, uniform] = adaptive_and_uniform(machine, job.str(), 0.001);
    std::cout << "[ blocks   ] " << file << ": adaptive " << adaptive << ", uniform " << uniform
              << " (ratio " << static_cast<double>(uniform) / static_cast<double>(adaptive)
              << ")\n";
    EXPECT_LE(adaptive, uniform) << file;
  }
}

TEST(Post, FewerBlocksThanUniformSplitting) {
  // Hektor near its anchors bends its joint paths far more than in the middle: adaptive splits
  // spend blocks there only.
  const auto [adaptive, uniform] = adaptive_and_uniform(
      test::load_example("hektor.toml"),
      "G21 G90 F600\nG1 X10 Y-12\nG1 X90 Y-12\nG1 X50 Y-90\nG1 X10 Y-12\nM2\n", 0.01);
  std::cout << "[ blocks   ] adaptive " << adaptive << ", uniform " << uniform << " (ratio "
            << static_cast<double>(uniform) / static_cast<double>(adaptive) << ")\n";
  EXPECT_LT(adaptive, uniform);
}

}  // namespace
}  // namespace pkm::post

namespace pkm::post {
namespace {

TEST(ExportMach3, FormulasReproduceTheMachinesInverseKinematics) {
  // Each exported formula, evaluated by muparser as a formula machine would, gives the joints of
  // the machine's own model at random poses; the Hektor formulas read as the source document's.
  for (const std::string& file :
       {std::string("hektor.toml"), std::string("wall-plotter.toml"),
        std::string("matrix-mill.toml"), std::string("triaglide.toml"),
        std::string("triaglide-fanned.toml"), std::string("linear-delta.toml"),
        std::string("mach3-formula.toml")}) {
    const Machine machine = test::load_example(file);
    const auto formulas = mach3_formulas(machine);
    FormulaDefinition definition;
    for (int axis = 0; axis < 3; ++axis) {
      if (machine.kinematics().dof().controls(axis)) definition.axes.push_back(axis);
    }
    for (std::size_t i = 0; i < formulas.size(); ++i) {
      definition.formulas.emplace_back(machine.joints()[i].name, formulas[i].second);
    }
    const FormulaKinematics exported(definition);
    std::mt19937_64 rng(4);
    for (const Pose& pose : test::sample_reachable_poses(machine, 200, rng)) {
      JointVector expected, actual;
      ASSERT_TRUE(machine.kinematics().inverse(pose, expected).ok());
      ASSERT_TRUE(exported.inverse(pose, actual).ok()) << file;
      EXPECT_LT((expected - actual).cwiseAbs().maxCoeff(), 1e-9) << file;
    }
  }
  const auto hektor = mach3_formulas(test::load_example("hektor.toml"));
  EXPECT_EQ(hektor[0], (std::pair<char, std::string>{'a', "sqrt((x^2) + (y^2))"}));
  EXPECT_EQ(hektor[1], (std::pair<char, std::string>{'b', "sqrt(((100 - x)^2) + (y^2))"}));
  EXPECT_THROW(mach3_formulas(test::load_example("hexapod-bit.toml")), std::invalid_argument);
}

}  // namespace
}  // namespace pkm::post
