// One sample as a row of numbers: the columns of the sample files (CSV, NPY) and of the Python
// module's sample arrays, in the same order and units, so that each is the others' number for
// number. Columns: t (s), line, x y z (mm), a b c (deg) where the machine controls orientation,
// j_<name> per joint (mm, deg for rotary joints), then pen (1 down, 0 up) on machines with a pen
// channel.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::io {

std::vector<std::string> sample_columns(const machine::Machine& machine);

// The values of a row in column order and interface units.
class SampleRows {
 public:
  // The most columns a row has: t, line, six pose coordinates, the joints, the pen.
  static constexpr std::size_t kMaxColumns = 32;

  explicit SampleRows(const machine::Machine& machine);
  // Writes the row of `sample` to `row` (room for kMaxColumns) and returns its length.
  std::size_t fill(const motion::Sample& sample, double* row) const;
  std::size_t columns() const { return columns_; }
  bool pen() const { return pen_; }

 private:
  const machine::Machine& machine_;
  bool orientation_;
  bool pen_;
  std::size_t columns_;
};

}  // namespace pkm::io
