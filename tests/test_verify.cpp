// pkm verify: joint programs held against the job they must trace. Programs that come back over
// their own path (closed contours, retraced lines, stacked helix passes), a block off by 0.05 mm,
// truncated and empty programs, the pen channel; and verify's maximum against an independent
// forward-kinematics check at 1,000 points per block.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/tool_table.hpp"
#include "pkm/motion/segment_builder.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/block_deviation.hpp"
#include "pkm/verify/job_path.hpp"
#include "pkm/verify/joint_path.hpp"
#include "test_support.hpp"

namespace pkm::verify {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(PKM_SOURCE_DIR).parent_path() / "shared" / "gcode" / "real";
const geometry::Vector6d kSheet =
    (geometry::Vector6d() << 600.0, -800.0, 0.0, 0.0, 0.0, 0.0).finished();
// The issue's square: a closed contour (it ends where it starts) on the wall plotter.
const char* const kSquare = "G0 X0 Y0\nG1 F400 X5 Y20\nG1 X15\nG1 X15 Y0\nG1 X0\nM2\n";

fs::path temp_file(const std::string& name) {
  return fs::temp_directory_path() / ("pkm-verify-" + std::to_string(::getpid()) + "-" + name);
}

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path path = temp_file(name);
  std::ofstream(path) << text;
  return path;
}

fs::path write_lines(const std::string& name, const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return write_file(name, text);
}

// Lines first..last (from 1) of a file of the real corpus, or "" when the corpus is absent.
std::string real_lines(const std::string& file, int first, int last) {
  std::ifstream in(kCorpus / file);
  std::string line, text;
  for (int n = 1; n <= last && std::getline(in, line); ++n) {
    if (n >= first) text += line + "\n";
  }
  return text;
}

// The body pkm post writes for `job` (line k of the vector is line k + 1 of the file).
std::vector<std::string> posted(const machine::Machine& machine, const fs::path& job,
                                const geometry::Vector6d& origin, double tolerance_mm) {
  post::PostOptions options;
  options.tolerance_mm = tolerance_mm;
  options.origin = origin;
  std::vector<std::string> lines;
  post::post_program(machine, job, {}, options,
                     [&](const std::string& line) { lines.push_back(line); });
  return lines;
}

VerifyReport verify(const machine::Machine& machine, const fs::path& joints, const fs::path& job,
                    const geometry::Vector6d& origin, double tolerance_mm) {
  VerifyOptions options;
  options.tolerance_mm = tolerance_mm;
  options.origin = origin;
  return verify_joint_program(machine, joints, job, options);
}

// The wall plotter's text without its [controller] table: a servo pen (M280) is no grbl command.
std::string wall_plotter_for_a_servo() {
  std::ifstream in(test::example_machine_path("wall-plotter.toml"));
  std::stringstream file;
  file << in.rdbuf();
  std::string plotter = file.str();
  plotter.replace(plotter.find("[controller]\nkind = \"grbl\"\n"), 27, "");
  return plotter;
}

// The wall plotter with a servo pen: Z below 0 puts it down.
machine::Machine pen_plotter() {
  return machine::parse_machine(
      wall_plotter_for_a_servo() +
          "\n[tool]\nz = \"pen\"\ndown_below = 0.0\ndown = \"M280 P0 S30\"\nup = "
          "\"M280 P0 S90\"\n",
      "wall-plotter-pen.toml");
}

// A G1 block to the joints of pose x y (mm, machine coordinates) at a joint feed of 3000 mm/min.
std::string block_to(const machine::Machine& machine, double x, double y) {
  kinematics::JointVector q;
  EXPECT_TRUE(machine.inverse(geometry::Pose::from_mm_deg(x, y, 0.0), q).ok());
  char text[96];
  std::snprintf(text, sizeof text, "G1 X%.5f Y%.5f", q[0], q[1]);
  return text;
}

