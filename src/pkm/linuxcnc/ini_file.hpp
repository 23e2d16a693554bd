// A LinuxCNC INI file as LinuxCNC reads it: [SECTION]s of KEY = VALUE lines, keys that repeat
// (HALFILE), whole-line comments (# or ;), and #INCLUDE directives; every value remembers the file
// and line it came from, so errors point there.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace pkm::linuxcnc {

// A problem in a LinuxCNC configuration: "file:line: message", or "file:line:[SECTION]KEY:
// message" where a key is concerned; "file: message" when the file cannot be read.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, const std::string& message)
      : std::runtime_error(file + ": " + message) {}
  ConfigError(const std::string& file, int line, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ": " + message) {}
  ConfigError(const std::string& file, int line, const std::string& key, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ":" + key + ": " + message) {}
};

// Where a value was read: file and 1-based line.
struct SourceLocation {
  std::string file;
  int line = 0;
};

struct IniEntry {
  std::string section;  // as written, without brackets
  std::string key;
  std::string value;  // surrounding blanks removed; '#' and ';' inside a value are part of it
  SourceLocation where;
};

// The whole text of a file, or ConfigError "file: cannot open (reason)" naming `what` it is.
std::string read_config_text(const std::filesystem::path& path);

class IniFile {
 public:
  // Reads `path` and the files it #INCLUDEs (relative to the including file's directory; up to 16
  // levels; a file that includes itself is an error).
  static IniFile read(const std::filesystem::path& path);
  // `text` as the file `source_name` (includes are looked up beside it).
  static IniFile parse(std::string_view text, const std::string& source_name);

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path directory() const { return path_.parent_path(); }
  const std::vector<IniEntry>& entries() const { return entries_; }

  bool has_section(std::string_view section) const;
  // The first entry of the key in the section, as LinuxCNC takes it; nullptr when absent.
  const IniEntry* find(std::string_view section, std::string_view key) const;
  // Every entry of a repeated key (HALFILE), in file order.
  std::vector<const IniEntry*> find_all(std::string_view section, std::string_view key) const;
  // The value of a number key; nullopt when absent; ConfigError (file:line:[SECTION]KEY) when it
  // is not a finite number.
  std::optional<double> number(std::string_view section, std::string_view key) const;
  // Several numbers separated by blanks (HOME = 0 0 20 0 0 0).
  std::optional<std::vector<double>> numbers(std::string_view section, std::string_view key) const;
  // Where the section starts (its header line), or the file's first line when it is absent: for
  // errors about a key that is missing.
  SourceLocation section_location(std::string_view section) const;
  // ConfigError at the entry: "file:line:[SECTION]KEY: message".
  [[noreturn]] void fail(const IniEntry& entry, const std::string& message) const;
  // ConfigError about a missing key, located at its section.
  [[noreturn]] void fail_missing(std::string_view section, std::string_view key,
                                 const std::string& why) const;

 private:
  void parse_into(std::string_view text, const std::string& source_name, int depth,
                  std::vector<std::string>& open_files, std::string& section);

  std::filesystem::path path_;
  std::vector<IniEntry> entries_;
  std::vector<std::pair<std::string, SourceLocation>> sections_;
  // Bytes of the file and its #INCLUDEs read so far: bounded as one file's, since includes
  // within the depth limit can still fan out without end (each file including another twice).
  std::size_t parsed_bytes_ = 0;
};

// A number written as LinuxCNC configs write them ("270", "-1e6", "1.0"), whole and finite.
std::optional<double> parse_config_number(std::string_view text);
// `text` without leading and trailing blanks.
std::string_view trim(std::string_view text);
// Blank-separated words.
std::vector<std::string> split_words(std::string_view text);

}  // namespace pkm::linuxcnc
