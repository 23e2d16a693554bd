// A real job of the corpus as pkmkit reads it, without GoogleTest: the tests (real_corpus.hpp) and
// the benchmarks (bench/bench_post.cpp) post the same text.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pkm::test {

// The job `relative` under `corpus`, with the lines that only its firmware or its configuration
// gives a meaning blanked in a copy of this process, so every other line keeps its number: a
// Rotrics DexArm header's firmware modes (M2000 line mode, M888 P0 write-and-draw), and the
// remapped M428/M429 of LinuxCNC's xyzac-trt sample, which switch its kinematics to the
// tool-centre ones pkmkit always runs and back to trivkins at the end. pkmkit refuses both at
// their column, as LinuxCNC without the firmware or the remap does. Other files are used as they
// are.
inline std::filesystem::path readable_real_job(const std::filesystem::path& corpus,
                                               const std::string& relative) {
  const std::filesystem::path original = corpus / relative;
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