// Blocks along the straight line from (x0, y0) to (x1, y1), each `step` mm of it.
void blocks_along(const machine::Machine& machine, double x0, double y0, double x1, double y1,
                  std::vector<std::string>& lines, double step = 1.0) {
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::hypot(x1 - x0, y1 - y0) / step)));
  for (int k = 1; k <= pieces; ++k) {
    const double t = static_cast<double>(k) / pieces;
    lines.push_back(block_to(machine, x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
  }
}

// ---- the independent check: 1,000 points of forward kinematics per block --------------------

// The programmed path as polylines in chunks of a few points, each with its bounding box, so a
// point is compared only with the chunks near it.
struct Chunk {
  std::vector<Eigen::Vector3d> points;  // controlled coordinates
  Eigen::Vector3d low, high;
};

void add_chunks(const std::vector<Eigen::Vector3d>& points, std::vector<Chunk>& chunks) {
  constexpr std::size_t kChunk = 32;
  for (std::size_t first = 0; first + 1 < points.size(); first += kChunk) {
    Chunk chunk;
    const std::size_t last = std::min(points.size() - 1, first + kChunk);
    chunk.points.assign(points.begin() + static_cast<long>(first),
                        points.begin() + static_cast<long>(last) + 1);
    chunk.low = chunk.high = chunk.points.front();
    for (const auto& p : chunk.points) {
      chunk.low = chunk.low.cwiseMin(p);
      chunk.high = chunk.high.cwiseMax(p);
    }
    chunks.push_back(std::move(chunk));
  }
}

// Pieces of the polyline of a move: one for a line; for an arc, chords whose sagitta is at most
// 1e-5 mm (0.1 % of a 0.01 mm tolerance).
int polyline_pieces(const motion::Segment& segment) {
  if (segment.kind != motion::SegmentKind::arc) return 1;
  const double radius =
      std::hypot(segment.start[segment.first_axis] - segment.centre[segment.first_axis],
                 segment.start[segment.second_axis] - segment.centre[segment.second_axis]);
  const double chord = std::sqrt(8.0 * 1e-5 * std::max(radius, 1e-6));
  return std::clamp(static_cast<int>(std::ceil(segment.length() / chord)), 16, 200000);
}

// The chunks, and a grid of 2 mm cells naming the chunks within 0.5 mm of each.
struct ProgrammedPath {
  static constexpr double kCell = 2.0, kMargin = 0.5;
  std::vector<Chunk> chunks;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  std::vector<std::size_t> everywhere;  // chunks over too many cells to list: always compared

  static std::int64_t cell_of(double x) { return static_cast<std::int64_t>(std::floor(x / kCell)); }
  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(y & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(z & 0x1fffff);
  }
  void index(std::size_t c) {
    const Chunk& chunk = chunks[c];
    const Eigen::Vector3d span = (chunk.high - chunk.low).array() + 2.0 * kMargin + kCell;
    if (span.prod() / (kCell * kCell * kCell) > 1e4) {
      everywhere.push_back(c);
      return;
    }
    for (std::int64_t x = cell_of(chunk.low.x() - kMargin); x <= cell_of(chunk.high.x() + kMargin);
         ++x) {
      for (std::int64_t y = cell_of(chunk.low.y() - kMargin);
           y <= cell_of(chunk.high.y() + kMargin); ++y) {
        for (std::int64_t z = cell_of(chunk.low.z() - kMargin);
             z <= cell_of(chunk.high.z() + kMargin); ++z) {
          cells[key(x, y, z)].push_back(c);
        }
      }
    }
  }
};

ProgrammedPath programmed_path(const machine::Machine& machine, const fs::path& job,
                               const geometry::Vector6d& origin) {
  const geometry::Vector6d home = machine.home().as_vector();
  const Eigen::Vector3d mask = position_mask(machine);
  motion::SegmentBuilder builder(home, origin, false);
  ProgrammedPath path;
  gcode::Interpreter(job, motion::starting_at({}, home, origin))
      .run([&](const gcode::Canon& canon) {
        for (const motion::Segment& segment : builder.take(canon)) {
          if (segment.kind == motion::SegmentKind::dwell) continue;
          std::vector<Eigen::Vector3d> points;
          const int count = polyline_pieces(segment);
          for (int k = 0; k <= count; ++k) {
            points.push_back(segment.at(k / double(count)).head<3>().cwiseProduct(mask));
          }
          add_chunks(points, path.chunks);
        }
      });
  for (std::size_t c = 0; c < path.chunks.size(); ++c) path.index(c);
  return path;
}

double distance_to_chunk(const Eigen::Vector3d& p, const Chunk& chunk) {
  double nearest = INFINITY;
  for (std::size_t k = 1; k < chunk.points.size(); ++k) {
    const Eigen::Vector3d a = chunk.points[k - 1], ab = chunk.points[k] - a;
    const double squared = ab.squaredNorm();
    const double t = squared > 0.0 ? std::clamp((p - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
    nearest = std::min(nearest, (a + t * ab - p).norm());
  }
  return nearest;
}

// Exact to the polylines: the chunks of p's cell when one is within the cells' margin, else all.
double distance_to_path(const Eigen::Vector3d& p, const ProgrammedPath& path) {
  double nearest = INFINITY;
  const auto cell = path.cells.find(ProgrammedPath::key(ProgrammedPath::cell_of(p.x()),
                                                        ProgrammedPath::cell_of(p.y()),
                                                        ProgrammedPath::cell_of(p.z())));
  for (const std::size_t c : path.everywhere) {
    nearest = std::min(nearest, distance_to_chunk(p, path.chunks[c]));
  }
  if (cell != path.cells.end()) {
    for (const std::size_t c : cell->second)
      nearest = std::min(nearest, distance_to_chunk(p, path.chunks[c]));
  }
  if (nearest <= ProgrammedPath::kMargin) return nearest;
  for (const Chunk& chunk : path.chunks) nearest = std::min(nearest, distance_to_chunk(p, chunk));
  return nearest;
}

// The largest distance from the whole job of the tool path of `joints`, FK at 1,001 points of
// every block, read back by the interpreter (pen lines skipped).
double independent_max_mm(const machine::Machine& machine, const fs::path& joints,
                          const fs::path& job, const geometry::Vector6d& origin) {
  const ProgrammedPath path = programmed_path(machine, job, origin);
  const Eigen::Vector3d mask = position_mask(machine);
  kinematics::JointVector previous;
  EXPECT_TRUE(machine.inverse(machine.home(), previous).ok());
  gcode::InterpreterOptions options;
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    const machine::JointSpec& joint = machine.joints()[i];
    const auto index = std::string("XYZABCUVW").find(joint.axis_letter);
    options.start_position[index] = joint.to_interface(previous[static_cast<int>(i)]);
  }
  options.event_lines = {machine.tool().down_command, machine.tool().up_command};
  geometry::Pose pose = machine.home();
  double worst = 0.0;
  gcode::Interpreter(joints, options).run([&](const gcode::Canon& canon) {
    if (canon.kind != gcode::CanonKind::traverse && canon.kind != gcode::CanonKind::feed) return;
    kinematics::JointVector q = previous;
    for (std::size_t i = 0; i < machine.joints().size(); ++i) {
      const machine::JointSpec& joint = machine.joints()[i];
      q[static_cast<int>(i)] =
          joint.from_interface(canon.end[std::string("XYZABCUVW").find(joint.axis_letter)]);
    }
    for (int k = 0; k <= 1000; ++k) {
      EXPECT_TRUE(
          machine.kinematics().forward(previous + (k / 1000.0) * (q - previous), pose).ok());
      worst = std::max(worst, distance_to_path(pose.position_mm.cwiseProduct(mask), path));
    }
    previous = q;
  });
  return worst;
}

// ---- revisits ------------------------------------------------------------------------------

TEST(Verify, FollowsTheIssuesSquareAClosedContour) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square.ngc", kSquare);
  const fs::path joints = write_lines("square-joints.ngc", posted(plotter, job, kSheet, 0.01));
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.011);
  EXPECT_TRUE(report.passed());
  EXPECT_TRUE(report.covered);
  // From home (750, -700) to the sheet's corner (600, -800), then the square's 20.616+10+20+15.
  EXPECT_NEAR(report.job_length_mm, std::hypot(150.0, 100.0) + std::hypot(5.0, 20.0) + 45.0, 1e-9);
  EXPECT_NEAR(report.traced_mm, report.job_length_mm, 0.011);
  const double independent = independent_max_mm(plotter, joints, job, kSheet);
  EXPECT_GT(independent, 0.001);  // a deviation worth comparing: post's blocks bow this far
  EXPECT_NEAR(report.max_deviation_mm, independent, 0.01 * independent);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, HoldsTheJointProgramToTheJobsPausesToolChangesAndIo) {
  // post carries them in their place (issue 26: they vanished and verify passed the program);
  // a joint program without one, or with one elsewhere, fails.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file(
      "commands.ngc",
      "G0 X0 Y0\nG1 F400 X5 Y20\nM0\nT2 M6\nG1 X15\nM62 P1\nM101 P2 Q3\nG1 X15 Y0\nM2\n");
  std::vector<std::string> lines = posted(plotter, job, kSheet, 0.01);
  const fs::path joints = write_lines("commands-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.011);
  EXPECT_TRUE(report.passed()) << report.commands_mismatch;
  EXPECT_EQ(report.commands_mismatch, "");
  // M62 P1 left out.
  std::vector<std::string> dropped = lines;
  dropped.erase(std::find(dropped.begin(), dropped.end(), "M62 P1"));
  const fs::path without = write_lines("commands-dropped.ngc", dropped);
  const VerifyReport missing = verify(plotter, without, job, kSheet, 0.011);
  EXPECT_FALSE(missing.passed());
  EXPECT_EQ(missing.commands_mismatch.rfind("job line 6: M62 P1 is not in the joint program", 0),
            0u)
      << missing.commands_mismatch;
  // M101 moved one block later: in order, but not in its place.
  std::vector<std::string> moved = lines;
  const auto user_code = std::find(moved.begin(), moved.end(), "M101 P2 Q3");
  ASSERT_NE(user_code, moved.end());
  const auto next_block = std::find_if(user_code + 1, moved.end(), [](const std::string& line) {
    return line.rfind("G1", 0) == 0 || line.rfind("G93", 0) == 0;
  });
  ASSERT_NE(next_block, moved.end());
  std::rotate(user_code, user_code + 1, next_block + 1);
  const fs::path late = write_lines("commands-late.ngc", moved);
  const VerifyReport misplaced = verify(plotter, late, job, kSheet, 0.011);
  EXPECT_NE(misplaced.commands_mismatch.find("job line 7: M101 P2 Q3 comes at "), std::string::npos)
      << misplaced.commands_mismatch;
  for (const fs::path& path : {job, joints, without, late}) fs::remove(path);
}

