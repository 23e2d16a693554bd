// The real G-code corpus (jobs from public projects, see its SOURCES.md) lives outside the
// repository, by default in ../shared/gcode/real (CMake: PKM_REAL_CORPUS). Tests that need it
// call PKM_SKIP_WITHOUT_REAL_CORPUS() first: without the corpus they are reported as skipped,
// with where it was looked for, instead of failing a plain clone.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "real_job_copy.hpp"

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

// A real job as pkmkit reads it (real_job_copy.hpp).
inline std::filesystem::path readable_real_job(const std::string& relative) {
  return readable_real_job(real_corpus(), relative);
}

}  // namespace pkm::test

#define PKM_SKIP_WITHOUT_REAL_CORPUS()                           \
  do {                                                           \
    if (!::pkm::test::have_real_corpus()) {                      \
      GTEST_SKIP() << ::pkm::test::missing_real_corpus_reason(); \
    }                                                            \
  } while (false)
