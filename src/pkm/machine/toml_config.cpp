#include "pkm/machine/toml_config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <vector>

#include "pkm/machine/machine_file_error.hpp"

namespace pkm::machine {

namespace {
int line_of_node(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}

// Edit distance (insertions, deletions, substitutions), case-insensitive.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// How unlike two key names are, or SIZE_MAX when one cannot be a misspelling of the other: a few
// letters wrong (a quarter of the name), or one cut short to at least half the other
// (`max_accel` for `max_acceleration`).
std::size_t misspelling_distance(std::string_view typed, std::string_view valid) {
  const std::size_t distance = edit_distance(typed, valid);
  const std::size_t longer = std::max(typed.size(), valid.size());
  const std::size_t shorter = std::min(typed.size(), valid.size());
  if (distance <= std::max<std::size_t>(1, longer / 4)) return distance;
  const bool prefix = typed.substr(0, shorter) == valid.substr(0, shorter);
  if (prefix && 2 * shorter >= longer && shorter >= 3) return distance;
  return std::numeric_limits<std::size_t>::max();
}

// Where a TOML scan stands: in which kind of string, if any.
enum class TomlText { plain, basic, literal, multiline_basic, multiline_literal, comment };

// The string that starts at text[at] (a quote), and how many quote characters open it.
std::pair<TomlText, std::size_t> opening(std::string_view text, std::size_t at) {
  const char quote = text[at];
  const bool triple = text.substr(at, 3) == std::string(3, quote);
  if (quote == '"') return {triple ? TomlText::multiline_basic : TomlText::basic, triple ? 3 : 1};
  return {triple ? TomlText::multiline_literal : TomlText::literal, triple ? 3 : 1};
}

// Whether text[at] closes a string of kind `in` (for a basic string: not escaped), and how many
// characters the closing takes.
std::size_t closing(std::string_view text, std::size_t at, TomlText in) {
  const char c = text[at];
  switch (in) {
    case TomlText::basic:
      return c == '"' ? 1 : 0;
    case TomlText::literal:
      return c == '\'' ? 1 : 0;
    case TomlText::multiline_basic:
      return text.substr(at, 3) == "\"\"\"" ? 3 : 0;
    case TomlText::multiline_literal:
      return text.substr(at, 3) == "\'\'\'" ? 3 : 0;
    default:
      return 0;
  }
}

[[noreturn]] void refuse_line(const std::string& source_name, int line, const std::string& what) {
  throw MachineFileError(source_name, line, "(syntax)", what);
}

}  // namespace

void KeyTracker::register_table(const toml::table& table, std::string path) {
  tables_.try_emplace(&table, Entry{std::move(path), {}, {}});
}

void KeyTracker::mark(const toml::table& table, std::string_view key) {
  const auto found = tables_.find(&table);
  if (found != tables_.end()) found->second.read.emplace(key);
}

void KeyTracker::note_asked(const toml::table& table, std::string_view key) {
  const auto found = tables_.find(&table);
  if (found != tables_.end()) found->second.asked.emplace(key);
}

std::string KeyTracker::unread_near(const toml::table& table, std::string_view wanted) const {
  const auto found = tables_.find(&table);
  if (found == tables_.end()) return "";
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& [key, node] : table) {
    // A key some reader asked for is valid here, whatever it looks like.
    if (found->second.read.count(key.str()) != 0 || found->second.asked.count(key.str()) != 0) {
      continue;
    }
    const std::size_t distance = misspelling_distance(key.str(), wanted);
    if (distance < best_distance) {
      best_distance = distance;
      best = std::string(key.str());
    }
  }
  return best;
}

void KeyTracker::check_all_read() const {
  int first_line = std::numeric_limits<int>::max();
  std::string first_key;
  std::string known;
  std::string suggestion;
  for (const auto& [table, entry] : tables_) {
    for (const auto& [key, node] : *table) {
      if (entry.read.count(key.str()) != 0) continue;
      const int line = line_of_node(node);
      if (line >= first_line) continue;
      first_line = line;
      first_key = std::string(key.str());
      first_key = entry.path.empty() ? first_key : entry.path + "." + first_key;
      known.clear();
      suggestion.clear();
      std::size_t best = std::numeric_limits<std::size_t>::max();
      for (const std::string& valid : entry.asked) {
        known += (known.empty() ? "" : ", ") + valid;
        const std::size_t distance = misspelling_distance(key.str(), valid);
        if (distance < best) {
          best = distance;
          suggestion = valid;
        }
      }
    }
  }
  if (first_key.empty()) return;
  const std::string name = first_key.substr(first_key.rfind('.') + 1);
  std::string message = "unknown key '" + name + "'";
  if (!suggestion.empty()) {
    message += " (did you mean '" + suggestion + "'?)";
  } else if (!known.empty()) {
    message += " (this table's keys: " + known + "; see docs/machine-file.md)";
  } else {
    message += " (see docs/machine-file.md for the keys of each table)";
  }
  throw MachineFileError(file_, first_line, first_key, message);
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
  tracker_->note_asked(table_, key);
  if (table_.contains(key)) tracker_->mark(table_, key);
  return table_.contains(key);
}

