// Output files appear whole or not at all: written to a temporary name beside the target, then
// renamed over it.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace pkm {

// A file being written under a temporary name. commit() renames it into place; destroying it
// uncommitted removes it, so a failed run leaves nothing behind.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::filesystem::path path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void write(std::string_view bytes);
  void write_at(long offset, std::string_view bytes);  // rewrite bytes already written
  std::FILE* stream() { return stream_; }              // for formatted writing
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& what, int error) const;
  std::filesystem::path path_;
  std::string temporary_;
  std::FILE* stream_ = nullptr;
  bool committed_ = false;
};

// Throws std::runtime_error naming the path and the system's reason; leaves no temporary behind.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace pkm
