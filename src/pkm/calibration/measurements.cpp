#include "pkm/calibration/measurements.hpp"
#include "pkm/text/text_file.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace pkm::calibration {

void for_each_csv_row(
    std::istream& in, const std::string& source_name, int& line_number, std::size_t fields_per_row,
    const std::function<void(const std::vector<CsvField>& fields, int line_number)>& row) {
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<CsvField> fields = split_csv_line(line);
    if (fields.size() != fields_per_row) {
      fail_at(source_name, line_number, 1,
              "has " + std::to_string(fields.size()) + " fields; the header has " +
                  std::to_string(fields_per_row));
    }
    row(fields, line_number);
  }
}

namespace {

// Largest value a measurement may hold, mm or deg (the message says 1e6): far beyond any
// machine, and small enough that the fit's arithmetic on it cannot overflow.
constexpr double kLargestValue = 1e6;

}  // namespace

std::vector<CsvField> split_csv_line(const std::string& line) {
  std::vector<CsvField> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string::npos ? line.size() : comma;
    std::string text = line.substr(start, end - start);
    const std::size_t first = text.find_first_not_of(" \t");
    const std::size_t last = text.find_last_not_of(" \t\r");
    text = first == std::string::npos ? "" : text.substr(first, last - first + 1);
    fields.push_back(
        {text, static_cast<int>(start + (first == std::string::npos ? 0 : first)) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool csv_number(const std::string& text, double& value) {
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  return !text.empty() && result.ec == std::errc() && result.ptr == text.data() + text.size();
}

std::string read_text_file(const std::filesystem::path& path) {
  try {
    return text::read_text_file(path, text::kMaxDataFileBytes);
  } catch (const text::FileReadError& error) {
    throw MeasurementFileError(path.string() + ":0:0: " + error.what());
  }
}

void fail_at(const std::string& source_name, int line, int column, const std::string& message) {
  throw MeasurementFileError(source_name + ":" + std::to_string(line) + ":" +
                             std::to_string(column) + ": " + message);
}

std::string csv_header_line(std::istream& in, const std::string& source_name, int& line_number,
                            const std::string& expected) {
  std::string line;
  line_number = 0;
  while (std::getline(in, line)) {  // blank lines before the header are skipped
    ++line_number;
    if (line.find_first_not_of(" \t\r") != std::string::npos) return line;
  }
  fail_at(source_name, 1, 1, "empty file: expected a header row " + expected);
}

namespace {

// What the header row says each column holds: a joint, a pose coordinate, or neither (t, line).
struct MeasurementColumns {
  std::vector<int> joint_of_column;  // -1 where the column is no joint
  std::vector<int> axis_of_column;   // -1 where the column is no pose coordinate
  std::array<bool, geometry::kPoseSize> axis_seen{};
};

// The header row, checked: every name known and once only, every joint there, and at least one
// measured pose coordinate, each one the machine controls.
MeasurementColumns read_header(const std::vector<CsvField>& header, int line_number,
                               const std::string& source_name, const machine::Machine& machine) {
  const auto fail = [&](int column, const std::string& message) {
    fail_at(source_name, line_number, column, message);
  };
  const int joint_count = static_cast<int>(machine.joints().size());
  MeasurementColumns columns;
  columns.joint_of_column.assign(header.size(), -1);
  columns.axis_of_column.assign(header.size(), -1);
  std::vector<bool> joint_seen(static_cast<std::size_t>(joint_count), false);
  for (std::size_t c = 0; c < header.size(); ++c) {
    const std::string& name = header[c].text;
    if (name == "t" || name == "line") continue;
    bool known = false;
    for (int j = 0; j < joint_count; ++j) {
      if (name == "j_" + machine.joints()[j].name) {
        if (joint_seen[j]) fail(header[c].column, "column '" + name + "' appears twice");
        columns.joint_of_column[c] = j;
        joint_seen[j] = true;
        known = true;
      }
    }
    const int axis = geometry::axis_index(name);
    if (!known && axis >= 0 && name.size() == 1 &&
        std::islower(static_cast<unsigned char>(name[0]))) {
      if (!machine.kinematics().dof().controls(axis)) {
        fail(header[c].column, "column '" + name + "': this machine does not control " + name);
      }
      if (columns.axis_seen[axis]) fail(header[c].column, "column '" + name + "' appears twice");
      columns.axis_of_column[c] = axis;
      columns.axis_seen[axis] = true;
      known = true;
    }
    if (!known) {
      fail(header[c].column,
           "unknown column '" + name + "' (expected j_<joint name>, x y z a b c, t or line)");
    }
  }
  for (int j = 0; j < joint_count; ++j) {
    if (!joint_seen[j]) fail(1, "no column 'j_" + machine.joints()[j].name + "'");
  }
  bool any_axis = false;
  for (const bool seen : columns.axis_seen) any_axis = any_axis || seen;
  if (!any_axis) fail(1, "no measured pose column (x y z a b c)");
  return columns;
}

// One data row: its joints in the machine's units (from the interface's mm or deg) and its
// measured pose coordinates in mm and radians.
Measurement read_row(const std::vector<CsvField>& fields, const MeasurementColumns& columns,
                     int line_number, const std::string& source_name,
                     const machine::Machine& machine) {
  const auto fail = [&](int column, const std::string& message) {
    fail_at(source_name, line_number, column, message);
  };
  Measurement measurement;
  measurement.joints.resize(static_cast<int>(machine.joints().size()));
  measurement.measured = columns.axis_seen;
  measurement.line = line_number;
  for (std::size_t c = 0; c < fields.size(); ++c) {
    const int joint = columns.joint_of_column[c];
    const int axis = columns.axis_of_column[c];
    if (joint < 0 && axis < 0) continue;
    double value = 0.0;
    const std::string& field = fields[c].text;
    if (!csv_number(field, value)) fail(fields[c].column, "'" + field + "' is not a number");
    if (!std::isfinite(value)) fail(fields[c].column, "must be finite");
    if (std::abs(value) > kLargestValue) {
      fail(fields[c].column,
           "'" + field + "' is beyond any machine (at most 1e6 mm or deg in size)");
    }
    if (joint >= 0) {
      measurement.joints[joint] = machine.joints()[joint].from_interface(value);
    } else {
      measurement.pose[axis] = axis < 3 ? value : geometry::degrees_to_radians(value);
    }
  }
  return measurement;
}

}  // namespace

std::vector<Measurement> parse_measurements_csv(const std::string& text,
                                                const std::string& source_name,
                                                const machine::Machine& machine) {
  std::istringstream in(text);
  int line_number = 0;
  const std::string line =
      csv_header_line(in, source_name, line_number, "such as j_left,j_right,x,y");
  const std::vector<CsvField> header = split_csv_line(line);
  const MeasurementColumns columns = read_header(header, line_number, source_name, machine);

  std::vector<Measurement> measurements;
  for_each_csv_row(in, source_name, line_number, header.size(),
                   [&](const std::vector<CsvField>& fields, int at) {
                     measurements.push_back(read_row(fields, columns, at, source_name, machine));
                   });
  if (measurements.empty())
    fail_at(source_name, line_number, 1, "no measurements after the header");
  return measurements;
}

std::vector<Measurement> read_measurements_csv(const std::filesystem::path& path,
                                               const machine::Machine& machine) {
  return parse_measurements_csv(read_text_file(path), path.string(), machine);
}

}  // namespace pkm::calibration
