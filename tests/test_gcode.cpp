// The G-code interpreter: expressions by hand, control flow, motion, and a table of errors that
// must name file:line:column and what is wrong.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <tuple>

#include "pkm/gcode/block.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/gcode/tool_table.hpp"

namespace pkm::gcode {
namespace {

struct Result {
  std::vector<Canon> canon;
  std::string error;  // "file:line:column: message" without the file, or empty
  int line = 0, column = 0;
  std::vector<Warning> warnings;
};

Result interpret(const std::string& program, InterpreterOptions options = {}) {
  static int counter = 0;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("pkm-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".ngc");
  std::ofstream(path, std::ios::binary) << program;
  Result result;
  Interpreter interpreter(path, std::move(options));
  try {
    interpreter.run([&](const Canon& canon) { result.canon.push_back(canon); });
  } catch (const GcodeError& error) {
    result.error = error.message();
    result.line = error.line();
    result.column = error.column();
    EXPECT_EQ(error.file(), path.string());
  }
  result.warnings = interpreter.warnings();
  std::filesystem::remove(path);
  return result;
}

std::vector<Canon> motion(const Result& result) {
  std::vector<Canon> moves;
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::traverse || c.kind == CanonKind::feed || c.kind == CanonKind::arc) {
      moves.push_back(c);
    }
  }
  return moves;
}

// The X the program's last move reaches.
double last_x(const std::string& program) {
  const Result result = interpret(program + "\nM2\n");
  EXPECT_EQ(result.error, "") << program;
  const auto moves = motion(result);
  return moves.empty() ? std::nan("") : moves.back().end[0];
}

TEST(Expressions, ByHand) {
  EXPECT_DOUBLE_EQ(last_x("G0 X[2+3*4]"), 14.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[2**3**2]"), 64.0);  // left to right: (2**3)**2
  EXPECT_DOUBLE_EQ(last_x("G0 X[7 MOD 3]"), 1.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[-7 MOD 3]"), 2.0);      // LinuxCNC's MOD is never negative
  EXPECT_DOUBLE_EQ(last_x("G0 X[1 EQ 1.00005]"), 1.0);  // EQ within 1e-4
  EXPECT_DOUBLE_EQ(last_x("G0 X[ATAN[1]/[1]]"), 45.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[SQRT[16] + ABS[-2]]"), 6.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[ROUND[2.5]]"), 3.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[FIX[-2.5]]"), -3.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[FUP[2.1]]"), 3.0);
  EXPECT_DOUBLE_EQ(last_x("G0 X[1 + 2 GT 2]"), 1.0);    // + binds tighter than GT
  EXPECT_DOUBLE_EQ(last_x("G0 X[1 AND 0 OR 1]"), 1.0);  // left to right
  EXPECT_NEAR(last_x("G0 X[SIN[30]]"), 0.5, 1e-15);     // degrees
  EXPECT_NEAR(last_x("G0 X[ACOS[0]]"), 90.0, 1e-12);
  EXPECT_DOUBLE_EQ(last_x("G0 X - [1 + 1]"), -2.0);
  EXPECT_DOUBLE_EQ(last_x("g0 x 1 0 . 5"), 10.5);  // spaces vanish, case ignored
  EXPECT_DOUBLE_EQ(last_x("G0 X.5"), 0.5);
}

TEST(Numbers, ReadExactlyAsStrtodReadsThem) {
  // The reader's fast path (an exact mantissa over an exact power of ten) must round as strtod.
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<int> digit(0, 9), length(1, 17), point(0, 17);
  const Parameters parameters;
  for (int trial = 0; trial < 20000; ++trial) {
    std::string text;
    const int digits = length(rng);
    const int dot = point(rng);
    for (int i = 0; i < digits; ++i) {
      if (i == dot) text += '.';
      text += static_cast<char>('0' + digit(rng));
    }
    const Block block = read_block("X" + text, parameters);
    ASSERT_TRUE(block.has('x')) << text;
    EXPECT_EQ(block.value('x'), std::strtod(text.c_str(), nullptr)) << text;
  }
}

TEST(Parameters, NumberedNamedAndScopes) {
  EXPECT_DOUBLE_EQ(last_x("#1=5\n#2=[#1*2]\nG0 X#2"), 10.0);
  // A line reads every value before it sets any; the last setting of a parameter wins.
  EXPECT_DOUBLE_EQ(last_x("#1=5 #1=7 G0 X#1"), 0.0);
  EXPECT_DOUBLE_EQ(last_x("#1=5 #1=7\nG0 X#1"), 7.0);
  EXPECT_DOUBLE_EQ(last_x("#<depth>=3\nG0 X#<de pth>"), 3.0);
  EXPECT_DOUBLE_EQ(last_x("#3=4\n#4=3\nG0 X##4"), 4.0);  // #[#4]
  EXPECT_DOUBLE_EQ(last_x("#<_g>=1\nG0 X[EXISTS[#<_g>] + EXISTS[#<nope>]]"), 1.0);
}

TEST(ControlFlow, SubroutinesLoopsAndConditions) {
  EXPECT_DOUBLE_EQ(last_x("o<add> sub\no<add> return [#1 + #2]\no<add> endsub\n"
                          "o<add> call [2] [3]\nG0 X#<_value>"),
                   5.0);
  // Subroutine locals do not leak; #1 outside is untouched.
  EXPECT_DOUBLE_EQ(last_x("#1=9\no1 sub\n#1=2\n#<local>=4\no1 endsub\no1 call [7]\n"
                          "G0 X[#1 + EXISTS[#<local>]]"),
                   9.0);
  EXPECT_DOUBLE_EQ(last_x("#1=0\no2 while [#1 LT 5]\n#1=[#1+1]\no2 endwhile\nG0 X#1"), 5.0);
  EXPECT_DOUBLE_EQ(last_x("#1=0\no3 do\n#1=[#1+2]\no3 while [#1 LT 7]\nG0 X#1"), 8.0);
  EXPECT_DOUBLE_EQ(last_x("#1=0\no4 repeat [4]\n#1=[#1+3]\no4 endrepeat\nG0 X#1"), 12.0);
  EXPECT_DOUBLE_EQ(last_x("#1=2\no5 if [#1 EQ 1]\nG0 X1\no5 elseif [#1 EQ 2]\nG0 X2\n"
                          "o5 else\nG0 X3\no5 endif"),
                   2.0);
  EXPECT_DOUBLE_EQ(last_x("#1=0\no6 while [1]\n#1=[#1+1]\no7 if [#1 GE 3]\no6 break\no7 endif\n"
                          "o6 endwhile\nG0 X#1"),
                   3.0);
  // A subroutine defined after its call is found.
  EXPECT_DOUBLE_EQ(last_x("o7 call [4]\nG0 X#<_value>\nM2\no7 sub\no7 return [#1*#1]\no7 endsub"),
                   16.0);
}

TEST(ControlFlow, JumpsAcrossReadsInLongCrlfPrograms) {
  // The source is read 64 KB at a time: a subroutine 500 KB before its call, a line longer
  // than one read, and a loop jumping back within what was read, all with CRLF line ends.
  std::string program = "o<twice> sub\r\n#<_v> = [#1 * 2]\r\no<twice> endsub\r\n";
  for (int i = 0; i < 20000; ++i) program += "(padding line " + std::to_string(i) + ")\r\n";
  program += "(" + std::string(100000, 'x') + ")\r\n";
  program +=
      "#1=0\r\no1 while [#1 LT 3]\r\no<twice> call [#1]\r\n#1=[#1+1]\r\no1 endwhile\r\n"
      "G0 X[#<_v> + #1]";
  EXPECT_DOUBLE_EQ(last_x(program), 7.0);  // the last call doubled 2; #1 is 3
}

TEST(Motion, ArcsUnitsAndOffsets) {
  const Result result = interpret(
      "G21 G17 G90\nG0 X0 Y0 Z0\nG1 F100 X10\nG3 X0 Y10 R10\nG18 G2 X20 Z0 I10 K0\n"
      "G20\nG0 X1\nG92 X0\nG0 X1\nG91 G0 X1\nG90 G54 G10 L2 P1 X2\nG0 X0\nM2\n");
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 8u);
  // G3 R10 from (10, 0) to (0, 10): the quarter circle about the origin, counterclockwise.
  EXPECT_EQ(moves[2].kind, CanonKind::arc);
  EXPECT_NEAR(moves[2].center[0], 0.0, 1e-12);
  EXPECT_NEAR(moves[2].center[1], 0.0, 1e-12);
  EXPECT_EQ(moves[2].turns, 1);
  // G18: first axis Z, second X; the centre from K and I.
  EXPECT_EQ(moves[3].plane, Plane::xz);
  EXPECT_NEAR(moves[3].center[0], 0.0, 1e-12);   // z + K
  EXPECT_NEAR(moves[3].center[1], 10.0, 1e-12);  // x + I
  EXPECT_EQ(moves[3].turns, -1);
  // Inches: X1 is 1 inch; G92 X0 there makes the next X1 one more inch on.
  EXPECT_EQ(moves[4].units, LengthUnits::inch);
  EXPECT_DOUBLE_EQ(moves[4].end[0], 1.0);
  EXPECT_DOUBLE_EQ(moves[5].end[0], 1.0);
  EXPECT_DOUBLE_EQ(moves[6].end[0], 2.0);  // G91: one more
  // G10 L2 P1 X2 (inches, 50.8 mm) moves the G54 origin; X0 is then 2 inches from machine 0.
  EXPECT_NEAR(moves[7].end[0], 0.0, 1e-12);
}

