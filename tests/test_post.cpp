// Joint-space programs: checked independently of the post-processor by reading them back with the
// interpreter and running forward kinematics densely along every joint-linear block.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "pkm/kinematics/formula.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/post/deviation_bound.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/mach3_export.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm::post {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("pkm-post-" + std::to_string(::getpid()) + "-" + name);
}

// The programmed moves of a job, in machine coordinates.
std::vector<motion::Segment> programmed_moves(
    const machine::Machine& machine, const std::filesystem::path& job,
    const geometry::Vector6d& origin = geometry::Vector6d::Zero()) {
  const geometry::Vector6d home = machine.home().as_vector();
  const gcode::InterpreterOptions options = motion::starting_at({}, home, origin);
  motion::SegmentBuilder builder(home, origin, false);
  std::vector<motion::Segment> moves;
  gcode::Interpreter(job, options).run([&](const gcode::Canon& canon) {
    for (const motion::Segment& segment : builder.take(canon)) {
      if (segment.kind != motion::SegmentKind::dwell) moves.push_back(segment);
    }
  });
  return moves;
}

// Exact distance from p to a line or to a planar arc (no motion along its normal); the positions
// the machine does not control are taken from p, so they never count.
double distance_to_move(Eigen::Vector3d p, const motion::Segment& move, geometry::Dof dof) {
  geometry::Vector6d start = move.start, end = move.end;
  for (int axis = 0; axis < 3; ++axis) {
    if (!dof.controls(axis)) start[axis] = end[axis] = p[axis];
  }
  if (move.kind == motion::SegmentKind::line) {
    return test::distance_to_segment(p, start.head<3>(), end.head<3>());
  }
  EXPECT_EQ(move.kind, motion::SegmentKind::arc);
  EXPECT_EQ(start[move.normal_axis], end[move.normal_axis]);
  const int a = move.first_axis, b = move.second_axis;
  // LinuxCNC's arcs may end at a slightly different radius: it blends linearly with the angle.
  const double start_radius = std::hypot(start[a] - move.centre[a], start[b] - move.centre[b]);
  const double end_radius = std::hypot(end[a] - move.centre[a], end[b] - move.centre[b]);
  const double start_angle = std::atan2(start[b] - move.centre[b], start[a] - move.centre[a]);
  double angle = std::atan2(p[b] - move.centre[b], p[a] - move.centre[a]) - start_angle;
  // The angle from the start in the arc's own direction, in [0, 2 pi).
  angle = std::fmod(move.sweep_rad >= 0.0 ? angle : -angle, 2.0 * M_PI);
  if (angle < 0.0) angle += 2.0 * M_PI;
  double nearest = std::min((p - start.head<3>()).norm(), (p - end.head<3>()).norm());
  if (angle <= std::abs(move.sweep_rad)) {
    // The arc's point in p's direction (the nearest up to the blend's slope, second order).
    const double radius =
        start_radius + angle / std::abs(move.sweep_rad) * (end_radius - start_radius);
    const double in_plane =
        std::abs(std::hypot(p[a] - move.centre[a], p[b] - move.centre[b]) - radius);
    nearest =
        std::min(nearest, std::hypot(in_plane, p[move.normal_axis] - start[move.normal_axis]));
  }
  return nearest;
}

// A lower bound on the distance from p to the move, from a sphere around it (controlled
// coordinates only), to skip the moves that cannot be the nearest.
double distance_to_move_at_least(const Eigen::Vector3d& p, const motion::Segment& move,
                                 geometry::Dof dof) {
  Eigen::Vector3d centre = 0.5 * (move.start.head<3>() + move.end.head<3>());
  double radius = 0.5 * (move.end.head<3>() - move.start.head<3>()).norm();
  if (move.kind == motion::SegmentKind::arc) {
    centre = move.centre;
    centre[move.normal_axis] = move.start[move.normal_axis];
    radius = std::max((move.start.head<3>() - centre).norm(), (move.end.head<3>() - centre).norm());
  }
  Eigen::Vector3d offset = p - centre;
  for (int axis = 0; axis < 3; ++axis) {
    if (!dof.controls(axis)) offset[axis] = 0.0;
  }
  return offset.norm() - radius;
}

// The distance from p to the nearest move; `hint`, the nearest for the previous point, is tried
// first.
double distance_to_path(const Eigen::Vector3d& p, const std::vector<motion::Segment>& moves,
                        geometry::Dof dof, std::size_t& hint) {
  double nearest = distance_to_move(p, moves[hint], dof);
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (i == hint || distance_to_move_at_least(p, moves[i], dof) >= nearest) continue;
    const double d = distance_to_move(p, moves[i], dof);
    if (d < nearest) {
      nearest = d;
      hint = i;
    }
  }
  return nearest;
}

// The joint values of every block of a joint-space program, read back by the interpreter.
std::vector<kinematics::JointVector> joint_blocks(const machine::Machine& machine,
                                                  const std::filesystem::path& file) {
  std::vector<kinematics::JointVector> blocks;
  kinematics::JointVector home;
  EXPECT_TRUE(machine.inverse(machine.home(), home).ok());
  gcode::InterpreterOptions options;
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    const int index = static_cast<int>(std::string("XYZABCUVW").find(joint.axis_letter));
    options.start_position[index] = joint.to_interface(home[static_cast<int>(i)]);
  }
  // A pen command is not a block, even where it is G-code (a servo on Z: "G0 Z90").
  if (machine.tool().z == machine::ToolZ::pen) {
    options.event_lines = {machine.tool().down_command, machine.tool().up_command};
  }
  blocks.push_back(home);
  gcode::Interpreter(file, options).run([&](const gcode::Canon& canon) {
    if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
    kinematics::JointVector q(static_cast<int>(machine.joints().size()));
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const machine::JointSpec& joint = machine.joints()[i];
      const double value = canon.end[std::string("XYZABCUVW").find(joint.axis_letter)];
      q[static_cast<int>(i)] = joint.from_interface(value);
    }
    blocks.push_back(q);
  });
  return blocks;
}

// The worst distance from the programmed path of the tool tip along every joint-linear block, by
// forward kinematics at `points` + 1 points per block.
double dense_deviation(const machine::Machine& machine,
                       const std::vector<kinematics::JointVector>& blocks,
                       const std::vector<motion::Segment>& moves, int points = 1000) {
  double worst = 0.0;
  geometry::Pose pose = machine.home();
  std::size_t hint = 0;
  for (std::size_t b = 1; b < blocks.size(); ++b) {
    for (int k = 0; k <= points; ++k) {
      const kinematics::JointVector q =
          blocks[b - 1] + (k / static_cast<double>(points)) * (blocks[b] - blocks[b - 1]);
      EXPECT_TRUE(machine.forward(q, pose).ok());
      worst = std::max(worst,
                       distance_to_path(pose.position_mm, moves, machine.kinematics().dof(), hint));
    }
  }
  return worst;
}

// A small job about home in the machine's first two controlled axes, with an arc and a run of
// short moves where those are x and y, and an attitude change on machines that control one.
std::string job_about_home(const machine::Machine& machine) {
  const geometry::Vector6d home = machine.home().as_vector();
  const bool xy = machine.kinematics().dof().controls(0) && machine.kinematics().dof().controls(1);
  char text[512];
  std::string job = "G21 G90 F600\n";
  std::snprintf(text, sizeof text, "G1 X%.4f Y%.4f\nG1 X%.4f Y%.4f\n", home[0] + 8, home[1],
                home[0] + 8, home[1] + 8);
  job += text;
  if (xy) {
    std::snprintf(text, sizeof text, "G3 X%.4f Y%.4f I-8 J0\n", home[0] - 8, home[1] + 8);
    job += text;
    // A run of 32 short moves along a gentle curve, which blocks may span.
    for (int k = 1; k <= 32; ++k) {
      std::snprintf(text, sizeof text, "G1 X%.4f Y%.4f\n", home[0] - 8 + 0.0004 * k * k,
                    home[1] + 8 - 0.25 * k);
      job += text;
    }
  }
  if (machine.kinematics().dof().any_rotation()) job += "G1 A4 B-3\n";
  std::snprintf(text, sizeof text, "G0 X%.4f Y%.4f\nM2\n", home[0], home[1]);
  return job + text;
}

