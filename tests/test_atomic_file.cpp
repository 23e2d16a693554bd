// Temporary files of atomic outputs: removed on a signal (through remove_open_temporaries), and
// found, named and removed when a killed run left them behind.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pkm/io/atomic_file.hpp"

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
    on_stale_temporary(nullptr);
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
  AtomicFileWriter writer(directory_ / "job.csv");
  const std::string prefix = ".job.csv.tmp-" + std::to_string(::getpid()) + "-";
  const std::string name = fs::path(writer.temporary_path()).filename().string();
  EXPECT_EQ(name.substr(0, prefix.size()), prefix);
  EXPECT_EQ(name.size(), prefix.size() + 6);  // mkstemp's six characters
  EXPECT_EQ(names(), std::vector<std::string>{name});
}

TEST_F(AtomicFileTest, SignalCleanupRemovesOpenTemporariesOnly) {
  write_file_atomically(directory_ / "done.json", "{}\n");
  {
    AtomicFileWriter first(directory_ / "a.csv");
    AtomicFileWriter second(directory_ / "b.csv");
    first.write("t,line\n");
    EXPECT_EQ(names().size(), 3u);
    remove_open_temporaries();  // what the SIGTERM handler of pkm calls
    EXPECT_EQ(names(), std::vector<std::string>{"done.json"});
  }  // the writers' own removal finds nothing left, and does not fail
  EXPECT_EQ(names(), std::vector<std::string>{"done.json"});
}

TEST_F(AtomicFileTest, CommittedOutputIsNoLongerATemporary) {
  AtomicFileWriter writer(directory_ / "a.csv");
  writer.write("t,line\n");
  writer.commit();
  remove_open_temporaries();
  EXPECT_EQ(names(), std::vector<std::string>{"a.csv"});
  EXPECT_EQ(fs::file_size(directory_ / "a.csv"), 7u);
}

TEST_F(AtomicFileTest, StaleTemporariesAreRemovedAndReported) {
  const long dead = finished_pid();
  const std::string killed = ".job.csv.tmp-" + std::to_string(dead) + "-AbCdEf";
  const std::string running = ".job.csv.tmp-" + std::to_string(::getpid()) + "-LiVe12";
  const std::string old_style = ".job.csv.tmp-QwErTy";  // pkm before PIDs in names
  make_file(killed, 1234);
  make_file(running, 10);
  make_file(".other.csv.tmp-" + std::to_string(dead) + "-AbCdEf", 10);  // another output's
  // No valid PID (kill() would take it for a process group): judged by age, and it is new.
  const std::string huge_pid = ".job.csv.tmp-99999999999-AbCdEf";
  make_file(huge_pid, 10);
  fs::last_write_time(make_file(old_style, 5),
                      fs::file_time_type::clock::now() - std::chrono::hours(1));
  std::vector<StaleTemporary> reported;
  on_stale_temporary([&](const StaleTemporary& stale) { reported.push_back(stale); });

  const std::vector<StaleTemporary> removed = remove_stale_temporaries(directory_ / "job.csv");

  ASSERT_EQ(removed.size(), 2u);
  ASSERT_EQ(reported.size(), 2u);
  for (const StaleTemporary& stale : removed) {
    if (stale.pid == 0) {
      EXPECT_EQ(stale.path, directory_ / old_style);
      EXPECT_EQ(stale.size_bytes, 5u);
    } else {
      EXPECT_EQ(stale.pid, dead);
      EXPECT_EQ(stale.path, directory_ / killed);
      EXPECT_EQ(stale.size_bytes, 1234u);
    }
    EXPECT_EQ(stale.failure, "");
  }
  std::vector<std::string> kept = {huge_pid, running,
                                   ".other.csv.tmp-" + std::to_string(dead) + "-AbCdEf"};
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(names(), kept);
}

TEST_F(AtomicFileTest, WritingAnOutputRemovesItsStaleTemporaries) {
  const std::string killed = ".job.csv.tmp-" + std::to_string(finished_pid()) + "-AbCdEf";
  make_file(killed, 100);
  std::vector<fs::path> reported;
  on_stale_temporary([&](const StaleTemporary& stale) { reported.push_back(stale.path); });
  write_file_atomically(directory_ / "job.csv", "t\n");
  EXPECT_EQ(reported, std::vector<fs::path>{directory_ / killed});
  EXPECT_EQ(names(), std::vector<std::string>{"job.csv"});
}

}  // namespace
}  // namespace pkm
