// Joint-space programs: checked independently of the post-processor by reading them back with the
// interpreter and running forward kinematics densely along every joint-linear block.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <random>

#include "pkm/geometry/distance.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/mach3_export.hpp"
#include "test_support.hpp"

namespace pkm::post {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("pkm-post-" + std::to_string(::getpid()) + "-" + name);
}

// The programmed path, densely sampled per move.
std::vector<std::vector<Eigen::Vector3d>> programmed_path(const Machine& machine,
                                                          const std::filesystem::path& job) {
  const Vector6d home = machine.home().as_vector();
  const gcode::InterpreterOptions options = motion::starting_at({}, home, Vector6d::Zero());
  motion::SegmentBuilder builder(home, Vector6d::Zero(), false);
  std::vector<std::vector<Eigen::Vector3d>> path;
  gcode::Interpreter(job, options).run([&](const gcode::Canon& canon) {
    const auto segment = builder.take(canon);
    if (!segment || segment->kind == motion::SegmentKind::dwell) return;
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k <= 1000; ++k) points.push_back(segment->at(k / 1000.0).head<3>());
    path.push_back(std::move(points));
  });
  return path;
}

double distance_to_path(const Eigen::Vector3d& p,
                        const std::vector<std::vector<Eigen::Vector3d>>& path) {
  double nearest = INFINITY;
  for (const auto& points : path) nearest = std::min(nearest, distance_to_polyline(p, points));
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

// The worst distance from the programmed path of the tool tip along every joint-linear block.
double dense_deviation(const Machine& machine, const std::vector<JointVector>& blocks,
                       const std::vector<std::vector<Eigen::Vector3d>>& path) {
  double worst = 0.0;
  Pose pose = machine.home();
  for (std::size_t b = 1; b < blocks.size(); ++b) {
    for (int k = 0; k <= 100; ++k) {
      const JointVector q = blocks[b - 1] + (k / 100.0) * (blocks[b] - blocks[b - 1]);
      EXPECT_TRUE(machine.forward(q, pose).ok());
      worst = std::max(worst, distance_to_path(pose.position_mm, path));
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

class PostEveryMachine : public ::testing::TestWithParam<std::string> {};

TEST_P(PostEveryMachine, StaysWithinTheToleranceCheckedDensely) {
  const Machine machine = test::load_example(GetParam());
  const auto job = temp_file("job.ngc");
  std::ofstream(job) << job_about_home(machine);
  const auto path = programmed_path(machine, job);
  for (const double tolerance : {0.1, 0.01, 0.001}) {
    const auto output = temp_file("joints.ngc");
    PostOptions options;
    options.tolerance_mm = tolerance;
    std::ofstream out(output);
    const PostReport report = post_program(machine, job, {}, options,
                                           [&](const std::string& line) { out << line << "\n"; });
    out.close();
    EXPECT_LE(report.max_deviation_mm, tolerance);
    const std::vector<JointVector> blocks = joint_blocks(machine, output);
    EXPECT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
    // A little above the tolerance would be the verifier's own polyline; the post checks the
    // exact path.
    EXPECT_LE(dense_deviation(machine, blocks, path), tolerance * 1.02)
        << "tolerance " << tolerance;
    std::filesystem::remove(output);
  }
  std::filesystem::remove(job);
}

INSTANTIATE_TEST_SUITE_P(Examples, PostEveryMachine,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

// The fewest equal pieces per move whose joint-linear blocks keep within `tolerance`, and the
// adaptive post's block count, for a job of straight moves through `corners` (x y of the
// machine's first two controlled axes, the rest at home).
std::pair<long, long> adaptive_and_uniform(const Machine& machine,
                                           const std::vector<Eigen::Vector2d>& corners,
                                           double tolerance) {
  int axes[2] = {0, 1};
  for (int axis = 0, n = 0; axis < 3 && n < 2; ++axis) {
    if (machine.kinematics().dof().controls(axis)) axes[n++] = axis;
  }
  const char letters[] = "XYZ";
  const auto job = temp_file("uniform-job.ngc");
  {
    std::ofstream out(job);
    out << "G21 G90 F600\n";
    for (const Eigen::Vector2d& c : corners) {
      out << "G1 " << letters[axes[0]] << c.x() << " " << letters[axes[1]] << c.y() << "\n";
    }
    out << "M2\n";
  }
  PostOptions options;
  options.tolerance_mm = tolerance;
  long adaptive = 0;
  post_program(machine, job, {}, options, [&](const std::string& line) {
    if (line.rfind("G1", 0) == 0 || line.rfind("G93", 0) == 0) ++adaptive;
  });
  const auto path = programmed_path(machine, job);
  std::filesystem::remove(job);
  const Vector6d home = machine.home().as_vector();
  const auto uniform_deviation = [&](int pieces) {
    std::vector<JointVector> blocks;
    JointVector q;
    EXPECT_TRUE(machine.inverse(machine.home(), q).ok());
    blocks.push_back(q);
    Eigen::Vector2d previous(home[axes[0]], home[axes[1]]);
    for (const Eigen::Vector2d& c : corners) {
      for (int k = 1; k <= pieces; ++k) {
        const Eigen::Vector2d p = previous + (k / static_cast<double>(pieces)) * (c - previous);
        Vector6d pose = home;
        pose[axes[0]] = p.x();
        pose[axes[1]] = p.y();
        EXPECT_TRUE(machine.inverse(Pose::from_vector(pose), q).ok());
        blocks.push_back(q);
      }
      previous = c;
    }
    return std::pair{dense_deviation(machine, blocks, path), static_cast<long>(blocks.size()) - 1};
  };
  int low = 1, high = 1;
  while (uniform_deviation(high).first > tolerance) {
    low = high;
    high *= 2;
  }
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    (uniform_deviation(middle).first > tolerance ? low : high) = middle;
  }
  return {adaptive, uniform_deviation(high).second};
}

TEST(Post, BlocksAgainstUniformSplittingOnEveryMachine) {
  // A square of 2 x 16 mm about home: reports the ratio per machine; adaptive is never worse.
  for (const std::string& file : test::example_machine_files()) {
    const Machine machine = test::load_example(file);
    int axes[2] = {0, 1};
    for (int axis = 0, n = 0; axis < 3 && n < 2; ++axis) {
      if (machine.kinematics().dof().controls(axis)) axes[n++] = axis;
    }
    const Vector6d home = machine.home().as_vector();
    const double x = home[axes[0]], y = home[axes[1]];
    const auto [adaptive, uniform] = adaptive_and_uniform(
        machine, {{x + 16, y}, {x + 16, y + 16}, {x - 16, y + 16}, {x - 16, y}, {x, y}}, 0.001);
    std::cout << "[ blocks   ] " << file << ": adaptive " << adaptive << ", uniform " << uniform
              << " (ratio " << static_cast<double>(uniform) / static_cast<double>(adaptive)
              << ")\n";
    EXPECT_LE(adaptive, uniform) << file;
  }
}

TEST(Post, FewerBlocksThanUniformSplitting) {
  // Hektor near its anchors bends its joint paths far more than in the middle: adaptive splits
  // spend blocks there only. Uniform: the smallest equal split per move that also meets 0.01 mm.
  const Machine hektor = test::load_example("hektor.toml");
  const auto job = temp_file("hektor.ngc");
  std::ofstream(job) << "G21 G90 F600\nG1 X10 Y-12\nG1 X90 Y-12\nG1 X50 Y-90\nG1 X10 Y-12\nM2\n";
  PostOptions options;
  options.tolerance_mm = 0.01;
  long adaptive = 0;
  post_program(hektor, job, {}, options, [&](const std::string& line) {
    if (line.rfind("G1", 0) == 0 || line.rfind("G93", 0) == 0) ++adaptive;
  });
  const auto path = programmed_path(hektor, job);
  // The same number of equal pieces per move: the fewest that meets the tolerance.
  const auto uniform_deviation = [&](int pieces) {
    std::vector<JointVector> blocks;
    JointVector q;
    EXPECT_TRUE(hektor.inverse(hektor.home(), q).ok());
    blocks.push_back(q);
    const std::vector<Eigen::Vector2d> corners = {
        {50, -50}, {10, -12}, {90, -12}, {50, -90}, {10, -12}};
    for (std::size_t c = 1; c < corners.size(); ++c) {
      for (int k = 1; k <= pieces; ++k) {
        const Eigen::Vector2d p =
            corners[c - 1] + (k / static_cast<double>(pieces)) * (corners[c] - corners[c - 1]);
        EXPECT_TRUE(hektor.inverse(Pose::from_mm_deg(p.x(), p.y(), 0), q).ok());
        blocks.push_back(q);
      }
    }
    return std::pair{dense_deviation(hektor, blocks, path), static_cast<long>(blocks.size()) - 1};
  };
  int low = 1, high = 1;
  while (uniform_deviation(high).first > 0.01) {
    low = high;
    high *= 2;
  }
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    (uniform_deviation(middle).first > 0.01 ? low : high) = middle;
  }
  const long uniform = uniform_deviation(high).second;
  std::filesystem::remove(job);
  ASSERT_GT(uniform, 0);
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