PostReport post_to_file(const machine::Machine& machine, const std::filesystem::path& job,
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
  const machine::Machine machine = test::load_example(GetParam());
  const auto job = temp_file("job.ngc");
  std::ofstream(job) << job_about_home(machine);
  const auto moves = programmed_moves(machine, job);
  for (const double tolerance : {0.1, 0.01, 0.001}) {
    const auto output = temp_file("joints.ngc");
    PostOptions options;
    options.tolerance_mm = tolerance;
    const PostReport report = post_to_file(machine, job, output, options);
    EXPECT_LE(report.max_deviation_mm, tolerance);
    const std::vector<kinematics::JointVector> blocks = joint_blocks(machine, output);
    EXPECT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
    const double dense = dense_deviation(machine, blocks, moves);
    std::cout << "[ bound    ] tolerance " << tolerance << ": " << report.blocks
              << " blocks, largest found " << dense << " mm, reported " << report.max_deviation_mm
              << " mm\n";
    if (report.bounded) {
      EXPECT_LE(dense, report.max_deviation_mm) << "tolerance " << tolerance;
    } else {
      // Only where the model itself has no second-derivative bound at home (a formula, cables
      // whose joints come from a balance of forces), or has more joints than the coordinates it
      // controls (an N-cable robot: the bound inverts a square Jacobian), is it sampled.
      const kinematics::Kinematics& model = machine.kinematics();
      const bool model_bounded =
          model.joint_count() == static_cast<int>(model.dof().axes().size()) &&
          bounds::inverse_hessian_bounds(model, machine.home().as_vector(), 0.0,
                                         bounds::pose_angle_scale_mm(model), {})
              .has_value();
      EXPECT_FALSE(model_bounded) << model.type() << " has a bound, the post did not use it";
      EXPECT_LE(dense, tolerance * 1.02) << "tolerance " << tolerance;
    }
    std::filesystem::remove(output);
  }
  std::filesystem::remove(job);
}

INSTANTIATE_TEST_SUITE_P(Examples, PostEveryMachine,
                         ::testing::ValuesIn(test::example_machine_files()),
                         [](const auto& test_info) { return test::test_name(test_info.param); });

// Posts `job_text` at 0.01 mm from `origin` and checks the program densely: nothing above the
// bound it reports, one joint block per block it counts. Returns the report.
PostReport post_within_its_bound(const machine::Machine& machine, const std::string& job_text,
                                 const geometry::Vector6d& origin) {
  const auto job = temp_file("bounded-job.ngc");
  std::ofstream(job) << job_text;
  const auto output = temp_file("bounded-joints.ngc");
  PostOptions options;
  options.tolerance_mm = 0.01;
  options.origin = origin;
  const PostReport report = post_to_file(machine, job, output, options);
  EXPECT_LE(report.max_deviation_mm, 0.01);
  const std::vector<kinematics::JointVector> blocks = joint_blocks(machine, output);
  EXPECT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
  EXPECT_LE(dense_deviation(machine, blocks, programmed_moves(machine, job, origin)),
            report.max_deviation_mm);
  std::filesystem::remove(job);
  std::filesystem::remove(output);
  return report;
}

// ---- Coverage: every programmed move traced from its start to its end ----

TEST(Post, DeltaStrutNearlySquareToItsRailIsPosted) {
  // cds.ngc (corpus, inches) with --origin 0 0 50 on the linear delta: its pocket's corner
  // (101.6, 99.441) puts tower b's strut 299.796 of its 300 mm across the rail, 2.1 deg from
  // square. The bound refused every block there (the drift of J^-1 over the reach, counted at
  // the strut's full curvature against the smallest singular value, stayed above 1 however short
  // the block); weighed by how little that strut moves the tool, short blocks pass.
  const geometry::Vector6d origin =
      (geometry::Vector6d() << 0.0, 0.0, 50.0, 0.0, 0.0, 0.0).finished();
  post_within_its_bound(test::load_example("linear-delta.toml"),
                        "G20 G90\nG0 Z2.1\nG0 X0 Y3.915\nG1 F16 Z1.6875\nG1 X4.0\nM2\n", origin);
}

TEST(Post, PassThroughJointOfACablePlotterIsBounded) {
  // The Maslow's router Z is a pass-through joint: a third joint beside the two chains. The bound
  // sized its second derivatives by the chains alone, read past them (the joint program of
  // calibration-benchmark-test.nc, line 11, was refused at random: "no block, however short").
  const machine::Machine maslow = test::load_example("maslow.toml");
  ASSERT_EQ(maslow.joints().size(), 3u);
  const auto bounds = pkm::bounds::inverse_hessian_bounds(maslow.kinematics(),
                                                          maslow.home().as_vector(), 1.0, 1.0, {});
  ASSERT_TRUE(bounds.has_value());
  EXPECT_EQ(bounds->norm.size(), 3u);  // one per joint, the pass-through's zero
  EXPECT_EQ(bounds->norm[2], 0.0);
  const geometry::Vector6d origin =
      (geometry::Vector6d() << 1489.2, -1072.6, 0.0, 0.0, 0.0, 0.0).finished();
  const PostReport report = post_within_its_bound(
      maslow, "G21\nG90\nG1 Z5 F500\nG0 X0 Y0\nG0 X-952.5 Y10\nG1 Z-2 F500\nG1 Y-10\nG1 Z5\nM2\n",
      origin);
  EXPECT_GT(report.blocks, 10);  // the 952 mm rapid across the chains' curvature
}

TEST(Post, AnInfiniteCurvatureBoundSplitsTheBlock) {
  // A 75 mm line from home on LinuxCNC's rdelta: over the ball of the whole line every arm's
  // curvature bound is infinite (its lever could halve there). The tool's error from that
  // infinite joint-error box came out NaN (inf - inf within J^-1 e), std::max dropped it, the
  // bound read 0 and the line went out as one block, 1.2 mm off its path.
  const geometry::Vector6d origin =
      (geometry::Vector6d() << 0.0, 0.0, -300.0, 0.0, 0.0, 0.0).finished();
  const PostReport report = post_within_its_bound(test::load_example("linuxcnc-rdelta.toml"),
                                                  "G21 G90 F1200\nG1 X40 Y0 Z-20\nM2\n", origin);
  EXPECT_GT(report.blocks, 10);
}

TEST(Post, PaperSphereOnTheHexapodNearItsBound) {
  // The paper's sphere (pkm demo) turns the tool through up to 47 deg per 30 deg arc. Bounding the
  // legs' chord error by its curvature alone (each rotation's second derivative at its worst,
  // whatever direction the leg points) held it to 0.00099 mm in 20,225 blocks; the joints at the
  // chord's middle and a third-derivative remainder give 3,024 blocks, and the largest deviation
  // found densely is most of the bound, never above it.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const auto sphere = std::filesystem::path(PKM_SOURCE_DIR) / "examples" / "jobs" / "sphere.ngc";
  const auto output = temp_file("sphere-joints.ngc");
  PostOptions options;
  options.tolerance_mm = 0.01;
  const PostReport report = post_to_file(hexapod, sphere, output, options);
  EXPECT_LE(report.blocks, 3100);
  const std::vector<kinematics::JointVector> blocks = joint_blocks(hexapod, output);
  ASSERT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
  const double dense = dense_deviation(hexapod, blocks, programmed_moves(hexapod, sphere), 100);
  std::cout << "[ bound    ] sphere: " << report.blocks << " blocks, largest found " << dense
            << " mm, reported " << report.max_deviation_mm << " mm\n";
  EXPECT_LE(dense, report.max_deviation_mm);
  EXPECT_GE(dense, 0.5 * report.max_deviation_mm);
  std::filesystem::remove(output);
}

