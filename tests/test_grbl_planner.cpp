// The grbl planner model (controller/grbl_planner.hpp) against hand-computed times, and post with
// a [controller] table on the wall plotter.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pkm/controller/grbl_planner.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/program_header.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

using controller::GrblPrediction;
using controller::GrblSetup;
using controller::GrblTimeModel;

// Two axes of 80 steps/mm, 100 mm/s and 1000 mm/s^2, grbl's defaults otherwise.
GrblSetup plotter_setup() {
  GrblSetup setup;
  setup.axes = {{'X', 80.0, 100.0, 1000.0}, {'Y', 80.0, 100.0, 1000.0}};
  return setup;
}

GrblPrediction predict(const GrblSetup& setup, const std::string& program) {
  GrblTimeModel model(setup);
  std::istringstream in(program);
  for (std::string line; std::getline(in, line);) model.add_line(line);
  return model.finish();
}

TEST(GrblPlanner, TrapezoidOfOneLongMove) {
  // 300 mm at 6000 mm/min = 100 mm/s, a = 1000: 0.1 s up (5 mm), 290 mm at 100 mm/s, 0.1 s down.
  EXPECT_NEAR(controller::trapezoid_time_s(300.0, 1000.0, 0.0, 100.0, 0.0), 3.1, 1e-12);
  // Too short to reach the feed: a triangle, 2 sqrt(L / a).
  EXPECT_NEAR(controller::trapezoid_time_s(4.0, 1000.0, 0.0, 100.0, 0.0), 2.0 * std::sqrt(0.004),
              1e-12);
  const GrblPrediction p = predict(plotter_setup(), "G21 G90 G94\nG1 X300 F6000\n");
  EXPECT_EQ(p.blocks, 1);
  // The lines arrive at 115200 baud: "G21 G90 G94\n" and "G1 X300 F6000\n" are 26 bytes.
  EXPECT_NEAR(p.motion_start_s, 26 * 10.0 / 115200.0, 1e-9);
  EXPECT_NEAR(p.time_s - p.motion_start_s, 3.1, 1e-9);
  EXPECT_NEAR(p.unlimited_time_s, 3.1, 1e-9);
}

TEST(GrblPlanner, ShortCollinearBlocksAreCappedByTheLookAhead) {
  // 500 blocks of 0.1 mm on one line at F6000: the newest of the 15 blocks grbl holds ends at
  // rest, so the speed settles near sqrt(2 a 14.5 L) = 53.9 mm/s, not 100 mm/s.
  std::string program = "G21 G90 G94\n";
  for (int i = 1; i <= 500; ++i) program += "G1 X" + std::to_string(i * 0.1) + " F6000\n";
  const GrblPrediction p = predict(plotter_setup(), program);
  EXPECT_EQ(p.blocks, 500);
  const double run_s = p.time_s - p.motion_start_s;
  // 50 mm at 14 to 15 blocks' braking distance: between sqrt(2 a 14 L) and sqrt(2 a 15 L), plus
  // the ramp up and down.
  EXPECT_GT(run_s, 50.0 / std::sqrt(2.0 * 1000.0 * 15 * 0.1));
  EXPECT_LT(run_s, 50.0 / std::sqrt(2.0 * 1000.0 * 14 * 0.1) + 0.1);
  // With every block known, only the ramps: 0.1 s up, 0.4 s at 100 mm/s, 0.1 s down.
  EXPECT_NEAR(p.unlimited_time_s, 0.6, 1e-6);
  // grblHAL's 35 blocks would allow 82 mm/s, but 19- and 20-byte lines at 115200 baud arrive
  // at 1.65 ms each, 0.1 mm: the line caps it at 58 to 61 mm/s.
  GrblSetup hal = plotter_setup();
  hal.settings.planner_blocks = 35;
  const double hal_s = predict(hal, program).time_s;
  EXPECT_LT(hal_s, p.time_s - 0.05);
  EXPECT_GT(hal_s, 500 * 19 * 10.0 / 115200.0);
}

TEST(GrblPlanner, CornerPassedAtTheJunctionDeviationSpeed) {
  // X 100 then Y 100: a right angle. sin(theta/2) = sqrt(0.5); the bisector's acceleration,
  // limited per axis along (-1, 1)/sqrt 2, is 1000 sqrt 2; v^2 = a d s / (1 - s).
  const double s = std::sqrt(0.5);
  const double v = std::sqrt(1000.0 * std::sqrt(2.0) * 0.01 * s / (1.0 - s));
  const double expected = controller::trapezoid_time_s(100.0, 1000.0, 0.0, 100.0, v) +
                          controller::trapezoid_time_s(100.0, 1000.0, v, 100.0, 0.0);
  const GrblPrediction p = predict(plotter_setup(), "G1 X100 F6000\nG1 Y100\n");
  EXPECT_NEAR(p.time_s - p.motion_start_s, expected, 1e-9);
  EXPECT_NEAR(v, 5.843, 0.001);  // mm/s: the corner nearly stops
}