// A probe is a feed move at its F (the planner's speed; it used to come with none, and plan
// refused the job as "a feed move with no feed rate"); an option refuses it at its column.
TEST(Motion, ProbeCarriesItsFeedOrIsRefusedAtItsColumn) {
  const std::string program = "G21 G90\nG1 X40 Y-50 F200\nG91 G38.2 X10 Y-10 F100\nM2\n";
  const Result result = interpret(program);
  ASSERT_EQ(result.error, "");
  const auto probe = std::find_if(result.canon.begin(), result.canon.end(),
                                  [](const Canon& c) { return c.kind == CanonKind::probe; });
  ASSERT_NE(probe, result.canon.end());
  EXPECT_EQ(probe->value, 100.0);
  EXPECT_EQ(probe->feed_mode, FeedMode::units_per_minute);
  EXPECT_EQ(probe->end[0], 50.0);
  EXPECT_EQ(probe->end[1], -60.0);

  InterpreterOptions refusing;
  refusing.probe_refusal = "no probing here";
  const Result refused = interpret(program, refusing);
  EXPECT_EQ(refused.error, "no probing here");
  EXPECT_EQ(refused.line, 3);
  EXPECT_EQ(refused.column, 5);  // the G38.2
}

// The last command of `kind` a run handed on.
const Canon& last_of(const Result& result, CanonKind kind) {
  const auto found = std::find_if(result.canon.rbegin(), result.canon.rend(),
                                  [&](const Canon& c) { return c.kind == kind; });
  EXPECT_NE(found, result.canon.rend());
  return *found;
}