TEST(Post, FullCircleIsTracedAllRound) {
  // G2 ending where it starts, radius 10 about (50, -50) on Hektor: the blocks' ends go once
  // clockwise round the circle. A chord of 2 pi / n keeps within 0.01 mm only for
  // 10 (1 - cos(pi / n)) <= 0.01, n >= 71: so at least 71 blocks.
  const machine::Machine hektor = test::load_example("hektor.toml");
  const auto job = temp_file("circle.ngc");
  std::ofstream(job) << "G21 G90 F600\nG1 X40 Y-50\nG2 X40 Y-50 I10 J0\nM2\n";
  const auto output = temp_file("circle-joints.ngc");
  PostOptions options;
  options.tolerance_mm = 0.01;
  const PostReport report = post_to_file(hektor, job, output, options);
  const std::vector<kinematics::JointVector> blocks = joint_blocks(hektor, output);
  ASSERT_EQ(static_cast<long>(blocks.size()) - 1, report.blocks);
  // The first blocks trace the line to the circle's start (40, -50); the rest go round it.
  geometry::Pose pose = hektor.home();
  std::size_t first = 1;
  for (; first < blocks.size(); ++first) {
    ASSERT_TRUE(hektor.forward(blocks[first], pose).ok());
    if ((pose.position_mm.head<2>() - Eigen::Vector2d(40.0, -50.0)).norm() < 1e-4) break;
  }
  double turned = 0.0, previous = M_PI;
  for (std::size_t b = first + 1; b < blocks.size(); ++b) {
    ASSERT_TRUE(hektor.forward(blocks[b], pose).ok());
    const Eigen::Vector2d from_centre(pose.position_mm.x() - 50.0, pose.position_mm.y() + 50.0);
    EXPECT_NEAR(from_centre.norm(), 10.0, 1e-4);
    const double angle = std::atan2(from_centre.y(), from_centre.x());
    const double step = std::remainder(angle - previous, 2.0 * M_PI);
    EXPECT_LT(step, 0.0) << "block " << b;  // clockwise, never back
    turned += step;
    previous = angle;
  }
  EXPECT_NEAR(turned, -2.0 * M_PI, 1e-6);
  EXPECT_GE(blocks.size() - 1 - first, 71u);
  EXPECT_LE(dense_deviation(hektor, blocks, programmed_moves(hektor, job)),
            report.max_deviation_mm);
  std::filesystem::remove(job);
  std::filesystem::remove(output);
}

// The lines of a joint program posted from `job_text`.
std::vector<std::string> posted_lines(const machine::Machine& machine, const std::string& job_text,
                                      PostOptions options = {}, PostReport* report_out = nullptr) {
  const auto job = temp_file("lines-job.ngc");
  std::ofstream(job) << job_text;
  std::vector<std::string> lines;
  const PostReport report = post_program(machine, job, {}, options,
                                         [&](const std::string& line) { lines.push_back(line); });
  if (report_out) *report_out = report;
  std::filesystem::remove(job);
  return lines;
}

TEST(Post, ZOnlyMovesOfAPlotterWriteNothingAndM5Once) {
  // Hektor controls x y only: the Z moves are no blocks; the job's M5 and M2's own spindle stop
  // give one M5.
  const machine::Machine hektor = test::load_example("hektor.toml");
  PostReport report;
  const auto lines = posted_lines(
      hektor, "G21 G90 F600\nM3 S1000\nG0 Z5\nG1 X40 Y-50\nG1 Z-1\nG0 Z5\nM5\nM2\n", {}, &report);
  EXPECT_EQ(report.moves, 4);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M5"), 1);
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                          [](const std::string& l) { return l.find(" A") != std::string::npos; }),
            report.blocks);
  PostReport without_z;
  posted_lines(hektor, "G21 G90 F600\nG1 X40 Y-50\nM2\n", {}, &without_z);
  EXPECT_EQ(report.blocks, without_z.blocks);
  EXPECT_EQ(lines.back(), "M2");
}

// The job's pauses, tool changes, I/O and user M-codes, each at its place in the joint
// program (issue 26: M0/M1/M60, T/M6, M100-M199 and M62-M68 vanished without a word).
const char* kJobWithMachineCommands =
    "G21 G90 F600\nG1 X40 Y-50\nM0\nT2 M6\nG1 X30\nM62 P1\nM66 P0 L3 Q2.5\nM67 E0 "
    "Q50\nM101 P2 Q3\nM1\nM60\nM49\nM19 R90 P2 Q1.5\nG1 X20\nM2\n";

// The lines of `lines` that are not moves.
std::vector<std::string> commands_among(const std::vector<std::string>& lines) {
  std::vector<std::string> commands;
  for (const std::string& line : lines) {
    if (line.rfind("G1 ", 0) == 0 || line.rfind("G0 ", 0) == 0 || line.rfind("G93 ", 0) == 0 ||
        line.rfind("G21", 0) == 0 || line.rfind("M5", 0) == 0 || line.rfind("M2", 0) == 0) {
      continue;
    }
    commands.push_back(line);
  }
  return commands;
}

TEST(Post, EveryPauseToolChangeIoAndUserCodeIsCarriedInItsPlace) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  const auto lines = posted_lines(hektor, kJobWithMachineCommands);
  EXPECT_EQ(commands_among(lines),
            (std::vector<std::string>{"M0", "T2", "M6", "M62 P1", "M66 P0 L3 Q2.5", "M67 E0 Q50",
                                      "M101 P2 Q3", "M1", "M60", "M49", "M19 R90 P2", "M19 Q1.5"}));
  // M0 comes after the first move's block and before the second's.
  const auto at = [&](const std::string& text) {
    return std::find(lines.begin(), lines.end(), text) - lines.begin();
  };
  const auto first_move = std::find_if(lines.begin(), lines.end(), [](const std::string& line) {
    return line.find(" A") != std::string::npos;
  });
  EXPECT_LT(first_move - lines.begin(), at("M0"));
  EXPECT_LT(at("M6"),
            std::find_if(lines.begin() + at("M6"), lines.end(), [](const std::string& line) {
              return line.find(" A") != std::string::npos;
            }) - lines.begin());
}

