// The real G-code corpus (jobs from public projects, see its SOURCES.md) lives outside the
// repository, by default in ../shared/gcode/real (CMake: PKM_REAL_CORPUS). Tests that need it
// call PKM_SKIP_WITHOUT_REAL_CORPUS() first: without the corpus they are reported as skipped,
// with where it was looked for, instead of failing a plain clone.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pkm::test {

inline std::filesystem::path real_corpus() {
  return PKM_REAL_CORPUS;
}

inline bool have_real_corpus() {
  return std::filesystem::is_regular_file(real_corpus() / "SOURCES.md");
}

inline std::string missing_real_corpus_reason() {
  return "the real G-code corpus is not at " + real_corpus().string() +
         " (a plain clone has no ../shared; see README, \"Tests\")";
}

// A real job as pkmkit reads it, with the lines that only its firmware or its configuration gives
// a meaning blanked in a copy of this process, so every other line keeps its number: a Rotrics
// DexArm header's firmware modes (M2000 line mode, M888 P0 write-and-draw), and the remapped
// M428/M429 of LinuxCNC's xyzac-trt sample, which switch its kinematics to the tool-centre ones
// pkmkit always runs and back to trivkins at the end. pkmkit refuses both at their column, as
// LinuxCNC without the firmware or the remap does. Other files are used as they are.
inline std::filesystem::path readable_real_job(const std::string& relative) {
  const std::filesystem::path original = real_corpus() / relative;
  const bool dexarm = relative.find("dexarm") != std::string::npos;
  const bool xyzac_trt = relative.find("linuxcnc-5axis") != std::string::npos;
  if (!dexarm && !xyzac_trt) return original;
  const std::filesystem::path copy =
      std::filesystem::temp_directory_path() /
      ("pkm-real-" + std::to_string(::getpid()) + "-" + original.filename().string());
  std::ifstream in(original, std::ios::binary);
  std::ofstream out(copy, std::ios::binary);
  for (std::string line; std::getline(in, line);) {
    const bool firmware_mode =
        dexarm && (line.rfind("M2000", 0) == 0 || line.rfind("M888", 0) == 0);
    const bool kinematics_switch =
        xyzac_trt && (line.rfind("M428", 0) == 0 || line.rfind("M429", 0) == 0);
    out << (firmware_mode || kinematics_switch ? "" : line) << "\n";
  }
  return copy;
}

}  // namespace pkm::test

#define PKM_SKIP_WITHOUT_REAL_CORPUS()                           \
  do {                                                           \
    if (!::pkm::test::have_real_corpus()) {                      \
      GTEST_SKIP() << ::pkm::test::missing_real_corpus_reason(); \
    }                                                            \
  } while (false)
