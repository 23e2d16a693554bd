#include "pkm/linuxcnc/config_migrate.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>

#include "pkm/linuxcnc/kins_adapter.hpp"

namespace pkm::linuxcnc {

namespace fs = std::filesystem;

const std::vector<std::string>& migratable_kinematics() {
  static const std::vector<std::string> modules = {"genhexkins", "lineardeltakins",
                                                   "rotarydeltakins", "matrixkins"};
  return modules;
}

namespace {

const char* const kMark = "# pkm linuxcnc migrate: ";

// INI keys whose values are directories or files looked up relative to the configuration
// (colon-separated lists for the paths).
const std::set<std::string> kPathKeys = {"PROGRAM_PREFIX", "SUBROUTINE_PATH", "USER_M_PATH",
                                         "PATH_PREPEND",   "PATH_APPEND",     "TOPLEVEL"};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : " ") + word;
  return text;
}

// The pins of the old kinematics: its own, switchkins' kinstype.is-N, and motion's
// switchkins-type (motion makes it only for a switchable module; pkmkins is not one).
struct OldPins {
  std::string module;
  bool operator()(const std::string& word) const {
    return word.rfind(module + ".", 0) == 0 || word.rfind("kinstype.", 0) == 0 ||
           word == "motion.switchkins-type";
  }
};

bool is_arrow(const std::string& word) {
  return word == "=>" || word == "<=" || word == "<=>";
}

// A net without the old module's pins: the arrow before a removed pin, arrows left next to each
// other and at the end dropped ("net s <= old => reader" -> "net s => reader").
std::vector<std::string> net_without(const std::vector<std::string>& words, const OldPins& old) {
  std::vector<std::string> kept(words.begin(), words.begin() + 2);  // net SIGNAL
  for (std::size_t i = 2; i < words.size(); ++i) {
    if (old(words[i])) {
      if (kept.size() > 2 && is_arrow(kept.back())) kept.pop_back();  // its arrow goes with it
      continue;
    }
    if (is_arrow(words[i]) && is_arrow(kept.back())) continue;
    kept.push_back(words[i]);
  }
  while (kept.size() > 2 && is_arrow(kept.back())) kept.pop_back();
  return kept;
}

// One HAL file's (or HALCMD's) edits, shared across files: the signals whose nets lost every pin
// (their `sets` lines go too).
struct HalEditor {
  OldPins old;
  std::string kinematics;  // what loads pkmkins: "pkmkins machine=hexapod.toml"
  std::set<std::string> dropped_signals;

  // The line's replacement, or nullopt when it stays as it is.
  std::optional<std::string> edit(const std::string& line, std::string& what) {
    const std::vector<std::string> words = split_words(line);
    if (words.empty() || words[0][0] == '#') return std::nullopt;
    if (words[0] == "loadrt" && words.size() > 1 && words[1] == old.module) {
      what = "loads " + kinematics + " instead of " + old.module;
      return std::string(kMark) + "was: " + line + "\nloadrt " + kinematics;
    }
    if (words[0] == "net" && words.size() > 2 && std::any_of(words.begin() + 2, words.end(), old)) {
      const std::vector<std::string> kept = net_without(words, old);
      if (kept.size() == 2) {
        dropped_signals.insert(words[1]);
        what = "net " + words[1] + " commented out: its pins were all the old kinematics'";
        return std::string(kMark) + line;
      }
      what = "net " + words[1] + " without the old kinematics' pins";
      return std::string(kMark) + "was: " + line + "\n" + joined(kept);
    }
    const bool sets_dropped =
        words[0] == "sets" && words.size() > 1 && dropped_signals.count(words[1]) > 0;
    if (sets_dropped || std::any_of(words.begin() + 1, words.end(), old)) {
      what = words[0] + " " + (words.size() > 1 ? words[1] : "") + " commented out" +
             (words[0] == "setp" ? " (the geometry is the machine file's)" : "");
      return std::string(kMark) + line;
    }
    return std::nullopt;
  }
};

class Migrator {
 public:
  Migrator(const fs::path& ini_path, const MigrateOptions& options)
      : ini_(IniFile::read(ini_path)),
        options_(options),
        source_(fs::absolute(ini_path).parent_path()) {
    editor_.old.module = module_name();
    editor_.kinematics = kinematics_value();
    migration_.module = editor_.old.module;
    migration_.ini_name = ini_path.filename().string();
  }

  Migration run() {
    check_joints();
    copy_directory();
    ini_lines_ = split_lines(file_text(migration_.ini_name));
    edit_kinematics();
    edit_ini_hal();
    edit_paths();
    set_file(migration_.ini_name, join_lines(ini_lines_));
    set_file(options_.machine_file_name, options_.machine_text);  // over a file of that name
    warn_switchkins_users();
    return std::move(migration_);
  }

