#include "pkm/machine/toml_config.hpp"

#include <cmath>
#include <limits>

#include "pkm/machine/machine_file_error.hpp"

namespace pkm {

namespace {
int line_of_node(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}
}  // namespace

void KeyTracker::register_table(const toml::table& table, std::string path) {
  tables_.try_emplace(&table, Entry{std::move(path), {}});
}

void KeyTracker::mark(const toml::table& table, std::string_view key) {
  const auto found = tables_.find(&table);
  if (found != tables_.end()) found->second.read.emplace(key);
}

void KeyTracker::check_all_read() const {
  int first_line = std::numeric_limits<int>::max();
  std::string first_key;
  for (const auto& [table, entry] : tables_) {
    for (const auto& [key, node] : *table) {
      if (entry.read.count(key.str()) != 0) continue;
      const int line = line_of_node(node);
      if (line < first_line) {
        first_line = line;
        first_key =
            entry.path.empty() ? std::string(key.str()) : entry.path + "." + std::string(key.str());
      }
    }
  }
  if (!first_key.empty()) {
    throw MachineFileError(file_, first_line, first_key,
                           "unknown key (see docs/machine-file.md for the keys of each table)");
  }
}

TomlSection::TomlSection(const toml::table& table, std::string path,
                         std::shared_ptr<KeyTracker> tracker, double mm_per_unit,
                         std::vector<std::string> joint_names)
    : table_(table),
      path_(std::move(path)),
      tracker_(std::move(tracker)),
      mm_per_unit_(mm_per_unit),
      joint_names_(std::move(joint_names)) {
  tracker_->register_table(table_, path_);
}

std::string TomlSection::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

int TomlSection::line_of(std::string_view key) const {
  if (const toml::node* node = table_.get(key)) return line_of_node(*node);
  return line_of_node(table_);
}

void TomlSection::raise(std::string_view key, std::string_view message) const {
  // A key like "formulas.left" names a value inside a sub-table: locate it there.
  int line = line_of(key);
  const auto dot = key.find('.');
  if (dot != std::string_view::npos) {
    if (const toml::table* sub = table_.get_as<toml::table>(key.substr(0, dot))) {
      if (const toml::node* node = sub->get(key.substr(dot + 1))) line = line_of_node(*node);
    }
  }
  throw MachineFileError(tracker_->file(), line, key_path(key), std::string(message));
}

bool TomlSection::has(std::string_view key) const {
  // Asking counts as reading: a model that looks for an optional key knows that key.
  if (table_.contains(key)) tracker_->mark(table_, key);
  return table_.contains(key);
}

const toml::node& TomlSection::require(std::string_view key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) fail(key, "missing (required)");
  tracker_->mark(table_, key);
  return *node;
}

double TomlSection::finite_number(const toml::node& node, std::string_view key) const {
  const std::optional<double> value = node.value<double>();
  if (!value || !(node.is_integer() || node.is_floating_point())) fail(key, "must be a number");
  if (!std::isfinite(*value)) fail(key, "must be finite, not nan or inf");
  return *value;
}

double TomlSection::number(std::string_view key) const {
  return finite_number(require(key), key);
}

const toml::array& TomlSection::require_array(std::string_view key) const {
  const toml::array* array = require(key).as_array();
  if (array == nullptr) fail(key, "must be an array");
  return *array;
}

std::vector<double> TomlSection::number_list(std::string_view key) const {
  std::vector<double> values;
  for (const toml::node& element : require_array(key)) {
    values.push_back(finite_number(element, key));
  }
  return values;
}

double TomlSection::length(std::string_view key) const {
  return number(key) * mm_per_unit_;
}

std::vector<double> TomlSection::length_list(std::string_view key) const {
  std::vector<double> values = number_list(key);
  for (double& value : values) value *= mm_per_unit_;
  return values;
}

Eigen::Vector3d TomlSection::length_vector3(std::string_view key) const {
  const std::vector<double> values = length_list(key);
  if (values.size() != 3) fail(key, "needs 3 numbers [x, y, z]");
  return {values[0], values[1], values[2]};
}

