#include "pkm/linuxcnc/ini_file.hpp"
#include "pkm/text/text_file.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace pkm::linuxcnc {

namespace {

// LinuxCNC's own limit on nested #INCLUDEs.
constexpr int kMaxIncludeDepth = 16;

std::string section_key(std::string_view section, std::string_view key) {
  return "[" + std::string(section) + "]" + std::string(key);
}

// An #INCLUDE's file name: absolute, home-relative (~/), or relative to the including file.
std::filesystem::path include_path(const std::string& name, const std::string& including_file) {
  if (name.rfind("~/", 0) == 0) {
    const char* home = std::getenv("HOME");
    if (home != nullptr) return std::filesystem::path(home) / name.substr(2);
  }
  const std::filesystem::path path(name);
  if (path.is_absolute()) return path;
  return std::filesystem::path(including_file).parent_path() / path;
}

}  // namespace

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> split_words(std::string_view text) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
    std::size_t end = i;
    while (end < text.size() && text[end] != ' ' && text[end] != '\t' && text[end] != '\r') ++end;
    if (end > i) words.emplace_back(text.substr(i, end - i));
    i = end;
  }
  return words;
}

std::optional<double> parse_config_number(std::string_view text) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::string read_config_text(const std::filesystem::path& path) {
  try {
    return text::read_text_file(path, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw ConfigError(path.string(), error.what());
  }
}

IniFile IniFile::read(const std::filesystem::path& path) {
  return parse(read_config_text(path), path.string());
}

IniFile IniFile::parse(std::string_view text, const std::string& source_name) {
  IniFile ini;
  ini.path_ = source_name;
  std::vector<std::string> open_files{source_name};
  std::string section;
  ini.parse_into(text, source_name, 0, open_files, section);
  return ini;
}

void IniFile::parse_into(std::string_view text, const std::string& source_name, int depth,
                         std::vector<std::string>& open_files, std::string& section) {
  parsed_bytes_ += text.size();
  std::istringstream in{std::string(text)};
  int line_number = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line_number;
    // #INCLUDE must start in the first column, in upper case, with a blank after it.
    if (raw.rfind("#INCLUDE", 0) == 0 && raw.size() > 8 && (raw[8] == ' ' || raw[8] == '\t')) {
      const std::string name(trim(std::string_view(raw).substr(9)));
      const std::filesystem::path included = include_path(name, source_name);
      if (depth + 1 >= kMaxIncludeDepth) {
        throw ConfigError(
            source_name, line_number,
            "#INCLUDE nested deeper than " + std::to_string(kMaxIncludeDepth) + " levels");
      }
      const std::string included_name = included.lexically_normal().string();
      if (std::find(open_files.begin(), open_files.end(), included_name) != open_files.end()) {
        throw ConfigError(
            source_name, line_number,
            "#INCLUDE " + name + " includes itself (directly or through another file)");
      }
      std::string included_text;
      try {
        included_text = read_config_text(included);
      } catch (const ConfigError& error) {
        throw ConfigError(source_name, line_number, "#INCLUDE " + name + ": " + error.what());
      }
      if (parsed_bytes_ + included_text.size() > text::kMaxConfigFileBytes) {
        throw ConfigError(source_name, line_number,
                          "#INCLUDE " + name + ": the configuration with its includes passes " +
                              std::to_string(text::kMaxConfigFileBytes >> 20) +
                              " MB (files included again and again?)");
      }
      open_files.push_back(included_name);
      parse_into(included_text, included.string(), depth + 1, open_files, section);
      open_files.pop_back();
      continue;
    }
    const std::string_view line = trim(raw);
    if (line.empty() || line.front() == '#' || line.front() == ';') continue;
    if (line.front() == '[') {
      const auto close = line.find(']');
      if (close == std::string_view::npos) {
        throw ConfigError(source_name, line_number, "section header without its closing ']'");
      }
      section = std::string(trim(line.substr(1, close - 1)));
      sections_.emplace_back(section, SourceLocation{source_name, line_number});
      continue;
    }
    const auto equals = line.find('=');
    if (equals == std::string_view::npos || section.empty()) continue;  // LinuxCNC ignores these
    entries_.push_back(IniEntry{section, std::string(trim(line.substr(0, equals))),
                                std::string(trim(line.substr(equals + 1))),
                                SourceLocation{source_name, line_number}});
  }
}

bool IniFile::has_section(std::string_view section) const {
  return std::any_of(sections_.begin(), sections_.end(),
                     [&](const auto& entry) { return entry.first == section; });
}

const IniEntry* IniFile::find(std::string_view section, std::string_view key) const {
  for (const IniEntry& entry : entries_) {
    if (entry.section == section && entry.key == key) return &entry;
  }
  return nullptr;
}

std::vector<const IniEntry*> IniFile::find_all(std::string_view section,
                                               std::string_view key) const {
  std::vector<const IniEntry*> found;
  for (const IniEntry& entry : entries_) {
    if (entry.section == section && entry.key == key) found.push_back(&entry);
  }
  return found;
}

std::optional<double> IniFile::number(std::string_view section, std::string_view key) const {
  const IniEntry* entry = find(section, key);
  if (entry == nullptr) return std::nullopt;
  const std::optional<double> value = parse_config_number(entry->value);
  if (!value) fail(*entry, "'" + entry->value + "' is not a number");
  return value;
}

std::optional<std::vector<double>> IniFile::numbers(std::string_view section,
                                                    std::string_view key) const {
  const IniEntry* entry = find(section, key);
  if (entry == nullptr) return std::nullopt;
  std::vector<double> values;
  for (const std::string& word : split_words(entry->value)) {
    const std::optional<double> value = parse_config_number(word);
    if (!value) fail(*entry, "'" + word + "' is not a number");
    values.push_back(*value);
  }
  return values;
}

SourceLocation IniFile::section_location(std::string_view section) const {
  for (const auto& [name, where] : sections_) {
    if (name == section) return where;
  }
  return SourceLocation{path_.string(), 1};
}

void IniFile::fail(const IniEntry& entry, const std::string& message) const {
  throw ConfigError(entry.where.file, entry.where.line, section_key(entry.section, entry.key),
                    message);
}

void IniFile::fail_missing(std::string_view section, std::string_view key,
                           const std::string& why) const {
  const SourceLocation where = section_location(section);
  const std::string absent = has_section(section) ? "has no " + std::string(key)
                                                  : "is missing ([" + std::string(section) + "] " +
                                                        std::string(key) + " is needed)";
  throw ConfigError(where.file, where.line, section_key(section, key),
                    "[" + std::string(section) + "] " + absent + ": " + why);
}

}  // namespace pkm::linuxcnc