TEST(GrblPlanner, DiagonalAtEachAxisLimitAndInverseTime) {
  // X and Y together: along (1,1)/sqrt 2 each axis may take 100 mm/s, so the move 141 mm/s.
  GrblSetup setup = plotter_setup();
  const GrblPrediction rapid = predict(setup, "G0 X300 Y300\n");
  const double length = 300.0 * std::sqrt(2.0);
  EXPECT_NEAR(rapid.time_s - rapid.motion_start_s,
              controller::trapezoid_time_s(length, 1000.0 * std::sqrt(2.0), 0.0,
                                           100.0 * std::sqrt(2.0), 0.0),
              1e-9);
  // G93 F12: the block takes 1/12 min = 5 s, at most: a 200 mm move at 40 mm/s.
  const GrblPrediction timed = predict(setup, "G93 G1 X200 F12\n");
  EXPECT_NEAR(timed.time_s - timed.motion_start_s,
              controller::trapezoid_time_s(200.0, 1000.0, 0.0, 40.0, 0.0), 1e-9);
}

TEST(GrblPlanner, StepsQuantiseTheBlocks) {
  // At 80 steps/mm, X0.004 is no step: no block. X0.01 is one step, 0.0125 mm.
  EXPECT_EQ(predict(plotter_setup(), "G1 X0.004 F600\n").blocks, 0);
  const GrblPrediction p = predict(plotter_setup(), "G1 X0.01 F600\n");
  EXPECT_EQ(p.blocks, 1);
  EXPECT_NEAR(p.time_s - p.motion_start_s,
              controller::trapezoid_time_s(0.0125, 1000.0, 0.0, 10.0, 0.0), 1e-12);
}

TEST(GrblPlanner, SpindleAndDwellWaitForTheMotion) {
  // M3 waits for the buffer to empty; G4 P0.5 adds half a second after the stop.
  const GrblPrediction p = predict(plotter_setup(), "G1 X100 F6000\nM3 S100\nG4 P0.5\nG1 X200\n");
  EXPECT_NEAR(p.time_s - p.motion_start_s, 2.0 * 1.1 + 0.5, 1e-3);
}

TEST(GrblPlanner, TheSerialLineCapsTinyBlocks) {
  // At 9600 baud a 19-byte line takes 19.8 ms: blocks of 0.05 mm arrive at 2.5 mm/s at most.
  GrblSetup setup = plotter_setup();
  setup.settings.baud = 9600;
  std::string program;
  for (int i = 1; i <= 200; ++i) {
    char line[40];
    std::snprintf(line, sizeof line, "G1 X%08.3f F6000", i * 0.05);  // 19 characters
    program += std::string(line) + "\n";
  }
  const GrblPrediction p = predict(setup, program);
  EXPECT_NEAR(p.time_s, 200 * 19 * 10.0 / 9600.0, 0.03);
}

TEST(GrblPlanner, ImpossibleSettingsAndALineTooLongAreRefused) {
  GrblSetup setup = plotter_setup();
  setup.settings.baud = 0;
  EXPECT_THROW(GrblTimeModel{setup}, std::invalid_argument);
  setup = plotter_setup();
  setup.axes[1].steps_per_unit = 0.0;
  EXPECT_THROW(GrblTimeModel{setup}, std::invalid_argument);
  GrblTimeModel model(plotter_setup());
  EXPECT_THROW(model.add_line(std::string(130, ' ') + "G1 X1 F100"), std::invalid_argument);
  EXPECT_THROW(model.add_line("G1 X F100"), std::invalid_argument);
}

// The wall plotter with a grbl board: 80 steps/mm on both cords; without a controller, the same
// machine with its [controller] table taken away.
machine::Machine plotter_on_grbl(bool with_controller, int planner_blocks = 16) {
  machine::Machine plotter = test::load_example("wall-plotter.toml");
  plotter.set_steps_per_unit(0, 80.0);
  plotter.set_steps_per_unit(1, 80.0);
  machine::ControllerSettings settings;
  settings.planner_blocks = planner_blocks;
  plotter.set_controller(with_controller ? std::optional<machine::ControllerSettings>(settings)
                                         : std::nullopt);
  return plotter;
}

post::PostReport post_text(const machine::Machine& machine, const std::string& job,
                           double tolerance_mm) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("grbl_planner_" + std::to_string(getpid()) + ".ngc");
  {
    std::ofstream out(path);
    out << job;
  }
  post::PostOptions options;
  options.dialect = post::Dialect::grbl;
  options.tolerance_mm = tolerance_mm;
  options.origin[0] = 700.0;
  options.origin[1] = -900.0;
  const post::PostReport report =
      post::post_program(machine, path, {}, options, [](const std::string&) {});
  std::filesystem::remove(path);
  return report;
}

