#include "app.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>

#include <unistd.h>

#include "embedded_machine.hpp"
#include "pkm/io/input_files.hpp"

namespace pkm::app {

machine::Machine load_machine_or_default(const std::string& path) {
  if (path.empty())
    return machine::parse_machine(kEmbeddedMachineToml, std::string(kEmbeddedMachineName));
  return machine::load_machine(path);
}

geometry::Pose pose_from_arguments(const machine::Machine& machine,
                                   const std::vector<double>& values) {
  const geometry::Dof dof = machine.kinematics().dof();
  int needed = 0;  // every controlled position coordinate must be given; angles default to home
  for (int axis = 0; axis < 3; ++axis) {
    if (dof.controls(axis)) needed = axis + 1;
  }
  if (static_cast<int>(values.size()) < needed || values.size() > geometry::kPoseSize) {
    std::string names;
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (dof.controls(axis))
        names += std::string(names.empty() ? "" : " ") + std::string(geometry::kAxisNames[axis]);
    }
    throw CommandError("this machine takes the pose as " + names + " (" + machine.length_unit() +
                       ", deg); got " + std::to_string(values.size()) + " numbers");
  }
  return geometry::Pose::from_vector(pose_vector_over(machine, machine.home().as_vector(), values));
}

geometry::Vector6d pose_vector_over(const machine::Machine& machine, geometry::Vector6d base,
                                    const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size() && i < geometry::kPoseSize; ++i) {
    const int axis = static_cast<int>(i);
    base[axis] = machine.axis_from_file(axis, values[i]);
  }
  return base;
}

double mm_from_machine_units(const machine::Machine& machine, double value) {
  return value * machine.mm_per_unit();
}

void add_tool_table_options(CLI::App& command, ToolTableOptions& options) {
  command.add_option("--tool-table", options.path, "LinuxCNC tool table (.tbl)");
  command
      .add_option("--tool-table-units", options.units,
                  "Units of the tool table's lengths: mm or inch (default: the machine file's "
                  "units, as LinuxCNC reads a table in its machine's units)")
      ->check(CLI::IsMember({"mm", "inch"}));
}

void add_subroutine_path_option(CLI::App& command,
                                std::vector<std::filesystem::path>& directories) {
  command
      .add_option("--subroutine-path", directories,
                  "Directories where o<name> call finds name.ngc (and M98 P100 finds 100.ngc) "
                  "when the program does not define it, after the program's own directory "
                  "(LinuxCNC's SUBROUTINE_PATH; DIR:DIR or repeated)")
      ->delimiter(':')
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
}

std::optional<gcode::ToolTable> read_tool_table(const machine::Machine& machine,
                                                const ToolTableOptions& options) {
  if (options.path.empty()) return std::nullopt;
  const bool inch = options.units.empty() ? machine.units() == machine::LengthUnit::inch
                                          : options.units == "inch";
  return gcode::read_tool_table(options.path,
                                inch ? gcode::LengthUnits::inch : gcode::LengthUnits::mm);
}

namespace {

// A number for messages, as short as it was likely typed.
std::string shown(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", value);
  return text;
}

}  // namespace

CLI::Validator number_in(double min, double max) {
  const std::string range = "[" + shown(min) + ", " + shown(max) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "'" + text + "' is not a number";
        if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
        if (value < min || value > max) {
          return text + " is outside " + range;
        }
        return std::string();
      },
      range);
}

CLI::Option* add_pose_option(CLI::App& command, const std::string& name,
                             std::vector<double>& values, const std::string& description) {
  return command.add_option(name, values, description)
      ->expected(2, 6)
      ->option_text("x y [z [a b c]]")
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
}

void refuse_overwriting_input(const std::string& output,
                              std::initializer_list<std::pair<std::string, std::string>> inputs) {
  std::vector<io::NamedInput> named;
  for (const auto& [what, path] : inputs) named.push_back({what, path});
  const std::string reason = io::overwrites_input(output, named);
  if (!reason.empty()) throw CommandError(reason);
}

CLI::Validator file_name() {
  return CLI::Validator(
      [](const std::string& text) {
        return text.empty() ? std::string("an empty file name; name the file to write")
                            : std::string();
      },
      "FILE");
}

// Why `path` cannot be written, "" when it can (as far as can be told before writing it).
static std::string unwritable_reason(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error)) return "it is a directory; name a file";
  const fs::path parent = fs::path(path).has_parent_path() ? fs::path(path).parent_path() : ".";
  if (!fs::exists(parent, error)) return "the directory " + parent.string() + " does not exist";
  if (!fs::is_directory(parent, error)) return parent.string() + " is not a directory";
  if (::access(parent.c_str(), W_OK | X_OK) != 0) {
    return "the directory " + parent.string() + " cannot be written (" + std::strerror(errno) + ")";
  }
  return "";
}

void check_outputs(std::initializer_list<OutputTarget> outputs) {
  namespace fs = std::filesystem;
  for (auto a = outputs.begin(); a != outputs.end(); ++a) {
    if (a->path.empty()) continue;
    const std::string reason = unwritable_reason(a->path);
    if (!reason.empty()) throw CommandError(a->option + " " + a->path + ": " + reason);
    // A device or pipe (/dev/null) may take several outputs: it is written in place.
    std::error_code status_error;
    const fs::file_status status = fs::status(a->path, status_error);
    if (fs::exists(status) && !fs::is_regular_file(status)) continue;
    for (auto b = outputs.begin(); b != a; ++b) {
      if (b->path.empty()) continue;
      std::error_code error_a, error_b, same_error;
      const bool same =
          fs::equivalent(a->path, b->path, same_error) ||
          fs::weakly_canonical(a->path, error_a) == fs::weakly_canonical(b->path, error_b);
      if (same) {
        throw CommandError(b->option + " " + b->path + " and " + a->option + " " + a->path +
                           " name the same file: two outputs would share one name; give each "
                           "its own");
      }
    }
  }
}

std::string size_text(double bytes) {
  static constexpr const char* kUnits[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  int unit = 0;
  while (bytes >= 1000.0 && unit < 5) bytes /= 1000.0, ++unit;
  char text[48];
  std::snprintf(text, sizeof text, "%.4g %s", bytes, kUnits[unit]);
  return text;
}

}  // namespace pkm::app
