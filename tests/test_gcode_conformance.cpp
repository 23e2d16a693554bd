// Differential test against LinuxCNC's rs274: every program of the real corpus, and the
// project's own test programs, must give the same motion (STRAIGHT_TRAVERSE, STRAIGHT_FEED,
// STRAIGHT_PROBE, ARC_FEED, DWELL, RIGID_TAP, the spindle synchronisation's start and stop, the
// override locks of the tapping and threading cycles and the spindle's turning within them, the
// spindle's orientation, M19) as
// `rs274 -t TOOLTABLE -g`, line for line, numbers within one unit of the fourth decimal rs274
// prints. Where rs274 stops with an error, its motion up to there counts.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "real_corpus.hpp"

namespace pkm::gcode {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = PKM_SOURCE_DIR;
const fs::path kCorpus = pkm::test::real_corpus();  // absent in a plain clone: nothing listed
const std::string kOwnPrefix = "tests/gcode/";
const fs::path kOwn = kSource / "tests" / "gcode";
const fs::path kToolTable = kSource / "tests" / "conformance" / "conformance.tbl";
// The subroutine files the project's own programs call (LinuxCNC's SUBROUTINE_PATH): not
// programs of their own.
const fs::path kOwnSubroutines = kOwn / "subroutines";

struct Program {
  std::string name;  // path relative to its corpus, as in unsupported.txt
  fs::path path;
};

void PrintTo(const Program& program, std::ostream* out) {
  *out << program.name;
}

// rs274 refuses a program without an end, but its motion up to there still counts.
bool refused_for_missing_end(const std::string& error) {
  return error.find("File ended with no percent sign or program end") != std::string::npos;
}

std::vector<Program> programs() {
  std::vector<Program> found;
  for (const fs::path& root : {kCorpus, kOwn}) {
    if (!fs::exists(root)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
      if (!entry.is_regular_file() || entry.path().filename() == "SOURCES.md") continue;
      if (entry.path().parent_path() == kOwnSubroutines) continue;
      const std::string relative = fs::relative(entry.path(), root).string();
      found.push_back({root == kOwn ? kOwnPrefix + relative : relative, entry.path()});
    }
  }
  std::sort(found.begin(), found.end(),
            [](const Program& a, const Program& b) { return a.name < b.name; });
  return found;
}

std::map<std::string, std::string> unsupported() {
  std::map<std::string, std::string> listed;
  std::ifstream in(kSource / "tests" / "conformance" / "unsupported.txt");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto bar = line.find(" | ");
    listed[line.substr(0, bar)] = bar == std::string::npos ? "" : line.substr(bar + 3);
  }
  return listed;
}

bool starts_with(const std::string& text, const char* start) {
  return text.rfind(start, 0) == 0;
}

// Which commands are compared. The spindle's commands count inside the tapping cycles (between
// their override locks), where the spindle's reversal is the cycle's: elsewhere rs274 adds stops
// of its own (at tool changes) that are no motion.
class MotionFilter {
 public:
  bool keep(const std::string& text) {
    static const char* const kMotion[] = {"STRAIGHT_TRAVERSE(",
                                          "STRAIGHT_FEED(",
                                          "STRAIGHT_PROBE(",
                                          "ARC_FEED(",
                                          "DWELL(",
                                          "RIGID_TAP(",
                                          "START_SPEED_FEED_SYNC(",
                                          "STOP_SPEED_FEED_SYNCH(",
                                          "ENABLE_SPEED_OVERRIDE(",
                                          "DISABLE_SPEED_OVERRIDE(",
                                          "ORIENT_SPINDLE(",
                                          "SPINDLE.0.WAIT_ORIENT_COMPLETE("};
    if (starts_with(text, "DISABLE_FEED_OVERRIDE(")) return locked_ = true;
    if (starts_with(text, "ENABLE_FEED_OVERRIDE(")) {
      locked_ = false;
      return true;
    }
    for (const char* start : kMotion) {
      if (starts_with(text, start)) return true;
    }
    return locked_ && (starts_with(text, "START_SPINDLE_") || starts_with(text, "STOP_SPINDLE_"));
  }

 private:
  bool locked_ = false;
};

struct ProgramRun {
  std::vector<std::string> motion;
  std::string error;  // empty when the program ran to its end
};

std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

ProgramRun run_rs274(const fs::path& program) {
  ProgramRun run;
  const fs::path errors =
      fs::temp_directory_path() / ("pkm-rs274-" + std::to_string(::getpid()) + ".err");
  // An INI file gives rs274 the own programs' subroutine path.
  const fs::path ini =
      fs::temp_directory_path() / ("pkm-rs274-" + std::to_string(::getpid()) + ".ini");
  std::ofstream(ini) << "[RS274NGC]\nSUBROUTINE_PATH = " << kOwnSubroutines.string() << "\n";
  const std::string command = "rs274 -t " + shell_quote(kToolTable.string()) + " -i " +
                              shell_quote(ini.string()) + " -g " + shell_quote(program.string()) +
                              " 2>" + shell_quote(errors.string());
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) {
    run.error = "cannot start rs274";
    return run;
  }
  // "   12 N..... STRAIGHT_FEED(...)": the command follows the sequence number and N label.
  static const std::regex kLine(R"(^\s*\d+ N\S*\s+(.*)$)");
  MotionFilter filter;
  char buffer[4096];
  std::string line;
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) {
    line += buffer;
    if (line.empty() || line.back() != '\n') continue;
    line.pop_back();
    std::smatch match;
    if (std::regex_match(line, match, kLine) && filter.keep(match[1])) {
      run.motion.push_back(match[1]);
    }
    line.clear();
  }
  const int status = ::pclose(pipe);
  std::ifstream error_file(errors);
  std::stringstream error_text;
  error_text << error_file.rdbuf();
  fs::remove(errors);
  fs::remove(ini);
  if (status != 0) run.error = error_text.str().empty() ? "rs274 failed" : error_text.str();
  return run;
}