TEST(Post, ADialectWithoutACommandRefusesTheJobAtItsLine) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  // Its joints are X and Y, which grbl takes; the job's origin is where the pen reaches.
  const machine::Machine wall_plotter = test::load_example("wall-plotter.toml");
  struct Case {
    std::string job;
    Dialect dialect;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"G21 F600\nG1 X40 Y-50\nM62 P1\nM2\n", Dialect::grbl,
       ":3: grbl has no digital or analog I/O code (M62 P1), and leaving it out would run the "
       "job differently: use --dialect linuxcnc or grblhal"},
      {"G21 F600\nM101 P2\nM2\n", Dialect::grblhal, ":2: grblhal has no user M-code (M101 P2)"},
      {"G21 F600\nM60\nM2\n", Dialect::mach3, ":2: mach3 has no M60 (M60)"},
      {"G21 F600\nM19 R90 Q2\nM2\n", Dialect::grblhal,
       ":2: grblhal has no spindle orientation (M19 R90 P0)"},
  };
  for (const Case& c : cases) {
    PostOptions options;
    options.dialect = c.dialect;
    options.origin = (geometry::Vector6d() << 700.0, -700.0, 0.0, 0.0, 0.0, 0.0).finished();
    try {
      posted_lines(wall_plotter, c.job, options);
      FAIL() << "posted " << c.job;
    } catch (const PostError& error) {
      EXPECT_NE(std::string(error.what()).find(c.message), std::string::npos) << error.what();
    }
  }
  // What changes no motion is left out with a warning; grbl's M1 is written, with a warning.
  PostReport report;
  PostOptions mach3;
  mach3.dialect = Dialect::mach3;
  const auto lines = posted_lines(hektor, "G21 F600\nM49\nM1\nM2\n", mach3, &report);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M49"), 0);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M1"), 1);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_EQ(report.warnings.back().line, 2);
  EXPECT_NE(report.warnings.back().message.find("M49 (an override switch) left out"),
            std::string::npos);
  // grbl has no M6: the tool is changed by hand at a pause (a Fusion 360 job's "T1 M6").
  PostOptions grbl;
  grbl.dialect = Dialect::grbl;
  grbl.origin = (geometry::Vector6d() << 700.0, -700.0, 0.0, 0.0, 0.0, 0.0).finished();
  PostReport grbl_report;
  const auto grbl_lines =
      posted_lines(wall_plotter, "G21 F600\nT2 M6\nG1 X40 Y-50\nM2\n", grbl, &grbl_report);
  EXPECT_EQ(std::count(grbl_lines.begin(), grbl_lines.end(), "T2"), 1);
  EXPECT_EQ(
      std::count(grbl_lines.begin(), grbl_lines.end(), "M0 (M6: change the tool, then resume)"), 1);
  ASSERT_FALSE(grbl_report.warnings.empty());
  EXPECT_NE(grbl_report.warnings.back().message.find("M6 written as M0"), std::string::npos);
}

TEST(Post, BlocksOfAMoveEstimatedByTheSagittaOfTheirChords) {
  // A full circle of radius 10 mm within 0.01 mm: 10 (1 - cos(pi / n)) <= 0.01 for n >= 71.
  motion::Segment circle;
  circle.kind = motion::SegmentKind::arc;
  circle.start << 40.0, -50.0, 0.0, 0.0, 0.0, 0.0;
  circle.end = circle.start;
  circle.centre = Eigen::Vector3d(50.0, -50.0, 0.0);
  circle.sweep_rad = -2.0 * M_PI;
  EXPECT_EQ(estimated_blocks(circle, 0.01), 71.0);
  circle.sweep_rad = -2.0 * M_PI * 1e6;  // P1000000: 70,242,... blocks
  EXPECT_NEAR(estimated_blocks(circle, 0.01), 2.0 * M_PI * 1e6 / (2.0 * std::acos(0.999)), 1.0);
  // A tolerance as large as the radius: half a turn per chord.
  EXPECT_EQ(estimated_blocks(circle, 10.0), 2e6);
  motion::Segment line;
  line.end << 100.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  EXPECT_EQ(estimated_blocks(line, 0.01), 1.0);
}

