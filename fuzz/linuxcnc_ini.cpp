// libFuzzer target: bytes as a LinuxCNC configuration, imported as `pkm import linuxcnc` imports
// one. The input is the INI, optionally followed by more files, each after a line
// `#FILE name` (a HAL file, an #INCLUDE, a Tcl file): all are written into this process's own
// directory, which is also the hallib, and which holds only the current input's files. Every '/'
// becomes '_' before writing, so an #INCLUDE, a HALFILE or LIB: can name only these files (or the
// directory itself, which is no regular file): the target reads nothing it did not write. Oracles:
// no sanitizer report, no exception but ConfigError naming one of the input's files, and an
// imported machine's text has no non-finite number.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fuzz_support.hpp"
#include "pkm/linuxcnc/config_import.hpp"
#include "pkm/linuxcnc/ini_file.hpp"

namespace {

constexpr std::string_view kFileMarker = "\n#FILE ";

bool plain_file_name(std::string_view name) {
  return !name.empty() && name != "." && name != ".." && name.size() <= 64 &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
         });
}

// (name, text) of every file of the input; the first is the INI.
std::vector<std::pair<std::string, std::string>> split_files(std::string text) {
  std::replace(text.begin(), text.end(), '/', '_');
  std::vector<std::pair<std::string, std::string>> files;
  std::string name = "fuzz.ini";
  std::size_t start = 0;
  while (true) {
    const std::size_t marker = text.find(kFileMarker, start);
    files.emplace_back(name, text.substr(start, marker == std::string::npos ? std::string::npos
                                                                            : marker + 1 - start));
    if (marker == std::string::npos) break;
    const std::size_t name_start = marker + kFileMarker.size();
    const std::size_t line_end = std::min(text.find('\n', name_start), text.size());
    name = text.substr(name_start, line_end - name_start);
    start = std::min(line_end + 1, text.size());
  }
  files.erase(std::remove_if(files.begin() + 1, files.end(),
                             [](const auto& file) {
                               return !plain_file_name(file.first) || file.first == "fuzz.ini";
                             }),
              files.end());
  return files;
}

// Writes the input's files into this process's configuration directory, which then holds them
// and nothing else. The directory is made once; a file of the previous input is rewritten in
// place, one this input lacks is moved to a spare directory beside it (where no input's name
// reaches: '/' is never in one), and a name new to this input takes a spare file. Removing the
// directory and making it and its files anew for every input held the target to 178 inputs a
// second, optimised: ext4 searches for every new inode past the ones just deleted.
std::filesystem::path write_input_files(
    const std::vector<std::pair<std::string, std::string>>& files) {
  static const std::filesystem::path directory = pkm::fuzz::input_directory() / "config";
  static const std::filesystem::path spares = pkm::fuzz::input_directory() / "spares";
  static std::set<std::string> previous;
  static std::vector<std::filesystem::path> spare_files;
  static long spares_made = 0;
  static const bool made = [] {
    for (const auto& made_directory : {directory, spares}) {
      std::filesystem::remove_all(made_directory);
      std::filesystem::create_directories(made_directory);
    }
    return true;
  }();
  (void)made;
  std::set<std::string> written;
  for (const auto& [name, text] : files) {
    const std::filesystem::path path = directory / name;
    if (previous.count(name) == 0 && written.count(name) == 0 && !spare_files.empty()) {
      std::filesystem::rename(spare_files.back(), path);
      spare_files.pop_back();
    }
    pkm::fuzz::rewrite_file(path, text);
    written.insert(name);
  }
  for (const std::string& name : previous) {
    if (written.count(name) != 0) continue;
    spare_files.push_back(spares / std::to_string(spares_made++));
    std::filesystem::rename(directory / name, spare_files.back());
  }
  previous = std::move(written);
  return directory;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path directory =
      write_input_files(split_files(std::string(reinterpret_cast<const char*>(data), size)));
  try {
    const pkm::linuxcnc::ImportedConfig config =
        pkm::linuxcnc::read_linuxcnc_config(directory / "fuzz.ini", {directory});
    pkm::fuzz::require_no_non_finite_text(pkm::linuxcnc::machine_file_text(config, "fuzz.toml"));
  } catch (const pkm::linuxcnc::ConfigError& error) {
    // A located error (in one of the input's files) is an expected end.
    if (std::string_view(error.what()).rfind(directory.string(), 0) != 0) {
      pkm::fuzz::oracle_failed(std::string("an error not in the input's files: ") + error.what());
    }
  }
  return 0;
}
