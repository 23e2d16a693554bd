// pkm verify on a large real drawing: the 15,000-line Inkscape mandala of the real corpus, posted
// for the wall plotter (16,656 joint blocks), verified against its job. Items = blocks.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <filesystem>
#include <fstream>

#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_path.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kSource = PKM_SOURCE_DIR;
const fs::path kDrawing = kSource.parent_path() / "shared" / "gcode" / "real" / "plotter" /
                          "inkscape" / "mandala_cnc_0001.gcode";

void verify_mandala_on_wall_plotter(benchmark::State& state) {
  if (!fs::exists(kDrawing)) {
    state.SkipWithError("the real corpus (../shared/gcode/real) is absent");
    return;
  }
  const pkm::machine::Machine machine =
      pkm::machine::load_machine(kSource / "examples" / "machines" / "wall-plotter.toml");
  const fs::path joints = fs::temp_directory_path() / "pkm-bench-mandala-joints.ngc";
  pkm::post::PostOptions post_options;
  post_options.origin << 700.0, -800.0, 0.0, 0.0, 0.0, 0.0;  // the drawing on the sheet
  {
    std::ofstream out(joints);
    pkm::post::post_program(machine, kDrawing, {}, post_options,
                            [&](const std::string& line) { out << line << '\n'; });
  }
  pkm::verify::VerifyOptions options;
  options.origin = post_options.origin;
  options.tolerance_mm = 0.011;
  long blocks = 0;
  for (auto _ : state) {
    const pkm::verify::VerifyReport report =
        pkm::verify::verify_joint_program(machine, joints, kDrawing, options);
    blocks += report.blocks;
    benchmark::DoNotOptimize(report.max_deviation_mm);
  }
  fs::remove(joints);
  state.SetItemsProcessed(blocks);  // items = joint blocks
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["max_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
}
BENCHMARK(verify_mandala_on_wall_plotter)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
