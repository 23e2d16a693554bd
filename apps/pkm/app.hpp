// Shared pieces of the command-line layer.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "pkm/gcode/tool_table.hpp"

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::app {

// A failure the user caused (bad pose, unreachable target): message to stderr, exit status 1.
class CommandError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The machine named by -m, or the embedded default (the paper's hexapod) when none is given.
machine::Machine load_machine_or_default(const std::string& path);

// Every length typed on the command line (poses, --origin, --start, tolerances, resolutions,
// jerk) is in the machine file's units (`units`: mm or inch), angles in degrees, as ik, fk and
// check print them (docs/machine-file.md). These turn them into mm and rad.

// x y z [a b c] in the machine file's units and deg from the command line; missing coordinates
// take the home pose's.
geometry::Pose pose_from_arguments(const machine::Machine& machine,
                                   const std::vector<double>& values);

// `base` (mm, rad) with its leading coordinates replaced by `values` (x y z a b c, in the machine
// file's units and deg), as --origin places a job.
geometry::Vector6d pose_vector_over(const machine::Machine& machine, geometry::Vector6d base,
                                    const std::vector<double>& values);

// A length (or a length per s, per s^2, per s^3) typed in the machine file's units, in mm.
double mm_from_machine_units(const machine::Machine& machine, double value);

// --tool-table FILE and --tool-table-units mm|inch, as plan, post and verify take them.
struct ToolTableOptions {
  std::string path;
  std::string units;  // "mm", "inch", or "" for the machine file's units
};
void add_tool_table_options(CLI::App& command, ToolTableOptions& options);

// --subroutine-path DIR (repeated, or DIR:DIR): where `o<name> call` and M98 look for name.ngc
// when the program does not define it, after the program's own directory.
void add_subroutine_path_option(CLI::App& command, std::vector<std::filesystem::path>& directories);
// The table the options name, or none without a file. Throws gcode::GcodeError (file:line).
std::optional<gcode::ToolTable> read_tool_table(const machine::Machine& machine,
                                                const ToolTableOptions& options);

// The one check of every number read from the command line: it must parse whole, be finite and
// lie within [min, max]. CLI11's own range checks let NaN through. For an option of several
// numbers it checks each.
CLI::Validator number_in(double min, double max);

// Largest coordinate accepted from the command line, mm or inch (and deg for a b c): far beyond any
// machine, small enough that no arithmetic on it overflows.
inline constexpr double kMaxCoordinate = 1e6;
// Tolerances on the tool tip's path (post, verify), in the machine file's units: finer than any
// machine can resolve is refused, because the work to honour it grows without end.
inline constexpr double kMinTolerance = 1e-4, kMaxTolerance = 1000.0;
// post's tolerance when none is given, mm (whatever the machine file's units).
inline constexpr double kDefaultTolerance_mm = 0.01;

// x y [z [a b c]] options such as --origin and --start (the machine file's units, deg): 2 to 6
// numbers, each checked.
CLI::Option* add_pose_option(CLI::App& command, const std::string& name,
                             std::vector<double>& values, const std::string& description);

// Refuses to write `output` over one of the inputs ({what, path}: "the job", "job.ngc"): the same
// file by any path. Inputs that are empty are skipped.
void refuse_overwriting_input(const std::string& output,
                              std::initializer_list<std::pair<std::string, std::string>> inputs);

// `pkm check -m MACHINE JOB`: the certified check of a job (commands_certify.cpp).
struct CertifiedCheckArguments {
  std::string job;
  std::vector<double> origin;  // x y [z [a b c]], the machine file's units and deg
  bool json = false;
};
void run_certified_check(const machine::Machine& machine, const CertifiedCheckArguments& arguments);

// "12.3 MB": a size in the unit that keeps it short.
std::string size_text(double bytes);

// An output's file name from the command line: "" (--html "") is refused when parsing.
CLI::Validator file_name();

// An output of a command: the option that names it ("--html") and the path, "" when not given.
struct OutputTarget {
  std::string option;
  std::string path;
};
// Refuses, before any work is done, outputs that could only fail at the end: two options naming
// the same file, a directory, a file in a directory that does not exist or cannot be written.
void check_outputs(std::initializer_list<OutputTarget> outputs);

void register_kinematics_commands(CLI::App& app);
void register_calibrate_commands(CLI::App& app);
void register_gcode_commands(CLI::App& app);
void register_plan_commands(CLI::App& app);
void register_post_commands(CLI::App& app);
void register_verify_commands(CLI::App& app);
void register_view_commands(CLI::App& app);
// Adds `linuxcnc` to the `export` command (register_post_commands first).
void register_linuxcnc_commands(CLI::App& app);
void register_linuxcnc_import_commands(CLI::App& app);
// Adds the firmware targets to `export` and `import` (both registered first;
// commands_firmware.cpp).
void register_firmware_commands(CLI::App& app);
// `pkm export TARGET`: a firmware's configuration of a machine its own kinematics can drive.
struct FirmwareExportOptions {
  std::string machine;
  std::string output;
  bool approximate = false;
  bool kinematics_wanted = false;  // grblhal: its kinematics' settings, not the joints'
};
void add_firmware_export_options(CLI::App& command, FirmwareExportOptions& options);
void run_firmware_export(const std::string& target_name, const FirmwareExportOptions& options);
void register_home_commands(CLI::App& app);
void register_workspace_commands(CLI::App& app);
void register_stream_commands(CLI::App& app);

}  // namespace pkm::app
