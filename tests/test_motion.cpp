// Time-division interpolation: samples on the programmed path, speeds and accelerations within
// their limits, closed-form durations, joints equal to IK of every sample, limits named by line.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "pkm/io/sample_files.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "test_support.hpp"

namespace pkm::motion {
namespace {

struct Collect final : SampleSink {
  std::vector<Sample> samples;
  void write(const Sample& sample) override { samples.push_back(sample); }
};

std::filesystem::path write_program(const std::string& text) {
  static int counter = 0;
  const auto path =
      std::filesystem::temp_directory_path() /
      ("pkm-motion-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".ngc");
  std::ofstream(path) << text;
  return path;
}

PlanReport plan(const machine::Machine& machine, const std::string& program, Collect& out,
                const PlanOptions& options = {}) {
  const auto path = write_program(program);
  PlanReport report;
  try {
    report = plan_program(machine, path, {}, options, out);
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
  std::filesystem::remove(path);
  return report;
}

TEST(SegmentBuilder, ProgramStartsAtTheMachinePoseSeenFromItsOrigin) {
  gcode::InterpreterOptions options;
  options.block_delete = true;
  geometry::Vector6d start_mm_rad, origin_mm_rad;
  start_mm_rad << 10.0, 20.0, 30.0, std::numbers::pi / 2.0, 0.0, -std::numbers::pi / 4.0;
  origin_mm_rad << 1.0, -2.0, 3.0, 0.0, std::numbers::pi / 6.0, 0.0;
  const gcode::InterpreterOptions started = starting_at(options, start_mm_rad, origin_mm_rad);
  const double expected_mm_deg[6] = {9.0, 22.0, 27.0, 90.0, -30.0, -45.0};
  for (int axis = 0; axis < 6; ++axis) {
    EXPECT_NEAR(started.start_position[axis], expected_mm_deg[axis], 1e-12) << "axis " << axis;
  }
  EXPECT_TRUE(started.block_delete);  // the other options pass through
}

TEST(SegmentBuilder, ATurnedCoordinateSystemTurnsLinesAndArcsAboutItsOrigin) {
  // G54 at (10, 5) turned by 90 deg, G92 shifting the program by (1, 0) first: program (0, 0) is
  // machine (10, 6) (G92 is turned with the system); an arc about program (-1, 0) ends at
  // program (-1, 1), machine (9, 5). G53 X0 Y0 is the machine origin.
  const auto path = write_program(
      "G21 G90\nG10 L2 P1 X10 Y5 R90\nG54\nG0 X1 Y0\nG92 X0 Y0\nG0 X0 Y0\n"
      "G3 X-1 Y1 I-1 J0 F100\nG53 G0 X0 Y0\nM2\n");
  SegmentBuilder builder(geometry::Vector6d::Zero(), geometry::Vector6d::Zero(), false);
  std::vector<Segment> segments;
  gcode::Interpreter(path).run([&](const gcode::Canon& canon) {
    for (const Segment& segment : builder.take(canon)) segments.push_back(segment);
  });
  std::filesystem::remove(path);
  ASSERT_EQ(segments.size(), 4u);
  EXPECT_NEAR((segments[1].end.head<2>() - Eigen::Vector2d(10.0, 6.0)).norm(), 0.0, 1e-12);
  ASSERT_EQ(segments[2].kind, SegmentKind::arc);
  EXPECT_NEAR((segments[2].centre.head<2>() - Eigen::Vector2d(10.0, 5.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((segments[2].end.head<2>() - Eigen::Vector2d(9.0, 5.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(segments[2].sweep_rad, std::numbers::pi / 2.0, 1e-12);  // a quarter, ccw
  EXPECT_NEAR(segments[3].end.head<2>().norm(), 0.0, 1e-12);
}

TEST(Plan, LineSamplesLieOnTheLineAndTheDurationIsClosedForm) {
  // Hexapod: 1000 mm/s^2. G1 X50 at F3000 (50 mm/s) from home: ramps of 0.05 s over 1.25 mm
  // each, 47.5 mm cruising at 50 mm/s: 1.05 s.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  Collect out;
  const PlanReport report = plan(hexapod, "G21 G90\nG1 F3000 X50 Y0 Z1000\nM2\n", out);
  EXPECT_NEAR(report.duration_s, 1.05, 1e-12);
  EXPECT_NEAR(report.path_length_mm, 50.0, 1e-12);
  ASSERT_EQ(out.samples.size(), 1051u);  // t = 0, 0.001, ..., 1.050 (the end)
  double peak_speed = 0.0, peak_acceleration = 0.0, previous_speed = 0.0;
  for (std::size_t k = 0; k < out.samples.size(); ++k) {
    const Sample& s = out.samples[k];
    EXPECT_LE(std::abs(s.pose[1]), 1e-9);
    EXPECT_LE(std::abs(s.pose[2] - 1000.0), 1e-9);
    EXPECT_NEAR(s.time_s, std::min(0.001 * static_cast<double>(k), 1.05), 1e-12);
    if (k == 0) continue;
    const double dt = s.time_s - out.samples[k - 1].time_s;
    const double speed = (s.pose[0] - out.samples[k - 1].pose[0]) / dt;
    peak_speed = std::max(peak_speed, speed);
    if (k > 1)
      peak_acceleration = std::max(peak_acceleration, std::abs(speed - previous_speed) / dt);
    previous_speed = speed;
  }
  EXPECT_LE(peak_speed, 50.0 * (1 + 1e-9));
  EXPECT_GT(peak_speed, 49.99);
  EXPECT_LE(peak_acceleration, 1000.0 * (1 + 1e-6));
  EXPECT_DOUBLE_EQ(out.samples.back().pose[0], 50.0);
}

TEST(Plan, JerkLimitedRampsAreSCurves) {
  // J = 100,000 mm/s^3 reaches 1000 mm/s^2 in 0.01 s; each ramp to 50 mm/s takes
  // 50/1000 + 1000/100000 = 0.06 s over 1.5 mm; 47 mm cruising at 50 mm/s: 1.06 s in all.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  PlanOptions options;
  options.jerk_mm_per_s3 = 100000.0;
  Collect out;
  const PlanReport report = plan(hexapod, "G21 G90\nG1 F3000 X50 Y0 Z1000\nM2\n", out, options);
  EXPECT_NEAR(report.duration_s, 1.06, 1e-9);
  double peak_jerk = 0.0, peak_acceleration = 0.0;
  const double t = 0.001;
  for (std::size_t k = 3; k + 1 < out.samples.size(); ++k) {
    const double x0 = out.samples[k - 3].pose[0], x1 = out.samples[k - 2].pose[0];
    const double x2 = out.samples[k - 1].pose[0], x3 = out.samples[k].pose[0];
    peak_jerk = std::max(peak_jerk, std::abs(x3 - 3 * x2 + 3 * x1 - x0) / (t * t * t));
    peak_acceleration = std::max(peak_acceleration, std::abs(x3 - 2 * x2 + x1) / (t * t));
  }
  EXPECT_LE(peak_jerk, 100000.0 * 1.001);
  EXPECT_GT(peak_jerk, 90000.0);
  EXPECT_LE(peak_acceleration, 1000.0 * 1.001);
  EXPECT_GT(peak_acceleration, 990.0);
  EXPECT_DOUBLE_EQ(out.samples.back().pose[0], 50.0);
}

TEST(Plan, ShortJerkLimitedRampsNeverReachFullAcceleration) {
  // J = 10,000 mm/s^3 and a change of 50 mm/s: a^2/J = 100 > 50, so the acceleration peaks at
  // sqrt(50 * 10000) = 707 mm/s^2 and each ramp takes 2 * 0.0707 s over 3.536 mm.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  PlanOptions options;
  options.jerk_mm_per_s3 = 10000.0;
  Collect out;
  const PlanReport report = plan(hexapod, "G21 G90\nG1 F3000 X50 Y0 Z1000\nM2\n", out, options);
  const double ramp_s = 2.0 * std::sqrt(50.0 / 10000.0);
  EXPECT_NEAR(report.duration_s, 2 * ramp_s + (50.0 - 50.0 * ramp_s) / 50.0, 1e-9);
}

TEST(Plan, ArcSamplesStayOnTheirRadius) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  Collect out;
  plan(hexapod, "G21 G90 G17\nG0 X40 Y0 Z1000\nG3 X-40 Y0 I-40 J0 Z1005 F1200\nM2\n", out);
  int on_arc = 0;
  for (const Sample& s : out.samples) {
    if (s.line != 3) continue;
    ++on_arc;
    EXPECT_NEAR(std::hypot(s.pose[0], s.pose[1]), 40.0, 1e-9);
    // The helix rises linearly with the angle swept.
    const double angle = std::atan2(s.pose[1], s.pose[0]);
    EXPECT_NEAR(s.pose[2], 1000.0 + 5.0 * (angle < 0 ? angle + 2 * M_PI : angle) / M_PI, 1e-9);
  }
  EXPECT_GT(on_arc, 100);
}

TEST(Plan, EverySamplesJointsAreTheIkOfItsPose) {
  for (const std::string& file : test::example_machine_files()) {
    const machine::Machine machine = test::load_example(file);
    const geometry::Vector6d home = machine.home().as_vector();
    // A small square around home in the first two controlled axes, then back.
    int axes[2] = {-1, -1};
    for (int axis = 0, n = 0; axis < 3 && n < 2; ++axis) {
      if (machine.kinematics().dof().controls(axis)) axes[n++] = axis;
    }
    const char letters[] = {'X', 'Y', 'Z'};
    const auto word = [&](int n, double offset) {
      return std::string(1, letters[axes[n]]) + std::to_string(home[axes[n]] + offset);
    };
    std::string program = "G21 G90 F600\n";
    program += "G1 " + word(0, 5) + " " + word(1, 0) + "\n";
    program += "G1 " + word(0, 5) + " " + word(1, 5) + "\n";
    program += "G0 " + word(0, 0) + " " + word(1, 0) + "\nM2\n";
    Collect out;
    const PlanReport report = plan(machine, program, out);
    for (const Sample& s : out.samples) {
      kinematics::JointVector joints;
      ASSERT_TRUE(machine.inverse(geometry::Pose::from_vector(s.pose), joints).ok()) << file;
      EXPECT_LT((joints - s.joints).cwiseAbs().maxCoeff(), 1e-12) << file;
    }
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const machine::JointSpec& joint = machine.joints()[i];
      EXPECT_GE(report.joints[i].min, joint.min) << file;
      EXPECT_LE(report.joints[i].max, joint.max) << file;
      EXPECT_LE(report.joints[i].peak_velocity, joint.max_velocity) << file << " " << joint.name;
      EXPECT_LE(report.joints[i].peak_acceleration, joint.max_acceleration * (1 + 1e-6))
          << file << " " << joint.name;
    }
  }
}

TEST(Plan, JointVelocityLimitsLowerTheFeed) {
  // Hektor's cables allow 60 mm/s; with its Cartesian limit raised, a 6000 mm/min (100 mm/s)
  // move must slow down for them.
  std::ifstream in(test::example_machine_path("hektor.toml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  text.replace(text.find("max_feed = 2400.0"), 17, "max_feed = 12000.0");
  const machine::Machine hektor = machine::parse_machine(text, "fast-hektor.toml");
  Collect out;
  const PlanReport report = plan(hektor, "G21 G90\nG1 F6000 X80 Y-50\nM2\n", out);
  ASSERT_FALSE(report.feed_limits.empty());
  EXPECT_EQ(report.feed_limits.front().line, 2);
  for (const JointStatistics& joint : report.joints) EXPECT_LE(joint.peak_velocity, 60.0);
}

TEST(Plan, UnreachableMoveNamesItsLine) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  Collect out;
  try {
    plan(hektor, "G21 G90\nG1 F600 X50 Y-60\nG1 X50 Y10\nM2\n", out);
    FAIL() << "a move above the anchors was planned";
  } catch (const PlanError& error) {
    EXPECT_EQ(error.line(), 3);
    EXPECT_NE(std::string(error.what()).find("leaves the machine's reach"), std::string::npos)
        << error.what();
  }
}

TEST(Plan, OriginPlacesTheProgramOnTheMachine) {
  // A drawing made about (0, 0), placed 700 mm right of and 800 mm below the left anchor.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  Collect out;
  PlanOptions options;
  options.origin << 700, -800, 0, 0, 0, 0;
  plan(plotter, "G21 G90 F3000\nG1 X10 Y-5\nG1 Y5\nM2\n", out, options);
  EXPECT_NEAR(out.samples.back().pose[0], 710.0, 1e-12);
  EXPECT_NEAR(out.samples.back().pose[1], -795.0, 1e-12);
  // The machine starts at home (750, -700): the first move runs from there to (710, -805).
  EXPECT_EQ(out.samples.front().pose.head<2>(), Eigen::Vector2d(750, -700));
}

// How far the tool axis strays from the great circle between its first and last direction over
// the samples of `line`, and whether it moves on steadily along it.
std::pair<double, bool> tool_axis_off_great_circle(const std::vector<Sample>& samples, int line) {
  std::vector<Eigen::Vector3d> axes;
  for (const Sample& s : samples) {
    if (s.line == line) axes.push_back(geometry::rotation_from_abc(s.pose.tail<3>()).col(2));
  }
  const Eigen::Vector3d normal = axes.front().cross(axes.back()).normalized();
  double off = 0.0, previous_angle = -1.0;
  bool monotonic = true;
  for (const Eigen::Vector3d& axis : axes) {
    off = std::max(off, std::abs(axis.dot(normal)));
    const double angle = std::acos(std::clamp(axis.dot(axes.front()), -1.0, 1.0));
    monotonic = monotonic && angle >= previous_angle - 1e-12;
    previous_angle = angle;
  }
  return {off, monotonic};
}

TEST(Plan, GreatCircleAttitudeKeepsTheToolAxisOnItsGreatCircle) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const std::string program = "G21 G90 F600\nG1 X0 Y0 Z1000 A0 B0 C0\nG1 X10 A30 B20 C10\nM2\n";
  Collect great, linear;
  PlanOptions options;
  options.great_circle_attitude = true;
  plan(hexapod, program, great, options);
  plan(hexapod, program, linear);
  const auto [off_great, steady] = tool_axis_off_great_circle(great.samples, 3);
  EXPECT_LT(off_great, 1e-12);
  EXPECT_TRUE(steady);
  // LinuxCNC's linear A B C takes the axis off that circle: the test can tell the two apart.
  EXPECT_GT(tool_axis_off_great_circle(linear.samples, 3).first, 1e-3);
  // Both end exactly on the programmed attitude.
  const geometry::Vector6d end = great.samples.back().pose;
  EXPECT_NEAR(geometry::radians_to_degrees(end[3]), 30.0, 1e-9);
  EXPECT_NEAR(geometry::radians_to_degrees(end[4]), 20.0, 1e-9);
  EXPECT_NEAR(geometry::radians_to_degrees(end[5]), 10.0, 1e-9);
}

TEST(Plan, DwellHoldsThePose) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  Collect out;
  const PlanReport report = plan(hexapod, "G21\nG4 P0.25\nM2\n", out);
  EXPECT_NEAR(report.duration_s, 0.25, 1e-12);
  EXPECT_EQ(out.samples.size(), 251u);
  for (const Sample& s : out.samples) EXPECT_EQ(s.pose, hexapod.home().as_vector());
}

// The tool tip's peak speed and acceleration (vector finite differences over the samples).
std::pair<double, double> peak_speed_and_acceleration(const std::vector<Sample>& samples) {
  double peak_speed = 0.0, peak_acceleration = 0.0;
  Eigen::Vector3d previous_velocity = Eigen::Vector3d::Zero();
  double previous_dt = 0.0;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const double dt = samples[k].time_s - samples[k - 1].time_s;
    if (dt <= 0.0) continue;
    const Eigen::Vector3d velocity =
        (samples[k].pose.head<3>() - samples[k - 1].pose.head<3>()) / dt;
    peak_speed = std::max(peak_speed, velocity.norm());
    if (k > 1) {
      peak_acceleration = std::max(
          peak_acceleration, (velocity - previous_velocity).norm() / (0.5 * (dt + previous_dt)));
    }
    previous_velocity = velocity;
    previous_dt = dt;
  }
  return {peak_speed, peak_acceleration};
}

TEST(LookAhead, AMicrometresMoveOnTheWayCostsNoTime) {
  // Two lines along X at F6000 on the wall plotter, and the same with a move of 1e-6 mm between
  // them (CAM rounding leaves such moves). The joints' differences over its grid's 2.5e-7 mm
  // steps are rounding: its cables' bend read thousands per mm^2 and the plan crawled through it
  // (4.573 s against 4.486 s).
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  PlanOptions options;
  options.estimate_only = true;
  options.origin << 650.0, -900.0, 0.0, 0.0, 0.0, 0.0;
  struct : SampleSink {
    void write(const Sample&) override {}
  } none;
  const auto duration = [&](const std::string& middle) {
    const test::TempProgram job("G21 G90 G64\nG1 X0 Y0 F6000\nG1 X100 Y0\n" + middle +
                                "G1 X200 Y0\nM2\n");
    return plan_program(plotter, job.path(), {}, options, none).duration_s;
  };
  const double straight = duration("");
  EXPECT_NEAR(duration("G1 X100.000001 Y0\n"), straight, 1e-6 * straight);
  EXPECT_NEAR(duration("G1 X100.0001 Y0\n"), straight, 1e-6 * straight);
}

TEST(Segment, ItsRatesAreTheDerivativesOfItsPoses) {
  // A line, an arc with a radius that drifts and a rise, and a blend: d pose/du and d2 pose/du2
  // against central differences of at() (step 1e-5: errors of 1e-9 at these sizes).
  Segment line;
  line.start << 1.0, 2.0, 3.0, 0.1, 0.2, 0.3;
  line.end << 4.0, -2.0, 5.0, 0.2, 0.1, 0.3;
  Segment arc = line;
  arc.kind = SegmentKind::arc;
  arc.start << 10.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  arc.end << 0.0, 10.5, 2.0, 0.0, 0.0, 0.1;
  arc.centre = Eigen::Vector3d::Zero();
  arc.sweep_rad = M_PI / 2.0;
  Segment blend;
  blend.kind = SegmentKind::blend;
  blend.centre << 5.0, 5.0, 0.0;
  blend.radius_mm = 2.0;
  blend.axis_u = Eigen::Vector3d::UnitX();
  blend.axis_v = Eigen::Vector3d::UnitY();
  blend.sweep_rad = 1.2;
  blend.start = blend.at(0.0);
  blend.end << 5.0 + 2.0 * std::cos(1.2), 5.0 + 2.0 * std::sin(1.2), 0.0, 0.0, 0.0, 0.0;
  const double h = 1e-5;
  for (const Segment* segment : {&line, &arc, &blend}) {
    for (const double u : {0.1, 0.5, 0.9}) {
      const geometry::Vector6d first = (segment->at(u + h) - segment->at(u - h)) / (2.0 * h);
      const geometry::Vector6d second =
          (segment->at(u + h) - 2.0 * segment->at(u) + segment->at(u - h)) / (h * h);
      EXPECT_LT((segment->velocity_at(u) - first).norm(), 1e-6) << u;
      EXPECT_LT((segment->acceleration_at(u) - second).norm(), 1e-3) << u;
    }
  }
}

TEST(LookAhead, ShortCamSegmentsRunAtTheProgrammedFeed) {
  // A circle of radius 20 mm as 0.1 mm chords at F600 (10 mm/s): G64 must not stop at each one.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  std::string program = "G21 G90 G64 P0.01\nG1 F600 X20 Y0 Z1000\n";
  const int chords = static_cast<int>(2 * M_PI * 20 / 0.1);
  for (int i = 1; i <= chords; ++i) {
    const double angle = 2 * M_PI * i / chords;
    program += "X" + std::to_string(20 * std::cos(angle)) + " Y" +
               std::to_string(20 * std::sin(angle)) + "\n";
  }
  program += "M2\n";
  Collect out;
  const PlanReport report = plan(hexapod, program, out);
  // 20 + 125.66 mm at 10 mm/s and its ramps (14.57 s), not 1,257 stops.
  EXPECT_LT(report.duration_s, 14.6);
  // The 90 deg corner into the circle is rounded within 0.01 mm: 0.015 mm shorter.
  EXPECT_NEAR(report.path_length_mm, 20.0 + 2 * M_PI * 20, 0.02);
  std::vector<Sample> circle;
  for (const Sample& s : out.samples) {
    if (s.line >= 3) circle.push_back(s);
  }
  const auto [speed, acceleration] = peak_speed_and_acceleration(out.samples);
  EXPECT_LE(speed, 10.0 * (1 + 1e-9));
  EXPECT_LE(acceleration, 1000.0 * 1.01);
  // In the middle of the circle the tool runs at the programmed feed.
  const std::size_t from = circle.size() / 4, to = 3 * circle.size() / 4;
  double path = 0.0;
  for (std::size_t k = from + 1; k <= to; ++k) {
    path += (circle[k].pose.head<3>() - circle[k - 1].pose.head<3>()).norm();
  }
  EXPECT_GT(path / (circle[to].time_s - circle[from].time_s), 9.9);
}

TEST(LookAhead, CornersStayWithinTheTolerance) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const std::vector<Eigen::Vector3d> corners = {
      {0, 0, 1000}, {30, 0, 1000}, {30, 20, 1000}, {0, 20, 1005}, {0, 0, 1000}};
  std::string program = "G21 G90 G64 P0.05\nG1 F3000 X0 Y0 Z1000\n";
  for (std::size_t i = 1; i < corners.size(); ++i) {
    program += "X" + std::to_string(corners[i].x()) + " Y" + std::to_string(corners[i].y()) + " Z" +
               std::to_string(corners[i].z()) + "\n";
  }
  program += "M2\n";
  Collect out;
  plan(hexapod, program, out);
  double worst = 0.0;
  double slowest_at_corner = 1e9;
  for (std::size_t k = 1; k < out.samples.size(); ++k) {
    const Eigen::Vector3d p = out.samples[k].pose.head<3>();
    worst = std::max(worst, test::distance_to_polyline(p, corners));
    if ((p - corners[1]).norm() < 0.5) {
      const double speed = (p - out.samples[k - 1].pose.head<3>()).norm() /
                           (out.samples[k].time_s - out.samples[k - 1].time_s);
      slowest_at_corner = std::min(slowest_at_corner, speed);
    }
  }
  EXPECT_LE(worst, 0.05 + 1e-9);
  EXPECT_GT(worst, 0.01);             // it did round the corners
  EXPECT_GT(slowest_at_corner, 1.0);  // ...without stopping
  const auto [speed, acceleration] = peak_speed_and_acceleration(out.samples);
  EXPECT_LE(speed, 50.0 * (1 + 1e-9));
  EXPECT_LE(acceleration, 1000.0 * 1.01);
}

TEST(LookAhead, ExactStopModeStopsAtEveryCorner) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  Collect out;
  const PlanReport report = plan(hexapod, "G21 G90 G61\nG1 F3000 X0 Y0 Z1000\nX30\nY20\nM2\n", out);
  // Two rest-to-rest moves: 30 mm and 20 mm at 50 mm/s and 1000 mm/s^2.
  EXPECT_NEAR(report.duration_s, (0.1 + (30 - 2.5) / 50.0) + (0.1 + (20 - 2.5) / 50.0), 1e-9);
  for (const Sample& s : out.samples) {
    EXPECT_LE(test::distance_to_segment(s.pose.head<3>(), {0, 0, 1000}, {30, 0, 1000}) *
                  test::distance_to_segment(s.pose.head<3>(), {30, 0, 1000}, {30, 20, 1000}),
              1e-12);
  }
}

// The paper's test parts on its machine: legs within 600..1500 mm, their speeds and
// accelerations within their limits (finite differences over the 1 ms samples), the tool path as
// generated by tools/make-paper-jobs.py.
void expect_paper_job_within_limits(const std::string& machine_file, const std::string& job,
                                    double path_length_mm) {
  const machine::Machine hexapod = test::load_example(machine_file);
  struct Count final : SampleSink {
    long n = 0;
    void write(const Sample&) override { ++n; }
  } count;
  const PlanReport report = plan_program(
      hexapod, std::filesystem::path(PKM_SOURCE_DIR) / "examples" / "jobs" / job, {}, {}, count);
  EXPECT_EQ(count.n, report.samples);
  EXPECT_NEAR(report.path_length_mm, path_length_mm, 0.001) << job;
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_GE(report.joints[i].min, 600.0) << job;
    EXPECT_LE(report.joints[i].max, 1500.0) << job;
    EXPECT_LE(report.joints[i].peak_velocity, 150.0) << job;
    EXPECT_LE(report.joints[i].peak_acceleration, 1500.0) << job;
  }
}

TEST(Paper, TheSphereStaysWithinEveryLegLimit) {
  expect_paper_job_within_limits("hexapod-bit.toml", "sphere.ngc", 4077.779);
}

TEST(Paper, TheHyperboloidStaysWithinEveryLegLimit) {
  expect_paper_job_within_limits("hexapod-bit-200.toml", "hyperboloid.ngc", 2652.331);
}

TEST(SampleFiles, NpyHasItsShapeAndColumns) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  const auto path =
      std::filesystem::temp_directory_path() / ("pkm-" + std::to_string(::getpid()) + ".npy");
  {
    auto file = io::SampleFile::open(path, hektor);
    Sample s;
    s.time_s = 0.5;
    s.line = 7;
    s.pose << 34, -40, 0, 0, 0, 0;
    ASSERT_TRUE(hektor.inverse(geometry::Pose::from_vector(s.pose), s.joints).ok());
    file->write(s);
    file->write(s);
    file->commit();
  }
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::filesystem::remove(path);
  ASSERT_EQ(bytes.substr(0, 6), "\x93NUMPY");
  const std::size_t header_length =
      static_cast<unsigned char>(bytes[8]) + 256u * static_cast<unsigned char>(bytes[9]);
  const std::string header = bytes.substr(10, header_length);
  EXPECT_EQ((10 + header_length) % 64, 0u);
  // One named float64 field per column, one record per sample: NumPy reads the column names.
  EXPECT_EQ(header.substr(0, header.find("   ")),
            "{'descr': [('t', '<f8'), ('line', '<f8'), ('x', '<f8'), ('y', '<f8'), ('z', '<f8'), "
            "('j_left', '<f8'), ('j_right', '<f8')], 'fortran_order': False, 'shape': (");
  EXPECT_NE(header.find("'shape': (                   2,), }"), std::string::npos) << header;
  ASSERT_EQ(bytes.size(), 10 + header_length + 2 * 7 * sizeof(double));
  double row[7];
  std::memcpy(row, bytes.data() + 10 + header_length, sizeof row);
  EXPECT_EQ(row[0], 0.5);
  EXPECT_EQ(row[1], 7.0);
  EXPECT_EQ(row[2], 34.0);
  EXPECT_NEAR(row[5], 52.498, 5e-4);  // columns t line x y z j_left j_right
  EXPECT_EQ(io::sample_columns(hektor),
            (std::vector<std::string>{"t", "line", "x", "y", "z", "j_left", "j_right"}));
}

TEST(SampleFiles, AnUncommittedFileLeavesNothing) {
  const machine::Machine hektor = test::load_example("hektor.toml");
  const auto path =
      std::filesystem::temp_directory_path() / ("pkm-" + std::to_string(::getpid()) + ".csv");
  { auto file = io::SampleFile::open(path, hektor); }
  EXPECT_FALSE(std::filesystem::exists(path));
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
    EXPECT_EQ(
        entry.path().filename().string().find(".pkm-" + std::to_string(::getpid()) + ".csv.tmp"),
        std::string::npos);
  }
}

}  // namespace
}  // namespace pkm::motion
