// Output files appear whole or not at all: written to a temporary name beside the target
// (`.NAME.tmp-PID-XXXXXX`), then renamed over it. The temporaries of writers still open are
// listed where a signal handler can reach them (remove_open_temporaries); temporaries left by a
// killed run are found, removed and reported when the same output is written again.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pkm::files {

// A file being written under a temporary name. commit() renames it into place; destroying it
// uncommitted removes it, so a failed run leaves nothing behind. Opening one first removes the
// stale temporaries of the same output (see StaleTemporary). A directory is refused at once; an
// existing device, FIFO or socket (/dev/null, a pipe) is written in place, since renaming over
// it would replace it with a file.
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
  const std::string& temporary_path() const { return temporary_; }

 private:
  [[noreturn]] void fail(const std::string& what, int error) const;
  void open_in_place();
  std::filesystem::path path_;
  std::string temporary_;
  std::FILE* stream_ = nullptr;
  int slot_ = -1;  // its entry among the open temporaries, -1 when not listed
  bool committed_ = false;
  bool in_place_ = false;  // a device or pipe, written directly (no temporary)
};

// Throws std::runtime_error naming the path and the system's reason; leaves no temporary behind.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

// Files that belong together (a calibration pattern's drawing and its marks): all written whole
// before any is renamed into place, and never one new beside another old. A failure or a
// signal between the renames leaves the later files absent, not stale.
struct FileContent {
  std::filesystem::path path;
  std::string_view content;
};
void write_files_together(std::span<const FileContent> files);

// A directory built under a temporary name and renamed into place whole (a LinuxCNC
// configuration). Its files and subdirectories, each added once made, are listed with the
// writers' temporaries, so that a signal's remove_open_temporaries() removes them and the
// directory; destroyed uncommitted, it removes the whole tree.
class TemporaryTree {
 public:
  explicit TemporaryTree(std::filesystem::path root);  // made anew, empty
  ~TemporaryTree();
  TemporaryTree(const TemporaryTree&) = delete;
  TemporaryTree& operator=(const TemporaryTree&) = delete;

  const std::filesystem::path& root() const { return root_; }
  void add_file(const std::filesystem::path& path);
  void add_directory(const std::filesystem::path& path);
  // Renames the tree to `target` (a missing or empty directory); throws on failure.
  void commit_to(const std::filesystem::path& target);
  // Puts the tree in the place of `target`, an existing directory, and removes the old one: the
  // two are swapped in one step (renameat2's RENAME_EXCHANGE), so that `target` is at every
  // instant the whole old directory or the whole new one. Where the file system cannot swap, the
  // old directory is renamed aside and the tree renamed in (the old one put back if that fails),
  // and `target` is missing in between. Signals are held back until the old directory is gone.
  // Throws, leaving `target` as it was, when neither can be done.
  void replace(const std::filesystem::path& target);

 private:
  void release_slots();
  void replace_by_renames(const std::filesystem::path& target);
  std::filesystem::path root_;
  std::vector<int> slots_;
  bool committed_ = false;
};

// Removes the temporary file of every AtomicFileWriter still open and every TemporaryTree not
// committed. Async-signal-safe (it only calls unlink and rmdir), for the SIGINT/SIGTERM handler
// of a program: the library installs none itself.
void remove_open_temporaries() noexcept;

// A temporary beside an output, left by a run that was killed before it could remove it: the
// PID in its name runs no more, or runs a process started after the file was last written (the
// PID was reused, say after a reboot); a name without a PID (an older pkm) is stale when it was
// last written before this process started. A temporary whose writer still runs is another
// run's, and left alone.
struct StaleTemporary {
  std::filesystem::path path;
  long pid = 0;     // of the run that wrote it; 0 when its name carries none
  std::string why;  // why it is stale: "pid 4242, no longer running", ...
  std::uintmax_t size_bytes = 0;
  std::string failure;  // why it could not be removed; empty when it was
};

// Called for every stale temporary an AtomicFileWriter finds (and removes) beside its output,
// so that the program can name it to the user. Without one they are removed silently.
void on_stale_temporary(std::function<void(const StaleTemporary&)> report);

// The stale temporaries beside `output`, removed (each reported to on_stale_temporary's
// function and returned).
std::vector<StaleTemporary> remove_stale_temporaries(const std::filesystem::path& output);

}  // namespace pkm::files