TEST(Offsets, G52GivesTheOffsetWhereG92GivesThePosition) {
  // G52 X10 Y5: the G92/G52 offset becomes (10, 5) whatever the position; G0 X0 Y0 then goes
  // to (10, 5) from the G54 origin. G92 X0 there keeps it (0 + 10 - 0); G52 X3 then sets X's to
  // 3 and moves the program position by 7 so the machine stays; G92.1 clears both.
  const Result result =
      interpret("G21 G90\nG52 X10 Y5\nG0 X0 Y0\nG92 X0\nG52 X3\nG0 X1\nG92.1\nG0 X0\nM2\n");
  ASSERT_EQ(result.error, "");
  std::vector<std::array<double, 2>> g92;
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::g92_offset) g92.push_back({c.end[0], c.end[1]});
  }
  ASSERT_GE(g92.size(), 4u);
  EXPECT_EQ(g92[0], (std::array<double, 2>{10.0, 5.0}));  // G52 X10 Y5
  EXPECT_EQ(g92[1], (std::array<double, 2>{10.0, 5.0}));  // G92 X0 at X0
  EXPECT_EQ(g92[2], (std::array<double, 2>{3.0, 5.0}));   // G52 X3
  EXPECT_EQ(g92[3], (std::array<double, 2>{0.0, 0.0}));   // G92.1
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_DOUBLE_EQ(moves[1].end[0], 1.0);  // program X1 is machine 4 now
  EXPECT_DOUBLE_EQ(moves[2].end[0], 0.0);
}

TEST(Offsets, ToolTouchOffByHand) {
  // Tool 1 is 10 mm long: with G43 H1, G0 Z5 goes to machine Z15, and G52 Z4 makes that
  // program Z1. G10 L10 P1 Z-2 asks for the length that makes it program Z-2 with the G52 offset
  // kept: 15 - 4 - (-2) = 13; G43 H1 after G52 Z0 takes it up, and G53 Z0 is then program Z-13.
  // G10 L11 P2 Z3 measures from G59.3's origin (Z-20) without the G52 offset: 15 + 20 - 3 = 32.
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T1 P1 Z10 D6\nT2 P2 Z0 D6\n", "t.tbl", LengthUnits::mm);
  const Result result = interpret(
      "G21 G90\nG10 L2 P9 Z-20\nT1 M6\nG43 H1\nG0 Z5\nG52 Z4\nG10 L10 P1 Z-2\n"
      "G10 L11 P2 Z3\nG52 Z0\nG43 H1\nG53 G0 Z0\nM2\n",
      options);
  ASSERT_EQ(result.error, "");
  EXPECT_DOUBLE_EQ(options.tool_table->at(1).offset[2], 10.0);  // the caller's table is a copy
  EXPECT_DOUBLE_EQ(last_of(result, CanonKind::tool_length_offset).end[2], 13.0);
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 2u);
  EXPECT_DOUBLE_EQ(moves[1].end[2], -13.0);
  const Result fixture = interpret(
      "G21 G90\nG10 L2 P9 Z-20\nT1 M6\nG43 H1\nG0 Z5\nG52 Z4\nG10 L11 P2 Z3\nT2 M6\nG43 H2\n"
      "M2\n",
      options);
  ASSERT_EQ(fixture.error, "");
  EXPECT_DOUBLE_EQ(last_of(fixture, CanonKind::tool_length_offset).end[2], 32.0);
}

TEST(Offsets, G43KeepsTheMachineWhereItIs) {
  // rs274: G0 Z10, then G43 with a 12.7 mm tool, then G0 X5: Z goes to -2.7 in the program.
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T1 P1 Z12.7 D6\n", "t.tbl", LengthUnits::mm);
  const Result result = interpret("G21\nG0 Z10\nT1 M6\nG43 H1\nG0 X5\nG49\nG0 X6\nM2\n", options);
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_NEAR(moves[1].end[2], -2.7, 1e-12);
  EXPECT_NEAR(moves[2].end[2], 10.0, 1e-12);
}

