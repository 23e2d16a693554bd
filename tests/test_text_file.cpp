// The whole-file readers (machine files, INI and HAL files, tool tables, CSVs, pattern JSON):
// regular files only, bounded in size, so that a FIFO, a device or an include fan-out neither
// blocks nor fills the memory (issue 26: a FIFO blocked forever, /dev/zero read gigabytes and
// `#INCLUDE /dev/zero` ended in a successful import).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "pkm/linuxcnc/ini_file.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/text/text_file.hpp"

namespace pkm {
namespace {

namespace fs = std::filesystem;

class TextFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("pkm-text-file-" + std::to_string(::getpid()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path fifo(const std::string& name) const {
    const fs::path path = directory_ / name;
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    return path;
  }

  fs::path directory_;
};

std::string read_error(const fs::path& path, std::size_t max_bytes) {
  try {
    text::read_text_file(path, max_bytes);
  } catch (const text::FileReadError& error) {
    return error.what();
  }
  return "(read)";
}

TEST_F(TextFileTest, ReadsARegularFileUpToItsLimit) {
  const fs::path path = write("ten.txt", "0123456789");
  EXPECT_EQ(text::read_text_file(path, 10), "0123456789");
  EXPECT_EQ(read_error(path, 9), "cannot read (it is larger than the 1 MB such a file may be)");
  EXPECT_EQ(text::read_text_file(write("empty.txt", ""), 10), "");
}

TEST_F(TextFileTest, RefusesWhatIsNotARegularFileAtOnce) {
  EXPECT_EQ(read_error(fifo("pipe"), 1 << 20), "cannot open (it is a FIFO, not a regular file)");
  EXPECT_EQ(read_error("/dev/zero", 1 << 20), "cannot open (it is a device, not a regular file)");
  EXPECT_EQ(read_error(directory_, 1 << 20), "cannot open (it is a directory)");
  EXPECT_EQ(read_error(directory_ / "absent", 1 << 20), "cannot open (No such file or directory)");
}

TEST_F(TextFileTest, AMachineFileThatIsAFifoOrADeviceIsRefusedWithItsName) {
  for (const fs::path& path : {fifo("machine.toml"), fs::path("/dev/zero")}) {
    try {
      machine::load_machine(path);
      FAIL() << "loaded " << path;
    } catch (const machine::MachineFileError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(path.string() + ": cannot open (it is a ", 0), 0u)
          << error.what();
    }
  }
}

TEST_F(TextFileTest, AnIncludeOfADeviceIsRefusedAtItsLine) {
  const fs::path ini = write("machine.ini", "[EMC]\nMACHINE = x\n#INCLUDE /dev/zero\n");
  try {
    linuxcnc::IniFile::read(ini);
    FAIL() << "#INCLUDE /dev/zero was read";
  } catch (const linuxcnc::ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("machine.ini:3: #INCLUDE /dev/zero: "),
              std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("it is a device"), std::string::npos) << error.what();
  }
}

TEST_F(TextFileTest, IncludesThatFanOutStopAtTheSizeOfOneFile) {
  // Each level includes the next twice: 2^15 copies of a 64 KB comment within the depth limit.
  const std::string padding = "# " + std::string(64 * 1024, '.') + "\n";
  for (int level = 0; level < 16; ++level) {
    const std::string next = "level" + std::to_string(level + 1) + ".ini";
    write("level" + std::to_string(level) + ".ini",
          padding + (level < 15 ? "#INCLUDE " + next + "\n#INCLUDE " + next + "\n" : ""));
  }
  try {
    linuxcnc::IniFile::read(directory_ / "level0.ini");
    FAIL() << "2^15 includes were read";
  } catch (const linuxcnc::ConfigError& error) {
    EXPECT_NE(std::string(error.what()).find("the configuration with its includes passes 16 MB"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace pkm