std::vector<Eigen::Vector3d> TomlSection::length_vector3_list(std::string_view key) const {
  std::vector<Eigen::Vector3d> points;
  for (const toml::node& element : require_array(key)) {
    const toml::array* point = element.as_array();
    if (point == nullptr || point->size() != 3) fail(key, "each point needs 3 numbers [x, y, z]");
    Eigen::Vector3d value;
    for (int k = 0; k < 3; ++k) value[k] = finite_number(*point->get(k), key) * mm_per_unit_;
    points.push_back(value);
  }
  return points;
}

Eigen::Matrix3d TomlSection::matrix3(std::string_view key) const {
  const toml::array& rows = require_array(key);
  if (rows.size() != 3) fail(key, "needs 3 rows of 3 numbers");
  Eigen::Matrix3d matrix;
  for (int row = 0; row < 3; ++row) {
    const toml::array* values = rows.get(row)->as_array();
    if (values == nullptr || values->size() != 3) fail(key, "needs 3 rows of 3 numbers");
    for (int col = 0; col < 3; ++col) matrix(row, col) = finite_number(*values->get(col), key);
  }
  return matrix;
}

bool TomlSection::boolean(std::string_view key) const {
  const std::optional<bool> value = require(key).value_exact<bool>();
  if (!value) fail(key, "must be true or false");
  return *value;
}

std::string TomlSection::string(std::string_view key) const {
  const std::optional<std::string> value = require(key).value_exact<std::string>();
  if (!value) fail(key, "must be a string");
  return *value;
}

std::vector<std::string> TomlSection::string_list(std::string_view key) const {
  std::vector<std::string> values;
  for (const toml::node& element : require_array(key)) {
    const std::optional<std::string> value = element.value_exact<std::string>();
    if (!value) fail(key, "must be an array of strings");
    values.push_back(*value);
  }
  return values;
}

std::vector<std::pair<std::string, double>> TomlSection::number_table(std::string_view key) const {
  const toml::table* table = require(key).as_table();
  if (table == nullptr) fail(key, "must be a table of numbers");
  std::vector<std::pair<std::string, double>> entries;
  for (const auto& [name, node] : *table) {
    const std::string name_path = std::string(key) + "." + std::string(name.str());
    entries.emplace_back(std::string(name.str()), finite_number(node, name_path));
  }
  return entries;
}

std::vector<std::pair<std::string, std::string>> TomlSection::string_table(
    std::string_view key) const {
  const toml::table* table = require(key).as_table();
  if (table == nullptr) fail(key, "must be a table of strings");
  std::vector<std::pair<std::string, std::string>> entries;
  for (const auto& [name, node] : *table) {
    const std::optional<std::string> value = node.value_exact<std::string>();
    if (!value) fail(std::string(key) + "." + std::string(name.str()), "must be a string");
    entries.emplace_back(std::string(name.str()), *value);
  }
  return entries;
}

std::vector<std::unique_ptr<ModelConfig>> TomlSection::table_list(std::string_view key) const {
  const toml::array* array = require(key).as_array();
  if (array == nullptr || !array->is_array_of_tables() || array->empty()) {
    fail(key, "must be one or more [[" + key_path(key) + "]] tables");
  }
  std::vector<std::unique_ptr<ModelConfig>> sections;
  int index = 1;
  for (const toml::node& element : *array) {
    sections.push_back(std::make_unique<TomlSection>(
        *element.as_table(), key_path(key) + "[" + std::to_string(index++) + "]", tracker_,
        mm_per_unit_, joint_names_));
  }
  return sections;
}

TomlSection TomlSection::section(std::string_view key) const {
  const toml::table* table = require(key).as_table();
  if (table == nullptr) fail(key, "must be a table [" + key_path(key) + "]");
  return TomlSection(*table, key_path(key), tracker_, mm_per_unit_, joint_names_);
}

}  // namespace pkm