TEST(Offsets, ToolLengthCodesByHand) {
  // Tool 1 is 10 mm long, tool 2 3 mm. At program Z20, G43 H0 takes the tool in the spindle
  // (tool 1, as rs274 does): Z20 - 10 = 10. G43.1 X2 replaces X's offset only: X1 - 2 = -1, Z's
  // 10 stays. G43.2 H2 adds tool 2's 3: Z10 + 10 - 13 = 7. G49 gives back X2 and Z13: (1, 20).
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T1 P1 Z10 D6\nT2 P2 Z3 D6\n", "t.tbl", LengthUnits::mm);
  const Result result = interpret(
      "G21 G90\nG0 X0 Y0 Z20\nT1 M6\nG43 H0\nG0 X1\nG43.1 X2\nG0 Y1\nG43.2 H2\nG0 Y2\nG49\n"
      "G0 Y3\nM2\n",
      options);
  ASSERT_EQ(result.error, "");
  std::vector<std::array<double, 3>> offsets;
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::tool_length_offset) offsets.push_back({c.end[0], c.end[1], c.end[2]});
  }
  EXPECT_EQ(offsets,
            (std::vector<std::array<double, 3>>{{0, 0, 10}, {2, 0, 10}, {2, 0, 13}, {0, 0, 0}}));
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 5u);
  const std::array<std::array<double, 3>, 4> expected{
      {{1, 0, 10}, {-1, 1, 10}, {-1, 2, 7}, {1, 3, 20}}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(moves[i + 1].end[axis], expected[i][axis], 1e-12) << "move " << i + 2;
    }
  }
}

TEST(Offsets, ToolLengthOffsetFollowsAUnitChange) {
  // G20: the machine at Z1 inch (25.4 mm), G43 with a 12.7 mm tool: program Z0.5 inch, 12.7 mm
  // after G21. G49 takes the 12.7 mm back, so Z stays at machine 25.4 mm, as LinuxCNC's machine
  // (its task canon converts the offset to the new units) does. The stand-alone rs274 keeps the
  // number 0.5 and goes to 13.2 (tests/gcode/tool-length-unit-change.ngc).
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T1 P1 Z12.7 D6\n", "t.tbl", LengthUnits::mm);
  const Result result =
      interpret("G20 G90\nG0 Z1\nT1 M6\nG43 H1\nG21\nG0 X1\nG49\nG0 X2\nM2\n", options);
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_NEAR(moves[1].end[2], 12.7, 1e-12);
  EXPECT_NEAR(moves[2].end[2], 25.4, 1e-12);
}

TEST(Offsets, RotationByHand) {
  // G54 at (10, 5) turned by 90 deg: program (1, 0) is machine (10, 6), program (0, 0) machine
  // (10, 5). G53 X0 leaves machine Y where it is (6): program (1, 10). G28.1 there stores
  // machine (0, 6); from G55 (unturned, at the machine origin) G28 goes to (0, 6).
  const Result result =
      interpret("G21 G90\nG10 L2 P1 X10 Y5 R90\nG54\nG0 X1 Y0\nG53 G0 X0\nG28.1\nG55\nG28\nM2\n");
  ASSERT_EQ(result.error, "");
  std::vector<double> rotations;  // G10 on the active system, G54, G55 (not turned), M2 (G54)
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::xy_rotation) rotations.push_back(c.value);
  }
  EXPECT_EQ(rotations, (std::vector<double>{90.0, 90.0, 0.0, 90.0}));
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 4u);
  EXPECT_NEAR(moves[0].end[0], 1.0, 1e-12);
  EXPECT_NEAR(moves[1].end[0], 1.0, 1e-12);
  EXPECT_NEAR(moves[1].end[1], 10.0, 1e-12);
  EXPECT_NEAR(moves[3].end[0], 0.0, 1e-12);
  EXPECT_NEAR(moves[3].end[1], 6.0, 1e-12);
}

TEST(Events, UserCodesArePassedOnWithAWarning) {
  const Result result = interpret("G21\nM101 P2\nG0 X1\n");  // and no program end
  ASSERT_EQ(result.error, "");
  std::vector<std::string> events;
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::event) events.push_back(c.text);
  }
  EXPECT_EQ(events, (std::vector<std::string>{"M101 P2"}));
  ASSERT_EQ(result.warnings.size(), 2u);
  EXPECT_NE(result.warnings[0].message.find("M101 (user M-code)"), std::string::npos);
  EXPECT_NE(result.warnings[1].message.find("no M2"), std::string::npos);
  EXPECT_EQ(result.canon.back().kind, CanonKind::program_end);
}

