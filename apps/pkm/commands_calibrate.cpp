// pkm calibrate matrix, pkm calibrate fit (measured poses, or distances between drawn marks),
// pkm calibrate pattern, pkm calibrate readings (joint readings at poses nobody measured).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "app.hpp"
#include "embedded_machine.hpp"
#include "pkm/calibration/calibration_pattern.hpp"
#include "pkm/calibration/distance_fit.hpp"
#include "pkm/calibration/fit_report.hpp"
#include "pkm/calibration/geometry_fit.hpp"
#include "pkm/calibration/matrix_calibration.hpp"
#include "pkm/calibration/readings_fit.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/text/text_file.hpp"

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
  std::string distances;
  std::string pattern;
  std::string output;
  std::string params;
  bool json = false;
};

struct ReadingsCommandOptions {
  std::string machine;
  std::string data;
  std::string output;
  std::string params;
  bool absolute = false;
  bool motor_degrees = false;
  bool json = false;
};

struct PatternCommandOptions {
  std::string machine;
  std::string output;
  int marks = 12;
  double cross_size = 0.0;
  std::vector<double> sheet;
  std::optional<double> down_z, up_z;
  bool json = false;
};

std::string machine_text(const std::string& path) {
  if (path.empty()) return std::string(kEmbeddedMachineToml);
  try {
    return text::read_text_file(path, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw CommandError(path + ": " + error.what());
  }
}

// Writes the machine file with its kinematics replaced, after checking that it loads.
void write_machine(const std::string& original_path, const machine::Machine& machine,
                   const kinematics::Kinematics& kinematics, const std::string& output) {
  const std::string text = machine::replace_kinematics_section(
      machine_text(original_path), machine.source(), kinematics, machine.units());
  machine::parse_machine(text, output);  // refuses to write a file that would not load
  files::write_file_atomically(output, text);
}

std::optional<std::pair<double, double>> pair_of(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return std::make_pair(values[0], values[1]);
}

void run_matrix(const MatrixOptions& options) {
  calibration::MatrixMeasurements measurements;
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
  std::optional<machine::Machine> machine;
  Eigen::Matrix3d start = Eigen::Matrix3d::Identity();
  const kinematics::MatrixKinematics* model = nullptr;
  if (!options.add_to.empty()) {
    machine = machine::load_machine(options.add_to);
    // The cast is the honest answer: the adjustments add to a matrix's nine coefficients, which
    // no other model has.
    model = dynamic_cast<const kinematics::MatrixKinematics*>(&machine->kinematics());
    if (model == nullptr) {
      throw CommandError(options.add_to + " is a " + std::string(machine->kinematics().type()) +
                         " machine; --add-to needs a matrix machine");
    }
    start = model->coefficients();
  }
  Eigen::Matrix3d matrix;
  try {
    matrix = calibration::calibrate_matrix(measurements, start);
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  if (!options.output.empty()) {
    const kinematics::MatrixKinematics updated(matrix, model->passthrough_axes());
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
  std::printf("\nfor the LinuxCNC HAL file:\n%s", calibration::linuxcnc_setp_lines(matrix).c_str());
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

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// The fit of measured poses (DATA.csv) or of distances between drawn marks (--distances and
// --pattern), whichever was given.
calibration::FitReport fit_machine(const FitCommandOptions& options, machine::Machine& machine) {
  calibration::FitOptions fit_options;
  fit_options.parameters = split_names(options.params);
  try {
    if (!options.data.empty()) {
      const std::vector<calibration::Measurement> measurements =
          calibration::read_measurements_csv(options.data, machine);
      return calibration::fit_geometry(machine.kinematics(), machine.home(), measurements,
                                       fit_options);
    }
    const std::vector<calibration::PatternMark> marks =
        calibration::read_pattern_json(options.pattern);
    const std::vector<calibration::MarkDistance> distances =
        calibration::read_distances_csv(options.distances, marks);
    return calibration::fit_distances(machine.kinematics(), machine.home(), marks, distances,
                                      fit_options);
  } catch (const calibration::MeasurementFileError& error) {
    throw CommandError(error.what());
  } catch (const calibration::PatternFileError& error) {
    throw CommandError(error.what());
  } catch (const calibration::FitError& error) {
    throw CommandError(error.what());
  }
}

void print_fit_json(const calibration::FitReport& report, const std::string& output) {
  std::cout << calibration::fit_report_json(report, output).dump(2) << "\n";
}

void print_fit_text(const calibration::FitReport& report, const std::string& output,
                    bool distances) {
  std::printf(
      "%d %s; residual (per %s, mm): RMS %.6f max %.6f before, "
      "RMS %.6f max %.6f after (largest at line %d)\n",
      report.measurements, distances ? "distances" : "measurements",
      distances ? "distance" : "measurement", report.rms_before_mm, report.max_before_mm,
      report.rms_after_mm, report.max_after_mm, report.max_after_line);
  std::printf("%-24s %16s %16s %12s\n", "parameter", "nominal", "fitted", "std dev");
  for (const calibration::ParameterEstimate& p : report.parameters) {
    if (p.free) {
      std::printf("%-24s %16.6f %16.6f %12.6f %s\n", p.name.c_str(), p.nominal, p.fitted,
                  p.standard_deviation, p.unit.c_str());
    } else {
      std::printf("%-24s %16.6f %16s %12s %s\n", p.name.c_str(), p.nominal, "(held)", "",
                  p.unit.c_str());
    }
  }
  if (!report.held_rigid_motion.empty()) {
    std::printf(
        "distances cannot see where the drawing sits or how it is turned: held %s (they "
        "only move the whole drawing)\n",
        joined(report.held_rigid_motion).c_str());
  }
  for (const auto& group : report.indistinguishable) {
    std::printf("the data cannot tell these apart: %s\n", joined(group).c_str());
  }
  for (const calibration::PoorlyDetermined& p : report.poorly_determined)
    std::printf("warning: %s\n", calibration::poorly_determined_text(p).c_str());
  if (!report.no_effect.empty()) {
    std::printf(
        "no effect on the data at the nominal geometry (or at the edge of their range): %s\n",
        joined(report.no_effect).c_str());
  }
  if (!report.held.empty()) {
    std::printf("held at nominal (not identifiable from these measurements): %zu parameters\n",
                report.held.size());
  }
  if (!report.converged) std::printf("warning: the solver did not converge\n");
  if (!output.empty()) std::printf("wrote %s\n", output.c_str());
}

void run_fit(const FitCommandOptions& options) {
  const bool distances = !options.distances.empty() || !options.pattern.empty();
  if (distances == !options.data.empty()) {
    throw CommandError(
        "give either the measured poses (DATA.csv) or --distances D.csv with --pattern "
        "PATTERN.json");
  }
  if (distances && (options.distances.empty() || options.pattern.empty())) {
    throw CommandError(
        "--distances and --pattern go together: the distances name the marks of "
        "the pattern");
  }
  refuse_overwriting_input(options.output, {{"the machine file", options.machine},
                                            {"the measurements", options.data},
                                            {"the distances", options.distances},
                                            {"the pattern", options.pattern}});
  machine::Machine machine = load_machine_or_default(options.machine);
  const calibration::FitReport report = fit_machine(options, machine);
  try {
    write_machine(options.machine, machine, machine.kinematics(), options.output);
  } catch (const machine::MachineFileError& error) {
    // Show what the fit found: it is what the user must look at.
    if (!options.json) print_fit_text(report, "", distances);
    throw CommandError(
        "the fitted geometry does not make a usable machine, so nothing was "
        "written (as it would have read: " +
        std::string(error.what()) + ")");
  }
  if (options.json) {
    print_fit_json(report, options.output);
  } else {
    print_fit_text(report, options.output, distances);
  }
}

// What the readings were: "counted from home", "absolute" or "motor degrees from the origin".
const char* readings_kind(const ReadingsCommandOptions& options) {
  if (options.motor_degrees) return "motor degrees from the origin";
  return options.absolute ? "absolute" : "counted from home";
}

void print_readings_text(const calibration::ReadingsFitReport& readings, const char* kind,
                         bool relative, const std::string& output) {
  const calibration::FitReport& report = readings.fit;
  std::printf(
      "%d samples of %d readings (%s), %d pose coordinates each solved for; residual (per "
      "reading, mm): RMS %.6f max %.6f before, RMS %.6f max %.6f after (largest at line %d); "
      "noise of a reading by the residuals %.6f mm\n",
      readings.samples, readings.readings_per_sample, kind, readings.pose_coordinates,
      report.rms_before_mm, report.max_before_mm, report.rms_after_mm, report.max_after_mm,
      report.max_after_line, readings.noise_mm);
  std::printf("%-24s %16s %16s %12s %12s\n", "parameter", "nominal", "fitted", "change", "std dev");
  for (const calibration::ParameterEstimate& p : report.parameters) {
    if (p.free) {
      std::printf("%-24s %16.6f %16.6f %12.6f %12.6f %s\n", p.name.c_str(), p.nominal, p.fitted,
                  p.fitted - p.nominal, p.standard_deviation, p.unit.c_str());
    } else {
      std::printf("%-24s %16.6f %16s %12s %12s %s\n", p.name.c_str(), p.nominal, "(held)", "", "",
                  p.unit.c_str());
    }
  }
  if (!report.held_rigid_motion.empty()) {
    std::printf(
        "the readings cannot see these (%s, a point moved with its cable): held at the "
        "machine file's values: %s\n",
        relative ? "the frame turned about home" : "the frame moved or turned as a whole",
        joined(report.held_rigid_motion).c_str());
  }
  for (const auto& group : report.indistinguishable) {
    std::printf("the data cannot tell these apart: %s\n", joined(group).c_str());
  }
  for (const calibration::PoorlyDetermined& p : report.poorly_determined)
    std::printf("warning: %s\n", calibration::poorly_determined_text(p).c_str());
  if (!report.no_effect.empty()) {
    std::printf("no effect on the readings: %s\n", joined(report.no_effect).c_str());
  }
  if (!report.converged) std::printf("warning: the solver did not converge\n");
  // Gaussian residuals reach about 3 of their spreads among a few hundred; 8 is no noise.
  if (report.max_after_mm > 8.0 * readings.residual_spread_mm) {
    std::printf(
        "warning: a reading at line %d is %.3f mm off the fit, %.0f times the others' spread "
        "(%.4f mm, 1.4826 x their median): a slack line, a slipped belt or a misread sample? "
        "leave it out and fit again\n",
        report.max_after_line, report.max_after_mm,
        report.max_after_mm / readings.residual_spread_mm, readings.residual_spread_mm);
  }
  std::printf("poses found (mm):\n");
  for (std::size_t k = 0; k < readings.poses.size(); ++k) {
    const Eigen::Vector3d& p = readings.poses[k].position_mm;
    std::printf("  line %d: %.3f %.3f %.3f\n", readings.lines[k], p.x(), p.y(), p.z());
  }
  if (!output.empty()) std::printf("wrote %s\n", output.c_str());
}

nlohmann::json readings_json(const calibration::ReadingsFitReport& readings, bool relative,
                             const std::string& output) {
  nlohmann::json json = calibration::fit_report_json(readings.fit, output);
  json["samples"] = readings.samples;
  json["readings_per_sample"] = readings.readings_per_sample;
  json["relative_to_home"] = relative;
  json["noise_mm"] = readings.noise_mm;
  json["residual_spread_mm"] = readings.residual_spread_mm;
  nlohmann::json poses = nlohmann::json::array();
  for (std::size_t k = 0; k < readings.poses.size(); ++k) {
    const Eigen::Vector3d& p = readings.poses[k].position_mm;
    poses.push_back({{"line", readings.lines[k]}, {"x", p.x()}, {"y", p.y()}, {"z", p.z()}});
  }
  json["poses"] = poses;
  return json;
}

void run_readings(const ReadingsCommandOptions& options) {
  refuse_overwriting_input(options.output,
                           {{"the machine file", options.machine}, {"the readings", options.data}});
  machine::Machine machine = load_machine_or_default(options.machine);
  calibration::ReadingsFitOptions fit_options;
  fit_options.fit.parameters = split_names(options.params);
  fit_options.relative_to_home = !options.absolute;
  const calibration::ReadingUnit unit = options.motor_degrees
                                            ? calibration::ReadingUnit::motor_degrees
                                            : calibration::ReadingUnit::joint;
  // Motor positions count from line position 0, the origin, whatever the machine's home.
  geometry::Pose zeroed_at = machine.home();
  if (options.motor_degrees) {
    if (options.absolute) {
      throw CommandError(
          "--motor-degrees: motor positions count from the origin; --absolute is "
          "for the joints' own values");
    }
    try {
      calibration::require_spools(machine);
    } catch (const calibration::FitError& error) {
      throw CommandError((options.machine.empty() ? std::string("the machine") : options.machine) +
                         ": " + error.what());
    }
    zeroed_at.position_mm.setZero();
  }
  calibration::ReadingsFitReport report;
  try {
    const std::vector<calibration::JointReadings> samples =
        calibration::read_readings_csv(options.data, machine, unit);
    report = calibration::fit_readings(machine.kinematics(), zeroed_at, samples, fit_options);
  } catch (const calibration::MeasurementFileError& error) {
    throw CommandError(error.what());
  } catch (const calibration::SampleFitError& error) {
    throw CommandError(options.data + ":" + std::to_string(error.line()) + ":1: " + error.what());
  } catch (const calibration::FitError& error) {
    throw CommandError(options.data + ": " + error.what());
  }
  try {
    write_machine(options.machine, machine, machine.kinematics(), options.output);
  } catch (const machine::MachineFileError& error) {
    if (!options.json)
      print_readings_text(report, readings_kind(options), fit_options.relative_to_home, "");
    throw CommandError(
        "the fitted geometry does not make a usable machine, so nothing was written (as it "
        "would have read: " +
        std::string(error.what()) + ")");
  }
  if (options.json) {
    std::cout << readings_json(report, fit_options.relative_to_home, options.output).dump(2)
              << "\n";
  } else {
    print_readings_text(report, readings_kind(options), fit_options.relative_to_home,
                        options.output);
  }
}

// A reach found by bisection ends a hair off zero: "-0.0" says nothing more than 0.
double shown(double value_mm) {
  return std::abs(value_mm) < 0.05 ? 0.0 : value_mm;
}

// pattern.ngc -> pattern.json beside it.
std::string pattern_json_path(const std::string& gcode_path) {
  std::filesystem::path path(gcode_path);
  if (path.extension() == ".json") {
    throw CommandError("-o names the G-code program; pattern.json is written beside it");
  }
  return path.replace_extension(".json").string();
}

void run_pattern(const PatternCommandOptions& options) {
  const machine::Machine machine = load_machine_or_default(options.machine);
  calibration::PatternOptions pattern_options;
  pattern_options.marks = options.marks;
  pattern_options.cross_size_mm = options.cross_size;
  if (!options.sheet.empty())
    pattern_options.sheet_mm = {options.sheet[0], options.sheet[1], options.sheet[2],
                                options.sheet[3]};
  const std::string json_path = pattern_json_path(options.output);
  refuse_overwriting_input(options.output, {{"the machine file", options.machine}});
  refuse_overwriting_input(json_path, {{"the machine file", options.machine}});
  calibration::CalibrationPattern pattern;
  std::string program;
  calibration::DistanceIdentification identified;
  try {
    pattern = calibration::design_pattern(machine, pattern_options);
    calibration::PenHeights pen = calibration::default_pen_heights(machine);
    if (options.down_z) {
      const double up_side = machine.tool().down_above ? -5.0 : 5.0;
      pen = {*options.down_z, *options.down_z + up_side};
    }
    if (options.up_z) pen.up_mm = *options.up_z;
    try {
      program = calibration::pattern_gcode(machine, pattern, pen);
    } catch (const std::invalid_argument& error) {
      throw CommandError(std::string(error.what()) +
                         "; give the pen's heights with --down-z and --up-z (mm)");
    }
    identified = calibration::identify_from_distances(
        machine.kinematics(), machine.home(), pattern.marks, calibration::all_pairs(pattern.marks),
        calibration::FitOptions{});
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  } catch (const calibration::FitError& error) {
    throw CommandError(error.what());
  }
  const std::string marks_json = calibration::pattern_json_text(pattern.marks);
  const files::FileContent pair[] = {{options.output, program}, {json_path, marks_json}};
  files::write_files_together(pair);
  const std::size_t pairs = pattern.marks.size() * (pattern.marks.size() - 1) / 2;
  if (options.json) {
    std::cout << nlohmann::json{{"marks", pattern.marks.size()},
                                {"cross_size_mm", pattern.cross_size_mm},
                                {"identified", identified.identified},
                                {"poorly_determined",
                                 calibration::poorly_determined_json(identified.poorly_determined)},
                                {"held_rigid_motion", identified.held_rigid_motion},
                                {"indistinguishable", identified.indistinguishable},
                                {"no_effect", identified.no_effect},
                                {"gcode", options.output},
                                {"pattern", json_path}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf("%zu marks (crosses of +-%.1f mm) over x %.1f..%.1f y %.1f..%.1f mm\n",
              pattern.marks.size(), pattern.cross_size_mm, shown(pattern.sheet_min_x_mm),
              shown(pattern.sheet_max_x_mm), shown(pattern.sheet_min_y_mm),
              shown(pattern.sheet_max_y_mm));
  std::printf("all %zu distances between them identify: %s\n", pairs,
              identified.identified.empty() ? "nothing" : joined(identified.identified).c_str());
  if (!identified.held_rigid_motion.empty())
    std::printf("not seen by distances (they only move the whole drawing): %s\n",
                joined(identified.held_rigid_motion).c_str());
  for (const auto& group : identified.indistinguishable)
    std::printf("cannot be told apart: %s\n", joined(group).c_str());
  for (const calibration::PoorlyDetermined& p : identified.poorly_determined)
    std::printf(
        "%s\n",
        calibration::poorly_determined_text(p, calibration::FitOptions{}.design_noise_mm).c_str());
  if (!identified.no_effect.empty())
    std::printf("no effect at the nominal geometry (or at the edge of their range): %s\n",
                joined(identified.no_effect).c_str());
  std::printf("wrote %s and %s\n", options.output.c_str(), json_path.c_str());
}

// `pkm calibrate matrix`: matrixkins coefficients from the shop measurements.
void register_matrix_command(CLI::App& calibrate) {
  auto matrix = std::make_shared<MatrixOptions>();
  CLI::App* matrix_command = calibrate.add_subcommand(
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
}

// `pkm calibrate fit`: the geometry fitted to measured poses or drawn distances.
void register_fit_command(CLI::App& calibrate) {
  auto fit = std::make_shared<FitCommandOptions>();
  CLI::App* fit_command = calibrate.add_subcommand(
      "fit", "Least-squares fit of the machine's geometry to measured poses");
  fit_command->add_option("-m,--machine", fit->machine, "Machine file (default: embedded hexapod)");
  fit_command->add_option("data", fit->data, "CSV: j_<joint> columns and measured x y z [a b c]");
  fit_command->add_option("--distances", fit->distances,
                          "CSV mark_a,mark_b,distance_mm: distances between drawn marks");
  fit_command->add_option("--pattern", fit->pattern,
                          "pattern.json of `pkm calibrate pattern` (with --distances)");
  fit_command->add_option("-o,--output", fit->output, "Corrected machine file to write")
      ->required();
  fit_command->add_option("--params", fit->params,
                          "Comma-separated parameter names to fit, '*' wildcards (default: all)");
  fit_command->add_flag("--json", fit->json, "Print the report as JSON");
  fit_command->callback([fit] { run_fit(*fit); });
}

// `pkm calibrate readings`: the geometry fitted to joint readings at poses nobody measured.
void register_readings_command(CLI::App& calibrate) {
  auto readings = std::make_shared<ReadingsCommandOptions>();
  CLI::App* command = calibrate.add_subcommand(
      "readings",
      "Fit the geometry to joint readings at unknown poses (a machine with more joints than "
      "coordinates: Hangprinter's auto-calibration)");
  command->add_option("-m,--machine", readings->machine,
                      "Machine file (default: embedded hexapod)");
  command
      ->add_option("data", readings->data, "CSV: one j_<joint> column per joint, a row per sample")
      ->required();
  command->add_option("-o,--output", readings->output, "Corrected machine file to write")
      ->required();
  command->add_option("--params", readings->params,
                      "Comma-separated parameter names to fit, '*' wildcards (default: all)");
  command->add_flag("--absolute", readings->absolute,
                    "The readings are the joints' values, not counted from home");
  command->add_flag("--motor-degrees", readings->motor_degrees,
                    "The readings are a cable robot's motor positions (deg) counted from the "
                    "origin, as Hangprinter's encoders give them: turned into line lengths through "
                    "the machine file's spools");
  command->add_flag("--json", readings->json, "Print the report as JSON");
  command->callback([readings] { run_readings(*readings); });
}

// `pkm calibrate pattern`: the drawing of numbered crosses and its pattern.json.
void register_pattern_command(CLI::App& calibrate) {
  auto pattern = std::make_shared<PatternCommandOptions>();
  CLI::App* pattern_command = calibrate.add_subcommand(
      "pattern", "G-code drawing numbered crosses to measure with a tape (and pattern.json)");
  pattern_command->add_option("-m,--machine", pattern->machine,
                              "Machine file (default: embedded hexapod)");
  pattern_command->add_option("-o,--output", pattern->output, "G-code program to write")
      ->required();
  pattern_command->add_option("--marks", pattern->marks, "Number of marks (default 12)")
      ->check(CLI::Range(3, 999));
  pattern_command
      ->add_option("--cross-size", pattern->cross_size,
                   "Half the arm of a cross, mm (default: 1/80 of the sheet, 2..10 mm)")
      ->check(number_in(0.01, 1000.0));
  pattern_command
      ->add_option("--sheet", pattern->sheet,
                   "The sheet: x min, y min, x max, y max, mm (default: the reach)")
      ->expected(4)
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  pattern_command
      ->add_option("--down-z", pattern->down_z,
                   "Program Z with the pen down, mm (default: 1 mm past [tool] down_below or "
                   "down_above, or 0)")
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  pattern_command
      ->add_option(
          "--up-z", pattern->up_z,
          "Program Z with the pen up, mm (default: 5 past --down-z on the pen's up side if given)")
      ->check(number_in(-kMaxCoordinate, kMaxCoordinate));
  pattern_command->add_flag("--json", pattern->json, "Print the report as JSON");
  pattern_command->callback([pattern] { run_pattern(*pattern); });
}

}  // namespace

void register_calibrate_commands(CLI::App& app) {
  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate a machine from measurements");
  calibrate->require_subcommand(1);

  register_matrix_command(*calibrate);
  register_fit_command(*calibrate);
  register_pattern_command(*calibrate);
  register_readings_command(*calibrate);
}

}  // namespace pkm::app
