// The pkmkins LinuxCNC module's inverse and forward kinematics per call, next to LinuxCNC's own
// genhexkins on the same geometry (LinuxCNC's hexapod simulator, inches): the calls LinuxCNC's
// servo thread makes, along a servo-rate path (1 ms steps of a 1 in/s helix with A B C), forward
// seeded with the previous pose as LinuxCNC does.
//
// genhexkins is LinuxCNC's installed module (/usr/lib/linuxcnc/modules/genhexkins.so), loaded
// here with dlopen; the HAL and RTAPI calls it makes when it starts are answered by the small
// stand-ins below (its pins become plain memory, its default geometry is the simulator's). Its
// cases are skipped, saying why, where LinuxCNC is not installed.
#include <benchmark/benchmark.h>
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "pkm/linuxcnc/kins_adapter.hpp"

// HAL and RTAPI stand-ins for genhexkins.so (C linkage; the executable exports them).
extern "C" {
int hal_init(const char*) {
  return 1;
}
int hal_ready(int) {
  return 0;
}
int hal_exit(int) {
  return 0;
}
void* hal_malloc(long size) {
  return std::calloc(1, static_cast<std::size_t>(size));
}
static int new_pin(void** pointer_to_data) {
  *pointer_to_data = std::calloc(1, sizeof(double));
  return *pointer_to_data == nullptr ? -1 : 0;
}
int hal_pin_float_newf(int, void** data, int, const char*, ...) {
  return new_pin(data);
}
int hal_pin_bit_newf(int, void** data, int, const char*, ...) {
  return new_pin(data);
}
int hal_pin_u32_newf(int, void** data, int, const char*, ...) {
  return new_pin(data);
}
int hal_pin_s32_newf(int, void** data, int, const char*, ...) {
  return new_pin(data);
}
int hal_pin_bit_new(const char*, int, void** data, int) {
  return new_pin(data);
}
int hal_pin_s32_new(const char*, int, void** data, int) {
  return new_pin(data);
}
void rtapi_print(const char*, ...) {}
void rtapi_print_msg(int, const char*, ...) {}
}

