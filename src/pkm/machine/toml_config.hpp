// ModelConfig over a toml++ table: typed reads with unit conversion, file:line:key errors, and a
// record of every key read so that unknown keys can be reported.
#pragma once

#include <toml++/toml.h>

#include <map>
#include <memory>
#include <set>
#include <string>

#include "pkm/kinematics/model_config.hpp"

namespace pkm::machine {

// Bounds on a machine file's text, checked before toml++ reads it: toml++ recurses once per part
// of a dotted key and per level of nested arrays and inline tables, so text beyond these would
// overflow the stack. docs/machine-file.md states them.
inline constexpr std::size_t kMaxTomlLineBytes = 65536;
inline constexpr int kMaxTomlKeyParts = 32;  // parts of one dotted key ("a.b.c" has 3)
inline constexpr int kMaxTomlNesting = 32;   // arrays and inline tables inside one another
// Throws MachineFileError (file:line:(syntax)) for the first line beyond a bound.
void refuse_unbounded_toml(std::string_view text, const std::string& source_name);

// Shared by a file's sections: which keys of which table have been read.
class KeyTracker {
 public:
  explicit KeyTracker(std::string file) : file_(std::move(file)) {}
  void register_table(const toml::table& table, std::string path);
  void mark(const toml::table& table, std::string_view key);
  // A reader looked for `key` (present or not): a name valid in this table.
  void note_asked(const toml::table& table, std::string_view key);
  // Throws MachineFileError for the first key (in file order) that no reader asked for, with the
  // closest valid name of its table.
  void check_all_read() const;
  // A key of `table` nobody has read that looks like a misspelling of `wanted`, or "".
  std::string unread_near(const toml::table& table, std::string_view wanted) const;
  const std::string& file() const { return file_; }

 private:
  struct Entry {
    std::string path;
    std::set<std::string, std::less<>> read;
    std::set<std::string, std::less<>> asked;
  };
  std::string file_;
  std::map<const toml::table*, Entry> tables_;
};

class TomlSection final : public kinematics::ModelConfig {
 public:
  TomlSection(const toml::table& table, std::string path, std::shared_ptr<KeyTracker> tracker,
              double mm_per_unit, std::vector<std::string> joint_names);

  bool has(std::string_view key) const override;
  double number(std::string_view key) const override;
  std::vector<double> number_list(std::string_view key) const override;
  double length(std::string_view key) const override;
  std::vector<double> length_list(std::string_view key) const override;
  Eigen::Vector3d length_vector3(std::string_view key) const override;
  std::vector<std::vector<double>> length_points(std::string_view key,
                                                 std::size_t dimension) const override;
  Eigen::Matrix3d matrix3(std::string_view key) const override;
  bool boolean(std::string_view key) const override;
  bool is_list(std::string_view key) const override;
  std::string string(std::string_view key) const override;
  std::vector<std::string> string_list(std::string_view key) const override;
  std::vector<std::pair<std::string, double>> number_table(std::string_view key) const override;
  std::vector<std::pair<std::string, std::string>> string_table(
      std::string_view key) const override;
  std::vector<std::unique_ptr<kinematics::ModelConfig>> table_list(
      std::string_view key) const override;
  std::vector<std::string> joint_names() const override { return joint_names_; }
  double mm_per_file_unit() const override { return mm_per_unit_; }
  void raise(std::string_view key, std::string_view message) const override;

  // The typed sub-table at `key` (required), as a section of its own.
  TomlSection section(std::string_view key) const;
  // Line of `key` in the file, or of this table when the key is absent.
  int line_of(std::string_view key) const;
  std::string key_path(std::string_view key) const;
  void set_joint_names(std::vector<std::string> names) { joint_names_ = std::move(names); }

 private:
  const toml::node& require(std::string_view key) const;
  double finite_number(const toml::node& node, std::string_view key) const;
  const toml::array& require_array(std::string_view key) const;
  // A length of the file in mm, refused beyond a kilometre.
  double to_length(double value, std::string_view key) const;

  const toml::table& table_;
  std::string path_;
  std::shared_ptr<KeyTracker> tracker_;
  double mm_per_unit_;
  std::vector<std::string> joint_names_;
};

}  // namespace pkm::machine
