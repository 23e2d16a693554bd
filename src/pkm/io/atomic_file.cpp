#include "pkm/io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace pkm {

AtomicFileWriter::AtomicFileWriter(std::filesystem::path path) : path_(std::move(path)) {
  const std::filesystem::path directory =
      path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
  std::string name = ".";
  name.append(path_.filename().string()).append(".tmp-XXXXXX");
  temporary_ = (directory / name).string();
  const int descriptor = ::mkstemp(temporary_.data());
  if (descriptor < 0) fail("creating a temporary file in " + directory.string(), errno);
  // mkstemp creates 0600; an output file should have the usual permissions.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(descriptor, 0666 & ~mask);
  stream_ = ::fdopen(descriptor, "w+b");
  if (stream_ == nullptr) {
    const int error = errno;
    ::close(descriptor);
    ::unlink(temporary_.c_str());
    fail("opening the temporary file", error);
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (committed_) return;
  if (stream_ != nullptr) std::fclose(stream_);
  ::unlink(temporary_.c_str());
}

void AtomicFileWriter::fail(const std::string& what, int error) const {
  throw std::runtime_error("cannot write " + path_.string() + ": " + what + ": " +
                           std::strerror(error));
}

void AtomicFileWriter::write(std::string_view bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), stream_) != bytes.size()) fail("writing", errno);
}

void AtomicFileWriter::write_at(long offset, std::string_view bytes) {
  const long end = std::ftell(stream_);
  if (std::fseek(stream_, offset, SEEK_SET) != 0) fail("seeking", errno);
  write(bytes);
  if (std::fseek(stream_, end, SEEK_SET) != 0) fail("seeking", errno);
}

void AtomicFileWriter::commit() {
  if (std::fflush(stream_) != 0) fail("flushing", errno);
  if (::fsync(::fileno(stream_)) != 0) fail("flushing to disk", errno);
  const int closed = std::fclose(stream_);
  stream_ = nullptr;
  if (closed != 0) fail("closing", errno);
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    fail("renaming the temporary file into place", errno);
  }
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  AtomicFileWriter file(path);
  file.write(content);
  file.commit();
}

}  // namespace pkm