TEST(Post, AJobPastTheBlockBoundIsRefusedAtItsLine) {
  // Issue 26: an arc of a million turns kept post writing. Its estimate (70 million blocks)
  // refuses it before a block of it is covered: nothing but the program's opening is written.
  const machine::Machine hektor = test::load_example("hektor.toml");
  PostOptions options;
  options.max_blocks = kDefaultMaxBlocks;
  options.origin = (geometry::Vector6d() << 10.0, 0.0, 0.0, 0.0, 0.0, 0.0).finished();
  std::vector<std::string> lines;
  const auto job = temp_file("helix.ngc");
  std::ofstream(job) << "G21 G90 F600\nG1 X40 Y-50\nG2 X40 Y-50 I10 J0 P1000000\nM2\n";
  try {
    post_program(hektor, job, {}, options, [&](const std::string& line) { lines.push_back(line); });
    FAIL() << "posted a million turns";
  } catch (const BlockBoundError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(":3: this arc (62831853.07 mm of path, 1000000 "
                        "turns) needs about 70242"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(lines, std::vector<std::string>{"G21 G90 G94"});
  std::filesystem::remove(job);
  // Ten turns take 75 blocks a turn where the estimate says 71: a bound between the two
  // passes the estimate and refuses the job at the block past it, having written exactly that
  // many; the bound of the job's own count posts it.
  const std::string ten_turns = "G21 G90 F600\nG1 X40 Y-50\nG2 X40 Y-50 I10 J0 P10\nM2\n";
  options.max_blocks = 0;
  PostReport unbounded;
  posted_lines(hektor, ten_turns, options, &unbounded);
  ASSERT_GT(unbounded.blocks, 720 + 1);
  options.max_blocks = 720;
  EXPECT_THROW(posted_lines(hektor, ten_turns, options), BlockBoundError);
  options.max_blocks = unbounded.blocks;
  PostReport bounded;
  posted_lines(hektor, ten_turns, options, &bounded);
  EXPECT_EQ(bounded.blocks, unbounded.blocks);
}

TEST(Post, TellsItsProgressLineByLineInOrder) {
  // The hook of the progress bar: each line that makes a command (a comment is one), once, in
  // order, to M2's line; the empty line makes none.
  const machine::Machine hektor = test::load_example("hektor.toml");
  PostOptions options;
  std::vector<int> lines;
  options.on_line = [&](int line) { lines.push_back(line); };
  posted_lines(hektor, "G21 G90 F600\n\nG1 X40 Y-50\n(a comment)\nG1 X30\nG1 X20\nM2\n", options);
  EXPECT_EQ(lines, (std::vector<int>{1, 3, 4, 5, 6, 7}));
}

// ---- Feeds: rounded down, never above a joint's velocity ----

TEST(Post, InverseTimeFeedIsRoundedDown) {
  // The matrix mill is linear: G1 from home x 300 to x 306 at F700 is one block of 6 mm at
  // 700 mm/min, 1 / F = 6 / 700 min, F = 116.666..., written 116.666 (nearest would be 116.667,
  // a shorter block than programmed).
  const machine::Machine mill = test::load_example("matrix-mill.toml");
  const auto lines = posted_lines(mill, "G21 G90\nG1 X306 F700\nM2\n");
  ASSERT_EQ(lines.size(), 4u);  // G21 G90 G94, the block, M2's spindle stop, M2
  EXPECT_EQ(lines[1].substr(0, 7), "G93 G1 ");
  EXPECT_EQ(lines[1].substr(lines[1].size() - 9), " F116.666");
}

TEST(Post, NoJointAboveItsVelocityAfterRounding) {
  // Hektor with 30 mm/s joints and X Y letters (so every dialect takes it), its anchors 150 mm
  // apart so that the arc (out to x = 113.8) hangs between them, run at F2400
  // (40 mm/s): many blocks are limited by a joint, not by the feed. Read back by the
  // interpreter, each G93 block's joint speeds |dq| F / 60 stay within the limit, and some reach
  // it (within 0.1 %).
  const std::string text = R"(name = "slow Hektor"
[kinematics]
type = "cable_plotter"
anchor_distance = 150.0
[[joints]]
name = "left"
min = 5.0
max = 180.0
max_velocity = 30.0
max_acceleration = 600.0
axis = "X"
[[joints]]
name = "right"
min = 5.0
max = 180.0
max_velocity = 30.0
max_acceleration = 600.0
axis = "Y"
[cartesian]
max_feed = 2400.0
max_acceleration = 500.0
home = [50.0, -50.0]
)";
  const machine::Machine machine = machine::parse_machine(text, "slow-hektor.toml");
  const std::string job =
      "G21 G90 F2400\nG1 X10 Y-12\nG1 X90 Y-12\nG2 X50 Y-90 I-20 J-39\nG1 X10 Y-12\nM2\n";
  for (const Dialect dialect :
       {Dialect::linuxcnc, Dialect::mach3, Dialect::grbl, Dialect::grblhal}) {
    PostOptions options;
    options.dialect = dialect;
    const auto job_file = temp_file("fast-job.ngc");
    const auto output = temp_file("fast-joints.ngc");
    std::ofstream(job_file) << job;
    post_to_file(machine, job_file, output, options);
    kinematics::JointVector home;
    ASSERT_TRUE(machine.inverse(machine.home(), home).ok());
    gcode::InterpreterOptions start;
    start.start_position[0] = home[0];
    start.start_position[1] = home[1];
    double previous[2] = {home[0], home[1]};
    int at_limit = 0, feed_blocks = 0;
    gcode::Interpreter(output, start).run([&](const gcode::Canon& canon) {
      if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
      if (canon.kind == gcode::CanonKind::feed) {
        EXPECT_EQ(canon.feed_mode, gcode::FeedMode::inverse_time);
        const double speed = std::max(std::abs(canon.end[0] - previous[0]),
                                      std::abs(canon.end[1] - previous[1])) *
                             canon.value / 60.0;  // F: blocks per minute
        EXPECT_LE(speed, 30.0) << dialect_name(dialect) << ": line " << canon.line;
        if (speed > 30.0 * 0.999) ++at_limit;
        ++feed_blocks;
      }
      previous[0] = canon.end[0];
      previous[1] = canon.end[1];
    });
    std::filesystem::remove(job_file);
    std::filesystem::remove(output);
    EXPECT_GT(at_limit, 10) << dialect_name(dialect) << " of " << feed_blocks;
  }
}

// ---- Dialects: axis letters and line length ----

TEST(Post, DialectsRefuseLettersTheyDoNotTake) {
  const auto message = [](const machine::Machine& machine, Dialect dialect) -> std::string {
    try {
      check_axis_letters(machine, dialect);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  const machine::Machine hektor = test::load_example("hektor.toml");  // A and B
  EXPECT_EQ(message(hektor, Dialect::grbl),
            "dialect grbl accepts the axes X Y Z only; the machine writes joint 'left' as A, "
            "'right' as B: use --dialect linuxcnc or mach3 or grblhal, or change the joints' "
            "axis letters in the machine file");
  EXPECT_EQ(message(hektor, Dialect::mach3), "");
  EXPECT_EQ(message(hektor, Dialect::grblhal), "");
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");  // X Y Z A B C
  EXPECT_NE(message(hexapod, Dialect::grbl).find("'leg4' as A, 'leg5' as B, 'leg6' as C"),
            std::string::npos);
  EXPECT_EQ(message(hexapod, Dialect::mach3), "");
  // U V W: LinuxCNC and grblHAL take them, Mach3 does not.
  std::string text = R"(name = "glide on U V W"
[kinematics]
type = "glide"
)";
  const std::string rails[3][2] = {
      {"[0.0, 200.0, 0.0]", "[0.0, 40.0, 0.0]"},
      {"[-173.20508075688772, -100.0, 0.0]", "[-34.64101615137755, -20.0, 0.0]"},
      {"[173.20508075688772, -100.0, 0.0]", "[34.64101615137755, -20.0, 0.0]"}};
  for (const auto& rail : rails) {
    text += "[[kinematics.rails]]\norigin = " + rail[0] +
            "\ndirection = [0.0, 0.0, 1.0]\nstrut = 300.0\nattach = " + rail[1] + "\n";
  }
  for (const char* letter : {"U", "V", "W"}) {
    text += std::string("[[joints]]\nname = \"") + letter +
            "\"\nmin = 0.0\nmax = 700.0\nmax_velocity = 300.0\nmax_acceleration = 3000.0\n"
            "axis = \"" +
            letter + "\"\n";
  }
  text += "[cartesian]\nmax_feed = 6000.0\nmax_acceleration = 1000.0\nhome = [0.0, 0.0, 100.0]\n";
  const machine::Machine uvw = machine::parse_machine(text, "uvw.toml");
  EXPECT_EQ(message(uvw, Dialect::mach3),
            "dialect mach3 accepts the axes X Y Z A B C only; the machine writes joint 'U' as U, "
            "'V' as V, 'W' as W: use --dialect linuxcnc or grblhal, or change the joints' axis "
            "letters in the machine file");
  EXPECT_EQ(message(uvw, Dialect::linuxcnc), "");
  EXPECT_THROW(
      posted_lines(hektor, "G1 X40 Y-50 F600\nM2\n", {0.01, Dialect::grbl, {}, {}, true, 0, {}}),
      std::invalid_argument);
}

TEST(Post, GrblLinesWithin80Characters) {
  // The wall plotter at X Y in grbl's 3 decimals, across a drawing of arcs and lines.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  PostOptions options;
  options.dialect = Dialect::grbl;
  const auto lines = posted_lines(
      plotter, "G21 G90 F3000\nG1 X700 Y-900\nG2 X800 Y-900 I50 J0\nG0 X750 Y-700\nM2\n", options);
  EXPECT_GT(lines.size(), 10u);
  for (const std::string& line : lines) EXPECT_LE(line.size(), 80u) << line;
}

// ---- Bad inputs: a clear error, nothing written ----

TEST(Post, BadOptionsAreRefusedWithTheirReason) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  const std::string job = "G21 G90 F600\nG1 X40 Y-50\nM2\n";
  struct Case {
    double tolerance_mm;
    double origin_x;
    std::string message;
  };
  for (const Case& c : std::vector<Case>{
           {NAN, 0.0, "the tolerance must be a positive number of mm"},
           {INFINITY, 0.0, "the tolerance must be a positive number of mm"},
           {0.0, 0.0, "the tolerance must be a positive number of mm"},
           {-0.01, 0.0, "the tolerance must be a positive number of mm"},
           {0.01, NAN, "the origin must be finite (mm, deg)"},
           {0.01, -INFINITY, "the origin must be finite (mm, deg)"},
       }) {
    PostOptions options;
    options.tolerance_mm = c.tolerance_mm;
    options.origin[0] = c.origin_x;
    try {
      const auto lines = posted_lines(hektor, job, options);
      ADD_FAILURE() << c.message << ": accepted, " << lines.size() << " lines";
    } catch (const std::invalid_argument& error) {
      EXPECT_EQ(std::string(error.what()), c.message);
    }
  }
  // A tolerance the dialect's rounding alone exceeds: located, with the decimals.
  PostOptions options;
  options.tolerance_mm = 1e-9;
  try {
    posted_lines(hektor, job, options);
    ADD_FAILURE() << "1e-9 mm accepted";
  } catch (const PostError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(":2: cannot keep within 1e-09 mm here: no block, however short, is "
                        "(a singularity, or a tolerance too small for joints rounded to 5 "
                        "decimals)"),
              std::string::npos)
        << error.what();
  }
}

TEST(Post, ALargeToleranceStillPosts) {
  // 50 mm on Hektor (100 mm between anchors): the argument's reach stays within 1.5 mm, so the
  // blocks near the anchors are still bounded, and the bound is within the tolerance.
  PostOptions options;
  options.tolerance_mm = 50.0;
  PostReport report;
  posted_lines(test::load_example("hektor.toml"),
               "G21 G90 F600\nG1 X10 Y-12\nG1 X90 Y-12\nG1 X50 Y-90\nG1 X10 Y-12\nM2\n", options,
               &report);
  EXPECT_GE(report.blocks, 4);
  EXPECT_LE(report.max_deviation_mm, 50.0);
}

