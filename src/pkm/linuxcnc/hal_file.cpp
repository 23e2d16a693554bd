#include "pkm/linuxcnc/hal_file.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace pkm::linuxcnc {

namespace {

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.';
}

// halcmd's comments: a '#' at the start of a word ends the line.
std::string without_comment(const std::string& line) {
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
      return line.substr(0, i);
    }
  }
  return line;
}

bool is_arrow(const std::string& word) {
  return word == "=>" || word == "<=" || word == "<=>";
}

// A HALFILE line's file: LIB:name in the hallib; a relative name beside the INI, else in the
// hallib (as the linuxcnc script looks it up); an absolute name as it is.
std::filesystem::path hal_file_path(const std::string& name, const IniFile& ini,
                                    const std::filesystem::path& hallib) {
  if (name.rfind("LIB:", 0) == 0) return hallib / name.substr(4);
  const std::filesystem::path path(name);
  if (path.is_absolute()) return path;
  const std::filesystem::path beside = ini.directory() / path;
  std::error_code code;
  if (std::filesystem::exists(beside, code)) return beside;
  if (std::filesystem::exists(hallib / path, code)) return hallib / path;
  return beside;
}

// Tcl HAL files: a line is read only when it is a plain HAL command (no Tcl variables, command
// substitutions or braces), the rest can only be noted.
bool plain_tcl_command(const std::string& line) {
  return line.find_first_of("$[]{}\"\\;") == std::string::npos;
}

}  // namespace

std::string substitute_ini_values(const std::string& line, const IniFile& ini,
                                  const SourceLocation& where) {
  std::string out;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] != '[') {
      out += line[i++];
      continue;
    }
    const std::size_t close = line.find(']', i);
    if (close == std::string::npos) {
      out += line.substr(i);
      break;
    }
    const std::string section = line.substr(i + 1, close - i - 1);
    std::size_t key_begin = close + 1, key_end = key_begin;
    const bool parenthesised = key_begin < line.size() && line[key_begin] == '(';
    if (parenthesised) {
      key_end = line.find(')', key_begin);
      if (key_end == std::string::npos) key_end = key_begin;
      ++key_begin;
    } else {
      while (key_end < line.size() && is_name_char(line[key_end]) && line[key_end] != '.') {
        ++key_end;
      }
    }
    const std::string key = line.substr(key_begin, key_end - key_begin);
    if (section.empty() || key.empty()) {
      out += line[i++];
      continue;
    }
    const IniEntry* entry = ini.find(section, key);
    if (entry == nullptr) {
      throw ConfigError(where.file, where.line,
                        "[" + section + "]" + key + " is not in " + ini.path().string());
    }
    out += entry->value;
    i = parenthesised ? key_end + 1 : key_end;
  }
  return out;
}

HalConfig HalConfig::read(const IniFile& ini, const std::filesystem::path& hallib) {
  HalConfig hal;
  const auto files = [&](const char* key) {
    for (const IniEntry* entry : ini.find_all("HAL", key)) {
      const std::vector<std::string> words = split_words(entry->value);
      if (words.empty()) continue;
      const std::filesystem::path path = hal_file_path(words.front(), ini, hallib);
      std::error_code code;
      if (!std::filesystem::is_regular_file(path, code)) {
        ini.fail(*entry, "HAL file " + path.string() + " does not exist" +
                             (words.front().rfind("LIB:", 0) == 0
                                  ? " (LIB: is LinuxCNC's " + hallib.string() + ")"
                                  : ""));
      }
      hal.read_file(path, ini, path.extension() == ".tcl");
    }
  };
  files("HALFILE");
  for (const IniEntry* entry : ini.find_all("HAL", "HALCMD")) {
    hal.command(split_words(substitute_ini_values(entry->value, ini, entry->where)), entry->where);
  }
  files("POSTGUI_HALFILE");
  return hal;
}

void HalConfig::read_file(const std::filesystem::path& path, const IniFile& ini, bool tcl) {
  std::istringstream in(read_config_text(path));
  if (tcl) tcl_files_.push_back(path.string());
  int line_number = 0;
  std::string pending;  // a line continued with a trailing backslash
  int pending_start = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line_number;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    if (pending.empty()) pending_start = line_number;
    if (!tcl && !raw.empty() && raw.back() == '\\') {
      pending += raw.substr(0, raw.size() - 1) + " ";
      continue;
    }
    const std::string line = std::string(trim(without_comment(pending + raw)));
    pending.clear();
    if (line.empty()) continue;
    const SourceLocation where{path.string(), pending_start};
    if (tcl) {
      const std::vector<std::string> words = split_words(line);
      const bool hal_command = words.front() == "setp" || words.front() == "sets" ||
                               words.front() == "net" || words.front() == "loadrt";
      if (hal_command && plain_tcl_command(line)) {
        command(words, where);
      } else if (hal_command || line.find("kins") != std::string::npos) {
        unread_.push_back(UnreadLine{where, line});
      }
      continue;
    }
    command(split_words(substitute_ini_values(line, ini, where)), where);
  }
}

void HalConfig::command(const std::vector<std::string>& words, const SourceLocation& where) {
  if (words.empty()) return;
  const std::string& verb = words.front();
  if (verb == "loadrt" && words.size() >= 2) {
    modules_.push_back(HalModule{words[1], {words.begin() + 2, words.end()}, where});
  } else if (verb == "setp" && words.size() >= 3) {
    setp_[words[1]] = HalValue{words[2], where, "setp " + words[1]};
  } else if (verb == "sets" && words.size() >= 3) {
    sets_[words[1]] = HalValue{words[2], where, "sets " + words[1]};
  } else if (verb == "net" && words.size() >= 2) {
    for (std::size_t i = 2; i < words.size(); ++i) {
      if (is_arrow(words[i])) continue;
      signal_of_pin_[words[i]] = words[1];
      pins_of_signal_[words[1]].push_back(words[i]);
    }
  } else if ((verb == "linkps" || verb == "linksp") && words.size() >= 3) {
    const std::string& pin = verb == "linkps" ? words[1] : words[2];
    const std::string& signal = verb == "linkps" ? words[2] : words[1];
    signal_of_pin_[pin] = signal;
    pins_of_signal_[signal].push_back(pin);
  }
}

std::optional<HalValue> HalConfig::value_of(const std::string& pin) const {
  if (const auto signal = signal_of_pin_.find(pin); signal != signal_of_pin_.end()) {
    if (const auto set = sets_.find(signal->second); set != sets_.end()) {
      HalValue value = set->second;
      value.how += " (the signal of " + pin + ")";
      return value;
    }
  }
  if (const auto set = setp_.find(pin); set != setp_.end()) return set->second;
  return std::nullopt;
}

std::optional<double> HalConfig::number_of(const std::string& pin) const {
  const std::optional<HalValue> value = value_of(pin);
  if (!value) return std::nullopt;
  const std::optional<double> number = parse_config_number(value->text);
  if (!number) {
    throw ConfigError(value->where.file, value->where.line, pin,
                      value->how + ": '" + value->text + "' is not a number");
  }
  return number;
}

std::optional<std::string> HalConfig::driven_by(const std::string& pin) const {
  const auto signal = signal_of_pin_.find(pin);
  if (signal == signal_of_pin_.end() || sets_.count(signal->second) != 0) return std::nullopt;
  std::string others;
  for (const std::string& other : pins_of_signal_.at(signal->second)) {
    if (other != pin) others += (others.empty() ? "" : ", ") + other;
  }
  if (others.empty()) return std::nullopt;
  return others;
}

}  // namespace pkm::linuxcnc
