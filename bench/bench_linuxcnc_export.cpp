// pkm export linuxcnc: the joint-rate bound over each example machine's work envelope (with the
// bisection of the box), which is most of an export's time.
#include <benchmark/benchmark.h>

#include <string>

#include "pkm/linuxcnc/config_export.hpp"
#include "pkm/machine/machine.hpp"

namespace {

void bound_and_limits(benchmark::State& state, const std::string& file) {
  const pkm::machine::Machine machine =
      pkm::machine::load_machine(std::string(PKM_SOURCE_DIR) + "/examples/machines/" + file);
  const pkm::bounds::EnvelopeBox requested = pkm::bounds::work_envelope(machine);
  long cells = 0;
  for (auto _ : state) {
    const pkm::bounds::FittedEnvelope fitted = pkm::bounds::fit_envelope(machine, requested);
    const pkm::linuxcnc::AxisRateLimits limits =
        pkm::linuxcnc::axis_rate_limits(machine, fitted.bound, machine.kinematics().dof());
    benchmark::DoNotOptimize(limits.velocity);
    cells = fitted.bound.cells;
  }
  state.counters["cells"] = static_cast<double>(cells);
}

BENCHMARK_CAPTURE(bound_and_limits, wall_plotter, std::string("wall-plotter.toml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bound_and_limits, linear_delta, std::string("linear-delta.toml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bound_and_limits, triaglide, std::string("triaglide.toml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bound_and_limits, hexapod_bit, std::string("hexapod-bit.toml"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bound_and_limits, hexaglide, std::string("hexaglide.toml"))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