 private:
  std::string module_name() const {
    const IniEntry* entry = ini_.find("KINS", "KINEMATICS");
    if (entry == nullptr) ini_.fail_missing("KINS", "KINEMATICS", "it names the kinematics");
    const std::vector<std::string> words = split_words(entry->value);
    const std::string name = words.empty() ? "" : words.front();
    const auto& known = migratable_kinematics();
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      ini_.fail(*entry, "'" + name + "' is not a kinematics module pkm linuxcnc migrate " +
                            "switches from (genhexkins, lineardeltakins, rotarydeltakins, " +
                            "matrixkins)");
    }
    return name;
  }

  void check_joints() const {
    const IniEntry* joints = ini_.find("KINS", "JOINTS");
    if (joints == nullptr) ini_.fail_missing("KINS", "JOINTS", "pkmkins needs the joint count");
    if (joints->value != std::to_string(options_.machine_joints)) {
      ini_.fail(*joints, "[KINS] JOINTS = " + joints->value + " but " + options_.machine_file_name +
                             " has " + std::to_string(options_.machine_joints) +
                             " joints: pkmkins drives exactly the machine file's joints (give a "
                             "machine file with a joint for each, or edit the configuration's "
                             "joints first)");
    }
  }

  // The INI's directory: its files, and the subdirectories its path keys name, recursively.
  void copy_directory() {
    for (const fs::directory_entry& entry : fs::directory_iterator(source_)) {
      if (entry.is_regular_file()) add_copy(entry.path());
    }
    for (const IniEntry& entry : ini_.entries()) {
      if (kPathKeys.count(entry.key) == 0) continue;
      for (const std::string& element : path_elements(entry.value)) {
        const fs::path inside = inside_source(element);
        if (inside.empty() || !fs::is_directory(source_ / inside)) continue;
        for (const fs::directory_entry& file : fs::recursive_directory_iterator(source_ / inside))
          if (file.is_regular_file()) add_copy(file.path());
      }
    }
  }

  void add_copy(const fs::path& path) {
    const std::string name = fs::relative(path, source_).lexically_normal().string();
    for (const ConfigFile& file : migration_.files)
      if (file.name == name) return;
    migration_.files.push_back({name, read_config_text(path)});
  }

  static std::vector<std::string> path_elements(const std::string& value) {
    std::vector<std::string> elements;
    std::size_t start = 0;
    while (start <= value.size()) {
      const std::size_t end = std::min(value.find(':', start), value.size());
      const std::string element(trim(value.substr(start, end - start)));
      if (!element.empty()) elements.push_back(element);
      start = end + 1;
    }
    return elements;
  }

  // The element relative to the configuration's directory when it lies inside it; empty else.
  fs::path inside_source(const std::string& element) const {
    const fs::path path(element);
    if (path.is_absolute() || element[0] == '~') return {};
    const fs::path relative = path.lexically_normal();
    if (relative.empty() || *relative.begin() == "..") return {};
    return relative;
  }

  std::string& file_text(const std::string& name) {
    for (ConfigFile& file : migration_.files)
      if (file.name == name) return file.text;
    throw ConfigError(name, "not in the configuration's directory");
  }

  void set_file(const std::string& name, const std::string& text) {
    for (ConfigFile& file : migration_.files) {
      if (file.name == name) {
        file.text = text;
        return;
      }
    }
    migration_.files.push_back({name, text});
  }

  bool in_main_ini(const IniEntry& entry) const {
    return fs::path(entry.where.file) == ini_.path();
  }

  std::string at(const IniEntry& entry) const {
    return migration_.ini_name + ":" + std::to_string(entry.where.line) + ": ";
  }

  void replace_ini_line(const IniEntry& entry, const std::string& text) {
    ini_lines_[static_cast<std::size_t>(entry.where.line - 1)] = text;
  }

  // pkmkins with the machine file, and LinuxCNC's unit where it is not the machine file's.
  std::string kinematics_value() const {
    std::string value = "pkmkins machine=" + options_.machine_file_name;
    if (const IniEntry* units = ini_.find("TRAJ", "LINEAR_UNITS")) {
      const std::optional<machine::LengthUnit> unit = parse_world_unit(units->value);
      const std::string name = unit == machine::LengthUnit::inch ? "inch" : "mm";
      if (unit && name != options_.machine_units) value += " units=" + name;
    }
    return value;
  }

  void edit_kinematics() {
    const IniEntry& entry = *ini_.find("KINS", "KINEMATICS");
    if (!in_main_ini(entry)) {
      throw ConfigError(entry.where.file, entry.where.line, "[KINS]KINEMATICS",
                        "is in a file the INI includes: pkm linuxcnc migrate edits the INI "
                        "itself; move [KINS] into it");
    }
    const std::string value = editor_.kinematics;
    replace_ini_line(entry, std::string(kMark) + "was: KINEMATICS = " + entry.value +
                                "\nKINEMATICS = " + value +
                                "\nPKM_MACHINE = " + options_.machine_file_name);
    migration_.edits.push_back(at(entry) + "[KINS] KINEMATICS = " + entry.value + " -> " + value +
                               " (and PKM_MACHINE)");
  }

  // HALCMD lines, and the HAL files of HALFILE and POSTGUI_HALFILE.
  void edit_ini_hal() {
    for (const IniEntry& entry : ini_.entries()) {
      if (entry.section != "HAL" || !in_main_ini(entry)) continue;
      if (entry.key == "HALCMD") {
        std::string what;
        if (const std::optional<std::string> edited = editor_.edit(entry.value, what)) {
          replace_ini_line(entry, hal_command_lines(*edited));
          migration_.edits.push_back(at(entry) + "HALCMD: " + what);
        }
      } else if (entry.key == "HALFILE" || entry.key == "POSTGUI_HALFILE") {
        edit_hal_file(entry);
      }
    }
  }

  // An edited HAL command as INI lines: comments stay comments, the command is a HALCMD.
  static std::string hal_command_lines(const std::string& edited) {
    std::string text;
    for (const std::string& line : split_lines(edited))
      text += (text.empty() ? "" : "\n") + (line[0] == '#' ? line : "HALCMD = " + line);
    return text;
  }

  void edit_hal_file(const IniEntry& entry) {
    const std::vector<std::string> words = split_words(entry.value);
    if (words.empty()) return;
    const bool from_lib = words[0].rfind("LIB:", 0) == 0;
    const std::string name = from_lib ? words[0].substr(4) : words[0];
    const fs::path local = source_ / name;
    const bool is_local = !from_lib && fs::exists(local);
    const fs::path path = is_local ? local : options_.hallib / name;
    if (!fs::exists(path)) return;  // LinuxCNC itself says so at start
    std::vector<std::string> lines = split_lines(read_config_text(path));
    std::vector<std::string> what_all;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      std::string what;
      if (const std::optional<std::string> edited = editor_.edit(lines[i], what)) {
        lines[i] = *edited;
        what_all.push_back(name + ":" + std::to_string(i + 1) + ": " + what);
      }
    }
    if (what_all.empty()) return;
    const std::string copy_name =
        is_local ? fs::relative(local, source_).string() : fs::path(name).filename().string();
    set_file(copy_name, join_lines(lines));
    if (!is_local && from_lib) {
      std::string rest = entry.value.substr(words[0].size());
      replace_ini_line(entry, std::string(kMark) + "was: " + entry.key + " = " + entry.value +
                                  "\n" + entry.key + " = " + copy_name + rest);
      migration_.edits.push_back(at(entry) + entry.key + " " + entry.value +
                                 ": LinuxCNC's library file copied into the directory as " +
                                 copy_name + " and edited");
    }
    if (!is_local && !from_lib) {
      migration_.edits.push_back(at(entry) + entry.key + " " + entry.value +
                                 ": LinuxCNC's library file copied into the directory (found "
                                 "there first) and edited");
    }
    migration_.edits.insert(migration_.edits.end(), what_all.begin(), what_all.end());
  }

  // Relative paths that leave the directory would not follow the copy: made absolute.
  void edit_paths() {
    for (const IniEntry& entry : ini_.entries()) {
      if (kPathKeys.count(entry.key) == 0 || !in_main_ini(entry)) continue;
      std::string value;
      bool changed = false;
      for (const std::string& element : path_elements(entry.value)) {
        std::string kept = element;
        const fs::path path(element);
        if (!path.is_absolute() && element[0] != '~' && inside_source(element).empty()) {
          kept = (source_ / path).lexically_normal().string();
          if (element.back() == '/' && kept.back() != '/') kept += "/";
          changed = true;
        }
        value += (value.empty() ? "" : ":") + kept;
      }
      if (!changed) continue;
      replace_ini_line(entry, std::string(kMark) + "was: " + entry.key + " = " + entry.value +
                                  "\n" + entry.key + " = " + value);
      migration_.edits.push_back(at(entry) + entry.key + " = " + entry.value + " -> " + value +
                                 " (outside the directory: made absolute)");
    }
  }

  // G-code (remaps) that switches kinematics through motion.switchkins-type.
  void warn_switchkins_users() {
    for (const ConfigFile& file : migration_.files) {
      const std::string extension = fs::path(file.name).extension().string();
      if (extension != ".ngc" || file.text.find("switchkins-type") == std::string::npos) continue;
      migration_.warnings.push_back(
          file.name +
          " reads motion.switchkins-type, which pkmkins (one kinematics, not switchable) does not "
          "have: a remap that switches kinematics ends the program if it is called");
    }
  }

  IniFile ini_;
  MigrateOptions options_;
  fs::path source_;
  HalEditor editor_;
  Migration migration_;
  std::vector<std::string> ini_lines_;
};

}  // namespace

Migration migrate_linuxcnc_config(const fs::path& ini_path, const MigrateOptions& options) {
  return Migrator(ini_path, options).run();
}

}  // namespace pkm::linuxcnc
