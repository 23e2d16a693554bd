// pkm gcode --canon: the canonical commands of a program, in the text form of `rs274 -g`.
#include <cstdio>
#include <memory>

#include "app.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"

namespace pkm::app {

namespace {

struct GcodeOptions {
  std::string program;
  std::string tool_table;
  std::string tool_table_units = "mm";
  bool canon = false;
  bool block_delete = false;
};

void run_gcode(const GcodeOptions& options) {
  if (!options.canon) throw CommandError("pkm gcode: give --canon (the only output so far)");
  gcode::InterpreterOptions interpreter_options;
  interpreter_options.block_delete = options.block_delete;
  try {
    if (!options.tool_table.empty()) {
      interpreter_options.tool_table = gcode::read_tool_table(
          options.tool_table,
          options.tool_table_units == "inch" ? gcode::LengthUnits::inch : gcode::LengthUnits::mm);
    }
    gcode::Interpreter interpreter(options.program, interpreter_options);
    // The preamble rs274 prints when its canonical interface starts.
    int sequence = 0;
    const auto print = [&](const std::string& label, const std::string& text) {
      std::printf("%5d N%-5s %s\n", ++sequence, label.empty() ? "....." : label.c_str(),
                  text.c_str());
    };
    print("", "USE_LENGTH_UNITS(CANON_UNITS_MM)");
    print("", "SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)");
    print("", "SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)");
    print("", "SET_XY_ROTATION(0.0000)");
    print("", "SET_FEED_REFERENCE(CANON_XYZ)");
    print("", "ON_RESET()");
    std::string error;
    try {
      interpreter.run(
          [&](const gcode::Canon& canon) { print(canon.n_label, gcode::canon_text(canon)); });
    } catch (const gcode::GcodeError& failure) {
      error = failure.what();
    }
    std::fflush(stdout);
    for (const gcode::Warning& warning : interpreter.warnings()) {
      std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", options.program.c_str(), warning.line,
                   warning.message.c_str());
    }
    if (!error.empty()) throw CommandError(error);
  } catch (const gcode::GcodeError& failure) {
    throw CommandError(failure.what());
  }
}

}  // namespace

void register_gcode_commands(CLI::App& app) {
  auto options = std::make_shared<GcodeOptions>();
  CLI::App* command = app.add_subcommand("gcode", "Interpret a G-code program as LinuxCNC does");
  command->add_flag("--canon", options->canon,
                    "Print the canonical commands as LinuxCNC's rs274 -g does");
  command->add_option("--tool-table", options->tool_table, "LinuxCNC tool table (.tbl)");
  command
      ->add_option("--tool-table-units", options->tool_table_units,
                   "Units of the tool table's lengths: mm (default) or inch (as LinuxCNC's "
                   "stand-alone rs274 reads them)")
      ->check(CLI::IsMember({"mm", "inch"}));
  command->add_flag("--block-delete", options->block_delete, "Skip lines starting with '/'");
  command->add_option("program", options->program, "The G-code file")->required();
  command->callback([options] { run_gcode(*options); });
}

}  // namespace pkm::app
