#include "pkm/text/text_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace pkm::text {

namespace {

// "it is a directory", "it is a FIFO, not a regular file", ...
std::string what_it_is(mode_t mode) {
  if (S_ISDIR(mode)) return "it is a directory";
  if (S_ISFIFO(mode)) return "it is a FIFO, not a regular file";
  if (S_ISSOCK(mode)) return "it is a socket, not a regular file";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "it is a device, not a regular file";
  return "it is not a regular file";
}

std::string megabytes(std::size_t bytes) {
  return std::to_string((bytes + (std::size_t{1} << 20) - 1) >> 20) + " MB";
}

std::string too_large(std::size_t max_bytes) {
  return "cannot read (it is larger than the " + megabytes(max_bytes) + " such a file may be)";
}

// Closes the descriptor on every path out.
struct Descriptor {
  int fd;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string read_text_file(const std::filesystem::path& path, std::size_t max_bytes) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const Descriptor file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC)};
  if (file.fd < 0) throw FileReadError(std::string("cannot open (") + std::strerror(errno) + ")");
  struct stat status {};
  if (::fstat(file.fd, &status) != 0) {
    throw FileReadError(std::string("cannot read (") + std::strerror(errno) + ")");
  }
  if (!S_ISREG(status.st_mode))
    throw FileReadError("cannot open (" + what_it_is(status.st_mode) + ")");
  if (static_cast<std::size_t>(status.st_size) > max_bytes)
    throw FileReadError(too_large(max_bytes));
  std::string text(static_cast<std::size_t>(status.st_size), '\0');
  std::size_t filled = 0;
  for (;;) {
    if (filled == text.size()) {
      // The file may have grown since fstat: read on, up to the limit.
      if (text.size() > max_bytes) throw FileReadError(too_large(max_bytes));
      text.resize(std::min(max_bytes + 1, std::max<std::size_t>(text.size() * 2, 4096)));
    }
    const ssize_t count = ::read(file.fd, text.data() + filled, text.size() - filled);
    if (count < 0) {
      if (errno == EINTR) continue;
      throw FileReadError(std::string("cannot read (") + std::strerror(errno) + ")");
    }
    if (count == 0) break;
    filled += static_cast<std::size_t>(count);
  }
  if (filled > max_bytes) throw FileReadError(too_large(max_bytes));
  text.resize(filled);
  return text;
}

}  // namespace pkm::text
