#include "pkm/machine/machine_writer.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <memory>
#include <span>
#include <sstream>
#include <vector>

#include "pkm/kinematics/model_config_writer.hpp"
#include "pkm/kinematics/registry.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/toml_config.hpp"

namespace pkm::machine {

std::string toml_number(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  std::string written(text, result.ptr);
  // Keep floats recognisable as floats in TOML.
  if (written.find_first_of(".en") == std::string::npos) written += ".0";
  return written;
}

std::string toml_string(const std::string& text) {
  std::string result = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      result += '\\';
      result += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", c);
      result += escape;
    } else {
      result += c;
    }
  }
  return result + "\"";
}

namespace {

// Rows of numbers: "[a, b, c]".
std::string toml_row(std::span<const double> values, double scale) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    text += (i ? ", " : "") + toml_number(values[i] * scale);
  }
  return text + "]";
}

// One TOML table as a model writes it: its keys in the order written, then its sub-tables (each
// after a blank line, under its own header), lengths converted from mm to the file's unit. An
// array of more than two rows (a matrix, a hexapod's six joints) puts each row on its own line.
class TomlTableWriter final : public kinematics::ModelConfigWriter {
 public:
  TomlTableWriter(std::string header, std::string path, double per_mm)
      : header_(std::move(header)), path_(std::move(path)), per_mm_(per_mm) {}

  void number(std::string_view key, double value) override { put(key, toml_number(value)); }
  void whole_number(std::string_view key, long long value) override {
    put(key, std::to_string(value));
  }
  void number_list(std::string_view key, std::span<const double> values) override {
    put(key, toml_row(values, 1.0));
  }
  void length(std::string_view key, double mm) override { put(key, toml_number(mm * per_mm_)); }
  void length_list(std::string_view key, std::span<const double> mm) override {
    put(key, toml_row(mm, per_mm_));
  }
  void length_points(std::string_view key,
                     const std::vector<std::vector<double>>& points_mm) override {
    rows(key, points_mm, per_mm_);
  }
  void matrix3(std::string_view key, const Eigen::Matrix3d& matrix) override {
    std::vector<std::vector<double>> values;
    for (int row = 0; row < 3; ++row)
      values.push_back({matrix(row, 0), matrix(row, 1), matrix(row, 2)});
    rows(key, values, 1.0);
  }
  void boolean(std::string_view key, bool value) override { put(key, value ? "true" : "false"); }
  void string(std::string_view key, std::string_view value) override {
    put(key, toml_string(std::string(value)));
  }
  void string_list(std::string_view key, std::span<const std::string> values) override {
    std::string text = "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      text += (i ? ", " : "") + toml_string(values[i]);
    put(key, text + "]");
  }
  void number_table(std::string_view key,
                    const std::vector<std::pair<std::string, double>>& entries) override {
    TomlTableWriter& table = sub_table("[", key, "]");
    for (const auto& [name, value] : entries) table.number(name, value);
  }
  void string_table(std::string_view key,
                    const std::vector<std::pair<std::string, std::string>>& entries) override {
    TomlTableWriter& table = sub_table("[", key, "]");
    for (const auto& [name, value] : entries) table.string(name, value);
  }
  kinematics::ModelConfigWriter& table_list_entry(std::string_view key) override {
    return sub_table("[[", key, "]]");
  }

  std::string text() const {
    std::string text = header_ + "\n" + keys_;
    for (const auto& table : tables_) text += "\n" + table->text();
    return text;
  }

 private:
  void put(std::string_view key, const std::string& value) {
    keys_ += std::string(key) + " = " + value + "\n";
  }
  void rows(std::string_view key, const std::vector<std::vector<double>>& values, double scale) {
    if (values.size() <= 2) {
      std::string text = "[";
      for (std::size_t i = 0; i < values.size(); ++i) {
        text += (i ? ", " : "") + toml_row(values[i], scale);
      }
      put(key, text + "]");
      return;
    }
    std::string text = "[\n";
    for (const std::vector<double>& row : values) text += "  " + toml_row(row, scale) + ",\n";
    put(key, text + "]");
  }
  TomlTableWriter& sub_table(const char* open, std::string_view key, const char* close) {
    const std::string path = path_ + "." + std::string(key);
    tables_.push_back(std::make_unique<TomlTableWriter>(open + path + close, path, per_mm_));
    return *tables_.back();
  }

  std::string header_;
  std::string path_;
  double per_mm_;
  std::string keys_;
  std::vector<std::unique_ptr<TomlTableWriter>> tables_;
};

}  // namespace

std::string kinematics_toml(const kinematics::Kinematics& kinematics, LengthUnit units) {
  TomlTableWriter section("[kinematics]", "kinematics",
                          units == LengthUnit::inch ? 1.0 / 25.4 : 1.0);
  kinematics::write_kinematics_config(kinematics, section);
  return section.text();
}

std::string replace_kinematics_section(const std::string& original_text,
                                       const std::string& source_name,
                                       const kinematics::Kinematics& kinematics, LengthUnit units) {
  // Where the section starts and ends comes from the parser, not from scanning text: a line
  // beginning with '[' may as well be a row of a multi-line array.
  refuse_unbounded_toml(original_text, source_name);
  toml::table document;
  try {
    document = toml::parse(original_text, source_name);
  } catch (const toml::parse_error& error) {
    throw MachineFileError(source_name, static_cast<int>(error.source().begin.line), "(syntax)",
                           std::string(error.description()));
  }
  const toml::table* section = document.get_as<toml::table>("kinematics");
  if (section == nullptr || section->is_inline()) {
    throw MachineFileError(source_name, 1, "kinematics",
                           "cannot rewrite this file: it has no [kinematics] table header");
  }
  const auto first_line = static_cast<std::size_t>(section->source().begin.line);
  std::size_t next_line = std::numeric_limits<std::size_t>::max();
  const auto consider = [&](const toml::node& node) {
    const auto line = static_cast<std::size_t>(node.source().begin.line);
    if (line > first_line && line < next_line) next_line = line;
  };
  for (const auto& [key, node] : document) {
    if (key.str() == "kinematics") continue;
    if (const toml::table* table = node.as_table(); table != nullptr && !table->is_inline()) {
      consider(*table);
    } else if (const toml::array* array = node.as_array();
               array != nullptr && array->is_array_of_tables()) {
      for (const toml::node& element : *array) consider(element);
    }
  }
  std::vector<std::string> lines;
  {
    std::istringstream in(original_text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  const std::size_t begin = first_line - 1;  // 0-based
  std::size_t end = std::min(lines.size(), next_line - 1);
  // Comments and blank lines just before the next table belong to that table.
  while (end > begin + 1) {
    const std::string& previous = lines[end - 1];
    const auto first = previous.find_first_not_of(" \t\r");
    if (first != std::string::npos && previous[first] != '#') break;
    --end;
  }
  std::string text;
  for (std::size_t i = 0; i < begin; ++i) text += lines[i] + "\n";
  text += kinematics_toml(kinematics, units);
  for (std::size_t i = end; i < lines.size(); ++i) text += lines[i] + "\n";
  return text;
}

}  // namespace pkm::machine
