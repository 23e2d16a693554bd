// Temporary files of atomic outputs: removed on a signal (through remove_open_temporaries), and
// found, named and removed when a killed run left them behind; devices and pipes written in place.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "pkm/files/atomic_file.hpp"

namespace pkm {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("pkm-atomic-" + std::to_string(::getpid()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override {
    files::on_stale_temporary(nullptr);
    fs::remove_all(directory_);
  }
  fs::path make_file(const std::string& name, std::size_t bytes) const {
    std::ofstream(directory_ / name) << std::string(bytes, 'x');
    return directory_ / name;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(directory_)) {
      found.push_back(entry.path().filename().string());
    }
    std::sort(found.begin(), found.end());
    return found;
  }
  fs::path directory_;
};

// The PID of a process that has exited (and been reaped): no process runs under it now.
long finished_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST_F(AtomicFileTest, TemporaryIsNamedAfterTheOutputAndThisProcess) {
  files::AtomicFileWriter writer(directory_ / "job.csv");
  const std::string prefix = ".job.csv.tmp-" + std::to_string(::getpid()) + "-";
  const std::string name = fs::path(writer.temporary_path()).filename().string();
  EXPECT_EQ(name.substr(0, prefix.size()), prefix);
  EXPECT_EQ(name.size(), prefix.size() + 6);  // mkstemp's six characters
  EXPECT_EQ(names(), std::vector<std::string>{name});
}

TEST_F(AtomicFileTest, FilesWrittenTogetherAreNeverANewOneBesideAnOldOne) {
  // calibrate pattern's drawing and marks (issue 26: written one after the other, a fault
  // between them paired a new drawing with old marks).
  const fs::path drawing = make_file("pattern.ngc", 3), marks = make_file("pattern.json", 4);
  const std::string new_drawing = "G1 X1\n", new_marks = "[]\n";
  const files::FileContent pair[] = {{drawing, new_drawing}, {marks, new_marks}};
  files::write_files_together(pair);
  const auto read = [](const fs::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(read(drawing), new_drawing);
  EXPECT_EQ(read(marks), new_marks);
  EXPECT_EQ(names(), (std::vector<std::string>{"pattern.json", "pattern.ngc"}));
  // The second cannot be written (a directory holds its name): neither is replaced.
  fs::remove(marks);
  fs::create_directory(marks);
  const files::FileContent refused[] = {{drawing, std::string_view("G1 X2\n")}, {marks, new_marks}};
  EXPECT_THROW(files::write_files_together(refused), std::runtime_error);
  EXPECT_EQ(read(drawing), new_drawing);
  EXPECT_EQ(names(), (std::vector<std::string>{"pattern.json", "pattern.ngc"}));
}

TEST_F(AtomicFileTest, ASignalRemovesAStagingTreeWithItsFilesButNotACommittedOne) {
  // export linuxcnc's staging directory was left behind after SIGINT/SIGTERM/SIGHUP (issue 26):
  // the handler's remove_open_temporaries now removes its files, then its directories.
  {
    files::TemporaryTree tree(directory_ / ".config.tmp-1");
    fs::create_directories(tree.root() / "macros" / "deep");
    tree.add_directory(tree.root() / "macros");
    tree.add_directory(tree.root() / "macros" / "deep");
    for (const fs::path& file :
         {tree.root() / "machine.ini", tree.root() / "macros" / "deep" / "m"}) {
      std::ofstream(file) << "x";
      tree.add_file(file);
    }
    files::remove_open_temporaries();  // what the signal handler calls
    EXPECT_EQ(names(), std::vector<std::string>{});
  }
  files::TemporaryTree tree(directory_ / ".config.tmp-2");
  std::ofstream(tree.root() / "machine.ini") << "x";
  tree.add_file(tree.root() / "machine.ini");
  tree.commit_to(directory_ / "config");
  files::remove_open_temporaries();
  EXPECT_TRUE(fs::exists(directory_ / "config" / "machine.ini"));
  EXPECT_EQ(names(), std::vector<std::string>{"config"});
}

TEST_F(AtomicFileTest, SignalCleanupRemovesOpenTemporariesOnly) {
  files::write_file_atomically(directory_ / "done.json", "{}\n");
  {
    files::AtomicFileWriter first(directory_ / "a.csv");
    files::AtomicFileWriter second(directory_ / "b.csv");
    first.write("t,line\n");
    EXPECT_EQ(names().size(), 3u);
    files::remove_open_temporaries();  // what the SIGTERM handler of pkm calls
    EXPECT_EQ(names(), std::vector<std::string>{"done.json"});
  }  // the writers' own removal finds nothing left, and does not fail
  EXPECT_EQ(names(), std::vector<std::string>{"done.json"});
}

TEST_F(AtomicFileTest, CommittedOutputIsNoLongerATemporary) {
  files::AtomicFileWriter writer(directory_ / "a.csv");
  writer.write("t,line\n");
  writer.commit();
  files::remove_open_temporaries();
  EXPECT_EQ(names(), std::vector<std::string>{"a.csv"});
  EXPECT_EQ(fs::file_size(directory_ / "a.csv"), 7u);
}

TEST_F(AtomicFileTest, StaleTemporariesAreRemovedAndReported) {
  const long dead = finished_pid();
  const std::string me = std::to_string(::getpid());
  const auto an_hour_ago = fs::file_time_type::clock::now() - std::chrono::hours(1);
  const std::string killed = ".job.csv.tmp-" + std::to_string(dead) + "-AbCdEf";
  const std::string running = ".job.csv.tmp-" + me + "-LiVe12";
  // This process's PID, but written before it started: the PID was reused.
  const std::string reused = ".job.csv.tmp-" + me + "-ReUsEd";
  const std::string old_style = ".job.csv.tmp-QwErTy";  // pkm before PIDs in names
  // No valid PID (kill() would take it for a process group): judged by age, and it is new.
  const std::string huge_pid = ".job.csv.tmp-99999999999-AbCdEf";
  const std::string other_output = ".other.csv.tmp-" + std::to_string(dead) + "-AbCdEf";
  make_file(killed, 1234);
  make_file(running, 10);
  fs::last_write_time(make_file(reused, 7), an_hour_ago);
  fs::last_write_time(make_file(old_style, 5), an_hour_ago);
  make_file(huge_pid, 10);
  make_file(other_output, 10);
  std::vector<files::StaleTemporary> reported;
  files::on_stale_temporary([&](const files::StaleTemporary& stale) { reported.push_back(stale); });

  std::vector<files::StaleTemporary> removed =
      files::remove_stale_temporaries(directory_ / "job.csv");

  std::sort(removed.begin(), removed.end(),
            [](const auto& a, const auto& b) { return a.path < b.path; });
  std::vector<std::tuple<std::string, long, std::string, std::uintmax_t>> expected = {
      {killed, dead, "pid " + std::to_string(dead) + ", no longer running", 1234},
      {reused, ::getpid(), "pid " + me + ", now another process", 7},
      {old_style, 0, "older than this run", 5}};
  std::sort(expected.begin(), expected.end());  // by name, as removed is by path
  ASSERT_EQ(removed.size(), expected.size());
  EXPECT_EQ(reported.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& [name, pid, why, size] = expected[i];
    EXPECT_EQ(removed[i].path, directory_ / name);
    EXPECT_EQ(removed[i].pid, pid);
    EXPECT_EQ(removed[i].why, why);
    EXPECT_EQ(removed[i].size_bytes, size);
    EXPECT_EQ(removed[i].failure, "");
  }
  std::vector<std::string> kept = {running, huge_pid, other_output};
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(names(), kept);
}

TEST_F(AtomicFileTest, WritingAnOutputRemovesItsStaleTemporaries) {
  const std::string killed = ".job.csv.tmp-" + std::to_string(finished_pid()) + "-AbCdEf";
  make_file(killed, 100);
  std::vector<fs::path> reported;
  files::on_stale_temporary(
      [&](const files::StaleTemporary& stale) { reported.push_back(stale.path); });
  files::write_file_atomically(directory_ / "job.csv", "t\n");
  EXPECT_EQ(reported, std::vector<fs::path>{directory_ / killed});
  EXPECT_EQ(names(), std::vector<std::string>{"job.csv"});
}

// `--html /dev/null` once replaced the device with a regular file (the rename went over it).
TEST_F(AtomicFileTest, ADeviceIsWrittenInPlaceAndStaysADevice) {
  files::write_file_atomically("/dev/null", "a page nobody wants\n");
  struct stat status {};
  ASSERT_EQ(::stat("/dev/null", &status), 0);
  EXPECT_TRUE(S_ISCHR(status.st_mode));
}

TEST_F(AtomicFileTest, AFifoReceivesTheBytesAndStaysAFifo) {
  const fs::path fifo = directory_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] {
    std::ifstream in(fifo);
    received.assign(std::istreambuf_iterator<char>(in), {});
  });
  files::write_file_atomically(fifo, "t,x\n0,1\n");
  reader.join();
  EXPECT_EQ(received, "t,x\n0,1\n");
  struct stat status {};
  ASSERT_EQ(::stat(fifo.c_str(), &status), 0);
  EXPECT_TRUE(S_ISFIFO(status.st_mode));
  EXPECT_EQ(names(), std::vector<std::string>{"pipe"});  // no temporary beside it
}

TEST_F(AtomicFileTest, ADirectoryIsRefusedBeforeAnythingIsWritten) {
  fs::create_directory(directory_ / "pages");
  try {
    files::AtomicFileWriter writer(directory_ / "pages");
    FAIL() << "a directory was accepted as an output";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("pages: it is a directory; name a file"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(names(), std::vector<std::string>{"pages"});
}

}  // namespace
}  // namespace pkm
