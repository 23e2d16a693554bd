// libFuzzer target: bytes as a G-code program, run to its end by the interpreter with every
// canonical command rendered as `pkm gcode --canon` renders it. Oracles: no sanitizer report, no
// exception but GcodeError, no non-finite number in a command or its text. A tool table and a
// plotter's pen lines are given, and subroutine files beside the program, so tool, event and
// subroutine-file paths are explored; the loop bounds are lowered so one input stays fast
// (tests/test_gcode_bad_input.cpp tests them at their defaults).
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "fuzz_support.hpp"
#include "pkm/gcode/canon.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/gcode/tool_table.hpp"

namespace {

// Subroutine files beside the program, so calls into files of their own are explored.
void write_subroutine_files() {
  const auto& directory = pkm::fuzz::input_directory();
  std::ofstream(directory / "sub.ngc") << "o<sub> sub\nG0 X#1\no<sub> endsub [#1]\nM2\n";
  std::ofstream(directory / "100.ngc") << "O100\nG91 G0 X1\nG90\nM99\n";
  std::ofstream(directory / "nosub.ngc") << "G0 X1\nM2\n";
}

pkm::gcode::InterpreterOptions fuzz_options() {
  write_subroutine_files();
  pkm::gcode::InterpreterOptions options;
  options.max_loop_iterations = 1000;
  options.max_program_iterations = 10000;
  options.tool_table =
      pkm::gcode::parse_tool_table("T1 P1 D6 Z10\nT2 P2 D3.175 Z25.4 X1\nT3 P3 D0 Z-5\n",
                                   "fuzz.tbl", pkm::gcode::LengthUnits::mm);
  options.event_lines = {"M280 P0 S30", "M280 P0 S90"};
  return options;
}

void check(const pkm::gcode::Canon& canon) {
  using pkm::fuzz::require_finite;
  for (const double value : canon.end) require_finite(value, "a command's end");
  require_finite(canon.center[0], "an arc's centre");
  require_finite(canon.center[1], "an arc's centre");
  require_finite(canon.value, "a command's value");
  require_finite(canon.value2, "a command's second value");
  const std::string text = pkm::gcode::canon_text(canon);
  if (canon.kind != pkm::gcode::CanonKind::comment &&
      canon.kind != pkm::gcode::CanonKind::message && canon.kind != pkm::gcode::CanonKind::event) {
    pkm::fuzz::require_no_non_finite_text(text);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const pkm::gcode::InterpreterOptions options = fuzz_options();
  const auto path = pkm::fuzz::input_file(data, size, ".ngc");
  try {
    pkm::gcode::Interpreter interpreter(path, options);
    interpreter.run(check);
  } catch (const pkm::gcode::GcodeError&) {
    // A located error: an expected end.
  }
  return 0;
}