TEST(Events, UnknownCodesAreRefusedAtTheirColumn) {
  // rs274 refuses them too ("M-code greater than 199", "Unknown m code used"); on a LinuxCNC
  // machine they mean what a remap makes them (remap-reentry's M405 moves), so nothing of their
  // line runs: no move to X1.
  for (const auto& [program, column, message] :
       {std::tuple{"G21\nG0 X1 M405\nM2\n", 7, "M405 is above M199"},
        std::tuple{"G21\nG0 X1 M280 P0 S90\nM2\n", 7, "M280 is above M199"},
        std::tuple{"G21\nG0 X1 M10\nM2\n", 7, "M10 is not a LinuxCNC M-code"}}) {
    const Result result = interpret(program);
    EXPECT_EQ(result.line, 2) << program;
    EXPECT_EQ(result.column, column) << program;
    EXPECT_NE(result.error.find(message), std::string::npos) << result.error;
    EXPECT_TRUE(motion(result).empty()) << program;
  }
}

TEST(CutterCompensation, CornersByHand) {
  // A 20 mm square, tool diameter 2 mm: first on the right going clockwise (inside the square:
  // concave corners end each line where the offset lines cross), then on the left (outside:
  // convex corners are rounded about the programmed corner).
  const Result result = interpret(
      "G21 G0 X-10 Y-10\nG42.1 D2\nG1 X0 Y0 F100\nY20\nX20\nG4 P1\nY0\nG40\nG0 X-10 Y-10\n"
      "G41.1 D2\nG1 X0 Y0\nY20\nX20\nM2\n");
  ASSERT_EQ(result.error, "");
  std::vector<Canon> moves;
  for (const Canon& c : result.canon) {
    if (c.kind == CanonKind::traverse || c.kind == CanonKind::feed || c.kind == CanonKind::arc ||
        c.kind == CanonKind::dwell) {
      moves.push_back(c);
    }
  }
  struct Expected {
    CanonKind kind;
    double x, y;
    double centre_x = 0.0, centre_y = 0.0;
    int turns = 0;
  };
  const double h = std::sqrt(0.5);          // the entry lines run at 45 degrees
  const double cross = std::sqrt(2.0) - 1;  // 1/tan(67.5 deg): where x = -1 meets the entry
  const Expected expected[] = {
      {CanonKind::traverse, -10, -10},
      // Right of the entry line, one radius square to it at its end; then a convex corner.
      {CanonKind::feed, h, -h},
      {CanonKind::arc, 1, 0, 0, 0, 1},
      // Concave corners: each line stops one radius short (90 degree corner, radius 1).
      {CanonKind::feed, 1, 19},
      {CanonKind::feed, 19, 19},
      {CanonKind::dwell, 0, 0},  // held behind the move whose end the next move settled
      {CanonKind::feed, 19, 0},  // G40: the last move ends where the tool is
      {CanonKind::traverse, -10, -10},
      // Left: the entry line is cut back to where it meets x = -1 (a 45 degree concave join).
      {CanonKind::feed, -1, cross},
      {CanonKind::feed, -1, 20},
      {CanonKind::arc, 0, 21, 0, 20, -1},
      {CanonKind::feed, 20, 21},
  };
  ASSERT_EQ(moves.size(), std::size(expected));
  for (std::size_t i = 0; i < moves.size(); ++i) {
    SCOPED_TRACE("move " + std::to_string(i));
    EXPECT_EQ(moves[i].kind, expected[i].kind);
    if (expected[i].kind == CanonKind::dwell) {
      EXPECT_DOUBLE_EQ(moves[i].value, 1.0);
      continue;
    }
    EXPECT_NEAR(moves[i].end[0], expected[i].x, 1e-12);
    EXPECT_NEAR(moves[i].end[1], expected[i].y, 1e-12);
    if (expected[i].kind == CanonKind::arc) {
      EXPECT_NEAR(moves[i].center[0], expected[i].centre_x, 1e-12);
      EXPECT_NEAR(moves[i].center[1], expected[i].centre_y, 1e-12);
      EXPECT_EQ(moves[i].turns, expected[i].turns);
    }
  }
}

TEST(CutterCompensation, InverseTimeBecomesTheProgrammedMovesRate) {
  // G93: F60 on the 14.142 mm entry means 848.5 mm/min; F30 on the 20 mm line 600 mm/min, for
  // the corner arc and the offset line alike (each piece would otherwise take 1/F minutes).
  const Result result =
      interpret("G21 G0 X-10 Y-10\nG93 G42.1 D2\nG1 X0 Y0 F60\nY20 F30\nG40\nG94\nM2\n");
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 4u);
  EXPECT_EQ(moves[2].kind, CanonKind::arc);
  EXPECT_NEAR(moves[1].value, 60.0 * std::sqrt(200.0), 1e-9);
  EXPECT_DOUBLE_EQ(moves[2].value, 600.0);
  EXPECT_DOUBLE_EQ(moves[3].value, 600.0);
  for (std::size_t i = 1; i < moves.size(); ++i) {
    EXPECT_EQ(moves[i].feed_mode, FeedMode::units_per_minute) << i;
  }
}