TEST(Verify, FollowsClosedContoursOfARealDrawing) {
  // Two closed contours of an Inkscape plotter drawing, with their pen-up and pen-down Z moves.
  const std::string cut = real_lines("plotter/inkscape/mandala_cnc_0001.gcode", 351, 404);
  if (cut.empty()) GTEST_SKIP() << "the real corpus (../shared/gcode/real) is absent";
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("mandala-cut.ngc", "G21\n" + cut + "M2\n");
  const fs::path joints = write_lines("mandala-joints.ngc", posted(plotter, job, kSheet, 0.01));
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.0105);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_TRUE(report.covered);
  // Z (5 mm up, 1 mm down) is the pen's, not a position of this machine: not a 6 mm deviation.
  EXPECT_LT(report.max_deviation_mm, 0.0105);
  const double independent = independent_max_mm(plotter, joints, job, kSheet);
  EXPECT_GT(independent, 0.001);  // a deviation worth comparing: post's blocks bow this far
  EXPECT_NEAR(report.max_deviation_mm, independent, 0.01 * independent);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, FollowsALineRetracedWithThePenUp) {
  // Draw 40 mm along X, lift the pen, travel back along the same line, draw down from there.
  const machine::Machine plotter = pen_plotter();
  const fs::path job = write_file(
      "retrace.ngc", "G0 X0 Y0\nG1 Z-1 F100\nG1 X40 F400\nG0 Z5\nG0 X0\nG1 Z-1\nG1 Y-30\nM2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F3000"};
  blocks_along(plotter, 750, -700, 600, -800, lines, 5.0);
  lines.push_back("M280 P0 S30");
  blocks_along(plotter, 600, -800, 640, -800, lines);
  lines.push_back("M280 P0 S90");
  blocks_along(plotter, 640, -800, 600, -800, lines);
  lines.push_back("M280 P0 S30");
  blocks_along(plotter, 600, -800, 600, -830, lines);
  lines.push_back("M2");
  const fs::path joints = write_lines("retrace-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm << " at line "
                               << report.max_deviation_joint_line;
  EXPECT_TRUE(report.covered);
  EXPECT_EQ(report.pen.count, 0);
  EXPECT_LT(report.max_deviation_mm, 0.005);  // blocks of 1 and 5 mm on a 1 m cable plotter
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, HoldsOneBlockAgainstSeveralShortMoves) {
  // Twenty collinear moves of 0.5 mm (as CAM output splits a line) traced by two blocks of 5 mm.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  std::string text = "G0 X0 Y0\nF400\n";
  for (int k = 1; k <= 20; ++k) text += "G1 X" + std::to_string(0.5 * k) + "\n";
  const fs::path job = write_file("short-moves.ngc", text + "M2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F3000"};
  blocks_along(plotter, 750, -700, 600, -800, lines, 1.0);
  const int first_draw_line = static_cast<int>(lines.size()) + 1;
  blocks_along(plotter, 600, -800, 610, -800, lines, 5.0);
  lines.push_back("M2");
  const fs::path joints = write_lines("short-moves-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_NEAR(report.traced_mm, std::hypot(150.0, 100.0) + 10.0, 1e-4);  // 5 decimals
  // The 5 mm chords in joint space bow away from the line: the most in the second block, which
  // verify holds against the moves of job lines 13 to 22.
  EXPECT_GT(report.max_deviation_mm, 1e-3);
  EXPECT_GE(report.max_deviation_joint_line, first_draw_line);
  EXPECT_GE(report.max_deviation_job_line, 3);
  const double independent = independent_max_mm(plotter, joints, job, kSheet);
  EXPECT_NEAR(report.max_deviation_mm, independent, 0.01 * independent);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, FollowsStackedHelixPassesOverOneCircle) {
  // The same circle of 30 mm twice, 1 mm apart in Z, on a linear delta (which controls Z).
  const machine::Machine delta = test::load_example("linear-delta.toml");
  const fs::path job = write_file("helix.ngc",
                                  "G0 X30 Y0 Z100\nG2 X30 Y0 Z99 I-30 J0 F600\n"
                                  "G2 X30 Y0 Z98 I-30 J0\nG0 Z100\nG0 X0 Y0\nM2\n");
  const fs::path joints =
      write_lines("helix-joints.ngc", posted(delta, job, geometry::Vector6d::Zero(), 0.01));
  const VerifyReport report = verify(delta, joints, job, geometry::Vector6d::Zero(), 0.0105);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_TRUE(report.covered);
  EXPECT_NEAR(report.job_length_mm, 30.0 + 2.0 * std::hypot(60.0 * M_PI, 1.0) + 2.0 + 30.0, 1e-6);
  const double independent = independent_max_mm(delta, joints, job, geometry::Vector6d::Zero());
  EXPECT_GT(independent, 0.001);  // a deviation worth comparing: post's blocks bow this far
  EXPECT_NEAR(report.max_deviation_mm, independent, 0.01 * independent);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, FollowsTheClosedTopCircleOfTheSphereDemo) {
  // The top circle of pkm demo's sphere (5 deg latitude, 17.4 mm across, the tool tilted along
  // the surface normal): twelve arcs ending where they start. Verify once lost its place here,
  // measuring the circle against its own far side: 16.09 mm.
  std::ifstream in(fs::path(PKM_SOURCE_DIR) / "examples" / "jobs" / "sphere.ngc");
  std::string line, header, circle;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n <= 5) header += line + "\n";
    if (n >= 150 && n <= 163) circle += line + "\n";  // the step up to it, the arcs, the retract
  }
  // Its first line, the step up from the circle below, becomes a rapid from home to the circle.
  const std::size_t step_end = circle.find('\n');
  ASSERT_EQ(circle.substr(0, 16), "G1 X8.7156 Y0.00");
  const std::string rapid = "G0" + circle.substr(2, step_end - 2) + "\nF1000\n";
  const fs::path job =
      write_file("top-circle.ngc", header + rapid + circle.substr(step_end + 1) + "M2\n");
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const fs::path joints =
      write_lines("top-joints.ngc", posted(hexapod, job, geometry::Vector6d::Zero(), 0.01));
  const VerifyReport report = verify(hexapod, joints, job, geometry::Vector6d::Zero(), 0.01);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_NEAR(report.job_length_mm, report.traced_mm, 1e-3);
  const double independent = independent_max_mm(hexapod, joints, job, geometry::Vector6d::Zero());
  EXPECT_GT(independent, 1e-4);
  EXPECT_NEAR(report.max_deviation_mm, independent, 0.01 * independent);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, PassesTheWholeSphereDemo) {
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  const fs::path sphere = fs::path(PKM_SOURCE_DIR) / "examples" / "jobs" / "sphere.ngc";
  const fs::path joints =
      write_lines("sphere-joints.ngc", posted(hexapod, sphere, geometry::Vector6d::Zero(), 0.01));
  const VerifyReport report = verify(hexapod, joints, sphere, geometry::Vector6d::Zero(), 0.01);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_NEAR(report.job_length_mm, 4077.779, 1e-3);  // as pkm demo plans it
  EXPECT_NEAR(report.traced_mm, report.job_length_mm, 1e-3);
  fs::remove(joints);
}

