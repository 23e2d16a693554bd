// A program's lines, cut from large reads of its file: the interpreter reads a line at a time
// and its control flow jumps back and forth by byte offset.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pkm::gcode {

// The longest line the interpreter reads, in bytes: a longer one is an error (memory stays
// bounded by it).
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

// "cannot open (reason)" for a program that did not open, or opened as a directory (which
// fopen allows and the first read refuses). Reads errno: call it right after the failure.
std::string cannot_open_reason(const std::filesystem::path& path, bool opened);

// A jump into what was last read costs nothing, any other seeks.
class LineSource {
 public:
  explicit LineSource(const std::filesystem::path& path);
  bool is_open() const { return file_ != nullptr; }
  // A read or seek failed (read() then returned nothing, as at the end of the file).
  bool failed() const { return failed_; }
  // The line read was longer than kMaxLineBytes (read() then returned nothing, and failed()).
  bool too_long() const { return too_long_; }

  // The line starting at byte `offset`, without its "\n" or "\r\n", as a view into the
  // buffer with a NUL after it (what the block reader needs); valid until the next read.
  // Returns it and the offset of the line after it, or nothing at the end of the file.
  std::optional<std::pair<std::string_view, std::int64_t>> read(std::int64_t offset);

 private:
  // Moves the buffer to `offset` unless it is within what was read; false when the seek failed.
  bool seek(std::int64_t offset);
  // Keeps the unfinished line starting at `begin` at the front and reads on; false on an error
  // or a line too long.
  bool read_more(std::size_t begin);

  struct Close {
    void operator()(std::FILE* file) const { std::fclose(file); }
  };
  std::unique_ptr<std::FILE, Close> file_;
  std::vector<char> buffer_ = std::vector<char>(std::size_t{1} << 16);
  std::int64_t buffer_offset_ = 0;  // the file offset of buffer_[0]
  std::size_t filled_ = 0;          // bytes of buffer_ read from the file
  bool at_end_ = false;             // the file ends after them
  char* patched_ = nullptr;         // where the last line's NUL stands
  char patched_character_ = 0;      // and what stood there
  bool failed_ = false;
  bool too_long_ = false;
};

// read() and seek() are on the path of every line: inline.
inline std::optional<std::pair<std::string_view, std::int64_t>> LineSource::read(
    std::int64_t offset) {
  if (patched_ != nullptr) {
    // The previous line's NUL stood on its line end; a jump back must find that again.
    *patched_ = patched_character_;
    patched_ = nullptr;
  }
  if (!seek(offset)) return std::nullopt;
  std::size_t begin = static_cast<std::size_t>(offset - buffer_offset_);
  while (true) {
    char* start = buffer_.data() + begin;
    const std::size_t available = filled_ - begin;
    char* newline = static_cast<char*>(std::memchr(start, '\n', available));
    if (newline != nullptr || at_end_) {
      if (newline == nullptr && available == 0) return std::nullopt;
      std::size_t length =
          newline != nullptr ? static_cast<std::size_t>(newline - start) : available;
      const std::int64_t following =
          offset + static_cast<std::int64_t>(length + (newline != nullptr ? 1 : 0));
      if (length > 0 && start[length - 1] == '\r') --length;
      // The buffer always has a byte to spare after what was read: the NUL fits.
      patched_ = start + length;
      patched_character_ = *patched_;
      *patched_ = '\0';
      return std::pair{std::string_view(start, length), following};
    }
    if (!read_more(begin)) return std::nullopt;
    begin = 0;
  }
}

inline bool LineSource::seek(std::int64_t offset) {
  if (offset >= buffer_offset_ && offset <= buffer_offset_ + static_cast<std::int64_t>(filled_)) {
    return true;
  }
  if (::fseeko(file_.get(), static_cast<off_t>(offset), SEEK_SET) != 0) {
    failed_ = true;
    return false;
  }
  buffer_offset_ = offset;
  filled_ = 0;
  at_end_ = false;
  return true;
}

}  // namespace pkm::gcode