TEST(CutterCompensation, DiameterFromTheToolTableAndWarningForNone) {
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T3 P3 D4.0\n", "test.tbl");
  // G41 D3: radius 2 mm from the table; the entry ends 2 mm left of (10, 0).
  const Result with_d = interpret("G21 G0 X0 Y0\nG41 D3\nG1 X10 F100\nG40\nM2\n", options);
  ASSERT_EQ(with_d.error, "");
  EXPECT_NEAR(motion(with_d)[1].end[1], 2.0, 1e-12);
  // Without D: the tool in the spindle. Tool 0 has no diameter: a warning, moves as programmed.
  const Result none = interpret("G21 G0 X0 Y0\nG41\nG1 X10 F100\nG40\nM2\n", options);
  ASSERT_EQ(none.error, "");
  EXPECT_NEAR(motion(none)[1].end[1], 0.0, 1e-12);
  ASSERT_FALSE(none.warnings.empty());
  EXPECT_NE(none.warnings[0].message.find("not offset"), std::string::npos);
  const Result spindle = interpret("G21 T3 M6\nG0 X0 Y0\nG42\nG1 X10 F100\nG40\nM2\n", options);
  ASSERT_EQ(spindle.error, "");
  EXPECT_NEAR(motion(spindle)[1].end[1], -2.0, 1e-12);
}

TEST(CutterCompensation, LatheToolGoesOutAtItsTipNotItsNoseCentre) {
  // Tool 2: nose radius 1 mm, orientation 2 (Q2). Turning along -Z with the tool right of the
  // path puts the nose's centre at X6 (one radius off X5); the tip of an orientation 2 tool lies
  // one radius below that centre in X and in Z, so the move ends at X5 Z-11 (as rs274 gives
  // it), not at the centre's X6 Z-10.
  InterpreterOptions options;
  options.tool_table = parse_tool_table("T2 P2 D2.0 Q2\n", "test.tbl");
  const Result result =
      interpret("G18 G21 G0 X5 Z1\nG42 D2\nG1 Z-10 F100\nG40\nG0 X8\nM2\n", options);
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_NEAR(moves[1].end[0], 5.0, 1e-12);
  EXPECT_NEAR(moves[1].end[2], -11.0, 1e-12);
  // After G40 the programmed point again.
  EXPECT_NEAR(moves[2].end[0], 8.0, 1e-12);
  EXPECT_NEAR(moves[2].end[2], -10.0, 1e-12);
  // G10 L1 Q sets the orientation as the table's Q does: Q7 puts the tip below in Z only.
  const Result g10 =
      interpret("G18 G21 G10 L1 P2 R1 Q7\nG0 X5 Z1\nG42 D2\nG1 Z-10 F100\nG40\nM2\n", options);
  ASSERT_EQ(g10.error, "");
  EXPECT_NEAR(motion(g10)[1].end[0], 6.0, 1e-12);
  EXPECT_NEAR(motion(g10)[1].end[2], -11.0, 1e-12);
  const Result bad = interpret("G21\nG10 L1 P2 R1 Q10\n", options);
  EXPECT_NE(bad.error.find("a lathe tool's orientation is a whole number from 0 to 9"),
            std::string::npos)
      << bad.error;
  EXPECT_EQ(bad.line, 2);
  EXPECT_EQ(bad.column, 14);
  // In G17 a lathe tool is refused, as rs274 refuses it ("G42 with lathe tool, but plane is
  // not G18").
  const Result g17 = interpret("G17 G21\nG42 D2\n", options);
  EXPECT_NE(g17.error.find("a lathe tool (orientation 2), needs the XZ plane"), std::string::npos)
      << g17.error;
  EXPECT_EQ(g17.column, 5);
}

TEST(ModalState, M73AndM72PutUnitsDistancePlaneAndFeedBack) {
  // The subroutine works in inches, incrementally, in G18 at F20; its M73 puts the caller's
  // millimetres, absolute distances, G17 and F600 back at endsub. M70 and M72 do the same by
  // hand in the main program.
  const Result result = interpret(
      "o<pocket> sub\nM73\nG20 G91 G18 F20\nG1 X1 Z-1\no<pocket> endsub\n"
      "G21 G90 G17 G0 X0 Y0 Z0\nF600\no<pocket> call\nG1 X10 Y10\n"
      "M70\nG91 F50\nG1 X1\nM72\nG1 X20\nM2\n");
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 5u);
  EXPECT_EQ(moves[1].units, LengthUnits::inch);  // inside: 1 inch along X and down Z
  EXPECT_NEAR(moves[1].end[0], 1.0, 1e-12);
  EXPECT_NEAR(moves[1].end[2], -1.0, 1e-12);
  // Back: X10 Y10 is absolute, in mm, in G17, at F600 (not 10 inches further along at F20).
  EXPECT_EQ(moves[2].units, LengthUnits::mm);
  EXPECT_EQ(moves[2].plane, Plane::xy);
  EXPECT_NEAR(moves[2].end[0], 10.0, 1e-12);
  EXPECT_NEAR(moves[2].end[1], 10.0, 1e-12);
  EXPECT_NEAR(moves[2].end[2], -25.4, 1e-12);
  EXPECT_DOUBLE_EQ(moves[2].value, 600.0);
  EXPECT_NEAR(moves[3].end[0], 11.0, 1e-12);  // G91 X1 at F50
  EXPECT_DOUBLE_EQ(moves[3].value, 50.0);
  EXPECT_NEAR(moves[4].end[0], 20.0, 1e-12);  // after M72: absolute again, F600
  EXPECT_DOUBLE_EQ(moves[4].value, 600.0);
  EXPECT_TRUE(result.warnings.empty());
}

