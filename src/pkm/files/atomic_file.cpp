#include "pkm/files/atomic_file.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace pkm::files {

namespace {

// The temporaries of open writers, in storage a signal handler may read: fixed arrays, and a
// lock-free state per entry. A writer claims an entry (free -> claimed), copies its path in, then
// arms it (claimed -> armed); the handler unlinks armed entries only. More writers open at once
// than entries go unlisted; the next run then finds their temporaries stale.
// An entry is a file (unlinked) or a directory (removed once empty, after the files).
enum SlotState : int { kFree = 0, kClaimed = 1, kArmed = 2, kArmedDirectory = 3 };
constexpr int kSlots = 128;
constexpr std::size_t kPathBytes = 4096;
std::array<std::atomic<int>, kSlots> slot_states{};
char slot_paths[kSlots][kPathBytes];

int list_temporary(const std::string& path, SlotState armed = kArmed) {
  if (path.size() >= kPathBytes) return -1;
  for (int slot = 0; slot < kSlots; ++slot) {
    int expected = kFree;
    if (!slot_states[slot].compare_exchange_strong(expected, kClaimed)) continue;
    std::memcpy(slot_paths[slot], path.c_str(), path.size() + 1);
    slot_states[slot].store(armed);
    return slot;
  }
  return -1;
}

void unlist_temporary(int slot) {
  if (slot >= 0) slot_states[slot].store(kFree);
}

// Holds back the signals that end a program while alive (its SIGINT/SIGTERM handler would
// otherwise remove a tree that has just become the output, or a signal end it with the output
// renamed aside); pending ones arrive on destruction.
class HeldSignals {
 public:
  HeldSignals() {
    sigset_t ending;
    sigemptyset(&ending);
    for (const int number : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaddset(&ending, number);
    ::pthread_sigmask(SIG_BLOCK, &ending, &previous_);
  }
  ~HeldSignals() { ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  HeldSignals(const HeldSignals&) = delete;
  HeldSignals& operator=(const HeldSignals&) = delete;

 private:
  sigset_t previous_{};
};

std::function<void(const StaleTemporary&)>& stale_reporter() {
  static std::function<void(const StaleTemporary&)> report;
  return report;
}

// When this run started, s since the epoch (static initialisation is early enough).
const std::time_t kRunStart_s = std::time(nullptr);

std::string temporary_prefix(const std::filesystem::path& output) {
  return "." + output.filename().string() + ".tmp-";
}

std::filesystem::path directory_of(const std::filesystem::path& output) {
  return output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
}

// The PID in a temporary's name after its prefix ("1234-Ab3xYz"), 0 for the older names that
// carry none ("Ab3xYz").
long writer_pid(std::string_view suffix) {
  const auto dash = suffix.find('-');
  if (dash == std::string_view::npos) return 0;
  long pid = 0;
  const auto [end, error] = std::from_chars(suffix.data(), suffix.data() + dash, pid);
  const bool valid = error == std::errc() && end == suffix.data() + dash && pid > 0 &&
                     pid <= std::numeric_limits<pid_t>::max();
  return valid ? pid : 0;  // never a group or "every process" for kill() below
}

bool is_running(long pid) {
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

// When process `pid` started, s since the epoch, from Linux's /proc; -1 where unknown.
std::time_t process_start_s(long pid) {
  std::ifstream process("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  std::getline(process, text);
  const auto name_end = text.rfind(')');  // the command name may hold spaces and parentheses
  if (name_end == std::string::npos) return -1;
  std::istringstream fields(text.substr(name_end + 1));
  std::string skipped;
  for (int field = 3; field < 22 && fields >> skipped; ++field) {
  }
  long long start_ticks = 0;  // field 22: clock ticks after boot
  if (!(fields >> start_ticks)) return -1;
  std::ifstream system("/proc/stat");
  for (std::string key; system >> key;) {
    long long boot_s = 0;
    if (key == "btime" && system >> boot_s) {
      return static_cast<std::time_t>(boot_s + start_ticks / ::sysconf(_SC_CLK_TCK));
    }
  }
  return -1;
}

// Last modified before `start_s`, with 2 s to spare: file times, boot time and process start
// times are each rounded differently.
bool predates(const struct stat& file, std::time_t start_s) {
  return start_s >= 0 && file.st_mtime < start_s - 2;
}

// Why a temporary is stale, or empty when it is not: its writer is gone (its PID runs no more,
// or runs a process started after the file was last written: the PID was reused, say after a
// reboot); without a PID in its name, it was last written before this run.
std::string why_stale(const std::filesystem::path& path, long pid) {
  struct stat file {};
  if (::stat(path.c_str(), &file) != 0) return {};
  if (pid == 0) return predates(file, kRunStart_s) ? "older than this run" : "";
  const std::string writer = "pid " + std::to_string(pid);
  if (!is_running(pid)) return writer + ", no longer running";
  if (predates(file, process_start_s(pid))) return writer + ", now another process";
  return {};
}

}  // namespace

void remove_open_temporaries() noexcept {
  for (int slot = 0; slot < kSlots; ++slot) {
    if (slot_states[slot].load() == kArmed) ::unlink(slot_paths[slot]);
  }
  // Directories inside others empty first: a pass per level, until none goes.
  for (bool removed = true; removed;) {
    removed = false;
    for (int slot = 0; slot < kSlots; ++slot) {
      if (slot_states[slot].load() != kArmedDirectory) continue;
      if (::rmdir(slot_paths[slot]) == 0) {
        slot_states[slot].store(kFree);
        removed = true;
      }
    }
  }
}

TemporaryTree::TemporaryTree(std::filesystem::path root) : root_(std::move(root)) {
  std::error_code error;
  std::filesystem::remove_all(root_, error);
  bool made = false;
  {
    // A signal between making it and listing it would leave it: held until it is listed.
    const HeldSignals held;
    made = std::filesystem::create_directory(root_, error);
    if (made) slots_.push_back(list_temporary(root_.string(), kArmedDirectory));
  }
  if (!made) {
    throw std::runtime_error("cannot create the directory " + root_.string() + ": " +
                             error.message());
  }
}

TemporaryTree::~TemporaryTree() {
  release_slots();
  if (committed_) return;
  std::error_code ignored;
  std::filesystem::remove_all(root_, ignored);
}

void TemporaryTree::add_file(const std::filesystem::path& path) {
  slots_.push_back(list_temporary(path.string(), kArmed));
}

void TemporaryTree::add_directory(const std::filesystem::path& path) {
  slots_.push_back(list_temporary(path.string(), kArmedDirectory));
}

void TemporaryTree::commit_to(const std::filesystem::path& target) {
  std::error_code error;
  std::filesystem::rename(root_, target, error);  // over an empty directory too
  if (error) {
    throw std::runtime_error("cannot rename the finished " + root_.string() + " to " +
                             target.string() + ": " + error.message());
  }
  committed_ = true;
  release_slots();
}

namespace {

// File systems that cannot swap two names (or kernels before 3.15) say so with these.
bool cannot_exchange(int error) {
  return error == EINVAL || error == ENOSYS || error == ENOTSUP || error == EOPNOTSUPP;
}

}  // namespace

void TemporaryTree::replace(const std::filesystem::path& target) {
  const HeldSignals held;
  if (::renameat2(AT_FDCWD, root_.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    // root_ now names the old directory.
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  } else if (const int error = errno; cannot_exchange(error)) {
    replace_by_renames(target);
  } else {
    throw std::runtime_error("cannot put the finished " + root_.string() + " in the place of " +
                             target.string() + ": " + std::strerror(error));
  }
  committed_ = true;
  release_slots();
}

void TemporaryTree::replace_by_renames(const std::filesystem::path& target) {
  std::filesystem::path aside = root_;
  aside += ".old";
  std::error_code error;
  std::filesystem::remove_all(aside, error);
  std::filesystem::rename(target, aside, error);
  if (error) {
    throw std::runtime_error("cannot move " + target.string() + " aside to " + aside.string() +
                             " to replace it: " + error.message());
  }
  std::filesystem::rename(root_, target, error);
  if (error) {
    std::error_code back;
    std::filesystem::rename(aside, target, back);
    throw std::runtime_error("cannot rename the finished " + root_.string() + " to " +
                             target.string() + ": " + error.message() +
                             (back ? "; the old one is left at " + aside.string() : ""));
  }
  std::filesystem::remove_all(aside, error);
}

void TemporaryTree::release_slots() {
  for (const int slot : slots_) unlist_temporary(slot);
  slots_.clear();
}

void on_stale_temporary(std::function<void(const StaleTemporary&)> report) {
  stale_reporter() = std::move(report);
}

std::vector<StaleTemporary> remove_stale_temporaries(const std::filesystem::path& output) {
  std::vector<StaleTemporary> found;
  const std::string prefix = temporary_prefix(output);
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory_of(output), error)) {
    const std::string name = entry.path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const long pid = writer_pid(std::string_view(name).substr(prefix.size()));
    if (!entry.is_regular_file(error)) continue;
    std::string why = why_stale(entry.path(), pid);
    if (why.empty()) continue;
    // Named as the output is: beside it, without a "./" the user did not write.
    StaleTemporary stale{
        output.parent_path() / name, pid, std::move(why), entry.file_size(error), {}};
    if (!std::filesystem::remove(entry.path(), error) && error) stale.failure = error.message();
    found.push_back(stale);
  }
  for (const StaleTemporary& stale : found) {
    if (stale_reporter()) stale_reporter()(stale);
  }
  return found;
}

namespace {

// A target that exists and is neither a regular file nor a directory (/dev/null, a FIFO, a
// terminal, a socket) is a stream the user chose: renaming over it would replace the device or
// pipe with a file, so it is written in place.
bool is_special_file(const std::filesystem::path& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return false;
  return !S_ISREG(status.st_mode) && !S_ISDIR(status.st_mode);
}

}  // namespace

AtomicFileWriter::AtomicFileWriter(std::filesystem::path path) : path_(std::move(path)) {
  std::error_code status_error;
  if (std::filesystem::is_directory(path_, status_error)) {
    throw std::runtime_error("cannot write " + path_.string() + ": it is a directory; name a file");
  }
  if (is_special_file(path_)) {
    open_in_place();
    return;
  }
  remove_stale_temporaries(path_);
  temporary_ =
      (directory_of(path_) / (temporary_prefix(path_) + std::to_string(::getpid()) + "-XXXXXX"))
          .string();
  int descriptor = -1;
  {
    // A signal between creating the temporary and listing it would leave it (and a staging
    // directory holding it): held until it is listed.
    const HeldSignals held;
    descriptor = ::mkstemp(temporary_.data());
    if (descriptor >= 0) slot_ = list_temporary(temporary_);
  }
  if (descriptor < 0) fail("creating a temporary file in " + directory_of(path_).string(), errno);
  // mkstemp creates 0600; an output file should have the usual permissions.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(descriptor, 0666 & ~mask);
  stream_ = ::fdopen(descriptor, "w+b");
  if (stream_ == nullptr) {
    const int error = errno;
    ::close(descriptor);
    ::unlink(temporary_.c_str());
    unlist_temporary(slot_);
    fail("opening the temporary file", error);
  }
}

void AtomicFileWriter::open_in_place() {
  stream_ = std::fopen(path_.c_str(), "wb");
  if (stream_ == nullptr) fail("opening it", errno);
  in_place_ = true;
}

AtomicFileWriter::~AtomicFileWriter() {
  if (committed_) return;
  if (in_place_) {
    if (stream_ != nullptr) std::fclose(stream_);
    return;
  }
  if (stream_ != nullptr) std::fclose(stream_);
  ::unlink(temporary_.c_str());
  unlist_temporary(slot_);
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
  if (std::fseek(stream_, offset, SEEK_SET) != 0) {
    fail(in_place_ ? "this output goes back to complete its header, which a device or pipe "
                     "cannot do; write it to a file"
                   : "seeking",
         errno);
  }
  write(bytes);
  if (std::fseek(stream_, end, SEEK_SET) != 0) fail("seeking", errno);
}

void AtomicFileWriter::commit() {
  if (in_place_) {
    const int closed = std::fclose(stream_);
    stream_ = nullptr;
    if (closed != 0) fail("closing", errno);
    committed_ = true;
    return;
  }
  if (std::fflush(stream_) != 0) fail("flushing", errno);
  if (::fsync(::fileno(stream_)) != 0) fail("flushing to disk", errno);
  const int closed = std::fclose(stream_);
  stream_ = nullptr;
  if (closed != 0) fail("closing", errno);
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    fail("renaming the temporary file into place", errno);
  }
  // Unlisted only once renamed: a signal in between finds no file under the temporary name.
  unlist_temporary(slot_);
  committed_ = true;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  AtomicFileWriter file(path);
  file.write(content);
  file.commit();
}

void write_files_together(std::span<const FileContent> files) {
  std::vector<std::unique_ptr<AtomicFileWriter>> writers;
  for (const FileContent& file : files) {
    writers.push_back(std::make_unique<AtomicFileWriter>(file.path));
    writers.back()->write(file.content);
  }
  // Every file is whole under its temporary name; the old ones after the first go before any
  // rename, so that an interruption between the renames leaves files missing, never a new one
  // beside an old one. Devices and pipes, written in place, stay.
  for (std::size_t i = 1; i < files.size(); ++i) {
    std::error_code error;
    if (std::filesystem::is_regular_file(std::filesystem::symlink_status(files[i].path, error))) {
      std::filesystem::remove(files[i].path, error);
    }
  }
  for (const auto& writer : writers) writer->commit();
}

}  // namespace pkm::files
