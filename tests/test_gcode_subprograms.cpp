// Subroutines in files of their own (found beside the program or on the subroutine path),
// Fanuc-style O-number programs called by M98 and ended by M99, and fractional line numbers: the
// behaviour rs274 shows, by hand, and every refusal located in the file it comes from.
// (tests/gcode/subroutine-files.ngc, fanuc-subprograms.ngc and line-numbers.ngc compare the
// same features with rs274 move for move in the conformance test.)
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"

namespace pkm::gcode {
namespace {

namespace fs = std::filesystem;

// A directory of program files, removed with the object.
class ProgramDirectory {
 public:
  explicit ProgramDirectory(const std::map<std::string, std::string>& files) {
    static int counter = 0;
    path_ = fs::temp_directory_path() /
            ("pkm-subprograms-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    for (const auto& [name, text] : files) {
      fs::create_directories((path_ / name).parent_path());
      std::ofstream(path_ / name, std::ios::binary) << text;
    }
  }
  ~ProgramDirectory() { fs::remove_all(path_); }
  ProgramDirectory(const ProgramDirectory&) = delete;
  ProgramDirectory& operator=(const ProgramDirectory&) = delete;
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

struct Outcome {
  std::vector<Canon> moves;  // traverses and feeds
  std::vector<Canon> all;
  std::string error, error_file;
  int line = 0, column = 0;
};

Outcome run(const fs::path& program, InterpreterOptions options = {}) {
  Outcome result;
  Interpreter interpreter(program, std::move(options));
  try {
    interpreter.run([&](const Canon& canon) {
      result.all.push_back(canon);
      if (canon.kind == CanonKind::traverse || canon.kind == CanonKind::feed) {
        result.moves.push_back(canon);
      }
    });
  } catch (const GcodeError& error) {
    result.error = error.message();
    result.error_file = error.file();
    result.line = error.line();
    result.column = error.column();
  }
  return result;
}

Outcome run_text(const std::string& program) {
  ProgramDirectory directory({{"main.ngc", program}});
  return run(directory / "main.ngc");
}

std::vector<double> xs(const Outcome& result) {
  std::vector<double> values;
  for (const Canon& move : result.moves) values.push_back(move.end[0]);
  return values;
}

TEST(SubroutineFiles, FoundBesideTheProgramThenOnThePathInOrder) {
  ProgramDirectory directory({
      {"main.ngc", "o<edge> call [3]\nG0 Y#<_value>\nM2\n"},
      // Beside the program: found first, whatever the path says.
      {"edge.ngc",
       "G0 X99 (before the sub line: never run)\no<edge> sub\nG0 X#1\n"
       "o<edge> endsub [[#1 * 2]]\nM2\n"},
      {"library/edge.ngc", "o<edge> sub\nG0 X-1\no<edge> endsub\nM2\n"},
      {"library/pocket.ngc", "o<pocket> sub\nG0 X7\no<pocket> endsub\nM2\n"},
      {"second/pocket.ngc", "o<pocket> sub\nG0 X-7\no<pocket> endsub\nM2\n"},
      {"uses_library.ngc", "o<pocket> call\nM2\n"},
  });
  const Outcome beside = run(directory / "main.ngc", {});
  ASSERT_EQ(beside.error, "");
  EXPECT_EQ(xs(beside), (std::vector<double>{3.0, 3.0}));
  EXPECT_EQ(beside.moves[1].end[1], 6.0);  // the value returned by endsub
  InterpreterOptions options;
  options.subroutine_path = {directory / "library", directory / "second"};
  const Outcome on_path = run(directory / "uses_library.ngc", options);
  ASSERT_EQ(on_path.error, "");
  EXPECT_EQ(xs(on_path), (std::vector<double>{7.0}));
  // Without the path the program cannot find it, and says where it looked.
  const Outcome without = run(directory / "uses_library.ngc", {});
  EXPECT_NE(without.error.find("unknown subroutine o<pocket>"), std::string::npos);
  EXPECT_NE(without.error.find((directory / "pocket.ngc").string()), std::string::npos);
  EXPECT_EQ(without.line, 1);
}

TEST(SubroutineFiles, ErrorsNameTheSubroutinesFileAndLine) {
  ProgramDirectory directory({
      {"main.ngc", "G21\no<broken> call\nM2\n"},
      {"broken.ngc", "o<broken> sub\nG0 X1\nG1 X2 (no feed)\no<broken> endsub\nM2\n"},
      {"empty_main.ngc", "o<empty> call\nM2\n"},
      {"empty.ngc", "(a file of that name without the subroutine)\nM2\n"},
  });
  const Outcome broken = run(directory / "main.ngc");
  EXPECT_EQ(broken.error_file, (directory / "broken.ngc").string());
  EXPECT_EQ(broken.line, 3);
  EXPECT_NE(broken.error.find("zero feed rate"), std::string::npos) << broken.error;
  const Outcome empty = run(directory / "empty_main.ngc");
  EXPECT_EQ(empty.error_file, (directory / "empty_main.ngc").string());
  EXPECT_NE(empty.error.find("empty.ngc has no o<empty> sub line"), std::string::npos)
      << empty.error;
}

TEST(SubroutineFiles, NamesThatAreNoFileNameAreLookedForNowhere) {
  ProgramDirectory directory({
      {"dir/main.ngc", "o<../outside> call\nM2\n"},
      {"outside.ngc", "o<../outside> sub\nG0 X1\no<../outside> endsub\nM2\n"},
  });
  const Outcome result = run(directory / "dir/main.ngc");
  EXPECT_NE(result.error.find("unknown subroutine o<../outside>"), std::string::npos)
      << result.error;
}

TEST(FanucPrograms, CallsRepeatsAndSharedNumberedParameters) {
  const Outcome result = run_text(
      "O1 (main)\n#1=2\nM98 P100 L3\nG0 Y#1\nM98 P0100 L0\nM98 P200\nG0 Z#1\nM30\n"
      "O100\nG91 G0 X1\nG90\n#1=[#1+1]\nM99\n"
      "O0200\n#<local>=4\n#1=#<local>\nM99\n");
  ASSERT_EQ(result.error, "");
  // Three runs of O100 (L3), each adding one to the caller's #1; L0 calls nothing; O200's
  // #<local> is its own but #1 is the caller's.
  ASSERT_EQ(result.moves.size(), 5u);
  EXPECT_EQ(xs(result), (std::vector<double>{1.0, 2.0, 3.0, 3.0, 3.0}));
  EXPECT_EQ(result.moves[3].end[1], 5.0);
  EXPECT_EQ(result.moves[4].end[2], 4.0);
}

TEST(FanucPrograms, M99InTheMainProgramEndsIt) {
  const Outcome result = run_text("G0 X1 M99\nG0 X2\nM30\n");
  ASSERT_EQ(result.error, "");
  EXPECT_EQ(xs(result), (std::vector<double>{1.0}));
  EXPECT_EQ(result.all.back().kind, CanonKind::program_end);
}

TEST(FanucPrograms, AProgramNumberRunIntoIsNothing) {
  // rs274 runs the lines after an O-number it reaches without M98, and M99 then ends the program.
  const Outcome result = run_text("G0 X1\nO100\nG0 X2\nM99\nG0 X3\nM30\n");
  ASSERT_EQ(result.error, "");
  EXPECT_EQ(xs(result), (std::vector<double>{1.0, 2.0}));
}

TEST(FanucPrograms, InTheirOwnFile) {
  ProgramDirectory directory({
      {"main.ngc", "M98 P777\nG0 Y1\nM30\n"},
      {"777.ngc", "O777 (tool change position)\nG0 X7\nM99\n"},
  });
  const Outcome result = run(directory / "main.ngc");
  ASSERT_EQ(result.error, "");
  EXPECT_EQ(xs(result), (std::vector<double>{7.0, 7.0}));
}

TEST(FanucPrograms, RecursionStopsAtLinuxCncsCallDepth) {
  const Outcome result = run_text("M98 P1\nM30\nO1\nG91 G0 X1\nM98 P1\nM99\n");
  EXPECT_NE(result.error.find("M98 P1: subroutine calls nested deeper than 9"), std::string::npos)
      << result.error;
  EXPECT_EQ(result.moves.size(), 9u);
  EXPECT_EQ(result.line, 5);
}

struct ErrorCase {
  std::string name, program;
  int line, column;
  std::string message;
};

std::ostream& operator<<(std::ostream& out, const ErrorCase& c) {
  return out << c.name;
}

class SubprogramErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(SubprogramErrors, LineColumnAndWhat) {
  const ErrorCase& c = GetParam();
  const Outcome result = run_text(c.program);
  EXPECT_NE(result.error.find(c.message), std::string::npos) << result.error;
  EXPECT_EQ(result.line, c.line) << result.error;
  EXPECT_EQ(result.column, c.column) << result.error;
}

const ErrorCase kSubprogramErrors[] = {
    {"m98_without_p", "M98\nM30\n", 1, 1, "M98 needs a P word"},
    {"m98_fractional_p", "M98 P1.5\nM30\n", 1, 5, "whole number from 0 to 999999999"},
    {"m98_negative_l", "M98 P1 L-1\nM30\nO1\nM99\n", 1, 8, "repeat count must be a whole number"},
    {"m98_fractional_l", "M98 P1 L2.5\nM30\nO1\nM99\n", 1, 8, "repeat count must be a whole"},
    {"m98_endless_l", "M98 P1 L[10**9]\nM30\nO1\nM99\n", 1, 8, "more than the 100000 iterations"},
    {"m98_with_motion", "G0 X1 M98 P1\nM30\nO1\nM99\n", 1, 7, "M98 takes only its P and L words"},
    {"m98_with_another_m_code", "M98 P1 M3\nM30\nO1\nM99\n", 1, 1, "M98 takes only its P and L"},
    {"m98_unknown_program", "M98 P777\nM30\n", 1, 5, "unknown program O777"},
    {"m98_of_a_subroutine", "M98 P100\nM30\no100 sub\no100 endsub\n", 1, 5,
     "o100 is a subroutine (o100 sub): call it with o100 call, not M98"},
    {"call_of_a_fanuc_program", "o100 call\nM30\nO100\nM99\n", 1, 1,
     "O100 is a Fanuc-style program: call it with M98 P100"},
    {"m99_in_a_subroutine", "o1 call\nM2\no1 sub\nM99\no1 endsub\n", 4, 1,
     "M99 in o1, a subroutine called by o1 call"},
    {"endsub_in_a_fanuc_program", "M98 P1\nM30\nO1\no1 endsub\n", 4, 1,
     "o1 endsub in O1, an M98 program: M99 ends it"},
    {"m99_with_p", "M98 P1\nM30\nO1\nM99 P5\n", 4, 5, "P word with no"},
    {"o_number_with_words", "O100 G0 X1\nM2\n", 1, 6, "unknown O-word keyword"},
};

INSTANTIATE_TEST_SUITE_P(Table, SubprogramErrors, ::testing::ValuesIn(kSubprogramErrors),
                         [](const auto& test_info) { return test_info.param.name; });

TEST(LineNumbers, FractionalOnesAreReadAndLabelTheLineByTheirWholePart) {
  const Outcome result = run_text("N10 G21 G0 X1\nN10.5 G0 X2\nN 10 . 75 G0 X3\nM2\n");
  ASSERT_EQ(result.error, "");
  ASSERT_EQ(result.moves.size(), 3u);
  EXPECT_EQ(result.moves[1].n_label, "10");  // rs274 prints N10 for N10.5
  EXPECT_EQ(result.moves[2].end[0], 3.0);
}

}  // namespace
}  // namespace pkm::gcode