TEST(GrblPlanner, PostWithAControllerPredictsTheTime) {
  // A circle of 50 mm radius at F3000 from home and back: without the table no prediction; with
  // it the prediction, from home (grbl zeroed there), above the circle's 6.28 s at 50 mm/s and
  // within the rapids' few seconds of it.
  const std::string job = "G21 G90\nG0 X50 Y0\nG1 F3000\nG2 X50 Y0 I-50 J0\nG0 X0 Y0\nM2\n";
  EXPECT_FALSE(post_text(plotter_on_grbl(false), job, 0.01).controller);
  const post::PostReport report = post_text(plotter_on_grbl(true), job, 0.01);
  ASSERT_TRUE(report.controller);
  const GrblPrediction& p = *report.controller;
  EXPECT_EQ(p.blocks, report.blocks);
  const double circle_s = 2.0 * M_PI * 50.0 / 50.0;
  EXPECT_GT(p.time_s, circle_s);
  EXPECT_LT(p.time_s, circle_s + 3.0);
}

TEST(GrblPlanner, PostWarnsWhereTheLookAheadSlowsTheProgram) {
  // The circle at F6000 on a controller of 4 planner blocks (3 of look-ahead): at 0.05 mm blocks
  // of some 4.5 mm, capped at sqrt(2 a 3 L) = 164 mm/s, above the feed: no warning; at 0.002 mm
  // blocks of some 0.9 mm, capped near 73 mm/s, below it: the warning, with both times.
  const std::string job = "G21 G90\nG0 X50 Y0\nG1 F6000\nG2 X50 Y0 I-50 J0\nG0 X0 Y0\nM2\n";
  const post::PostReport coarse = post_text(plotter_on_grbl(true, 4), job, 0.05);
  for (const gcode::Warning& w : coarse.warnings) {
    EXPECT_EQ(w.message.find("look-ahead"), std::string::npos) << w.message;
  }
  const post::PostReport fine = post_text(plotter_on_grbl(true, 4), job, 0.002);
  ASSERT_TRUE(fine.controller);
  EXPECT_GT(fine.blocks, 3 * coarse.blocks);
  bool warned = false;
  for (const gcode::Warning& w : fine.warnings) {
    if (w.message.find("4-block look-ahead") != std::string::npos) {
      warned = true;
      EXPECT_NE(w.message.find("instead of"), std::string::npos) << w.message;
    }
  }
  EXPECT_TRUE(warned);
  EXPECT_GT(fine.controller->time_s, coarse.controller->time_s + 1.0);
}

// The warning is the job's line where the stretch the look-ahead slows most starts: the circle of
// line 5 (between two dwells, each a stop), not the rapid of line 2 nor line 0.
TEST(GrblPlanner, LookAheadWarningAtTheSlowStretchsLine) {
  const std::string job =
      "G21 G90\nG0 X50 Y0\nG4 P0.1\nG1 F6000\nG2 X50 Y0 I-50 J0\nG4 P0.1\nG0 X0 Y0\nM2\n";
  const post::PostReport fine = post_text(plotter_on_grbl(true, 4), job, 0.002);
  ASSERT_TRUE(fine.controller);
  EXPECT_EQ(fine.controller->slowest_stretch_tag, 5);
  EXPECT_GT(fine.controller->slowest_stretch_lost_s, 0.5);
  int warned_at = -1;
  for (const gcode::Warning& w : fine.warnings) {
    if (w.message.find("4-block look-ahead") != std::string::npos) {
      warned_at = w.line;
      EXPECT_NE(w.message.find("the stretch slowed most"), std::string::npos) << w.message;
    }
  }
  EXPECT_EQ(warned_at, 5);
}

// grbl acts on ? ! ~ and on bytes above 0x7F even inside comments (a feed hold, feed overrides):
// the header of a grbl program carries none of them, whatever the machine and the job are named;
// LinuxCNC's keeps the name as it is.
TEST(GrblPlanner, HeaderCommentsAreSafeForGrbl) {
  std::ifstream in(test::example_machine_path("wall-plotter.toml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string name = "name = \"Wall plotter 1500\"";
  toml.replace(toml.find(name), name.size(), "name = \"Big plotter! Ni\xC3\xB1o ~1?\"");
  const machine::Machine machine = machine::parse_machine(toml, "named.toml");
  for (const post::Dialect dialect : {post::Dialect::grbl, post::Dialect::grblhal}) {
    const std::string header =
        post::joint_program_header(machine, "dr\xC3\xA1wing!.ngc", dialect, 0.01, nullptr);
    EXPECT_EQ(header.find_first_of("?!~"), std::string::npos) << header;
    for (const char c : header) {
      EXPECT_TRUE(c == '\n' || (c >= 0x20 && c <= 0x7E)) << header;
    }
    EXPECT_NE(header.find("(joint-space program by pkmkit for Big plotter_ Ni__o _1_)\n"),
              std::string::npos)
        << header;
    EXPECT_NE(header.find("(from dr__wing_.ngc, dialect "), std::string::npos) << header;
  }
  const std::string linuxcnc =
      post::joint_program_header(machine, "job.ngc", post::Dialect::linuxcnc, 0.01, nullptr);
  EXPECT_NE(linuxcnc.find("for Big plotter! Ni\xC3\xB1o ~1?)"), std::string::npos) << linuxcnc;
}

}  // namespace
}  // namespace pkm