TEST(Verify, PlacesTheJobWithItsToolTable) {
  // G43 lifts the path by tool 1's length (20 mm): verified with the table, 20 mm and more off
  // without it.
  const machine::Machine delta = test::load_example("linear-delta.toml");
  const fs::path table = write_file("tools.tbl", "T1 P1 Z20.0 D6.0 ;end mill\n");
  const fs::path job =
      write_file("tool-job.ngc", "T1 M6\nG43 H1\nG0 X0 Y0 Z80\nG1 X30 F600\nG1 Y30\nG0 Z100\nM2\n");
  gcode::InterpreterOptions with_table;
  with_table.tool_table = gcode::read_tool_table(table);
  post::PostOptions post_options;
  std::vector<std::string> lines;
  post::post_program(delta, job, with_table, post_options,
                     [&](const std::string& line) { lines.push_back(line); });
  const fs::path joints = write_lines("tool-joints.ngc", lines);
  VerifyOptions options;
  options.tolerance_mm = 0.0105;
  options.job_options = with_table;
  const VerifyReport report = verify_joint_program(delta, joints, job, options);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  options.job_options = {};
  const VerifyReport without = verify_joint_program(delta, joints, job, options);
  EXPECT_FALSE(without.passed());
  EXPECT_GT(without.max_deviation_mm, 19.9);
  for (const fs::path& file : {table, job, joints}) fs::remove(file);
}

