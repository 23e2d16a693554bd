// pkm calibrate matrix, pkm calibrate fit.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app.hpp"
#include "embedded_machine.hpp"
#include "pkm/calibration/geometry_fit.hpp"
#include "pkm/calibration/matrix_calibration.hpp"
#include "pkm/io/atomic_file.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::app {

namespace {

struct MatrixOptions {
  std::vector<double> diagonals, widths, x_to_spindle, y_to_spindle, z_tilt_x, z_tilt_y;
  std::string add_to;
  std::string output;
  bool json = false;
};

struct FitCommandOptions {
  std::string machine;
  std::string data;
  std::string output;
  std::string params;
  bool json = false;
};

std::string machine_text(const std::string& path) {
  if (path.empty()) return std::string(kEmbeddedMachineToml);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw CommandError("cannot read " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// Writes the machine file with its kinematics replaced, after checking that it loads.
void write_machine(const std::string& original_path, const Machine& machine,
                   const Kinematics& kinematics, const std::string& output) {
  const std::string text = replace_kinematics_section(machine_text(original_path), machine.source(),
                                                      kinematics, machine.units());
  parse_machine(text, output);  // refuses to write a file that would not load
  write_file_atomically(output, text);
}

std::optional<std::pair<double, double>> pair_of(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return std::make_pair(values[0], values[1]);
}

void run_matrix(const MatrixOptions& options) {
  MatrixMeasurements measurements;
  measurements.diagonals = pair_of(options.diagonals);
  measurements.widths = pair_of(options.widths);
  measurements.x_to_spindle = pair_of(options.x_to_spindle);
  measurements.y_to_spindle = pair_of(options.y_to_spindle);
  measurements.z_tilt_x = pair_of(options.z_tilt_x);
  measurements.z_tilt_y = pair_of(options.z_tilt_y);
  if (!measurements.diagonals && !measurements.widths && !measurements.x_to_spindle &&
      !measurements.y_to_spindle && !measurements.z_tilt_x && !measurements.z_tilt_y) {
    throw CommandError(
        "nothing to calibrate: give at least one measurement (--diagonals, "
        "--widths, --x-to-spindle, --y-to-spindle, --z-tilt-x, --z-tilt-y)");
  }
  if (!options.output.empty() && options.add_to.empty()) {
    throw CommandError("-o writes the updated machine file: name the machine with --add-to");
  }
  refuse_overwriting_input(options.output, {{"the machine file of --add-to", options.add_to}});
  std::optional<Machine> machine;
  Eigen::Matrix3d start = Eigen::Matrix3d::Identity();
  const MatrixKinematics* model = nullptr;
  if (!options.add_to.empty()) {
    machine = load_machine(options.add_to);
    model = dynamic_cast<const MatrixKinematics*>(&machine->kinematics());
    if (model == nullptr) {
      throw CommandError(options.add_to + " is a " + std::string(machine->kinematics().type()) +
                         " machine; --add-to needs a matrix machine");
    }
    start = model->coefficients();
  }
  Eigen::Matrix3d matrix;
  try {
    matrix = calibrate_matrix(measurements, start);
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  if (!options.output.empty()) {
    const MatrixKinematics updated(matrix, model->passthrough_axes());
    write_machine(options.add_to, *machine, updated, options.output);
  }
  if (options.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (int row = 0; row < 3; ++row)
      rows.push_back({matrix(row, 0), matrix(row, 1), matrix(row, 2)});
    std::cout << nlohmann::json{{"matrix", rows}}.dump() << "\n";
    return;
  }
  std::printf("matrix (joint = C * axis, rows x y z):\n");
  for (int row = 0; row < 3; ++row) {
    std::printf("  [%.9f, %.9f, %.9f]\n", matrix(row, 0), matrix(row, 1), matrix(row, 2));
  }
  std::printf("\nfor the LinuxCNC HAL file:\n%s", linuxcnc_setp_lines(matrix).c_str());
  if (!options.output.empty()) std::printf("\nwrote %s\n", options.output.c_str());
}

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> names;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    const auto first = name.find_first_not_of(' ');
    if (first != std::string::npos)
      names.push_back(name.substr(first, name.find_last_not_of(' ') - first + 1));
  }
  return names;
}

void run_fit(const FitCommandOptions& options) {
  refuse_overwriting_input(
      options.output, {{"the machine file", options.machine}, {"the measurements", options.data}});
  Machine machine = load_machine_or_default(options.machine);
  std::vector<Measurement> measurements;
  try {
    measurements = read_measurements_csv(options.data, machine);
  } catch (const MeasurementFileError& error) {
    throw CommandError(error.what());
  }
  FitOptions fit_options;
  fit_options.parameters = split_names(options.params);
  FitReport report;
  try {
    report = fit_geometry(machine.kinematics(), machine.home(), measurements, fit_options);
  } catch (const FitError& error) {
    throw CommandError(error.what());
  }
  write_machine(options.machine, machine, machine.kinematics(), options.output);
  if (options.json) {
    nlohmann::json parameters = nlohmann::json::array();
    for (const ParameterEstimate& p : report.parameters) {
      parameters.push_back({{"name", p.name},
                            {"unit", p.unit},
                            {"nominal", p.nominal},
                            {"fitted", p.fitted},
                            {"standard_deviation", p.standard_deviation},
                            {"held", !p.free}});
    }
    std::cout << nlohmann::json{{"measurements", report.measurements},
                                {"rms_before_mm", report.rms_before_mm},
                                {"max_before_mm", report.max_before_mm},
                                {"rms_after_mm", report.rms_after_mm},
                                {"max_after_mm", report.max_after_mm},
                                {"max_after_line", report.max_after_line},
                                {"parameters", parameters},
                                {"indistinguishable", report.indistinguishable},
                                {"held", report.held},
                                {"converged", report.converged},
                                {"output", options.output}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf(
      "%d measurements; residual (per measurement, mm): RMS %.6f max %.6f before, "
      "RMS %.6f max %.6f after (largest at line %d)\n",
      report.measurements, report.rms_before_mm, report.max_before_mm, report.rms_after_mm,
      report.max_after_mm, report.max_after_line);
  std::printf("%-24s %16s %16s %12s\n", "parameter", "nominal", "fitted", "std dev");
  for (const ParameterEstimate& p : report.parameters) {
    if (p.free) {
      std::printf("%-24s %16.6f %16.6f %12.6f %s\n", p.name.c_str(), p.nominal, p.fitted,
                  p.standard_deviation, p.unit.c_str());
    } else {
      std::printf("%-24s %16.6f %16s %12s %s\n", p.name.c_str(), p.nominal, "(held)", "",
                  p.unit.c_str());
    }
  }
  for (const auto& group : report.indistinguishable) {
    std::string names;
    for (const std::string& name : group) names += (names.empty() ? "" : ", ") + name;
    std::printf("the data cannot tell these apart: %s\n", names.c_str());
  }
  if (!report.held.empty()) {
    std::printf("held at nominal (not identifiable from these measurements): %zu parameters\n",
                report.held.size());
  }
  if (!report.converged) std::printf("warning: the solver did not converge\n");
  std::printf("wrote %s\n", options.output.c_str());
}

}  // namespace

void register_calibrate_commands(CLI::App& app) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate a machine from measurements");
  calibrate->require_subcommand(1);

  auto matrix = std::make_shared<MatrixOptions>();
  CLI::App* matrix_command = calibrate->add_subcommand(
      "matrix", "matrixkins coefficients from the documented shop measurements");
  matrix_command
      ->add_option("--diagonals", matrix->diagonals,
                   "Octagon diagonals A (X+/Y+) and B (X+/Y-), mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command->add_option("--widths", matrix->widths, "Octagon widths WX and WY, mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command
      ->add_option("--x-to-spindle", matrix->x_to_spindle, "Dial reading D after moving X by X, mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command
      ->add_option("--y-to-spindle", matrix->y_to_spindle, "Dial reading D after moving Y by Y, mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command
      ->add_option("--z-tilt-x", matrix->z_tilt_x, "Indicator difference X over a Z travel Z, mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command
      ->add_option("--z-tilt-y", matrix->z_tilt_y, "Indicator difference Y over a Z travel Z, mm")
      ->expected(2)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  matrix_command->add_option("--add-to", matrix->add_to,
                             "Matrix machine whose coefficients the adjustments add to");
  matrix_command->add_option("-o,--output", matrix->output,
                             "Write the updated machine file (needs --add-to)");
  matrix_command->add_flag("--json", matrix->json, "Print {\"matrix\": [[..],[..],[..]]}");
  matrix_command->callback([matrix] { run_matrix(*matrix); });

  auto fit = std::make_shared<FitCommandOptions>();
  CLI::App* fit_command = calibrate->add_subcommand(
      "fit", "Least-squares fit of the machine's geometry to measured poses");
  fit_command->add_option("-m,--machine", fit->machine, "Machine file (default: embedded hexapod)");
  fit_command->add_option("data", fit->data, "CSV: j_<joint> columns and measured x y z [a b c]")
      ->required();
  fit_command->add_option("-o,--output", fit->output, "Corrected machine file to write")
      ->required();
  fit_command->add_option("--params", fit->params,
                          "Comma-separated parameter names to fit, '*' wildcards (default: all)");
  fit_command->add_flag("--json", fit->json, "Print the report as JSON");
  fit_command->callback([fit] { run_fit(*fit); });
}

}  // namespace pkm::app
