// Reading a whole input file that pkm holds in memory at once (machine files, LinuxCNC INI and
// HAL files, tool tables, measurement CSVs, pattern JSON): only a regular file, and at most a
// given size, so that a FIFO cannot block a command and /dev/zero cannot fill the memory.
#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace pkm::text {

// The size limits of the readers, in bytes: far above any real file of the kind.
inline constexpr std::size_t kMaxConfigFileBytes = std::size_t{16} << 20;  // machine, INI, HAL
inline constexpr std::size_t kMaxDataFileBytes = std::size_t{256} << 20;   // CSV, JSON, tools

// Why a file could not be read, without its name ("cannot open (No such file or directory)",
// "is a FIFO, not a regular file", "is 300 MB, more than the 16 MB ..."): each reader puts its
// own location in front.
class FileReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The file's bytes. Throws FileReadError when it does not open, is not a regular file (a
// directory, FIFO, socket or device), or holds more than `max_bytes`.
std::string read_text_file(const std::filesystem::path& path, std::size_t max_bytes);

}  // namespace pkm::text
