// pkm view's trace of a joint program without its job (verify/joint_trace.hpp): a hand-made
// program on the wall plotter whose tool path is known in closed form, a block past a joint's
// travel found at its line, words the machine or the dialect does not have refused at their
// column, and a real drawing posted and traced, its lengths held against the job's.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pkm/io/json_reports.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/job_path.hpp"
#include "pkm/verify/joint_trace.hpp"
#include "pkm/view/html_page.hpp"
#include "real_corpus.hpp"
#include "test_support.hpp"

namespace pkm::verify {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path path =
      fs::temp_directory_path() / ("pkm-view-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(path) << text;
  return path;
}

// The example wall plotter (anchors at x 0 and 1500 mm, y 0) with a pen: M3 S1000 puts it down.
machine::Machine wall_plotter_with_pen() {
  std::ifstream in(test::example_machine_path("wall-plotter.toml"));
  std::stringstream text;
  text << in.rdbuf() << "\n[tool]\nz = \"pen\"\n";
  return machine::parse_machine(text.str(), "wall-plotter-pen.toml");
}

// The wall plotter's forward kinematics in closed form: the lower meeting point of the cords.
Eigen::Vector2d cords_meet(double left, double right) {
  const double x = (left * left - right * right + 1500.0 * 1500.0) / 3000.0;
  return {x, -std::sqrt(left * left - x * x)};
}

std::string exact(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.12f", value);
  return text;
}

TEST(JointView, TracesAHandMadeProgramAsItsClosedForm) {
  const machine::Machine plotter = wall_plotter_with_pen();
  // From home (750, -700) straight down to (750, -1000), both cords 1250 mm; the pen down; then
  // the cords to (900, -800)'s lengths, sqrt(1450000) and 1000 mm.
  const double left = std::sqrt(1450000.0);
  const fs::path program = write_file(
      "three.ngc", "G0 X1250 Y1250\nM3 S1000\nG1 X" + exact(left) + " Y1000 F1000\nM5\nM2\n");
  std::vector<TracePoint> ends;
  TraceOptions options;
  options.on_point = [&](const TracePoint& point) {
    if (point.block_end) ends.push_back(point);
  };
  const TraceReport report = trace_joint_program(plotter, program, options);
  EXPECT_EQ(report.blocks, 2);
  EXPECT_EQ(report.pen_downs, 1);
  EXPECT_NEAR(report.rapid_mm, 300.0, 1e-9);  // equal cords: a vertical line
  EXPECT_NEAR(report.travel_mm, 300.0, 1e-9);
  ASSERT_EQ(ends.size(), 3u);  // home and two blocks
  EXPECT_NEAR(ends[0].pose.position_mm.x(), 750.0, 1e-9);
  EXPECT_NEAR(ends[0].pose.position_mm.y(), -700.0, 1e-9);
  EXPECT_NEAR(ends[1].pose.position_mm.y(), -1000.0, 1e-9);
  EXPECT_NEAR(ends[2].pose.position_mm.x(), 900.0, 1e-9);
  EXPECT_NEAR(ends[2].pose.position_mm.y(), -800.0, 1e-9);
  EXPECT_EQ(ends[2].line, 3);
  EXPECT_TRUE(ends[2].drawn);
  EXPECT_FALSE(ends[1].drawn);
  // The drawn stroke: the cords interpolated linearly, a slight curve from (750, -1000) to
  // (900, -800), its length from the closed form at 100,000 points.
  double length = 0.0;
  Eigen::Vector2d last = cords_meet(1250.0, 1250.0);
  for (int k = 1; k <= 100000; ++k) {
    const double u = k / 100000.0;
    const Eigen::Vector2d point =
        cords_meet(1250.0 + u * (left - 1250.0), 1250.0 + u * (1000.0 - 1250.0));
    length += (point - last).norm();
    last = point;
  }
  EXPECT_GT(length, 250.0 + 1e-3);  // not the chord: the joints move linearly, the pen does not
  EXPECT_NEAR(report.drawn_mm, length, 1e-5);  // 16 chords: 1.6e-3 short
  EXPECT_NEAR(report.drawn_min.x(), 750.0, 1e-9);
  EXPECT_NEAR(report.drawn_max.x(), 900.0, 1e-9);
  EXPECT_NEAR(report.drawn_min.y(), -1000.0, 1e-9);
  EXPECT_NEAR(report.drawn_max.y(), -800.0, 1e-9);
  // Each joint's range from home on: home's cords are sqrt(750^2 + 700^2).
  EXPECT_NEAR(report.joints[0].low, std::hypot(750.0, 700.0), 1e-9);
  EXPECT_EQ(report.joints[0].low_line, 0);
  EXPECT_NEAR(report.joints[0].high, 1250.0, 1e-9);
  EXPECT_EQ(report.joints[0].high_line, 1);
  EXPECT_NEAR(report.joints[1].high, 1250.0, 1e-9);
  EXPECT_EQ(report.position.count, 0);
  fs::remove(program);
}

TEST(JointView, FindsABlockPastAJointsTravelAtItsLine) {
  const machine::Machine plotter = wall_plotter_with_pen();
  const fs::path program =
      write_file("past.ngc", "G0 X1250 Y1250\nM3 S1000\nG1 X2200 Y1250 F1000\nG1 X1250\nM2\n");
  const TraceReport report = trace_joint_program(plotter, program, {});
  ASSERT_EQ(report.position.count, 1);
  EXPECT_EQ(report.position.first[0].line, 3);
  EXPECT_EQ(report.position.first[0].joint, 0);
  EXPECT_DOUBLE_EQ(report.position.first[0].value, 2200.0);
  EXPECT_DOUBLE_EQ(report.position.first[0].limit, 2100.0);
  EXPECT_NE(report.position.first[0].detail.find("passes its max"), std::string::npos);
  EXPECT_DOUBLE_EQ(report.joints[0].high, 2200.0);
  EXPECT_EQ(report.joints[0].high_line, 3);
  const nlohmann::json json = io::view_report_json(plotter, program.string(), report);
  EXPECT_DOUBLE_EQ(json["joints"][0]["margin_high"].get<double>(), -100.0);
  fs::remove(program);
}

std::string refusal(const machine::Machine& machine, const std::string& text,
                    const JointDialect& dialect) {
  const fs::path program = write_file("bad.ngc", text);
  TraceOptions options;
  options.dialect = dialect;
  std::string message;
  try {
    trace_joint_program(machine, program, options);
  } catch (const TraceError& error) {
    message = error.what();
  }
  fs::remove(program);
  return message.substr(message.find("bad.ngc"));
}

TEST(JointView, RefusesWordsTheMachineOrTheDialectDoesNotHaveAtTheirColumn) {
  const machine::Machine plotter = wall_plotter_with_pen();
  const JointDialect linuxcnc;
  const JointDialect grbl{"grbl", "XYZ", 80, false};
  // A Cartesian job passed for its joint program: a Z no joint has.
  EXPECT_EQ(refusal(plotter, "G0 X1250 Y1250\nG1 X1200 Z-1 F100\n", linuxcnc),
            "bad.ngc:2:10: Z word: no joint of Wall plotter 1500 is on Z (its joints: left X, "
            "right Y): is this the Cartesian job rather than its joint program?");
  EXPECT_EQ(refusal(plotter, "G0 X1250 Y1250\nG2 X1200 Y1200 R500\n", linuxcnc).substr(0, 13),
            "bad.ngc:2:1: ");
  EXPECT_EQ(refusal(plotter, "G0 X1250\n#1=1250\nG0 Y#1\n", grbl),
            "bad.ngc:2:1: grbl has no #parameters");
  EXPECT_EQ(refusal(plotter, "G0 X1250 Y1250 (" + std::string(80, 'c') + ")\n", grbl),
            "bad.ngc:1:81: a line of 97 characters: grbl reads at most 80");
  // Cords that cannot meet (100 + 100 < 1500 mm): no tool pose, at the block's line.
  EXPECT_NE(
      refusal(plotter, "G0 X1250 Y1250\nG0 X100 Y100\n", linuxcnc).find("bad.ngc:2: no tool pose"),
      std::string::npos);
}

TEST(JointView, DrawsAsLongAsTheRealJobItWasPostedFrom) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  const machine::Machine plotter = wall_plotter_with_pen();
  const fs::path job = test::readable_real_job("plotter/dexarm-inkscape/vitruvianMan.gcode");
  const geometry::Vector6d origin =
      (geometry::Vector6d() << 750.0, -1000.0, 0.0, 0.0, 0.0, 0.0).finished();
  constexpr double kTolerance = 0.01;
  post::PostOptions post_options;
  post_options.tolerance_mm = kTolerance;
  post_options.origin = origin;
  std::string text;
  post::post_program(plotter, job, {}, post_options,
                     [&](const std::string& line) { text += line + "\n"; });
  const fs::path program = write_file("vitruvian.ngc", text);
  const TraceReport trace = trace_joint_program(plotter, program, {});
  // The job's own lengths in the plane, drawn where its Z puts the pen down (from its first Z).
  JobPath path(plotter, job, {}, origin);
  double job_drawn = 0.0, job_length = 0.0, smallest_radius = INFINITY;
  for (long index = 0; const JobPiece* piece = path.piece(index); ++index) {
    job_length += piece->length_mm;
    const bool down =
        piece->pen_follows_from <= 0.0 && plotter.tool().pen_down(piece->segment.at(0.5)[2]);
    if (down) job_drawn += piece->length_mm;
    if (piece->curvature_per_mm > 0.0) {
      smallest_radius = std::min(smallest_radius, 1.0 / piece->curvature_per_mm);
    }
    path.forget_before(index + 1);
  }
  VerifyOptions verify_options;
  verify_options.tolerance_mm = kTolerance;
  verify_options.origin = origin;
  const VerifyReport verified = verify_joint_program(plotter, program, job, verify_options);
  ASSERT_TRUE(verified.passed());
  EXPECT_EQ(trace.pen_downs, verified.job_pen_downs);
  EXPECT_EQ(trace.blocks, verified.blocks);
  EXPECT_NEAR(job_length, verified.traced_mm, 1e-6);
  // Chords of an arc of radius r whose sagitta is at most the tolerance t are shorter than the
  // arc by at most t / (3 r) of its length; lines are traced within t. So the drawing is at most
  // that much shorter than the job, and no longer than it beyond rounding.
  const double shortfall = kTolerance / (3.0 * smallest_radius);  // 1.1 %: radius 0.30 mm
  EXPECT_LE(trace.drawn_mm, job_drawn * (1.0 + 1e-5));
  EXPECT_GE(trace.drawn_mm, job_drawn * (1.0 - shortfall));
  EXPECT_NEAR(trace.travel_mm, job_length - job_drawn, 1e-4 * (job_length - job_drawn));
  EXPECT_EQ(trace.position.count, 0);
  std::printf("vitruvianMan: drawn %.3f of the job's %.3f mm, travel %.3f of %.3f mm, %ld blocks\n",
              trace.drawn_mm, job_drawn, trace.travel_mm, job_length - job_drawn, trace.blocks);
  fs::remove(program);
}

}  // namespace
}  // namespace pkm::verify