// ---- what verify must catch ------------------------------------------------------------------

TEST(Verify, CatchesOneBlockOffByFiftyMicronsAtItsLine) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-off.ngc", kSquare);
  std::vector<std::string> lines = posted(plotter, job, kSheet, 0.01);
  // The block ending inside the bottom edge (y = -800, x from 615 to 600, job line 5; post
  // splits it in two): moved 0.05 mm off the edge.
  int off_line = 0;
  for (std::size_t k = 0; k < lines.size() && off_line == 0; ++k) {
    double left = 0.0, right = 0.0;
    const std::size_t g1 = lines[k].find("G1 X");
    if (g1 == std::string::npos ||
        std::sscanf(lines[k].c_str() + g1, "G1 X%lf Y%lf", &left, &right) != 2) {
      continue;
    }
    kinematics::JointVector q(2);
    q << left, right;
    geometry::Pose pose = geometry::Pose::from_mm_deg(610, -780, 0);
    ASSERT_TRUE(plotter.forward(q, pose).ok());
    const Eigen::Vector3d p = pose.position_mm;
    if (std::abs(p.y() + 800.0) > 1e-3 || p.x() < 601.0 || p.x() > 614.0) continue;
    const std::string feed = lines[k].substr(lines[k].find(" F"));
    lines[k] = block_to(plotter, p.x(), p.y() + 0.05) + feed;
    off_line = static_cast<int>(k) + 1;
  }
  ASSERT_GT(off_line, 0);
  const fs::path joints = write_lines("square-off-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.011);
  EXPECT_FALSE(report.passed());
  EXPECT_TRUE(report.covered);
  ASSERT_GE(report.deviation.count, 1);
  EXPECT_EQ(report.deviation.first.front().line, off_line);
  EXPECT_EQ(report.deviation.first.front().job_line, 5);
  EXPECT_EQ(report.max_deviation_joint_line, off_line);
  EXPECT_NEAR(report.max_deviation_mm, 0.05, 0.002);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, ATruncatedProgramFailsWhereCoverageStops) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-cut.ngc", kSquare);
  std::vector<std::string> lines = posted(plotter, job, kSheet, 0.01);
  // Keep the travel to the sheet and the two blocks of the first side (job line 2), to its
  // corner: the tool standing there is within the tolerance of the next side's first 0.011 mm
  // too, so the job is traced into line 3 (200.904 mm), no further.
  std::vector<std::string> cut;
  int g1 = 0;
  for (const std::string& line : lines) {
    if (line.find("G1") != std::string::npos && ++g1 > 2) break;
    cut.push_back(line);
  }
  cut.push_back("M2");
  const fs::path joints = write_lines("square-cut-joints.ngc", cut);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.011);
  EXPECT_FALSE(report.covered);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.coverage_stopped_job_line, 3);
  EXPECT_EQ(report.coverage_stopped_joint_line, static_cast<int>(cut.size()) - 1);
  const double corner_mm = std::hypot(150.0, 100.0) + std::hypot(5.0, 20.0);
  EXPECT_GT(report.traced_mm, corner_mm);
  EXPECT_LE(report.traced_mm, corner_mm + 0.011);
  EXPECT_EQ(report.deviation.count, 0);  // what it does trace, it traces well
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, AnEmptyProgramFailsAtTheJobsFirstMove) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-empty.ngc", kSquare);
  const fs::path joints = write_file("empty-joints.ngc", "G21 G90\nM2\n");
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_EQ(report.blocks, 0);
  EXPECT_FALSE(report.covered);
  EXPECT_EQ(report.coverage_stopped_job_line, 1);
  EXPECT_EQ(report.traced_mm, 0.0);
  fs::remove(job);
  fs::remove(joints);
}

