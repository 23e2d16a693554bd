// Whether an output would be written over one of a command's inputs (the job, the machine file,
// a tool table, a subroutine file the job calls): the same file by any of its names, a symbolic
// or hard link included. The command line and the Python module refuse such an output alike.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pkm::io {

struct NamedInput {
  std::string what;  // "the job", "the machine file", "a subroutine file the job calls"
  std::filesystem::path path;
};

// "OUTPUT: the output is the input file PATH (WHAT); writing it would destroy the input, so
// choose another output name", or "" when `output` is none of `inputs` (or is empty).
std::string overwrites_input(const std::filesystem::path& output,
                             const std::vector<NamedInput>& inputs);

}  // namespace pkm::io
