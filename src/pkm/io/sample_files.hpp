// Sample tables on disk: CSV with a header row, or NPY (one record per sample, a named float64
// field per column). Columns: t (s), line, x y z (mm), a b c (deg) where the machine controls
// orientation, j_<name> per joint (mm, deg for rotary joints), then pen (1 down, 0 up) on
// machines with a pen channel.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "pkm/files/atomic_file.hpp"
#include "pkm/io/sample_rows.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::io {

class SampleFile : public motion::SampleSink {
 public:
  // The format follows the extension: .csv or .npy. Throws std::invalid_argument for another.
  static std::unique_ptr<SampleFile> open(const std::filesystem::path& path,
                                          const machine::Machine& machine);
  virtual void commit() = 0;  // complete the file and move it into place
};

}  // namespace pkm::io