// A block a hundred tolerances or more off the job fails whatever its exact peak: it is held to
// the estimates of the intervals it leaves unrefined (a bound, above every sample), without the
// halvings that would otherwise chase the peak of a corrupted program's metres-long moves.
TEST(Verify, HoldsABlockFarOffTheJobToABoundWithoutRefiningIt) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  JobPiece line;  // the job: a 600 mm line across the sheet
  const Eigen::Vector3d left = kSheet.head<3>() - Eigen::Vector3d(300.0, 0.0, 0.0);
  line.segment.start.head<3>() = left;
  line.segment.end.head<3>() = left + Eigen::Vector3d(600.0, 0.0, 0.0);
  line.segment.line = 7;
  line.mask = position_mask(plotter);
  line.length_mm = 600.0;
  const std::vector<PieceRange> stretch = {{&line, 0.0, 1.0}};
  // One joint-linear block from end to end: the cables' lengths change linearly, the pen bows off
  // the line in the middle, its peak between the grid's samples.
  geometry::Pose start = geometry::Pose::from_mm_deg(left.x(), left.y(), 0.0);
  geometry::Pose end = geometry::Pose::from_mm_deg(left.x() + 600.0, left.y(), 0.0);
  kinematics::JointVector q0, q1;
  ASSERT_TRUE(plotter.inverse(start, q0).ok());
  ASSERT_TRUE(plotter.inverse(end, q1).ok());
  BlockDeviation coarse, refined;
  BlockMeasure measure(plotter);
  ASSERT_TRUE(measure.sample_grid(q0, q1, start));
  ASSERT_TRUE(measure.measure(stretch, 0.01, coarse));  // thousands of tolerances off
  ASSERT_TRUE(measure.sample_grid(q0, q1, start));
  ASSERT_TRUE(measure.measure(stretch, 1000.0, refined));  // within: refined to its peak
  EXPECT_EQ(coarse.halvings, 0);
  EXPECT_GT(refined.halvings, 0);
  EXPECT_GT(refined.max_mm, 10.0) << "the bow is the test's premise";
  EXPECT_GE(coarse.max_mm, refined.max_mm);
  EXPECT_LT(coarse.max_mm, 1.5 * refined.max_mm);  // an estimate, not a wild one
  EXPECT_EQ(coarse.job_line, 7);
}

