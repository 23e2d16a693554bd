// pkm workspace per example machine, at about 1/200 of its search box (fixed orientation, home's),
// the paper's hexapod over +-10 deg at 32 to 4 mm, with 45 deg joints over +-10 deg at 32 to 8 mm
// (searched over the range like the legs), and with 40 mm legs as well (fixed orientation at
// 16 mm; +-2 deg at 32 mm: leg clearances split the orientation range).
// Counters: the proven-inside and the boundary volume (area for planar machines) and the cells
// judged.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "pkm/workspace/workspace.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kMachines = fs::path(PKM_SOURCE_DIR) / "examples" / "machines";

void run(benchmark::State& state, const pkm::machine::Machine& machine,
         const pkm::workspace::WorkspaceOptions& options) {
  pkm::workspace::Workspace ws;
  for (auto _ : state) {
    ws = pkm::workspace::compute_workspace(machine, options);
    benchmark::ClobberMemory();
  }
  char label[160];
  std::snprintf(label, sizeof label, "%s inside %.4g boundary %.4g estimate %.4g cells %lld",
                ws.planar ? "mm2" : "mm3", ws.inside_measure, ws.boundary_measure, ws.estimate,
                static_cast<long long>(ws.cells_judged));
  state.SetLabel(label);
  state.counters["resolution_mm"] = ws.resolution_mm;
}

void example_machine(benchmark::State& state, const std::string& file) {
  const pkm::machine::Machine machine = pkm::machine::load_machine(kMachines / file);
  pkm::workspace::WorkspaceOptions options = pkm::workspace::default_options(machine);
  const pkm::workspace::SearchBox search = pkm::workspace::search_box(machine, options);
  double longest = 0.0, shortest = 1e300;
  for (int axis = 0; axis < 3; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    const double size = search.box.max()[axis] - search.box.min()[axis];
    longest = std::max(longest, size);
    shortest = std::min(shortest, size);
  }
  options.resolution_mm = std::min(longest / 200.0, shortest / 4.0);
  run(state, machine, options);
}

void hexapod_over_ten_degrees(benchmark::State& state) {
  const pkm::machine::Machine machine = pkm::machine::load_machine(kMachines / "hexapod-bit.toml");
  pkm::workspace::WorkspaceOptions options = pkm::workspace::default_options(machine);
  options.resolution_mm = static_cast<double>(state.range(0));
  options.orientation_min_rad = Eigen::Vector3d::Constant(pkm::geometry::degrees_to_radians(-10.0));
  options.orientation_max_rad = Eigen::Vector3d::Constant(pkm::geometry::degrees_to_radians(10.0));
  run(state, machine, options);
}

// The paper's hexapod with max_joint_angle = 45 and, when state.range(2) is 1, leg_diameter = 40
// (the joint-angle and interference constraints); state.range(0): mm, state.range(1): +- deg.
void hexapod_with_leg_limits(benchmark::State& state) {
  std::string text;
  {
    std::FILE* file = std::fopen((kMachines / "hexapod-bit.toml").c_str(), "r");
    for (int c; file != nullptr && (c = std::fgetc(file)) != EOF;) text += static_cast<char>(c);
    if (file != nullptr) std::fclose(file);
  }
  const std::string tool = "tool_length = 30.0\n";
  text.replace(
      text.find(tool), tool.size(),
      tool + "max_joint_angle = 45.0\n" + (state.range(2) != 0 ? "leg_diameter = 40.0\n" : ""));
  const pkm::machine::Machine machine = pkm::machine::parse_machine(text, "hexapod-limited.toml");
  pkm::workspace::WorkspaceOptions options = pkm::workspace::default_options(machine);
  options.resolution_mm = static_cast<double>(state.range(0));
  const double spread = pkm::geometry::degrees_to_radians(static_cast<double>(state.range(1)));
  options.orientation_min_rad = Eigen::Vector3d::Constant(-spread);
  options.orientation_max_rad = Eigen::Vector3d::Constant(spread);
  run(state, machine, options);
}

const int kRegistered = [] {
  for (const auto& entry : fs::directory_iterator(kMachines)) {
    if (entry.path().extension() != ".toml") continue;
    const std::string file = entry.path().filename().string();
    benchmark::RegisterBenchmark(("workspace/" + file).c_str(),
                                 [file](benchmark::State& state) { example_machine(state, file); })
        ->Unit(benchmark::kMillisecond)
        ->Iterations(1)
        ->UseRealTime();
  }
  return 0;
}();

}  // namespace

BENCHMARK(hexapod_over_ten_degrees)
    ->Arg(32)
    ->Arg(16)
    ->Arg(8)
    ->Arg(4)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

BENCHMARK(hexapod_with_leg_limits)
    ->Args({32, 10, 0})
    ->Args({16, 10, 0})
    ->Args({8, 10, 0})
    ->Args({16, 0, 1})
    ->Args({32, 2, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

BENCHMARK_MAIN();
