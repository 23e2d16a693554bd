#include "pkm/calibration/measurements.hpp"
#include "pkm/text/text_file.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace pkm::calibration {

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

std::vector<Measurement> parse_measurements_csv(const std::string& text,
                                                const std::string& source_name,
                                                const machine::Machine& machine) {
  const auto fail = [&](int line, int column, const std::string& message) {
    throw MeasurementFileError(source_name + ":" + std::to_string(line) + ":" +
                               std::to_string(column) + ": " + message);
  };
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  // Header: which column is which joint or pose coordinate.
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") != std::string::npos) break;
  }
  if (line_number == 0 || line.find_first_not_of(" \t\r") == std::string::npos) {
    fail(1, 1, "empty file: expected a header row such as j_left,j_right,x,y");
  }
  const std::vector<CsvField> header = split_csv_line(line);
  const int joint_count = static_cast<int>(machine.joints().size());
  std::vector<int> joint_of_column(header.size(), -1);
  std::vector<int> axis_of_column(header.size(), -1);
  std::vector<bool> joint_seen(static_cast<std::size_t>(joint_count), false);
  std::array<bool, geometry::kPoseSize> axis_seen{};
  for (std::size_t c = 0; c < header.size(); ++c) {
    const std::string& name = header[c].text;
    if (name == "t" || name == "line") continue;
    bool known = false;
    for (int j = 0; j < joint_count; ++j) {
      if (name == "j_" + machine.joints()[j].name) {
        if (joint_seen[j])
          fail(line_number, header[c].column, "column '" + name + "' appears twice");
        joint_of_column[c] = j;
        joint_seen[j] = true;
        known = true;
      }
    }
    const int axis = geometry::axis_index(name);
    if (!known && axis >= 0 && name.size() == 1 &&
        std::islower(static_cast<unsigned char>(name[0]))) {
      if (!machine.kinematics().dof().controls(axis)) {
        fail(line_number, header[c].column,
             "column '" + name + "': this machine does not control " + name);
      }
      if (axis_seen[axis])
        fail(line_number, header[c].column, "column '" + name + "' appears twice");
      axis_of_column[c] = axis;
      axis_seen[axis] = true;
      known = true;
    }
    if (!known) {
      fail(line_number, header[c].column,
           "unknown column '" + name + "' (expected j_<joint name>, x y z a b c, t or line)");
    }
  }
  for (int j = 0; j < joint_count; ++j) {
    if (!joint_seen[j]) fail(line_number, 1, "no column 'j_" + machine.joints()[j].name + "'");
  }
  bool any_axis = false;
  for (const bool seen : axis_seen) any_axis = any_axis || seen;
  if (!any_axis) fail(line_number, 1, "no measured pose column (x y z a b c)");

  std::vector<Measurement> measurements;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<CsvField> fields = split_csv_line(line);
    if (fields.size() != header.size()) {
      fail(line_number, 1,
           "has " + std::to_string(fields.size()) + " fields; the header has " +
               std::to_string(header.size()));
    }
    Measurement measurement;
    measurement.joints.resize(joint_count);
    measurement.measured = axis_seen;
    measurement.line = line_number;
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (joint_of_column[c] < 0 && axis_of_column[c] < 0) continue;
      double value = 0.0;
      const std::string& field = fields[c].text;
      if (!csv_number(field, value)) {
        fail(line_number, fields[c].column, "'" + field + "' is not a number");
      }
      if (!std::isfinite(value)) fail(line_number, fields[c].column, "must be finite");
      if (std::abs(value) > kLargestValue) {
        fail(line_number, fields[c].column,
             "'" + field + "' is beyond any machine (at most 1e6 mm or deg in size)");
      }
      if (joint_of_column[c] >= 0) {
        measurement.joints[joint_of_column[c]] =
            machine.joints()[joint_of_column[c]].from_interface(value);
      } else {
        const int axis = axis_of_column[c];
        measurement.pose[axis] = axis < 3 ? value : geometry::degrees_to_radians(value);
      }
    }
    measurements.push_back(measurement);
  }
  if (measurements.empty()) fail(line_number, 1, "no measurements after the header");
  return measurements;
}

std::vector<Measurement> read_measurements_csv(const std::filesystem::path& path,
                                               const machine::Machine& machine) {
  return parse_measurements_csv(read_text_file(path), path.string(), machine);
}

}  // namespace pkm::calibration
