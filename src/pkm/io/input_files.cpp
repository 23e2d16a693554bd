#include "pkm/io/input_files.hpp"

#include <system_error>

namespace pkm::io {

std::string overwrites_input(const std::filesystem::path& output,
                             const std::vector<NamedInput>& inputs) {
  if (output.empty()) return "";
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path out = fs::weakly_canonical(output, error);
  for (const NamedInput& input : inputs) {
    if (input.path.empty()) continue;
    std::error_code same_error, canonical_error;
    // equivalent() sees hard links; the canonical names see an output not written yet.
    const bool same = fs::equivalent(output, input.path, same_error) ||
                      (!error && fs::weakly_canonical(input.path, canonical_error) == out);
    if (same) {
      return output.string() + ": the output is the input file " + input.path.string() + " (" +
             input.what + "); writing it would destroy the input, so choose another output name";
    }
  }
  return "";
}

}  // namespace pkm::io
