#include "pkm/gcode/line_source.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace pkm::gcode {

std::string cannot_open_reason(const std::filesystem::path& path, bool opened) {
  const int error = errno;
  std::error_code ignored;
  if (opened || std::filesystem::is_directory(path, ignored)) {
    return "cannot open (it is a directory)";
  }
  return std::string("cannot open (") + std::strerror(error) + ")";
}

LineSource::LineSource(const std::filesystem::path& path) : file_(std::fopen(path.c_str(), "rb")) {}

bool LineSource::read_more(std::size_t begin) {
  // The file stays positioned at buffer_offset_ + filled_.
  const std::size_t available = filled_ - begin;
  std::memmove(buffer_.data(), buffer_.data() + begin, available);
  buffer_offset_ += static_cast<std::int64_t>(begin);
  filled_ = available;
  if (filled_ + 1 >= buffer_.size()) {
    // The buffer holds at most kMaxLineBytes + 2: a line that fills it is too long, and any
    // line found in it is short enough without a test on the way.
    if (buffer_.size() >= kMaxLineBytes + 2) {
      too_long_ = failed_ = true;
      return false;
    }
    buffer_.resize(std::min(2 * buffer_.size(), kMaxLineBytes + 2));
  }
  const std::size_t count =
      std::fread(buffer_.data() + filled_, 1, buffer_.size() - 1 - filled_, file_.get());
  filled_ += count;
  at_end_ = count == 0;
  if (at_end_ && std::ferror(file_.get()) != 0) {
    failed_ = true;
    return false;
  }
  return true;
}

}  // namespace pkm::gcode
