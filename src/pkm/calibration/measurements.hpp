// Calibration measurements: joint readings with the tool pose measured at them.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <istream>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::calibration {

struct Measurement {
  kinematics::JointVector joints;  // mm (rad for rotary joints)
  geometry::Vector6d pose =
      geometry::Vector6d::Zero();  // x y z mm, a b c rad; only measured ones are used
  std::array<bool, geometry::kPoseSize> measured{};  // which pose coordinates were measured
  int line = 0;                                      // source line, for reports
};

// An error in a measurement file, located as file:line:column.
class MeasurementFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One field of a CSV line: its text, trimmed of blanks, and the 1-based column where it starts.
struct CsvField {
  std::string text;
  int column = 1;
};
std::vector<CsvField> split_csv_line(const std::string& line);
// Throws MeasurementFileError "source:line:column: message".
[[noreturn]] void fail_at(const std::string& source_name, int line, int column,
                          const std::string& message);
// A CSV's header row: its first line that is not blank, `line_number` its number (1-based);
// MeasurementFileError "source:1:1: empty file: expected a header row <expected>" without one.
std::string csv_header_line(std::istream& in, const std::string& source_name, int& line_number,
                            const std::string& expected);
// Each row after the header that is not blank, split, with its line number (`line_number`
// counts on from the header's); MeasurementFileError at a row whose fields are not
// `fields_per_row`.
void for_each_csv_row(
    std::istream& in, const std::string& source_name, int& line_number, std::size_t fields_per_row,
    const std::function<void(const std::vector<CsvField>& fields, int line_number)>& row);
// The whole of `text` as a number (from_chars: no blanks, no '+'); false otherwise.
bool csv_number(const std::string& text, double& value);
// A measurement file's text; MeasurementFileError "path:0:0: cannot open the file".
std::string read_text_file(const std::filesystem::path& path);

// Reads a CSV with a header row: one column per joint named `j_` + its name (mm, deg for rotary
// joints) and the measured pose coordinates `x y z` (mm) and `a b c` (deg), any subset of those
// the machine controls. Columns `t` and `line` (as in plan output) are ignored; any other column
// is an error, as is a missing joint column, a non-number or NaN.
std::vector<Measurement> read_measurements_csv(const std::filesystem::path& path,
                                               const machine::Machine& machine);
std::vector<Measurement> parse_measurements_csv(const std::string& text,
                                                const std::string& source_name,
                                                const machine::Machine& machine);

}  // namespace pkm::calibration