TEST(ModalState, RestoredFeedIsLinuxCncsOneDecimalWithAWarning) {
  // LinuxCNC's restore writes F with one decimal and S with none: F12.345 comes back as
  // F12.3, S300.4 as S300. pkm does the same and says so.
  const Result result = interpret("G21 F12.345 S300.4\nM70\nF100 S500\nM72\nG1 X1\nM2\n");
  ASSERT_EQ(result.error, "");
  const auto moves = motion(result);
  ASSERT_EQ(moves.size(), 1u);
  EXPECT_DOUBLE_EQ(moves[0].value, 12.3);
  ASSERT_EQ(result.warnings.size(), 2u);
  EXPECT_EQ(result.warnings[0].line, 4);
  EXPECT_NE(result.warnings[0].message.find("restores F12.345 as F12.3"), std::string::npos)
      << result.warnings[0].message;
  EXPECT_NE(result.warnings[1].message.find("restores S300.4 as S300"), std::string::npos)
      << result.warnings[1].message;
}

struct ErrorCase {
  std::string name;
  std::string program;
  int line;
  int column;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const ErrorCase& c) {
  return out << c.name;
}

class GcodeErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(GcodeErrors, NameLineColumnAndWhat) {
  const ErrorCase& c = GetParam();
  const Result result = interpret(c.program);
  EXPECT_NE(result.error.find(c.message), std::string::npos) << result.error;
  EXPECT_EQ(result.line, c.line) << result.error;
  EXPECT_EQ(result.column, c.column) << result.error;
}