// ---- The pen channel ----

// A joint program read back: the joints after each block, and where the pen went down (true) or
// up, as the index of the block it followed; and the dwells.
struct ReadBack {
  std::vector<kinematics::JointVector> blocks;
  std::vector<std::pair<std::size_t, bool>> pen;
  std::vector<double> dwells_s;
};

ReadBack read_back(const machine::Machine& machine, const std::filesystem::path& file) {
  ReadBack result;
  kinematics::JointVector home;
  EXPECT_TRUE(machine.inverse(machine.home(), home).ok());
  gcode::InterpreterOptions options;
  const std::string letters = "XYZABCUVW";
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    options.start_position[letters.find(joint.axis_letter)] =
        joint.to_interface(home[static_cast<int>(i)]);
  }
  result.blocks.push_back(home);
  int last_stop_line = -1;
  gcode::Interpreter(file, options).run([&](const gcode::Canon& canon) {
    using gcode::CanonKind;
    if (canon.kind == CanonKind::spindle_clockwise || canon.kind == CanonKind::spindle_stop) {
      result.pen.emplace_back(result.blocks.size() - 1, canon.kind == CanonKind::spindle_clockwise);
      last_stop_line = canon.kind == CanonKind::spindle_stop ? canon.line : -1;
    } else if (canon.kind == CanonKind::program_end && canon.line == last_stop_line) {
      result.pen.pop_back();  // M2's own spindle stop, not an M5 of the program
    } else if (canon.kind == CanonKind::dwell) {
      result.dwells_s.push_back(canon.value);
    } else if (canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed) {
      kinematics::JointVector q(static_cast<int>(machine.joints().size()));
      for (std::size_t i = 0; i < machine.joints().size(); ++i) {
        const machine::JointSpec& joint = machine.joints()[i];
        q[static_cast<int>(i)] = joint.from_interface(canon.end[letters.find(joint.axis_letter)]);
      }
      result.blocks.push_back(q);
    }
  });
  return result;
}

// Where the job's Z crosses the pen height, from its moves (lines: Z linear along them), in
// order: the x y there, and whether the pen goes down.
std::vector<std::pair<Eigen::Vector2d, bool>> job_pen_changes(
    const std::vector<motion::Segment>& moves, const machine::ToolChannel& tool, bool down) {
  std::vector<std::pair<Eigen::Vector2d, bool>> changes;
  for (const motion::Segment& move : moves) {
    if (tool.pen_down(move.end[2]) == down) continue;
    EXPECT_EQ(move.kind, motion::SegmentKind::line);
    const double u = (tool.pen_height_mm - move.start[2]) / (move.end[2] - move.start[2]);
    changes.emplace_back(move.start.head<2>() + u * (move.end.head<2>() - move.start.head<2>()),
                         !down);
    down = !down;
  }
  return changes;
}

// The wall plotter with a pen: M3 S1000 down, M5 up, 0.15 s.
machine::Machine pen_plotter() {
  machine::Machine machine = test::load_example("wall-plotter.toml");
  machine::ToolChannel tool;
  tool.z = machine::ToolZ::pen;
  tool.delay_s = 0.15;
  machine.set_tool(tool);
  return machine;
}

// Posts the job on the pen plotter in every dialect and checks, read back, that the pen goes
// down and up exactly where the job's Z crosses 0: after a block whose end is there (within the
// tolerance), each followed by its G4, and the program starts with the pen up.
void expect_pen_where_the_job_crosses(const std::filesystem::path& job,
                                      const geometry::Vector6d& origin,
                                      const machine::Machine& machine = pen_plotter()) {
  const auto moves = programmed_moves(machine, job, origin);
  const auto expected = job_pen_changes(moves, machine.tool(), false);
  ASSERT_GE(expected.size(), 2u);
  for (const Dialect dialect :
       {Dialect::linuxcnc, Dialect::mach3, Dialect::grbl, Dialect::grblhal}) {
    const auto output = temp_file("pen-joints.ngc");
    PostOptions options;
    options.dialect = dialect;
    options.origin = origin;
    const PostReport report = post_to_file(machine, job, output, options);
    const ReadBack back = read_back(machine, output);
    if (dialect == Dialect::linuxcnc) {  // forward kinematics at 1,001 points of every block
      const double dense = dense_deviation(machine, back.blocks, moves);
      std::cout << "[ bound    ] " << report.blocks << " blocks, largest found " << dense
                << " mm, reported " << report.max_deviation_mm << " mm\n";
      EXPECT_LE(dense, report.max_deviation_mm);
    }
    ASSERT_EQ(back.pen.size(), expected.size() + 1) << dialect_name(dialect);
    EXPECT_EQ(back.pen[0], (std::pair<std::size_t, bool>{0, false}));  // up before moving
    EXPECT_EQ(back.dwells_s, std::vector<double>(back.pen.size(), 0.15));
    geometry::Pose pose = machine.home();
    for (std::size_t k = 0; k < expected.size(); ++k) {
      const auto& [block, down] = back.pen[k + 1];
      EXPECT_EQ(down, expected[k].second) << k;
      ASSERT_TRUE(machine.forward(back.blocks[block], pose).ok());
      EXPECT_LE((pose.position_mm.head<2>() - expected[k].first).norm(), report.max_deviation_mm)
          << dialect_name(dialect) << " pen change " << k;
    }
    std::filesystem::remove(output);
  }
}

TEST(PostPen, PenChangesWhereARampCrossesThePenHeight) {
  // A ramp from Z 1 to Z -1 over 10 mm and back up: down at X 5, up at X 15 (hand-computed).
  const auto job = temp_file("ramp.ngc");
  std::ofstream(job) << "G21 G90\nG0 X0 Y0 Z1\nG1 X10 Z-1 F600\nG1 X20 Z1\nM2\n";
  const machine::Machine machine = pen_plotter();
  const auto moves =
      programmed_moves(machine, job, geometry::Pose::from_mm_deg(750, -700, 0).as_vector());
  const auto expected = job_pen_changes(moves, machine.tool(), false);
  ASSERT_EQ(expected.size(), 2u);
  EXPECT_LT((expected[0].first - Eigen::Vector2d(755, -700)).norm(), 1e-9);
  EXPECT_LT((expected[1].first - Eigen::Vector2d(765, -700)).norm(), 1e-9);
  expect_pen_where_the_job_crosses(job, geometry::Pose::from_mm_deg(750, -700, 0).as_vector());
  std::filesystem::remove(job);
}

TEST(PostPen, RealDrawingWithPenZ) {
  // The start of a real Inkscape pen drawing (../shared corpus, Rotrics DexArm header left out):
  // three paths, pen Z -1 / 5, arcs, placed on the wall 1.1 m below the motors.
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const auto drawing = test::real_corpus() / "plotter/dexarm-inkscape/vitruvianMan.gcode";
  std::ifstream in(drawing);
  std::string line, cut;
  for (int number = 1; std::getline(in, line) && number <= 90; ++number) {
    if (number >= 9) cut += line + "\n";
  }
  const auto job = temp_file("vitruvian.ngc");
  std::ofstream(job) << cut << "G00 Z 5.0000\nM2\n";
  expect_pen_where_the_job_crosses(job, geometry::Pose::from_mm_deg(750, -1100, 0).as_vector());
  std::filesystem::remove(job);
}

