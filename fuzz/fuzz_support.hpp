// What the fuzz targets share: the input as a file (the readers under test read paths), and the
// oracle that every number handed out is finite.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace pkm::fuzz {

// This process's own directory in the temp directory (a RAM disk when TMPDIR points at one):
// what the G-code interpreter finds beside its program is only what a target puts there.
inline const std::filesystem::path& input_directory() {
  static const std::filesystem::path directory = [] {
    const auto path =
        std::filesystem::temp_directory_path() / ("pkm-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  return directory;
}

// The oracle's failure: libFuzzer keeps the input that reached it.
[[noreturn]] inline void oracle_failed(const std::string& what) {
  std::fprintf(stderr, "oracle failed: %s\n", what.c_str());
  std::abort();
}

// `path` holding `bytes`: written over what it held, then cut to their length, never truncated
// to 0 first. ext4 flushes a file truncated to 0 and written again as it is closed (its
// auto_da_alloc), and a new file costs a new inode, searched for past those just deleted: a few
// milliseconds an input, many times what most readers under test take.
inline void rewrite_file(const std::filesystem::path& path, std::string_view bytes) {
  const int descriptor = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  const bool written =
      descriptor >= 0 &&
      ::pwrite(descriptor, bytes.data(), bytes.size(), 0) == static_cast<ssize_t>(bytes.size()) &&
      ::ftruncate(descriptor, static_cast<off_t>(bytes.size())) == 0;
  if (descriptor >= 0) ::close(descriptor);
  if (!written) oracle_failed("cannot write the input to " + path.string());
}

// A file of this process holding `bytes`, rewritten for each input.
inline std::filesystem::path input_file(const std::uint8_t* data, std::size_t size,
                                        const char* extension) {
  static const std::filesystem::path path = input_directory() / (std::string("input") + extension);
  rewrite_file(path, std::string_view(reinterpret_cast<const char*>(data), size));
  return path;
}

inline void require_finite(double value, std::string_view what) {
  if (!std::isfinite(value)) oracle_failed(std::string(what) + " is not finite");
}

// No "inf" or "nan" in text meant for people or LinuxCNC.
inline void require_no_non_finite_text(std::string_view text) {
  for (const std::string_view word : {"inf", "nan", "INF", "NAN"}) {
    for (std::size_t at = text.find(word); at != std::string_view::npos;
         at = text.find(word, at + 1)) {
      // A whole number token: preceded by a sign, space, '(' or ',' (not a word like "info").
      const char before = at == 0 ? ' ' : text[at - 1];
      const char after = at + 3 < text.size() ? text[at + 3] : ' ';
      const bool alone = (before == ' ' || before == '-' || before == '(' || before == ',' ||
                          before == '+' || before == '=') &&
                         !std::isalpha(static_cast<unsigned char>(after));
      if (alone) oracle_failed("non-finite number in \"" + std::string(text) + "\"");
    }
  }
}

}  // namespace pkm::fuzz
