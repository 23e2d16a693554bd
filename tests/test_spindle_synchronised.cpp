// Spindle-synchronised motion end to end: the canonical commands of G33, G33.1, G84/G74, G76
// and G95 (as rs274 prints them, checked by hand here and against rs274 by the conformance
// test), the errors at their line and column, and the times plan and post give them from the
// spindle speed, computed by hand.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_path.hpp"
#include "test_support.hpp"

namespace pkm {
namespace {

std::filesystem::path write_program(const std::string& text) {
  static int counter = 0;
  const auto path =
      std::filesystem::temp_directory_path() /
      ("pkm-sync-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".ngc");
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

struct Interpreted {
  std::vector<gcode::Canon> canon;
  std::vector<std::string> text;  // canon_text of each command
  std::string error;              // the message alone
  int line = 0, column = 0;
};

Interpreted interpret(const std::string& program) {
  const auto path = write_program(program);
  Interpreted run;
  gcode::Interpreter interpreter(path);
  try {
    interpreter.run([&](const gcode::Canon& canon) {
      run.canon.push_back(canon);
      run.text.push_back(gcode::canon_text(canon));
    });
  } catch (const gcode::GcodeError& error) {
    run.error = error.message();
    run.line = error.line();
    run.column = error.column();
  }
  std::filesystem::remove(path);
  return run;
}

// The commands from the first one starting with `first`, `count` of them.
std::vector<std::string> from(const Interpreted& run, const std::string& first, std::size_t count) {
  const auto start = std::find_if(run.text.begin(), run.text.end(),
                                  [&](const std::string& t) { return t.rfind(first, 0) == 0; });
  if (start == run.text.end()) return {};
  return {start, start + std::min<std::ptrdiff_t>(count, run.text.end() - start)};
}

TEST(Synchronised, G33IsAFeedAtThePitchBetweenSyncStartAndStop) {
  const Interpreted run = interpret("G21 G18\nS500 M3\nG0 X10 Z5\nG33 Z-10 K1.5\nM2\n");
  ASSERT_EQ(run.error, "");
  EXPECT_EQ(
      from(run, "START_SPEED_FEED_SYNC", 3),
      (std::vector<std::string>{"START_SPEED_FEED_SYNC(1.500000,0)",
                                "STRAIGHT_FEED(10.0000, 0.0000, -10.0000, 0.0000, 0.0000, 0.0000)",
                                "STOP_SPEED_FEED_SYNCH()"}));
  const auto feed = std::find_if(run.canon.begin(), run.canon.end(), [](const gcode::Canon& c) {
    return c.kind == gcode::CanonKind::feed;
  });
  ASSERT_NE(feed, run.canon.end());
  EXPECT_EQ(feed->feed_mode, gcode::FeedMode::units_per_revolution);
  EXPECT_EQ(feed->value, 1.5);
  EXPECT_EQ(feed->spindle_rpm, 500.0);
}

TEST(Synchronised, RigidTapGoesToItsPointAndLeavesTheToolWhereItWas) {
  // The A word of a G33.1 is no part of the tap; rs274 keeps it as the position, so the next
  // move turns A.
  const Interpreted run =
      interpret("G21 S500 M3\nG0 X1 Y2 Z3 A10\nG33.1 Z-8 A20 K1.25\nG0 X0\nG91 G33.1 Z-5 K1\nM2\n");
  ASSERT_EQ(run.error, "");
  EXPECT_EQ(from(run, "START_SPEED_FEED_SYNC", 4),
            (std::vector<std::string>{
                "START_SPEED_FEED_SYNC(1.250000,0)", "RIGID_TAP(1.0000, 2.0000, -8.0000)",
                "STOP_SPEED_FEED_SYNCH()",
                "STRAIGHT_TRAVERSE(0.0000, 2.0000, 3.0000, 20.0000, 0.0000, 0.0000)"}));
  // Incremental from the point the first tap came back to.
  EXPECT_EQ(from(run, "RIGID_TAP(0", 1),
            (std::vector<std::string>{"RIGID_TAP(0.0000, 2.0000, -2.0000)"}));
}

TEST(Synchronised, G95FeedsPerRevolutionAndG94ForgetsTheFeed) {
  const Interpreted run = interpret("G21 S1000 M3\nG95 F0.2\nG1 X5\nG94\nG1 X6\nM2\n");
  EXPECT_EQ(from(run, "SET_FEED_MODE", 4),
            (std::vector<std::string>{"SET_FEED_MODE(0, 1)", "SET_FEED_RATE(0.0000)",
                                      "SET_FEED_RATE(0.2000)",
                                      "STRAIGHT_FEED(5.0000, 0.0000, 0.0000, 0.0000, 0.0000, "
                                      "0.0000)"}));
  const auto feed = std::find_if(run.canon.begin(), run.canon.end(), [](const gcode::Canon& c) {
    return c.kind == gcode::CanonKind::feed;
  });
  ASSERT_NE(feed, run.canon.end());
  EXPECT_EQ(feed->feed_mode, gcode::FeedMode::units_per_revolution);
  EXPECT_EQ(feed->value, 0.2);
  EXPECT_EQ(feed->spindle_rpm, 1000.0);
  // G94 sets the feed to 0, as rs274: the G1 after it has none.
  EXPECT_EQ(run.line, 5);
  EXPECT_NE(run.error.find("zero feed rate"), std::string::npos) << run.error;
}

TEST(Synchronised, G84ReversesTheSpindleAtTheBottomAndG74IsItsMirror) {
  const Interpreted run = interpret(
      "G21 S300 M3 F300\nG0 X0 Y0 Z10\nG84 X5 Y5 Z-6 R2\nG80\nM4\nG98 G74 X9 Z-4 R2 P0.5\nM2\n");
  ASSERT_EQ(run.error, "");
  EXPECT_EQ(from(run, "DISABLE_FEED_OVERRIDE", 12),
            (std::vector<std::string>{
                "DISABLE_FEED_OVERRIDE()", "DISABLE_SPEED_OVERRIDE(0)",
                "STRAIGHT_FEED(5.0000, 5.0000, -6.0000, 0.0000, 0.0000, 0.0000)",
                "STOP_SPINDLE_TURNING(0)", "START_SPINDLE_COUNTERCLOCKWISE(0)", "DWELL(0.0000)",
                "STRAIGHT_FEED(5.0000, 5.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
                "STOP_SPINDLE_TURNING(0)", "START_SPINDLE_CLOCKWISE(0)", "ENABLE_FEED_OVERRIDE()",
                "ENABLE_SPEED_OVERRIDE(0)", "START_SPINDLE_COUNTERCLOCKWISE(0)"}));
  // G74 with G98: back out to the level the series began at (Z2, where G80 left the tool).
  EXPECT_EQ(from(run, "STRAIGHT_FEED(9", 6),
            (std::vector<std::string>{
                "STRAIGHT_FEED(9.0000, 5.0000, -4.0000, 0.0000, 0.0000, 0.0000)",
                "STOP_SPINDLE_TURNING(0)", "START_SPINDLE_CLOCKWISE(0)", "DWELL(0.5000)",
                "STRAIGHT_FEED(9.0000, 5.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
                "STOP_SPINDLE_TURNING(0)"}));
}

TEST(Synchronised, G84InTheXzPlaneIsRefusedAtItsColumn) {
  // rs274 2.9 feeds to a point with its coordinates mixed up here (the tap leaves its hole
  // sideways); pkm neither copies that nor runs the program differently from LinuxCNC: it refuses
  // the cycle at its code, before any of its motion (docs/gcode.md).
  const Interpreted run =
      interpret("G21 S300 M3 F300\nG18 G0 X10 Y20 Z10\nG84 X10 Z5 Y-8 R5\nM2\n");
  EXPECT_EQ(run.error.rfind("G84 in the XZ plane (G18) is not supported", 0), 0u) << run.error;
  EXPECT_EQ(run.line, 3);
  EXPECT_EQ(run.column, 1);
  EXPECT_TRUE(from(run, "STRAIGHT_FEED", 1).empty());
}

TEST(Synchronised, G76PassesByHand) {
  // From X10 Z2, an outside thread (I-1): the drive line is X10, the crest 1 below it, the
  // first cut J0.4 deeper, then J * n for n = 2, 3 (R1) while short of the full depth K1, which
  // is cut once (no H). Depths 1.4, 1.8, 2.0: X 8.6, 8.2, 8.0; each pass comes back out to
  // X (10 - depth + 2) at the end, Z-5, and starts again from there.
  const Interpreted run = interpret("G21 G18 S100 M3\nG0 X10 Z2\nG76 P1 Z-5 I-1 J0.4 K1\nM2\n");
  ASSERT_EQ(run.error, "");
  std::vector<std::string> moves;
  for (const std::string& text : run.text) {
    if (text.rfind("STRAIGHT_", 0) == 0) moves.push_back(text.substr(0, text.find(", 0.0000")));
  }
  const std::vector<std::string> expected = {
      "STRAIGHT_TRAVERSE(10.0000",  // G0 X10 Z2
      "STRAIGHT_TRAVERSE(10.6000", "STRAIGHT_TRAVERSE(8.6000",  "STRAIGHT_FEED(8.6000",
      "STRAIGHT_TRAVERSE(10.6000", "STRAIGHT_TRAVERSE(10.2000", "STRAIGHT_TRAVERSE(8.2000",
      "STRAIGHT_FEED(8.2000",      "STRAIGHT_TRAVERSE(10.2000", "STRAIGHT_TRAVERSE(10.0000",
      "STRAIGHT_TRAVERSE(8.0000",  "STRAIGHT_FEED(8.0000",      "STRAIGHT_TRAVERSE(10.0000",
      "STRAIGHT_TRAVERSE(10.0000"};  // to the block's end point, X10 Z-5
  EXPECT_EQ(moves, expected);
  EXPECT_EQ(std::count(run.text.begin(), run.text.end(), "START_SPEED_FEED_SYNC(1.000000,0)"), 3);
  const auto last_move = std::find_if(run.text.rbegin(), run.text.rend(), [](const std::string& t) {
    return t.rfind("STRAIGHT_", 0) == 0;
  });
  EXPECT_EQ(*last_move, "STRAIGHT_TRAVERSE(10.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)");
}

struct ErrorCase {
  std::string name, program;
  int line, column;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const ErrorCase& c) {
  return out << c.name;
}

class SynchronisedErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(SynchronisedErrors, NameLineColumnAndWhat) {
  const ErrorCase& c = GetParam();
  const Interpreted run = interpret(c.program);
  EXPECT_NE(run.error.find(c.message), std::string::npos) << run.error;
  EXPECT_EQ(run.line, c.line) << run.error;
  EXPECT_EQ(run.column, c.column) << run.error;
}

const ErrorCase kErrors[] = {
    {"g33_spindle_stopped", "G21\nG33 Z-10 K1.5\n", 2, 1, "spindle not turning in G33"},
    {"g33_without_k", "G21 S500 M3\nG33 Z-10\n", 2, 1, "K word (the pitch, per revolution)"},
    {"g33_with_f", "G21 S500 M3\nG33 Z-10 K1 F100\n", 2, 13, "F word used with G33"},
    {"g33_continued_without_k", "G21 S500 M3\nG33 Z-10 K1\nZ-12\n", 3, 1, "K word"},
    {"g33_1_without_axes", "G21 S500 M3\nG33.1 K1\n", 2, 1, "all axes missing with G33.1"},
    {"g33_1_spindle_stopped", "G21 S500\nG33.1 Z-5 K1\n", 2, 1, "spindle not turning in G33.1"},
    {"g33_with_compensation", "G21 S500 M3 G41.1 D2\nG33 X10 K1\n", 2, 1,
     "cannot use G33 (spindle-synchronised motion) with cutter radius compensation on"},
    {"g84_spindle_stopped", "G21 F100\nG0 Z5\nG84 Z-5 R1\n", 3, 1, "spindle not turning in G84"},
    {"g84_spindle_reversed", "G21 F100 S300 M4\nG0 Z5\nG84 Z-5 R1\n", 3, 1,
     "spindle turning counterclockwise in G84"},
    {"g74_spindle_forward", "G21 F100 S300 M3\nG0 Z5\nG74 Z-5 R1\n", 3, 1,
     "spindle turning clockwise in G74"},
    {"g84_with_q", "G21 F100 S300 M3\nG0 Z5\nG84 Z-5 R1 Q1\n", 3, 12, "Q word with no"},
    {"g76_spindle_stopped", "G21 G18\nG76 P1 Z-5 I-1 J0.2 K1\n", 2, 1,
     "spindle not turning in G76"},
    {"g76_without_p", "G21 G18 S100 M3\nG76 Z-5 I-1 J0.2 K1\n", 2, 1,
     "P word (the thread's pitch)"},
    {"g76_zero_pitch", "G21 G18 S100 M3\nG76 P0 Z-5 I-1 J0.2 K1\n", 2, 5, "must be positive"},
    {"g76_without_j", "G21 G18 S100 M3\nG76 P1 Z-5 I-1 K1\n", 2, 1, "I, J or K word missing"},
    {"g76_i_zero", "G21 G18 S100 M3\nG76 P1 Z-5 I0 J0.2 K1\n", 2, 12, "I (the thread's offset)"},
    {"g76_j_zero", "G21 G18 S100 M3\nG76 P1 Z-5 I-1 J0 K1\n", 2, 16, "J (the first cut)"},
    {"g76_k_not_above_j", "G21 G18 S100 M3\nG76 P1 Z-5 I-1 J0.4 K0.4\n", 2, 21,
     "K (the full depth) must be above J"},
    {"g76_rotary_axis", "G21 G18 S100 M3\nG76 P1 Z-5 A5 I-1 J0.2 K1\n", 2, 1,
     "cannot move the rotary or U V W axes with G76"},
    {"g76_half_spring_pass", "G21 G18 S100 M3\nG76 P1 Z-5 I-1 J0.2 K1 H1.5\n", 2, 24,
     "H must be a whole number"},
    {"g76_with_compensation", "G21 G18 S100 M3 G41.1 D2\nG76 P1 X5 Z-5 I-1 J0.2 K1\n", 2, 1,
     "cannot use G76"},
    {"g95_zero_spindle_speed", "G21 G95 F0.1\nG1 X10\n", 2, 1,
     "zero spindle speed in feed per revolution mode (G95)"},
    {"g95_probe", "G21 S500 M3 G95 F0.1\nG38.2 Z-10\n", 2, 1,
     "cannot probe in feed per revolution mode (G95)"},
    {"lathe_finishing_cycle", "G21 G18\nG70 P1 Q2\n", 2, 1, "G70 (lathe finishing cycle)"},
    {"lathe_roughing_cycle", "G21 G18\nG0 X1 G71.2 P1 Q2\n", 2, 7, "G71.2 (lathe roughing cycle)"},
    {"lathe_facing_cycle", "G72 P1 Q2\n", 1, 1, "G72 (lathe roughing cycle) is not supported"},
    {"lathe_diameter_mode", "G21 G18 G7\nG0 X10\n", 1, 9, "G7 (lathe diameter mode)"},
};

INSTANTIATE_TEST_SUITE_P(Table, SynchronisedErrors, ::testing::ValuesIn(kErrors),
                         [](const auto& test_info) { return test_info.param.name; });

// ---- Timing: plan and post, from S --------------------------------------------------------

motion::PlanReport plan(const std::string& program) {
  // The hexapod's Cartesian limit is 1000 mm/s^2; its home is X0 Y0 Z1000.
  const machine::Machine hexapod = test::load_example("hexapod-bit.toml");
  struct Ignore final : motion::SampleSink {
    void write(const motion::Sample&) override {}
  } ignore;
  const auto path = write_program(program);
  motion::PlanReport report;
  try {
    report = motion::plan_program(hexapod, path, {}, {}, ignore);
  } catch (...) {
    std::filesystem::remove(path);
    throw;
  }
  std::filesystem::remove(path);
  return report;
}

TEST(SynchronisedTiming, G33RunsAtThePitchTimesTheSpindleSpeed) {
  // K1.5 at S400: 600 mm/min, 10 mm/s; 30 mm from rest to rest at 1000 mm/s^2:
  // 30 / 10 + 10 / 1000 = 3.01 s.
  const auto report = plan("G21 G90 S400 M3\nG33 X30 Y0 Z1000 K1.5\nM2\n");
  EXPECT_NEAR(report.duration_s, 3.01, 1e-9);
}

TEST(SynchronisedTiming, G95FeedsFTimesS) {
  // F0.1 mm/rev at S1500: 150 mm/min, 2.5 mm/s; 10 mm: 10 / 2.5 + 2.5 / 1000 = 4.0025 s.
  const auto report = plan("G21 G90 S1500 M3 G95\nG1 X10 Y0 Z1000 F0.1\nM2\n");
  EXPECT_NEAR(report.duration_s, 4.0025, 1e-9);
}

TEST(SynchronisedTiming, RigidTapGoesDownAndBackAtThePitchTimesS) {
  // K1 at S600: 10 mm/s; 10 mm down, stop, 10 mm back up: 2 (10 / 10 + 10 / 1000) = 2.02 s, and
  // the tool ends where it started.
  const auto report = plan("G21 G90 S600 M3\nG33.1 X0 Y0 Z990 K1\nM2\n");
  EXPECT_NEAR(report.duration_s, 2.02, 1e-9);
  EXPECT_NEAR(report.path_length_mm, 20.0, 1e-12);
}

TEST(SynchronisedTiming, SpindleStoppedOrAtS0IsRefusedAtTheMovesLine) {
  // rs274 takes both (G95 checks only that S is not 0); no machine could run them.
  for (const std::string program : {"G21 G90 S1000 G95 F0.1\nG1 X10 Y0 Z1000\nM2\n",
                                    "G21 G90 S0 M3\nG0 X1\nG33 X10 Y0 Z1000 K1\nM2\n"}) {
    try {
      plan(program);
      ADD_FAILURE() << "planned: " << program;
    } catch (const gcode::GcodeError& error) {
      EXPECT_EQ(error.line(), program.find("G33") == std::string::npos ? 2 : 3) << program;
      EXPECT_NE(error.message().find("the spindle is stopped or at S0"), std::string::npos)
          << error.what();
    }
  }
}

std::vector<std::string> posted(const std::string& program) {
  const machine::Machine mill =
      test::load_example("matrix-mill.toml");  // linear, home X300 Y200 Z-100
  const auto path = write_program(program);
  std::vector<std::string> lines;
  post::post_program(mill, path, {}, {}, [&](const std::string& line) { lines.push_back(line); });
  std::filesystem::remove(path);
  return lines;
}

std::string feed_word(const std::string& line) {
  return line.substr(line.rfind(' ') + 1);
}

TEST(SynchronisedTiming, PostTimesTheRigidTapAndReversesTheSpindleForTheWayOut) {
  // 10 mm at K1 x S600 = 600 mm/min: 1/60 min each way, G93 F60.
  const auto lines = posted("G21 G90 S600 M3\nG33.1 X300 Y200 Z-110 K1\nM2\n");
  ASSERT_EQ(lines.size(), 9u);
  EXPECT_EQ(lines[1], "S600.0");
  EXPECT_EQ(lines[2], "M3");
  EXPECT_EQ(lines[3].substr(0, 7), "G93 G1 ");
  EXPECT_EQ(feed_word(lines[3]), "F60.000");
  EXPECT_EQ(lines[4], "M4");
  EXPECT_EQ(feed_word(lines[5]), "F60.000");
  EXPECT_EQ(lines[6], "M3");
}

TEST(SynchronisedTiming, PostTimesFeedPerRevolution) {
  // G1 6 mm at F0.1 mm/rev x S1000 = 100 mm/min: 6/100 min, F16.666 (rounded down).
  const auto lines = posted("G21 G90 S1000 M3 G95\nG1 X306 F0.1\nM2\n");
  const auto block = std::find_if(lines.begin(), lines.end(), [](const std::string& line) {
    return line.rfind("G93 G1", 0) == 0;
  });
  ASSERT_NE(block, lines.end());
  EXPECT_EQ(feed_word(*block), "F16.666");
}

TEST(SynchronisedTiming, VerifyReadsAJointProgramFedPerRevolution) {
  // The 5-axis machine (identity X Y Z, C passed through at 30 deg/s) checked against its own
  // job in G95: F1 mm/rev at S600 is 600 mm/min, X10 takes 1 s, so C turns at 90 deg/s. With the
  // spindle stopped the block cannot be timed: refused at its line.
  const machine::Machine trt = test::load_example("linuxcnc-xyzac-trt.toml");
  const auto job = write_program("G21 G90 S600 M3 G95\nG1 F1 X10 C90\nM2\n");
  const verify::VerifyReport report = verify::verify_joint_program(trt, job, job, {});
  std::filesystem::remove(job);
  ASSERT_EQ(report.velocity.count, 1);
  EXPECT_EQ(report.velocity.first[0].line, 2);
  EXPECT_NEAR(report.velocity.first[0].value, 90.0, 1e-9);
  const auto stopped = write_program("G21 G90 S600 G95\nG1 F1 X10 C90\nM2\n");
  try {
    verify::verify_joint_program(trt, stopped, stopped, {});
    ADD_FAILURE() << "verified a block fed per revolution with the spindle stopped";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find(":2: "), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("stopped"), std::string::npos) << error.what();
  }
  std::filesystem::remove(stopped);
}

}  // namespace
}  // namespace pkm