TEST(PostPen, ServoCommandsOfThePenPlotterVerbatimAndNoZ) {
  // examples/machines/pen-plotter.toml: its M280 lines where the pen changes, each with G4 P0.150;
  // the job's own spindle words are left out (the pen owns the tool), no Z word anywhere.
  const machine::Machine machine = test::load_example("pen-plotter.toml");
  PostOptions options;
  options.origin = geometry::Pose::from_mm_deg(750, -700, 0).as_vector();
  const auto lines = posted_lines(
      machine, "G21 G90 M3 S500\nG0 X0 Y0 Z5\nG1 Z-1 F600\nG1 X10\nG0 Z5\nM5\nM2\n", options);
  std::vector<std::string> commands;
  for (const std::string& l : lines) {
    EXPECT_EQ(l.find('Z'), std::string::npos) << l;
    if (l[0] == 'M' || l[0] == 'S' || l.rfind("G4", 0) == 0) commands.push_back(l);
  }
  EXPECT_EQ(commands, (std::vector<std::string>{"M280 P0 S90", "G4 P0.150", "M280 P0 S30",
                                                "G4 P0.150", "M280 P0 S90", "G4 P0.150", "M2"}));
}

// The start of LinuxText.ngc, the LinuxCNC splash text as drawn by the LinuxCNC polargraph of
// Chojins/LinuxCNC-Polargraph (nc_files/, commit 29149999): its first two letters. The pen draws
// at Z90 (the servo at 90 degrees) and travels at Z0; the Z moves are rapids.
constexpr const char* kLinuxTextStart =
    "G21 G90 G64 G40\nM3 S10000\nG17\n"
    "G0 X1.75781 Y0.5\nG0 Z90\nG1 F400.0 X5.95508 Y20.54297\nG1 X10.07031\n"
    "G1 X6.58398 Y3.84961\nG1 X16.7832\nG1 X16.08594 Y0.5\nG1 X1.75781\nG0 Z0\n"
    "G0 X18.72461\nG0 Z90\nG1 F400.0 X21.75977 Y15.01953\nG1 X25.68359\n"
    "G1 X22.64844 Y0.5\nG1 X18.72461\nG0 Z0\n"
    "G0 X26.09375 Y16.98828\nG0 Z90\nG1 F400.0 X22.16992\nG1 X22.9082 Y20.54297\n"
    "G1 X26.83203\nG1 X26.09375 Y16.98828\nG0 Z0\nM5\nM2\n";

// Chojins' polargraph (examples/machines/linuxcnc-polargraph-2366.toml) with the [tool] height
// its drawings need: `tool` replaces the example's [tool] table.
machine::Machine polargraph_2366(const std::string& tool) {
  std::ifstream in(test::example_machine_path("linuxcnc-polargraph-2366.toml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = text.substr(0, text.find("[tool]")) + tool;
  return machine::parse_machine(text, "polargraph-2366.toml");
}

TEST(PostPen, LinuxCncPolargraphDrawingDrawsAboveItsHeight) {
  // down_above = 45: down at each G0 Z90, up at each G0 Z0, three strokes; no warning.
  const machine::Machine machine = polargraph_2366(
      "[tool]\nz = \"pen\"\ndown_above = 45.0\ndown = \"G0 Z90\"\nup = \"G0 Z0\"\ndelay = 0.2\n");
  EXPECT_TRUE(machine.tool().down_above);
  const auto job = temp_file("linuxtext.ngc");
  std::ofstream(job) << kLinuxTextStart;
  const geometry::Vector6d origin = geometry::Pose::from_mm_deg(1130, -1200, 0).as_vector();
  const auto expected =
      job_pen_changes(programmed_moves(machine, job, origin), machine.tool(), false);
  ASSERT_EQ(expected.size(), 6u);  // three strokes
  PostOptions options;
  options.origin = origin;
  PostReport report;
  const auto lines = posted_lines(machine, kLinuxTextStart, options, &report);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "G0 Z90"), 3);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "G0 Z0"), 4);  // at the start, and 3 lifts
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front().message;
  std::filesystem::remove(job);
}

TEST(PostPen, PenIsUpAtTheStartWhateverHomesZ) {
  // down_below = 10 puts home's Z 0 on the drawing side: the pen stays up over the travel to the
  // first point and the job's own Z0 there, and goes down where the job first moves in Z down
  // (the G1 Z2 of line 5); line 4's lift was to Z 20.
  machine::Machine machine = pen_plotter();
  machine::ToolChannel tool = machine.tool();
  tool.pen_height_mm = 10.0;
  machine.set_tool(tool);
  PostOptions options;
  options.origin = geometry::Pose::from_mm_deg(750, -700, 0).as_vector();
  const auto lines = posted_lines(
      machine, "G21 G90\nG0 X10 Y10\nG1 X20 F600\nG0 Z20\nG1 Z2\nG1 X30\nG0 Z20\nM2\n", options);
  std::vector<std::string> pen;
  std::size_t moves_before_down = 0;
  for (const std::string& l : lines) {
    if (l == "M3 S1000" || l == "M5") pen.push_back(l);
    if (pen.size() < 2 && (l.rfind("G0 ", 0) == 0 || l.find("G1 ") != std::string::npos)) {
      ++moves_before_down;
    }
  }
  EXPECT_EQ(pen, (std::vector<std::string>{"M5", "M3 S1000", "M5"}));
  EXPECT_GE(moves_before_down, 2u);  // the travel and the G1 X20 with the pen up
}

TEST(PostPen, WarnsWhenThePenNeverGoesDown) {
  // The LinuxCNC polargraph's drawing (Z90 down) on examples/machines/pen-plotter.toml (down
  // below 0): nothing is drawn; the warning names the job's Z and the setting that draws it.
  const machine::Machine machine = test::load_example("pen-plotter.toml");
  PostOptions options;
  options.origin = geometry::Pose::from_mm_deg(750, -900, 0).as_vector();
  PostReport report;
  const auto lines = posted_lines(machine, kLinuxTextStart, options, &report);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M280 P0 S30"), 0);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0].line, 4);  // the job's first move in X and Y
  EXPECT_EQ(report.warnings[0].message,
            "the pen never goes down: the job's moves in X and Y run at Z 90 mm (feed), 0 mm "
            "(rapid); the pen draws below Z 0 mm ([tool] down_below); [tool] down_above = 45 "
            "would draw at Z 90 and lift the pen at Z 0");
}

TEST(PostPen, WarnsWhenThePenNeverComesUp) {
  // The same drawing with down_below = 100: every Z draws, the travel too.
  const machine::Machine machine =
      polargraph_2366("[tool]\nz = \"pen\"\ndown_below = 100.0\ndown = \"M3\"\nup = \"M5\"\n");
  PostOptions options;
  options.origin = geometry::Pose::from_mm_deg(1130, -1200, 0).as_vector();
  PostReport report;
  posted_lines(machine, kLinuxTextStart, options, &report);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0].line, 5);  // G0 Z90: the job's first move in Z
  EXPECT_NE(report.warnings[0].message.find("the pen goes down here and never comes up"),
            std::string::npos);
  EXPECT_NE(report.warnings[0].message.find("[tool] down_above = 45 would draw at Z 90"),
            std::string::npos)
      << report.warnings[0].message;
}

