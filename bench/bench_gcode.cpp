// G-code interpretation throughput on a large real program: lines/s and bytes/s, canonical
// commands made but not printed.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>

#include "pkm/gcode/interpreter.hpp"

namespace {

const std::filesystem::path kProgram = std::filesystem::path(PKM_SOURCE_DIR).parent_path() /
                                       "shared" / "gcode" / "real" / "linuxcnc" / "stellabee1.ngc";

void interpret_stellabee(benchmark::State& state) {
  if (!std::filesystem::exists(kProgram)) {
    state.SkipWithError("../shared/gcode/real/linuxcnc/stellabee1.ngc not found");
    return;
  }
  std::ifstream in(kProgram);
  long lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  const auto bytes = static_cast<int64_t>(std::filesystem::file_size(kProgram));
  long commands = 0;
  for (auto _ : state) {
    pkm::gcode::Interpreter interpreter(kProgram);
    interpreter.run([&](const pkm::gcode::Canon&) { ++commands; });
  }
  state.SetItemsProcessed(state.iterations() * lines);  // items = source lines
  state.SetBytesProcessed(state.iterations() * bytes);
  state.counters["canon_per_run"] =
      static_cast<double>(commands) / static_cast<double>(state.iterations());
}
BENCHMARK(interpret_stellabee)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
