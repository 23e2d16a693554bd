// Klipper's printer.cfg as its config reader sees it (docs/firmware-klipper.md): `[section]`
// headers, `key: value` or `key = value` options (keys case-insensitive), `#` and `;` comments,
// indented lines continuing the option above, later options overriding earlier ones, and the
// SAVE_CONFIG block (`#*# ` lines after Klipper's marker) overriding the rest. Includes are not
// followed: they are listed.
#pragma once

#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pkm::firmware {

struct KlipperOption {
  std::string value;
  int line = 0;
  bool used = false;  // read by the importer; the others become notes
};

struct KlipperSection {
  std::string name;
  int line = 0;
  std::map<std::string, KlipperOption> options;  // key lowercased
};

class KlipperConfig {
 public:
  // Throws FirmwareFileError ("file:line: why") for a line that is neither a header, an option
  // nor a continuation.
  KlipperConfig(std::string_view text, std::string source);

  const std::string& source() const { return source_; }
  KlipperSection* section(const std::string& name);
  const std::deque<KlipperSection>& sections() const { return sections_; }
  std::vector<std::string> includes() const { return includes_; }

  // An option's text, marked used; none when absent.
  std::optional<std::string> text(const std::string& section, const std::string& key);
  // An option as a number; none when absent. Throws FirmwareFileError "file:line: [section]
  // key: why" for text that is not a finite number.
  std::optional<double> number(const std::string& section, const std::string& key);
  // The same, required: a missing option is "file:line: [section] key: must be given" at the
  // section's header (line 1 when the section is missing).
  double required(const std::string& section, const std::string& key);
  // "file:line: [section] key: why" at the option's line (the section's when absent).
  [[noreturn]] void fail(const std::string& section, const std::string& key,
                         const std::string& why) const;
  // Sections and options nobody read, one note each ("[extruder] (12 options) not read").
  std::vector<std::string> unread() const;

 private:
  void parse(std::string_view text, int first_line);

  std::string source_;
  std::deque<KlipperSection> sections_;  // stable addresses while parsing
  std::vector<std::string> includes_;
};

// `value` as Klipper's float() reads it (leading/trailing blanks allowed); none otherwise.
std::optional<double> klipper_float(std::string_view value);

}  // namespace pkm::firmware
