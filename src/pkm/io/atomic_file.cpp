#include "pkm/io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

namespace pkm {

namespace {
[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what, int error) {
  throw std::runtime_error("cannot write " + path.string() + ": " + what + ": " +
                           std::strerror(error));
}
}  // namespace

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const std::filesystem::path directory =
      path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::string name = ".";
  name.append(path.filename().string()).append(".tmp-XXXXXX");
  std::string temporary = (directory / name).string();
  const int descriptor = ::mkstemp(temporary.data());
  if (descriptor < 0) fail(path, "creating a temporary file in " + directory.string(), errno);
  const auto abandon = [&](const std::string& what) {
    const int error = errno;
    ::close(descriptor);
    ::unlink(temporary.c_str());
    fail(path, what, error);
  };
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(descriptor, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      abandon("writing");
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(descriptor) != 0) abandon("flushing");
  // mkstemp creates 0600; an output file should have the usual permissions.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(descriptor, 0666 & ~mask) != 0) abandon("setting permissions");
  if (::close(descriptor) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(path, "closing", error);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(path, "renaming the temporary file into place", error);
  }
}

}  // namespace pkm