ProgramRun run_pkm(const fs::path& program) {
  ProgramRun run;
  InterpreterOptions options;
  options.tool_table = read_tool_table(kToolTable, LengthUnits::inch);  // as rs274 reads it
  options.subroutine_path = {kOwnSubroutines};
  Interpreter interpreter(program, options);
  MotionFilter filter;
  try {
    interpreter.run([&](const Canon& canon) {
      if (canon.kind == CanonKind::comment || canon.kind == CanonKind::message) return;
      std::string text = canon_text(canon);
      if (filter.keep(text)) run.motion.push_back(std::move(text));
    });
  } catch (const GcodeError& error) {
    run.error = error.what();
  }
  return run;
}

// Same command, same numbers within one unit of the printed fourth decimal.
bool same_line(const std::string& a, const std::string& b) {
  if (a == b) return true;
  const auto open_a = a.find('('), open_b = b.find('(');
  if (a.substr(0, open_a) != b.substr(0, open_b)) return false;
  std::istringstream in_a(a.substr(open_a + 1)), in_b(b.substr(open_b + 1));
  std::string token_a, token_b;
  while (std::getline(in_a, token_a, ',')) {
    if (!std::getline(in_b, token_b, ',')) return false;
    const double x = std::strtod(token_a.c_str(), nullptr),
                 y = std::strtod(token_b.c_str(), nullptr);
    if (std::abs(x - y) > 1.01e-4) return false;
  }
  return !std::getline(in_b, token_b, ',');
}

// The first difference, or empty when the motion matches.
std::string compare(const ProgramRun& reference, const ProgramRun& ours) {
  const std::size_t count = reference.motion.size();
  // A program rs274 runs to its end must run to its end here too, even when what pkmkit
  // refuses comes after the last move.
  if (reference.error.empty() && !ours.error.empty()) return "pkmkit refuses it: " + ours.error;
  if (reference.error.empty() && ours.motion.size() != count) {
    return "rs274 moves " + std::to_string(count) + " times, pkmkit " +
           std::to_string(ours.motion.size()) + (ours.error.empty() ? "" : " (" + ours.error + ")");
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (i >= ours.motion.size()) {
      return "pkmkit stops after " + std::to_string(i) + " moves: " + ours.error;
    }
    if (!same_line(reference.motion[i], ours.motion[i])) {
      return "move " + std::to_string(i + 1) + ": rs274 " + reference.motion[i] + ", pkmkit " +
             ours.motion[i];
    }
  }
  return {};
}

class Conformance : public ::testing::TestWithParam<Program> {};

TEST_P(Conformance, MotionMatchesRs274) {
  const Program& program = GetParam();
  ASSERT_EQ(std::system("command -v rs274 >/dev/null 2>&1"), 0)
      << "LinuxCNC's rs274 is not installed (scripts/setup installs linuxcnc-uspace)";
  const ProgramRun reference = run_rs274(program.path);
  const ProgramRun ours = run_pkm(program.path);
  const std::string difference = compare(reference, ours);
  const auto listed = unsupported();
  const auto entry = listed.find(program.name);
  if (entry == listed.end()) {
    EXPECT_EQ(difference, "") << program.name
                              << (reference.error.empty() ? "" : "\nrs274: " + reference.error);
  } else if (!reference.error.empty() && !refused_for_missing_end(reference.error)) {
    // rs274 itself refuses the program: there is nothing to compare beyond its first moves,
    // and those must match.
    EXPECT_EQ(difference, "") << program.name << "\nrs274: " << reference.error;
    std::cout << "[ refused  ] " << program.name << ": " << entry->second << "\n";
  } else {
    EXPECT_NE(difference, "") << program.name
                              << " now matches rs274: remove it from "
                                 "tests/conformance/unsupported.txt";
    std::cout << "[ listed   ] " << program.name << ": " << entry->second << "\n";
  }
}

// unsupported.txt names programs that exist, each with a reason: the project's own here, the
// real corpus's in ConformanceList.RealCorpus.
void expect_listed_programs_exist(bool from_real_corpus) {
  std::set<std::string> names;
  for (const Program& program : programs()) names.insert(program.name);
  for (const auto& [name, reason] : unsupported()) {
    if ((name.rfind(kOwnPrefix, 0) != 0) != from_real_corpus) continue;
    EXPECT_TRUE(names.count(name)) << name << " is listed but not in the corpus";
    EXPECT_FALSE(reason.empty()) << name << " is listed without a reason";
  }
}

TEST(ConformanceList, NamesOnlyExistingOwnPrograms) {
  expect_listed_programs_exist(false);
}

// Stands for the rs274 comparison of every real program, which a plain clone cannot run.
TEST(ConformanceList, RealCorpus) {
  PKM_SKIP_WITHOUT_REAL_CORPUS();
  expect_listed_programs_exist(true);
  const auto programs_found = programs();
  const auto real_programs =
      std::count_if(programs_found.begin(), programs_found.end(),
                    [](const Program& program) { return program.name.rfind(kOwnPrefix, 0) != 0; });
  EXPECT_GE(real_programs, 54) << "programs missing from " << kCorpus;
}

INSTANTIATE_TEST_SUITE_P(Corpus, Conformance, ::testing::ValuesIn(programs()),
                         [](const auto& test_info) {
                           std::string name = test_info.param.name;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace pkm::gcode
