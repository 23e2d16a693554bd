#include "pkm/firmware/klipper_cfg.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "pkm/firmware/target.hpp"

namespace pkm::firmware {
namespace {

// The line Klipper's SAVE_CONFIG writes above the options it saved (klippy/configfile.py).
constexpr std::string_view kAutosaveMarker =
    "#*# <---------------------- SAVE_CONFIG ---------------------->";

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::string lowercase(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// Klipper cuts every line at its first '#'; its parser also drops ';' comments that open the
// line or follow a blank.
std::string_view without_comment(std::string_view line) {
  line = line.substr(0, line.find('#'));
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == ';' && (i == 0 || std::isspace(static_cast<unsigned char>(line[i - 1])))) {
      return line.substr(0, i);
    }
  }
  return line;
}

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return lines;
}

}  // namespace

std::optional<double> klipper_float(std::string_view value) {
  const std::string text(trim(value));
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(number)) return std::nullopt;
  return number;
}

KlipperConfig::KlipperConfig(std::string_view text, std::string source)
    : source_(std::move(source)) {
  const std::vector<std::string_view> lines = split_lines(text);
  std::size_t marker = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (trim(lines[i]) == kAutosaveMarker) {
      marker = i;
      break;
    }
  }
  std::string regular, autosave;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i < marker) {
      regular += std::string(lines[i]) + "\n";
    } else if (i > marker && !lines[i].starts_with("#*# DO NOT EDIT")) {
      // "#*# key = value" holds the saved option; "#*#" alone is a blank line; Klipper's
      // header is the marker and its "DO NOT EDIT" line.
      const std::string_view line = lines[i];
      autosave +=
          std::string(line.starts_with("#*# ") ? line.substr(4) : std::string_view()) + "\n";
    }
  }
  parse(regular, 1);
  if (marker < lines.size()) parse(autosave, static_cast<int>(marker) + 2);
}

void KlipperConfig::parse(std::string_view text, int first_line) {
  KlipperSection* current = nullptr;
  KlipperOption* option = nullptr;
  const std::vector<std::string_view> lines = split_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const int number = first_line + static_cast<int>(i);
    const std::string_view raw = without_comment(lines[i]);
    const std::string_view line = trim(raw);
    const auto error = [&](const std::string& why) {
      throw FirmwareFileError(source_ + ":" + std::to_string(number) + ": " + why);
    };
    if (line.empty()) continue;
    if (std::isspace(static_cast<unsigned char>(raw.front()))) {
      if (option == nullptr)
        error("an indented line continues no option: '" + std::string(line) + "'");
      option->value += "\n" + std::string(line);
      continue;
    }
    option = nullptr;
    if (line.front() == '[') {
      if (line.back() != ']')
        error("a section header must end with ']': '" + std::string(line) + "'");
      const std::string name(trim(line.substr(1, line.size() - 2)));
      if (name.starts_with("include ")) {
        includes_.push_back(std::string(trim(std::string_view(name).substr(8))));
        current = nullptr;
        continue;
      }
      current = section(name);
      if (current == nullptr) {
        sections_.push_back(KlipperSection{name, number, {}});
        current = &sections_.back();
      }
      continue;
    }
    const std::size_t separator = line.find_first_of(":=");
    if (separator == std::string_view::npos || trim(line.substr(0, separator)).empty()) {
      error("'" + std::string(line) + "' is neither a [section], a 'key: value' option nor an " +
            "indented continuation");
    }
    if (current == nullptr) error("'" + std::string(line) + "' is in no section");
    const std::string key = lowercase(trim(line.substr(0, separator)));
    current->options[key] =
        KlipperOption{std::string(trim(line.substr(separator + 1))), number, false};
    option = &current->options[key];
  }
}

KlipperSection* KlipperConfig::section(const std::string& name) {
  for (KlipperSection& candidate : sections_) {
    if (candidate.name == name) return &candidate;
  }
  return nullptr;
}

std::optional<std::string> KlipperConfig::text(const std::string& section_name,
                                               const std::string& key) {
  KlipperSection* found = section(section_name);
  if (found == nullptr) return std::nullopt;
  const auto option = found->options.find(key);
  if (option == found->options.end()) return std::nullopt;
  option->second.used = true;
  return option->second.value;
}

std::optional<double> KlipperConfig::number(const std::string& section_name,
                                            const std::string& key) {
  const std::optional<std::string> value = text(section_name, key);
  if (!value) return std::nullopt;
  const std::optional<double> parsed = klipper_float(*value);
  if (!parsed) fail(section_name, key, "'" + *value + "' is not a number");
  return parsed;
}

double KlipperConfig::required(const std::string& section_name, const std::string& key) {
  const std::optional<double> value = number(section_name, key);
  if (!value) fail(section_name, key, "must be given");
  return *value;
}

void KlipperConfig::fail(const std::string& section_name, const std::string& key,
                         const std::string& why) const {
  int line = 1;
  for (const KlipperSection& candidate : sections_) {
    if (candidate.name != section_name) continue;
    line = candidate.line;
    const auto option = candidate.options.find(key);
    if (option != candidate.options.end()) line = option->second.line;
  }
  throw FirmwareFileError(source_ + ":" + std::to_string(line) + ": [" + section_name + "] " + key +
                          ": " + why);
}

std::vector<std::string> KlipperConfig::unread() const {
  std::vector<std::string> notes;
  for (const std::string& include : includes_) {
    notes.push_back("[include " + include + "] not followed: import the included file itself");
  }
  for (const KlipperSection& candidate : sections_) {
    std::string keys;
    int count = 0;
    for (const auto& [key, option] : candidate.options) {
      if (option.used) continue;
      keys += (keys.empty() ? "" : ", ") + key;
      ++count;
    }
    if (count == 0) continue;
    const bool whole = count == static_cast<int>(candidate.options.size());
    notes.push_back(
        "[" + candidate.name + "] " + (whole ? "not read" : "not read: " + keys) +
        (whole ? " (" + std::to_string(count) + (count == 1 ? " option)" : " options)") : ""));
  }
  return notes;
}

}  // namespace pkm::firmware