namespace {

using pkm::linuxcnc::WorldPose;

// LinuxCNC's kinematics entry points; EmcPose has WorldPose's layout (9 doubles).
using InverseFunction = int (*)(const WorldPose*, double*, const unsigned long*, unsigned long*);
using ForwardFunction = int (*)(const double*, WorldPose*, const unsigned long*, unsigned long*);

struct Genhexkins {
  InverseFunction inverse = nullptr;
  ForwardFunction forward = nullptr;
  std::string error;
};

const Genhexkins& genhexkins() {
  static const Genhexkins loaded = [] {
    Genhexkins module;
    void* library = dlopen("/usr/lib/linuxcnc/modules/genhexkins.so", RTLD_NOW | RTLD_LOCAL);
    if (library == nullptr) {
      module.error = std::string("LinuxCNC's genhexkins.so: ") + dlerror();
      return module;
    }
    // Its module parameter `coordinates` (rtapi_info_address_* holds the parameter's address).
    static char coordinates[] = "XYZABC";
    if (auto** address = static_cast<char***>(dlsym(library, "rtapi_info_address_coordinates"))) {
      **address = coordinates;
    }
    auto start = reinterpret_cast<int (*)()>(dlsym(library, "rtapi_app_main"));
    module.inverse = reinterpret_cast<InverseFunction>(dlsym(library, "kinematicsInverse"));
    module.forward = reinterpret_cast<ForwardFunction>(dlsym(library, "kinematicsForward"));
    if (start == nullptr || module.inverse == nullptr || module.forward == nullptr ||
        start() != 0) {
      module.error = "genhexkins.so did not start";
      module.inverse = nullptr;
    }
    return module;
  }();
  return loaded;
}

pkm::linuxcnc::KinsAdapter& pkmkins() {
  static pkm::linuxcnc::KinsAdapter adapter(
      pkm::load_machine(std::string(PKM_SOURCE_DIR) +
                        "/examples/machines/linuxcnc-hexapod-sim.toml"),
      std::nullopt);
  return adapter;
}

// 10 s of a servo-rate path: a helix of radius 2 in at 1 in/s, A B C swinging by a few degrees.
const std::vector<WorldPose>& path() {
  static const std::vector<WorldPose> poses = [] {
    std::vector<WorldPose> out;
    for (int k = 0; k < 10000; ++k) {
      const double t = k * 0.001;    // s
      const double angle = t / 2.0;  // rad: 1 in/s on a 2 in radius
      out.push_back({2.0 * std::cos(angle), 2.0 * std::sin(angle), 20.0 - 0.1 * t,
                     5.0 * std::sin(angle), 3.0 * std::cos(angle), 8.0 * std::sin(2 * angle)});
    }
    return out;
  }();
  return poses;
}

const std::vector<std::vector<double>>& path_joints() {
  static const std::vector<std::vector<double>> joints = [] {
    std::vector<std::vector<double>> out;
    for (const WorldPose& pose : path()) {
      std::vector<double> legs(6);
      pkmkins().inverse(pose, legs.data());
      out.push_back(legs);
    }
    return out;
  }();
  return joints;
}

void pkmkins_inverse(benchmark::State& state) {
  double joints[6];
  std::size_t k = 0;
  for (auto _ : state) {
    pkmkins().inverse(path()[k], joints);
    benchmark::DoNotOptimize(joints);
    k = (k + 1) % path().size();
  }
}
BENCHMARK(pkmkins_inverse);

void genhexkins_inverse(benchmark::State& state) {
  const Genhexkins& module = genhexkins();
  if (module.inverse == nullptr) {
    state.SkipWithError(module.error.c_str());
    return;
  }
  double joints[9];
  unsigned long iflags = 0, fflags = 0;
  std::size_t k = 0;
  double worst = 0.0;  // in: genhexkins and pkmkins give the same legs
  for (auto _ : state) {
    module.inverse(&path()[k], joints, &iflags, &fflags);
    for (int n = 0; n < 6; ++n) worst = std::max(worst, std::abs(joints[n] - path_joints()[k][n]));
    k = (k + 1) % path().size();
  }
  state.counters["worst_vs_pkmkins_in"] = worst;
}
BENCHMARK(genhexkins_inverse);

void pkmkins_forward(benchmark::State& state) {
  WorldPose pose = path()[0];
  std::size_t k = 0;
  for (auto _ : state) {
    pkmkins().forward(path_joints()[k].data(), pose);  // seeded with the previous pose
    benchmark::DoNotOptimize(pose);
    k = (k + 1) % path().size();
    if (k == 0) pose = path()[0];
  }
  state.counters["iterations_per_call"] = pkmkins().counters().fk_iterations;
}
BENCHMARK(pkmkins_forward);

void genhexkins_forward(benchmark::State& state) {
  const Genhexkins& module = genhexkins();
  if (module.inverse == nullptr) {
    state.SkipWithError(module.error.c_str());
    return;
  }
  WorldPose pose = path()[0];
  unsigned long iflags = 0, fflags = 0;
  std::size_t k = 0;
  double worst = 0.0;  // in or deg: genhexkins' forward of pkmkins' legs is the path's pose
  for (auto _ : state) {
    module.forward(path_joints()[k].data(), &pose, &fflags, &iflags);
    const WorldPose& want = path()[k];
    worst = std::max({worst, std::abs(pose.x - want.x), std::abs(pose.y - want.y),
                      std::abs(pose.z - want.z), std::abs(pose.a - want.a),
                      std::abs(pose.b - want.b), std::abs(pose.c - want.c)});
    k = (k + 1) % path().size();
    if (k == 0) pose = path()[0];
  }
  state.counters["worst_vs_path"] = worst;
}
BENCHMARK(genhexkins_forward);

}  // namespace

BENCHMARK_MAIN();
