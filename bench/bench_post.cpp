// pkm post on the real plotter drawings of ../shared/gcode/real/plotter, placed on the LinuxCNC
// polargraph where tests/test_real_jobs.cpp and bench/post_spanning.py place them, at 0.01 mm:
// with blocks that span programmed moves (the default) and with every move covered on its own
// (--no-span-moves). Counters: blocks written, programmed moves, moves per block; items = moves.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "pkm/post/joint_program.hpp"
#include "real_job_copy.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kSource = PKM_SOURCE_DIR;
const fs::path kPlotter = kSource.parent_path() / "shared" / "gcode" / "real" / "plotter";

struct Drawing {
  const char* job;  // under kPlotter
  double x, y;      // where its X0 Y0 sits on the polargraph, mm
};

const Drawing kDrawings[] = {
    {"inkscape/mandala_cnc_0001.gcode", 1130.0, -1200.0},
    {"dexarm-inkscape/vitruvianMan.gcode", 1150.0, -1100.0},
    {"svg2gcode/smooth_curves_circular_interpolation.gcode", 1000.0, -1200.0},
    {"inkscape/btc_laser_qr_unbt_0001.gcode", 1130.0, -1200.0},
    {"camotics/la_peinture.gc", 1130.0, -1200.0},
};

// Arguments: the drawing's index in kDrawings, 1 to span moves or 0 not to.
void post_drawing_on_polargraph(benchmark::State& state) {
  const Drawing& drawing = kDrawings[state.range(0)];
  if (!fs::exists(kPlotter / drawing.job)) {
    state.SkipWithError("the real corpus (../shared/gcode/real) is absent");
    return;
  }
  // As the tests read it: vitruvianMan's DexArm header modes blanked (pkm refuses M2000).
  const fs::path job = pkm::test::readable_real_job(kPlotter, drawing.job);
  const pkm::machine::Machine machine = pkm::machine::load_machine(
      kSource / "examples" / "machines" / "linuxcnc-polargraph-2366.toml");
  pkm::post::PostOptions options;
  options.tolerance_mm = 0.01;
  options.origin << drawing.x, drawing.y, 0.0, 0.0, 0.0, 0.0;
  options.span_moves = state.range(1) != 0;
  pkm::post::PostReport report;
  long moves = 0;
  for (auto _ : state) {
    std::size_t characters = 0;
    report = pkm::post::post_program(machine, job, {}, options,
                                     [&](const std::string& line) { characters += line.size(); });
    moves += report.moves;
    benchmark::DoNotOptimize(characters);
  }
  state.SetLabel(fs::path(drawing.job).filename().string() +
                 (options.span_moves ? " spanning" : " per move"));
  state.SetItemsProcessed(moves);
  state.counters["blocks"] = static_cast<double>(report.blocks);
  state.counters["moves"] = static_cast<double>(report.moves);
  state.counters["moves_per_block"] =
      static_cast<double>(report.moves) / static_cast<double>(report.blocks);
  state.counters["bound_mm"] = report.max_deviation_mm;
}
BENCHMARK(post_drawing_on_polargraph)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