const toml::node& TomlSection::require(std::string_view key) const {
  tracker_->note_asked(table_, key);
  const toml::node* node = table_.get(key);
  if (node == nullptr) {
    // A misspelt key is the likelier mistake than a forgotten one: name it, at its own line.
    const std::string near = tracker_->unread_near(table_, key);
    if (!near.empty()) {
      fail(near, "unknown key '" + near + "' (did you mean '" + std::string(key) + "'?)");
    }
    fail(key, "missing (required)");
  }
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

bool TomlSection::is_list(std::string_view key) const {
  return require(key).is_array();
}

std::vector<double> TomlSection::number_list(std::string_view key) const {
  std::vector<double> values;
  for (const toml::node& element : require_array(key)) {
    values.push_back(finite_number(element, key));
  }
  return values;
}

double TomlSection::to_length(double value, std::string_view key) const {
  // A machine within a kilometre: beyond that a length is a typo, and squares of it lose every
  // digit a machine needs.
  constexpr double kMaxLength_mm = 1e6;
  const double mm = value * mm_per_unit_;
  if (!(std::abs(mm) <= kMaxLength_mm)) fail(key, "must be within a kilometre (1e6 mm) of 0");
  return mm;
}

double TomlSection::length(std::string_view key) const {
  return to_length(number(key), key);
}

std::vector<double> TomlSection::length_list(std::string_view key) const {
  std::vector<double> values = number_list(key);
  for (double& value : values) value = to_length(value, key);
  return values;
}

Eigen::Vector3d TomlSection::length_vector3(std::string_view key) const {
  const std::vector<double> values = length_list(key);
  if (values.size() != 3) fail(key, "needs 3 numbers [x, y, z]");
  return {values[0], values[1], values[2]};
}

std::vector<std::vector<double>> TomlSection::length_points(std::string_view key,
                                                            std::size_t dimension) const {
  const std::string shape = dimension == 2 ? "[x, y]" : "[x, y, z]";
  std::vector<std::vector<double>> points;
  for (const toml::node& element : require_array(key)) {
    const toml::array* point = element.as_array();
    if (point == nullptr || point->size() != dimension) {
      fail(key, "each point needs " + std::to_string(dimension) + " numbers " + shape);
    }
    std::vector<double>& value = points.emplace_back(dimension);
    for (std::size_t k = 0; k < dimension; ++k) {
      value[k] = to_length(finite_number(*point->get(k), key), key);
    }
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

std::vector<std::unique_ptr<kinematics::ModelConfig>> TomlSection::table_list(
    std::string_view key) const {
  const toml::array* array = require(key).as_array();
  if (array == nullptr || !array->is_array_of_tables() || array->empty()) {
    fail(key, "must be one or more [[" + key_path(key) + "]] tables");
  }
  std::vector<std::unique_ptr<kinematics::ModelConfig>> sections;
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

void refuse_unbounded_toml(std::string_view text, const std::string& source_name) {
  TomlText in = TomlText::plain;
  int line = 1, nesting = 0, key_parts = 1;
  std::size_t line_start = 0;
  for (std::size_t at = 0; at < text.size(); ++at) {
    const char c = text[at];
    if (c == '\n') {
      if (at - line_start > kMaxTomlLineBytes) {
        refuse_line(source_name, line,
                    "line longer than " + std::to_string(kMaxTomlLineBytes) + " bytes");
      }
      ++line;
      line_start = at + 1;
      key_parts = 1;
      if (in == TomlText::comment || in == TomlText::basic || in == TomlText::literal) {
        in = TomlText::plain;  // a single-line string left open is toml++'s error to report
      }
      continue;
    }
    if (in == TomlText::comment) continue;
    if (in != TomlText::plain) {
      if (in == TomlText::basic || in == TomlText::multiline_basic) {
        if (c == '\\' && at + 1 < text.size() && text[at + 1] != '\n') {
          ++at;  // the escaped character cannot close the string
          continue;
        }
      }
      if (const std::size_t length = closing(text, at, in)) {
        at += length - 1;
        in = TomlText::plain;
      }
      continue;
    }
    switch (c) {
      case '#':
        in = TomlText::comment;
        break;
      case '"':
      case '\'': {
        const auto [kind, length] = opening(text, at);
        in = kind;
        at += length - 1;
        break;
      }
      case '[':
      case '{':
        if (++nesting > kMaxTomlNesting) {
          refuse_line(source_name, line,
                      "arrays and tables nested deeper than " + std::to_string(kMaxTomlNesting));
        }
        key_parts = 1;
        break;
      case ']':
      case '}':
        nesting = std::max(0, nesting - 1);
        key_parts = 1;
        break;
      case '=':
      case ',':
        key_parts = 1;
        break;
      case '.':
        // Numbers hold one point; only a key holds many.
        if (++key_parts > kMaxTomlKeyParts) {
          refuse_line(source_name, line,
                      "a dotted key of more than " + std::to_string(kMaxTomlKeyParts) + " parts");
        }
        break;
      default:
        break;
    }
  }
  if (text.size() - line_start > kMaxTomlLineBytes) {
    refuse_line(source_name, line,
                "line longer than " + std::to_string(kMaxTomlLineBytes) + " bytes");
  }
}

}  // namespace pkm::machine