TEST(PostPen, OneStrokeDrawingIsNoWarning) {
  // A guilloche of the same polargraph (guilloche-2014-02-14_16-21-51.ngc's shape): one feed
  // move at home's Z to the start, a ramp to Z65 that draws, one long stroke, the lift to Z90
  // at the end. With down_above = 32.5 the pen goes down once and stays down: not a warning.
  const machine::Machine machine =
      polargraph_2366("[tool]\nz = \"pen\"\ndown_above = 32.5\ndown = \"M3\"\nup = \"M5\"\n");
  PostOptions options;
  options.origin = geometry::Pose::from_mm_deg(1180, -1200, 0).as_vector();
  PostReport report;
  const auto lines = posted_lines(
      machine,
      "G21 G90 G64 G40\nT0 M6\nM3 S1000 F2000\nG1 X65.33 Y-31.45\n"
      "G1 G21 F600 X64.2 Y-31.39 Z65\nG1 X63.22 Y-31.35\nG1 X62.4 Y-31.29\nG1 X61.77 Y-31.18\n"
      "G1 X61.35 Y-31\nG1 X61.14 Y-30.71\nG0 Z90.0\nM5\nM30\n",
      options, &report);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M3"), 1);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front().message;
}

// Joints rounded as the linuxcnc dialect writes them (5 decimals of mm or deg).
kinematics::JointVector rounded_as_written(const machine::Machine& machine,
                                           const kinematics::JointVector& q) {
  kinematics::JointVector result = q;
  for (int i = 0; i < q.size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    result[i] = joint.from_interface(std::round(joint.to_interface(q[i]) * 1e5) / 1e5);
  }
  return result;
}

// Blocks of the adaptive post, and of uniform splitting held to the same bound: per move, the
// fewest equal pieces each of whose bound is within `tolerance`.
std::pair<long, long> adaptive_and_uniform(const machine::Machine& machine,
                                           const std::string& job_text, double tolerance) {
  const auto job = temp_file("uniform-job.ngc");
  std::ofstream(job) << job_text;
  PostOptions options;
  options.tolerance_mm = tolerance;
  const long adaptive = post_program(machine, job, {}, options, [](const std::string&) {}).blocks;
  const DeviationBound bound(machine, tolerance);
  long uniform = 0;
  for (const motion::Segment& move : programmed_moves(machine, job)) {
    const auto joints_at = [&](double u) {
      kinematics::JointVector q;
      EXPECT_TRUE(machine.inverse(geometry::Pose::from_vector(move.at(u)), q).ok());
      return q;
    };
    const auto fits = [&](int pieces) {
      for (int k = 0; k < pieces; ++k) {
        const double u0 = static_cast<double>(k) / pieces, u1 = static_cast<double>(k + 1) / pieces;
        const kinematics::JointVector q0 = joints_at(u0), q1 = joints_at(u1);
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
    const machine::Machine machine = test::load_example(file);
    if (!DeviationBound(machine, 0.01).available()) continue;  // formula machines: sampled
    int axes[2] = {0, 1};
    for (int axis = 0, n = 0; axis < 3 && n < 2; ++axis) {
      if (machine.kinematics().dof().controls(axis)) axes[n++] = axis;
    }
    const geometry::Vector6d home = machine.home().as_vector();
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
    const machine::Machine machine = test::load_example(file);
    const auto formulas = mach3_formulas(machine);
    kinematics::FormulaDefinition definition;
    for (int axis = 0; axis < 3; ++axis) {
      if (machine.kinematics().dof().controls(axis)) definition.axes.push_back(axis);
    }
    for (std::size_t i = 0; i < formulas.size(); ++i) {
      definition.formulas.emplace_back(machine.joints()[i].name, formulas[i].second);
    }
    const kinematics::FormulaKinematics exported(definition);
    std::mt19937_64 rng(4);
    for (const geometry::Pose& pose : test::sample_reachable_poses(machine, 200, rng)) {
      kinematics::JointVector expected, actual;
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

// The seconds the G93 blocks of a joint program take (60 / F each), and how many G0 blocks it has.
struct ProgramTimes {
  double inverse_time_s = 0.0;
  int rapid_blocks = 0;
};
ProgramTimes program_times(const std::vector<std::string>& lines) {
  ProgramTimes times;
  for (const std::string& line : lines) {
    if (line.rfind("G0 ", 0) == 0) ++times.rapid_blocks;
    const std::size_t f = line.find(" F");
    if (line.find("G1") != std::string::npos && f != std::string::npos) {
      times.inverse_time_s += 60.0 / std::stod(line.substr(f + 2));
    }
  }
  return times;
}

// grbl's G0 runs each joint at its own top rate, faster than the tool may go: for grbl, post
// times a rapid at [cartesian] max_feed (100 mm/s on the wall plotter, whose cords never change
// faster than the tool moves: 30 mm take 0.3 s); LinuxCNC keeps G0, as does --rapids g0.
TEST(Post, GrblRapidsTakeTheirTimeAtMaxFeed) {
  const machine::Machine wall_plotter = test::load_example("wall-plotter.toml");
  const std::string job = "G21 G90\nG0 X780 Y-700\nM2\n";
  PostOptions grbl;
  grbl.dialect = Dialect::grbl;
  const ProgramTimes timed = program_times(posted_lines(wall_plotter, job, grbl));
  EXPECT_EQ(timed.rapid_blocks, 0);
  EXPECT_NEAR(timed.inverse_time_s, 0.3, 0.3e-3);  // F rounded down to 3 decimals per block
  EXPECT_GE(timed.inverse_time_s, 0.3 - 1e-12);
  PostOptions as_g0 = grbl;
  as_g0.rapids = RapidsStyle::g0;
  const ProgramTimes kept = program_times(posted_lines(wall_plotter, job, as_g0));
  EXPECT_GE(kept.rapid_blocks, 1);
  EXPECT_EQ(kept.inverse_time_s, 0.0);
  EXPECT_GE(program_times(posted_lines(wall_plotter, job, {})).rapid_blocks, 1);  // linuxcnc
  EXPECT_EQ(rapids_style_of(Dialect::grblhal), RapidsStyle::timed);
  EXPECT_EQ(rapids_style_of(Dialect::mach3), RapidsStyle::g0);
  EXPECT_THROW(rapids_style_named("fast"), std::invalid_argument);
}

// With the spindle (a laser) on, a rapid stays G0 (grbl's laser mode switches the laser off in
// G0 only) and is warned of at its line, with the tool's speed: the triaglide's rails run at
// 250 mm/s where the tool may go 100.
TEST(Post, GrblRapidWithTheSpindleOnStaysG0AndIsWarnedOf) {
  const machine::Machine triaglide = test::load_example("triaglide.toml");
  PostOptions grbl;
  grbl.dialect = Dialect::grbl;
  PostReport report;
  const auto lines =
      posted_lines(triaglide, "G21 G90\nM3 S1000\nG0 X2 Y0 Z200\nM5\nG0 X0\nM2\n", grbl, &report);
  const auto g0 = std::find_if(lines.begin(), lines.end(),
                               [](const std::string& l) { return l.rfind("G0 ", 0) == 0; });
  ASSERT_NE(g0, lines.end());
  EXPECT_EQ(program_times(lines).rapid_blocks, 1);  // the rapid after M5 is timed
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0].line, 3);
  // The tool's average speed in that block: 2 mm over the time its fastest rail takes at 250.
  kinematics::JointVector home, end;
  ASSERT_TRUE(triaglide.inverse(triaglide.home(), home).ok());
  ASSERT_TRUE(triaglide
                  .inverse(geometry::Pose::from_vector(
                               (geometry::Vector6d() << 2, 0, 200, 0, 0, 0).finished()),
                           end)
                  .ok());
  const double speed = 2.0 / ((end - home).cwiseAbs().maxCoeff() / 250.0);
  char expected[64];
  std::snprintf(expected, sizeof expected, "averages up to %.1f mm/s", speed);
  EXPECT_GT(speed, 100.0);
  EXPECT_NE(report.warnings[0].message.find(expected), std::string::npos)
      << report.warnings[0].message;
  EXPECT_NE(report.warnings[0].message.find("above max_feed 100.0 mm/s"), std::string::npos);
}

}  // namespace
}  // namespace pkm::post
