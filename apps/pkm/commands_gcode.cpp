// pkm gcode: what a job does (units, box, path by kind of motion, feeds, tools, warnings), or with
// --canon its canonical commands in the text form of `rs274 -g`.
#include <cstdio>
#include <memory>

#include "app.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/motion/job_summary.hpp"

namespace pkm::app {

namespace {

struct GcodeOptions {
  std::string program;
  std::string tool_table;
  std::string tool_table_units = "mm";
  bool canon = false;
  bool block_delete = false;
  std::vector<std::filesystem::path> subroutine_path;
  double orient_offset_deg = 0.0;
};

void print_warnings(const std::string& program, const std::vector<gcode::Warning>& warnings) {
  for (const gcode::Warning& warning : warnings) {
    std::fprintf(stderr, "pkm: warning: %s:%d: %s\n", program.c_str(), warning.line,
                 warning.message.c_str());
  }
}

void print_box(const char* label, const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) {
    std::printf("  %-12s none\n", label);
    return;
  }
  std::printf("  %-12s x %.3f .. %.3f, y %.3f .. %.3f, z %.3f .. %.3f mm\n", label, box.min().x(),
              box.max().x(), box.min().y(), box.max().y(), box.min().z(), box.max().z());
}

void print_summary(const std::string& program, const motion::JobSummary& job) {
  std::string units;
  for (const gcode::LengthUnits u : job.units) {
    units += std::string(units.empty() ? "" : " and ") +
             (u == gcode::LengthUnits::inch ? "inch (G20)" : "mm (G21)");
  }
  std::printf("%s: %d moves, written in %s; below in mm, from X0 Y0 Z0 with the job's offsets\n",
              program.c_str(), job.moves, units.empty() ? "no units (no moves)" : units.c_str());
  print_box("box", job.box);
  print_box("feed box", job.feed_box);
  std::printf("  %-12s rapid %.3f mm, feed %.3f mm, arc %.3f mm (total %.3f mm)\n", "path",
              job.rapid_mm, job.feed_mm, job.arc_mm, job.rapid_mm + job.feed_mm + job.arc_mm);
  if (job.angles_deg > 0.0) {
    std::printf("  %-12s %.3f deg of moves that turn A B C alone\n", "turns", job.angles_deg);
  }
  if (job.max_feed_mm_per_min > 0.0) {
    std::printf("  %-12s F %.1f .. %.1f mm/min%s\n", "feeds", job.min_feed_mm_per_min,
                job.max_feed_mm_per_min, job.inverse_time ? ", and inverse time (G93)" : "");
  } else if (job.inverse_time) {
    std::printf("  %-12s inverse time (G93)\n", "feeds");
  }
  std::string tools;
  for (const int tool : job.tools) tools += (tools.empty() ? "T" : ", T") + std::to_string(tool);
  std::printf("  %-12s %s\n", "tools", tools.empty() ? "none named" : tools.c_str());
  if (job.dwell_s > 0.0) std::printf("  %-12s %.3f s\n", "dwells", job.dwell_s);
  std::printf("  %-12s %zu%s\n", "warnings", job.warnings.size(),
              job.warnings.empty() ? "" : " (on stderr)");
}

// The lines of `rs274 -g`, gathered in one buffer written out when it fills: a printf per line
// cost more than the interpreter (issue 16). No allocation per command once the buffer and the
// longest command have been seen.
class CanonPrinter {
 public:
  CanonPrinter() {
    // The preamble rs274 prints when its canonical interface starts.
    for (const char* text :
         {"USE_LENGTH_UNITS(CANON_UNITS_MM)",
          "SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
          "SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
          "SET_XY_ROTATION(0.0000)", "SET_FEED_REFERENCE(CANON_XYZ)", "ON_RESET()"}) {
      gcode::append_canon_line_start(++sequence_, "", buffer_);
      buffer_.append(text);
      buffer_.push_back('\n');
    }
  }
  ~CanonPrinter() { flush(); }  // what was printed before an exception
  CanonPrinter(const CanonPrinter&) = delete;
  CanonPrinter& operator=(const CanonPrinter&) = delete;
  void print(const gcode::Canon& canon) {
    gcode::append_canon_line_start(++sequence_, canon.n_label, buffer_);
    gcode::append_canon_text(canon, buffer_);
    buffer_.push_back('\n');
    if (buffer_.size() >= kFlushBytes) flush();
  }
  void flush() {
    if (!buffer_.empty()) std::fwrite(buffer_.view().data(), 1, buffer_.size(), stdout);
    std::fflush(stdout);
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kFlushBytes = std::size_t{1} << 16;
  text::TextBuffer buffer_{kFlushBytes + 4096};
  int sequence_ = 0;
};

void run_summary(const GcodeOptions& options,
                 const gcode::InterpreterOptions& interpreter_options) {
  const motion::JobSummary job = motion::summarize_job(options.program, interpreter_options);
  print_warnings(options.program, job.warnings);
  print_summary(options.program, job);
}

void run_gcode(const GcodeOptions& options) {
  gcode::InterpreterOptions interpreter_options;
  interpreter_options.block_delete = options.block_delete;
  interpreter_options.subroutine_path = options.subroutine_path;
  interpreter_options.orient_offset_deg = options.orient_offset_deg;
  try {
    if (!options.tool_table.empty()) {
      interpreter_options.tool_table = gcode::read_tool_table(
          options.tool_table,
          options.tool_table_units == "inch" ? gcode::LengthUnits::inch : gcode::LengthUnits::mm);
    }
    if (!options.canon) {
      run_summary(options, interpreter_options);
      return;
    }
    gcode::Interpreter interpreter(options.program, interpreter_options);
    CanonPrinter printer;
    std::string error;
    try {
      interpreter.run([&](const gcode::Canon& canon) { printer.print(canon); });
    } catch (const gcode::GcodeError& failure) {
      error = failure.what();
    }
    printer.flush();
    print_warnings(options.program, interpreter.warnings());
    if (!error.empty()) throw CommandError(error);
  } catch (const gcode::GcodeError& failure) {
    throw CommandError(failure.what());
  }
}

}  // namespace

void register_gcode_commands(CLI::App& app) {
  auto options = std::make_shared<GcodeOptions>();
  CLI::App* command = app.add_subcommand(
      "gcode",
      "Interpret a G-code program as LinuxCNC does: what it does (units, box, path, feeds, tools, "
      "warnings), or its canonical commands");
  command->add_flag("--canon", options->canon,
                    "Print the canonical commands as LinuxCNC's rs274 -g does");
  command->add_option("--tool-table", options->tool_table, "LinuxCNC tool table (.tbl)");
  command
      ->add_option("--tool-table-units", options->tool_table_units,
                   "Units of the tool table's lengths: mm (default) or inch (as LinuxCNC's "
                   "stand-alone rs274 reads them)")
      ->check(CLI::IsMember({"mm", "inch"}));
  command->add_flag("--block-delete", options->block_delete, "Skip lines starting with '/'");
  add_subroutine_path_option(*command, options->subroutine_path);
  command
      ->add_option("--orient-offset", options->orient_offset_deg,
                   "Degrees added to M19's R, as LinuxCNC's [RS274NGC] ORIENT_OFFSET (default 0)")
      ->check(CLI::Range(-360.0, 360.0));
  command->add_option("program", options->program, "The G-code file")->required();
  command->callback([options] { run_gcode(*options); });
}

}  // namespace pkm::app