// A joint program's repeat counts ask for work as a job's do: the job's loop bounds hold for it.
TEST(Verify, HoldsTheJointProgramToTheJobsLoopBounds) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-bounds.ngc", kSquare);
  const fs::path joints =
      write_file("repeat-joints.ngc", "G21 G90\no1 repeat [50]\nG4 P0\no1 endrepeat\nM2\n");
  VerifyOptions options;
  options.origin = kSheet;
  options.job_options.max_loop_iterations = 10;
  try {
    (void)verify_joint_program(plotter, joints, job, options);
    ADD_FAILURE() << "50 repeats passed a bound of 10";
  } catch (const gcode::GcodeError& error) {
    EXPECT_EQ(error.line(), 2);
    EXPECT_NE(std::string(error.what()).find("more than the 10 iterations one loop may make"),
              std::string::npos)
        << error.what();
  }
  options.job_options.max_loop_iterations = 50;
  EXPECT_FALSE(verify_joint_program(plotter, joints, job, options).covered);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, ReportsAProgramThatWandersOffAtBothLines) {
  // The same draw as the retrace test, but the program goes 5 mm off the line at X20.
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("wander.ngc", "G0 X0 Y0\nG1 X40 F400\nM2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F3000"};
  blocks_along(plotter, 750, -700, 600, -800, lines, 5.0);
  blocks_along(plotter, 600, -800, 620, -800, lines);
  const int wander_line = static_cast<int>(lines.size()) + 1;
  lines.push_back(block_to(plotter, 621, -795));
  blocks_along(plotter, 621, -795, 640, -800, lines);
  lines.push_back("M2");
  const fs::path joints = write_lines("wander-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_TRUE(report.covered);
  ASSERT_GE(report.deviation.count, 1);
  EXPECT_EQ(report.deviation.first.front().line, wander_line);
  EXPECT_EQ(report.deviation.first.front().job_line, 2);
  EXPECT_NEAR(report.max_deviation_mm, 5.0, 0.01);
  EXPECT_LE(report.deviation.first.size(), ViolationSummary::kFirst);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, FlagsACoarseJointProgramAtItsLine) {
  // Each move of the job as one joint-linear block: the arc (job line 3) becomes block line 3.
  const machine::Machine hektor = test::load_example("hektor.toml");
  const fs::path job = write_file(
      "coarse-job.ngc", "G21 G90 F600\nG1 X20 Y-60\nG2 X80 Y-60 I30 J0\nG1 X50 Y-20\nM2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F600"};
  for (const auto& [x, y] :
       std::vector<std::pair<double, double>>{{20, -60}, {80, -60}, {50, -20}}) {
    kinematics::JointVector q;
    ASSERT_TRUE(hektor.inverse(geometry::Pose::from_mm_deg(x, y, 0), q).ok());
    lines.push_back("G1 A" + std::to_string(q[0]) + " B" + std::to_string(q[1]));
  }
  lines.push_back("M2");
  const fs::path joints = write_lines("coarse-joints.ngc", lines);
  const VerifyReport report = verify(hektor, joints, job, geometry::Vector6d::Zero(), 0.01);
  EXPECT_EQ(report.blocks, 3);
  EXPECT_GT(report.max_deviation_mm, 10.0);  // the chord of a 30 mm arc in joint space
  EXPECT_EQ(report.max_deviation_joint_line, 3);
  EXPECT_EQ(report.max_deviation_job_line, 3);
  EXPECT_TRUE(report.covered);
  EXPECT_EQ(report.position.count + report.velocity.count, 0);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, ReadsG94FeedsAsLinuxCncDoesInDegreesForRotaryJoints) {
  // The 5-axis machine (identity X Y Z, A and C passed through, 30 deg/s) checked against its own
  // job. G94 F is the X Y Z length per minute when the block has one: X10 at F600 takes 1 s, so C
  // turns at 90 deg/s. A C-only block's F is deg/min: C90 at F6000 is 100 deg/s. Limits and
  // speeds in deg/s, as the machine file has them.
  const machine::Machine trt = test::load_example("linuxcnc-xyzac-trt.toml");
  const fs::path job =
      write_file("rotary.ngc", "G21 G90 G94\nG1 F600 X10 C90\nG1 F6000 C180\nM2\n");
  const VerifyReport report = verify(trt, job, job, geometry::Vector6d::Zero(), 0.01);
  ASSERT_EQ(report.velocity.count, 2);
  EXPECT_EQ(report.velocity.first[0].line, 2);
  EXPECT_EQ(report.velocity.first[0].joint, 4);
  EXPECT_NEAR(report.velocity.first[0].value, 90.0, 1e-9);
  EXPECT_NEAR(report.velocity.first[0].limit, 30.0, 1e-9);
  EXPECT_EQ(report.velocity.first[1].line, 3);
  EXPECT_NEAR(report.velocity.first[1].value, 100.0, 1e-9);
  EXPECT_EQ(report.deviation.count, 0);
  fs::remove(job);
}

TEST(Verify, TellsItsProgressLineByLineInOrder) {
  // The hook of the progress bar: each line of the joint program that makes a command, once, in
  // order, to its last (M2).
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-progress.ngc", kSquare);
  const std::vector<std::string> body = posted(plotter, job, kSheet, 0.01);
  const fs::path joints = write_lines("square-progress-joints.ngc", body);
  VerifyOptions options;
  options.origin = kSheet;
  std::vector<int> lines;
  options.on_line = [&](int line) { lines.push_back(line); };
  EXPECT_TRUE(verify_joint_program(plotter, joints, job, options).passed());
  ASSERT_GT(lines.size(), 5u);
  EXPECT_TRUE(std::is_sorted(lines.begin(), lines.end(), std::less_equal<int>()) &&
              std::adjacent_find(lines.begin(), lines.end()) == lines.end());
  EXPECT_EQ(body.back(), "M2");
  EXPECT_EQ(lines.back(), static_cast<int>(body.size()));
  fs::remove(job);
  fs::remove(joints);
}

// ---- the pen channel -----------------------------------------------------------------------

TEST(Verify, CatchesThePenDownWhereTheJobLiftsIt) {
  // Pen commands swapped: the draw is made with the pen up, the travel back with it down.
  const machine::Machine plotter = pen_plotter();
  const fs::path job =
      write_file("pen.ngc", "G0 X0 Y0\nG1 Z-1 F100\nG1 X40 F400\nG0 Z5\nG0 X0\nM2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F3000"};
  blocks_along(plotter, 750, -700, 600, -800, lines, 5.0);
  const int draw_line = static_cast<int>(lines.size()) + 1;
  blocks_along(plotter, 600, -800, 640, -800, lines);
  lines.push_back("M280 P0 S30");
  const int travel_line = static_cast<int>(lines.size()) + 1;
  blocks_along(plotter, 640, -800, 600, -800, lines);
  lines.push_back("M280 P0 S90");
  lines.push_back("M2");
  const fs::path joints = write_lines("pen-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_EQ(report.deviation.count, 0);
  EXPECT_TRUE(report.covered);
  ASSERT_EQ(report.pen.count, 2);  // one stretch each way
  EXPECT_EQ(report.pen.first[0].line, draw_line);
  EXPECT_EQ(report.pen.first[0].job_line, 3);
  EXPECT_EQ(report.pen.first[0].detail, "pen up where the job draws");
  EXPECT_NEAR(report.pen.first[0].value, 40.0, 1e-6);
  EXPECT_EQ(report.pen.first[1].line, travel_line);
  EXPECT_EQ(report.pen.first[1].job_line, 5);
  EXPECT_EQ(report.pen.first[1].detail, "pen down where the job lifts it");
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, CatchesAMissingDot) {
  // A dot: the pen goes down and up without moving. No stretch shows it; the count does.
  const machine::Machine plotter = pen_plotter();
  const fs::path job = write_file(
      "dot.ngc", "G0 X0 Y0\nG1 Z-1 F100\nG0 Z5\nG0 X10\nG1 Z-1\nG1 X20 F400\nG0 Z5\nM2\n");
  std::vector<std::string> lines = {"G21 G90 G94 F3000"};
  blocks_along(plotter, 750, -700, 600, -800, lines, 5.0);
  blocks_along(plotter, 600, -800, 610, -800, lines);  // no dot at the start
  lines.push_back("M280 P0 S30");
  blocks_along(plotter, 610, -800, 620, -800, lines);
  lines.push_back("M280 P0 S90");
  lines.push_back("M2");
  const fs::path joints = write_lines("dot-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_EQ(report.deviation.count, 0);
  EXPECT_EQ(report.pen.count, 0);
  EXPECT_FALSE(report.passed());
  EXPECT_EQ(report.pen_downs, 1);
  EXPECT_EQ(report.job_pen_downs, 2);
  EXPECT_EQ(report.first_job_pen_down_line, 2);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, PassesPostsPenCommandsInEveryDialect) {
  // The closed contours of the real drawing on the servo-pen plotter: post lifts and lowers the
  // pen where the job's Z crosses 0, and verify holds every stretch against the job's pen.
  const std::string cut = real_lines("plotter/inkscape/mandala_cnc_0001.gcode", 351, 404);
  if (cut.empty()) GTEST_SKIP() << "the real corpus (../shared/gcode/real) is absent";
  const machine::Machine plotter = test::load_example("pen-plotter.toml");
  const fs::path job = write_file("pen-cut.ngc", "G21\n" + cut + "M2\n");
  for (const post::Dialect dialect : {post::Dialect::linuxcnc, post::Dialect::mach3,
                                      post::Dialect::grbl, post::Dialect::grblhal}) {
    post::PostOptions options;
    options.origin = kSheet;
    options.dialect = dialect;
    std::vector<std::string> lines;
    post::post_program(plotter, job, {}, options,
                       [&](const std::string& line) { lines.push_back(line); });
    const fs::path joints = write_lines("pen-cut-joints.ngc", lines);
    const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
    EXPECT_TRUE(report.passed()) << static_cast<int>(dialect) << ": " << report.max_deviation_mm;
    EXPECT_EQ(report.pen.count, 0);
    EXPECT_EQ(std::count(lines.begin(), lines.end(), "M280 P0 S30"), 2);  // two contours
    fs::remove(joints);
  }
  fs::remove(job);
}

TEST(Verify, AgreesWithPostOnAPenLiftedFromHomesZ) {
  // down_below = 10 puts home's Z 0 on the drawing side. The job travels at home's Z, then ramps
  // up to Z 20 over 20 mm of X (crossing Z 10 half way), draws 20 mm at Z 2 and lifts. post
  // keeps the pen up over the travel and the whole ramp (the job lifting its pen first) and
  // lowers it once; verify expects just that: nothing on the ramp, one pen-down each.
  const machine::Machine plotter =
      machine::parse_machine(wall_plotter_for_a_servo() +
                                 "\n[tool]\nz = \"pen\"\ndown_below = 10.0\ndown = "
                                 "\"M280 P0 S30\"\nup = \"M280 P0 S90\"\n",
                             "wall-plotter-pen-10.toml");
  const fs::path job =
      write_file("lift.ngc", "G0 X0 Y0\nG1 X20 Z20 F600\nG1 Z2\nG1 X40\nG0 Z20\nG0 X0\nM2\n");
  post::PostOptions options;
  options.origin = kSheet;
  std::vector<std::string> lines;
  post::post_program(plotter, job, {}, options,
                     [&](const std::string& line) { lines.push_back(line); });
  EXPECT_EQ(std::count(lines.begin(), lines.end(), "M280 P0 S30"), 1);
  const fs::path joints = write_lines("lift-joints.ngc", lines);
  const VerifyReport report = verify(plotter, joints, job, kSheet, 0.01);
  EXPECT_TRUE(report.passed()) << report.max_deviation_mm;
  EXPECT_EQ(report.pen.count, 0);
  EXPECT_EQ(report.pen_downs, 1);
  EXPECT_EQ(report.job_pen_downs, 1);
  EXPECT_EQ(report.first_job_pen_down_line, 3);
  fs::remove(job);
  fs::remove(joints);
}

TEST(Verify, PenLinesReachTheReaderAsEvents) {
  const fs::path program = write_file("events.ngc", "G0 X1\n  M280 P0 S30 \nG1 X2 F10\nM2\n");
  const auto read = [&](const gcode::InterpreterOptions& options) {
    std::vector<std::string> seen;
    gcode::Interpreter interpreter(program, options);
    interpreter.run([&](const gcode::Canon& canon) {
      if (canon.kind == gcode::CanonKind::event || canon.kind == gcode::CanonKind::spindle_speed) {
        seen.push_back(std::to_string(canon.line) + ":" + canon.text + ":" +
                       std::to_string(canon.value));
      }
    });
    seen.push_back(std::to_string(interpreter.warnings().size()) + " warnings");
    return seen;
  };
  gcode::InterpreterOptions options;
  options.event_lines = {"M280 P0 S30"};
  EXPECT_EQ(read(options), (std::vector<std::string>{"2:M280 P0 S30:0.000000", "0 warnings"}));
  // Without the option the line is what rs274 makes of it: an M code it does not know, refused.
  try {
    read({});
    ADD_FAILURE() << "M280 without the option was not refused";
  } catch (const gcode::GcodeError& error) {
    EXPECT_EQ(error.line(), 2);
    EXPECT_EQ(error.column(), 3);
  }
  fs::remove(program);
}

// ---- the tolerance -------------------------------------------------------------------------

TEST(Verify, ReadsTheToleranceFromPostsHeader) {
  const fs::path with = write_file(
      "header.ngc",
      "(joint-space program by pkmkit for X)\n(from job.ngc, dialect linuxcnc)\n"
      "(tolerance     0.012500 mm; verified maximum deviation     0.009999 mm,         26 blocks)\n"
      "M2\n");
  EXPECT_EQ(tolerance_in_header(with), 0.0125);
  const fs::path without = write_file("no-header.ngc", "G21\nM2\n");
  EXPECT_EQ(tolerance_in_header(without), std::nullopt);
  const fs::path bad = write_file("nan-header.ngc", "(tolerance nan mm)\nM2\n");
  EXPECT_THROW(tolerance_in_header(bad), VerifyError);
  fs::remove(with);
  fs::remove(without);
  fs::remove(bad);
}

TEST(Verify, RefusesAToleranceThatIsNotAPositiveNumber) {
  const machine::Machine plotter = test::load_example("wall-plotter.toml");
  const fs::path job = write_file("square-nan.ngc", kSquare);
  for (const double tolerance : {std::nan(""), 0.0, -1.0, HUGE_VAL}) {
    EXPECT_THROW(verify(plotter, job, job, kSheet, tolerance), VerifyError) << tolerance;
  }
  fs::remove(job);
}

}  // namespace
}  // namespace pkm::verify
