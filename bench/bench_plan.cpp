// End to end: parse -> plan -> IK -> NPY, the paper's sphere on the paper's hexapod.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "pkm/io/sample_files.hpp"
#include "pkm/motion/planner.hpp"

namespace {

const std::filesystem::path kSource = PKM_SOURCE_DIR;

void plan_sphere_to_npy(benchmark::State& state) {
  const pkm::Machine machine =
      pkm::load_machine(kSource / "examples" / "machines" / "hexapod-bit.toml");
  const std::filesystem::path output =
      std::filesystem::temp_directory_path() / "pkm-bench-sphere.npy";
  long samples = 0;
  for (auto _ : state) {
    auto file = pkm::SampleFile::open(output, machine);
    const pkm::motion::PlanReport report = pkm::motion::plan_program(
        machine, kSource / "examples" / "jobs" / "sphere.ngc", {}, {}, *file);
    file->commit();
    samples += report.samples;
  }
  std::filesystem::remove(output);
  state.SetItemsProcessed(samples);  // items = samples
}
BENCHMARK(plan_sphere_to_npy)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