const ErrorCase kErrors[] = {
    {"unknown_g_code", "G21\nG0 X1 G5.3\n", 2, 7, "unknown G code G5.3"},
    {"bad_character", "G21\nG1 X1 $ F100\n", 2, 7, "bad character '$'"},
    {"g_without_number", "G21\nG1 X1 G F100\n", 2, 9, "unknown word or function"},
    {"two_codes_one_group", "G21\nG0 G1 X1 F100\n", 2, 4,
     "two G codes of one modal group: G0 and G1"},
    {"two_m_codes_one_group", "M3 M4\n", 1, 4, "two M codes of one modal group: M3 and M4"},
    {"lathe_orientation_outside_g18", "G17\nG41.1 D1 L2\n", 2, 10, "needs the XZ plane (G18)"},
    {"lathe_entry_arc_not_continued",
     "G18 G21 G0 X10 Z10\nG41.1 D1 L2 F100\nG3 X5 Z5 R5\nG1 X0 Z0\nG40\n", 4, 1,
     "starts with the arc on line 3"},
    {"m72_after_m71", "G21\nM70\nM71\nM72\n", 4, 1, "M72 with no modes saved here"},
    {"m72_of_another_frame", "o<s> sub\nM72\no<s> endsub\nM70\no<s> call\n", 2, 1,
     "M72 with no modes saved here"},
    {"m72_restores_what_compensation_refuses", "G21 G17\nM70\nG18 G41.1 D1\nM72\n", 4, 1,
     "M72 cannot restore the saved modes"},
    {"multiple_words", "G0 X1 X2\n", 1, 7, "multiple X words"},
    {"arc_end_not_on_circle", "G21 G0 X0 Y0\nG2 X10 Y0 I5.5 J0 F100\n", 2, 1,
     "radius to end of arc differs from radius to start"},
    {"r_arc_too_small", "G21 G0 X0 Y0\nG2 X30 Y0 R10 F100\n", 2, 11,
     "arc radius too small to reach the end point"},
    {"arc_without_centre", "G21\nG2 X10 F100\n", 2, 1, "R, I, J, K words all missing"},
    {"undefined_named_parameter", "G0 X#<nowhere>\n", 1, 5,
     "named parameter #<nowhere> not defined"},
    {"unterminated_comment", "G0 X1 (no end\n", 1, 7, "unclosed comment"},
    {"unterminated_expression", "G0 X[1+2\n", 1, 5, "unclosed expression"},
    {"division_by_zero", "G0 X[1/0]\n", 1, 7, "attempt to divide by zero"},
    {"feed_without_rate", "G21\nG1 X10\n", 2, 1, "zero feed rate"},
    {"inverse_time_without_f", "G93 G1 X10 F1\nG1 X20\n", 2, 1, "F word missing with inverse time"},
    {"negative_sqrt", "G0 X[SQRT[-1]]\n", 1, 6, "negative argument to SQRT"},
    {"unknown_subroutine", "o<nosuch> call\n", 1, 1, "unknown subroutine o<nosuch>"},
    {"endwhile_without_while", "o1 endwhile\n", 1, 1, "endwhile without its while"},
    {"if_without_endif", "o2 if [0]\nG0 X1\n", 1, 1, "no matching elseif/else/endif"},
    {"cycle_without_r", "G21 G0 Z5\nG81 X1 Z-1 F100\n", 2, 1, "R clearance plane unspecified"},
    {"axis_words_after_g80", "G80\nX1\n", 2, 1, "no motion mode"},
    {"g10_without_p", "G10 L2 X1\n", 1, 1, "G10 needs a P word"},
    {"percent_in_the_middle", "G0 X1\n%\n", 2, 1, "'%' only opens and closes a program"},
    {"o_word_not_first", "G0 X1 o100 sub\n", 1, 7, "an O-word must come first"},
    {"compensation_twice", "G21 G41.1 D2\nG42.1 D2\n", 2, 1, "already on"},
    {"compensation_in_yz", "G19 G41.1 D2\n", 1, 5, "XY (G17) or XZ (G18) plane only"},
    {"d_without_compensation", "G21 G1 D3 X1 F100\n", 1, 8, "D word with no G41"},
    {"compensation_without_tool_table", "G21 G41 D3\n", 1, 9, "needs a tool table"},
    {"compensation_entry_too_short", "G21 G0 X0 Y0\nG41.1 D4\nG1 X1 F100\n", 3, 1,
     "entry move is not longer than the tool radius"},
    {"arc_after_compensation_off", "G21 G0 X0 Y0\nG41.1 D2\nG1 X10 F100\nG40\nG2 X20 I5\n", 5, 1,
     "must be straight"},
    {"g28_with_compensation", "G21 G41.1 D2\nG28\n", 2, 1, "cannot use G28 or G30"},
    {"cycle_with_compensation", "G21 G0 Z5\nG41.1 D2\nG81 X1 Z-1 R1 F100\n", 3, 1,
     "cannot use G81 (canned cycle)"},
    {"g53_with_compensation", "G21 G0 X0 Y0\nG41.1 D2\nG1 X10 F100\nG53 G0 X20\n", 4, 1,
     "cannot use G53"},
    {"plane_change_with_compensation", "G21 G41.1 D2\nG18\n", 2, 1, "cannot change planes"},
    {"compensated_tool_does_not_fit", "G21 G0 X0 Y-10\nG41.1 D10\nG1 X0 Y0 F100\nX10\nY1\nX0\n", 6,
     1, "cannot be cut without gouging"},
    {"xz_arc_in_a_turned_system", "G21 G10 L2 P1 R30\nG54 G0 X0 Y0 Z0\nG18 G2 X10 Z0 I5 F100\n", 3,
     5, "XZ or YZ plane (G18, G19) in a coordinate system turned by G10 L2 R30"},
    {"rotation_in_g10_l20", "G21 G10 L20 P1 X0 R30\n", 1, 19, "R is not allowed in G10 L20"},
    // LinuxCNC taps off the axis in G18 and G19 (LinuxCNC's tests/interp/g84): refused.
    {"tap_in_xz_plane", "G20 S100 M3 G18\nG0 X0 Y2 Z0\nG84 X1 Z1 Y-1 R1 F10\n", 3, 1,
     "G84 in the XZ plane (G18) is not supported"},
    {"left_hand_tap_in_yz_plane", "G20 S100 M4 G19\nG0 X2 Y0 Z0\nG74 Y1 Z1 X-1 R1 F10\n", 3, 1,
     "G74 in the YZ plane (G19) is not supported"},
    // G96's D (its spindle speed limit) is no cutter compensation's D: G96 itself is refused.
    {"css_with_its_speed_limit", "G18 G95\nG96 M3 S250 D700\n", 2, 1,
     "G96 (constant surface speed) is not supported"},
    {"return_value_is_read_only", "#<_value> = 3\n", 1, 1, "#<_value> is read-only"},
    {"return_value_of_a_definition", "o1 sub\no1 endsub [7]\nG0 X#<_value>\n", 3, 5,
     "#<_value> is not known here"},
    {"orientation_direction", "M19 R10 P3\n", 1, 9, "the direction must be 0"},
    {"orientation_wait_not_positive", "M19 Q0\n", 1, 5, "Q word with M19 requires a value > 0"},
    {"exists_of_a_fraction", "G0 X[EXISTS[#1.5]]\n", 1, 13, "in EXISTS is not a whole number"},
    {"exists_of_no_parameter", "G0 X[EXISTS[1]]\n", 1, 13, "EXISTS needs a parameter"},
    {"parameter_above_linuxcncs", "#5602 = 1\n", 1, 1, "out of range (1 to 5601)"},
};

INSTANTIATE_TEST_SUITE_P(Table, GcodeErrors, ::testing::ValuesIn(kErrors),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(GcodeErrors, MissingFileIsAnError) {
  Interpreter interpreter("/nonexistent/program.ngc");
  EXPECT_THROW(interpreter.run([](const Canon&) {}), GcodeError);
}

}  // namespace
}  // namespace pkm::gcode
