// The pkmkins LinuxCNC module's inverse and forward kinematics per call, next to LinuxCNC's own
// modules on the same geometry: genhexkins on LinuxCNC's hexapod simulator (inches),
// lineardeltakins on its linear delta (mm), rotarydeltakins on its rotary delta (inches). The
// calls LinuxCNC's servo thread makes, along a servo-rate path (1 ms steps of a helix, with A B C
// on the hexapod), forward seeded with the previous pose as LinuxCNC does.
//
// LinuxCNC's modules are the installed ones (/usr/lib/linuxcnc/modules/NAME.so), loaded here with
// dlopen; the HAL and RTAPI calls they make when they start are answered by the small stand-ins
// below (their pins become plain memory, set by name to the example machine's geometry). Their
// cases are skipped, saying why, where LinuxCNC is not installed.
#include <benchmark/benchmark.h>
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pkm/linuxcnc/kins_adapter.hpp"

// HAL and RTAPI stand-ins for LinuxCNC's modules (C linkage; the executable exports them).
namespace {
// Every float pin the modules made, by name, to set their geometry.
std::map<std::string, double*>& float_pins() {
  static std::map<std::string, double*> pins;
  return pins;
}
int new_pin(void** pointer_to_data) {
  *pointer_to_data = std::calloc(1, sizeof(double));
  return *pointer_to_data == nullptr ? -1 : 0;
}
}  // namespace

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
int hal_pin_float_newf(int, void** data, int, const char* format, ...) {
  char name[128];
  va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(name, sizeof name, format, arguments);
  va_end(arguments);
  const int result = new_pin(data);
  if (result == 0) float_pins()[name] = static_cast<double*>(*data);
  return result;
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

struct LinuxcncModule {
  InverseFunction inverse = nullptr;
  ForwardFunction forward = nullptr;
  std::string error;
};

// One of LinuxCNC's installed kinematics modules, started, its geometry pins set.
LinuxcncModule load_module(const std::string& name,
                           const std::vector<std::pair<std::string, double>>& geometry) {
  LinuxcncModule module;
  const std::string file = "/usr/lib/linuxcnc/modules/" + name + ".so";
  void* library = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr) {
    module.error = "LinuxCNC's " + name + ".so: " + dlerror();
    return module;
  }
  // genhexkins' module parameter `coordinates` (rtapi_info_address_* holds its address).
  static char coordinates[] = "XYZABC";
  if (auto** address = static_cast<char***>(dlsym(library, "rtapi_info_address_coordinates"))) {
    **address = coordinates;
  }
  auto start = reinterpret_cast<int (*)()>(dlsym(library, "rtapi_app_main"));
  module.inverse = reinterpret_cast<InverseFunction>(dlsym(library, "kinematicsInverse"));
  module.forward = reinterpret_cast<ForwardFunction>(dlsym(library, "kinematicsForward"));
  if (start == nullptr || module.inverse == nullptr || module.forward == nullptr || start() != 0) {
    module.error = name + ".so did not start";
    module.inverse = nullptr;
    return module;
  }
  for (const auto& [pin, value] : geometry) {
    const auto found = float_pins().find(pin);
    if (found == float_pins().end()) {
      module.error = name + ".so has no pin " + pin;
      module.inverse = nullptr;
      return module;
    }
    *found->second = value;
  }
  return module;
}

// A machine, its LinuxCNC module and a servo-rate path in the machine's units.
struct Case {
  const char* machine_file;  // in examples/machines
  const char* module;
  std::vector<std::pair<std::string, double>> geometry;  // the module's pins: the machine's
  WorldPose (*pose_at)(double t_s);
  int joints;
};

// 10 s of a helix of radius 2 in at 1 in/s, A B C swinging by a few degrees.
WorldPose hexapod_path(double t) {
  const double angle = t / 2.0;  // rad: 1 in/s on a 2 in radius
  return {2.0 * std::cos(angle), 2.0 * std::sin(angle), 20.0 - 0.1 * t,
          5.0 * std::sin(angle), 3.0 * std::cos(angle), 8.0 * std::sin(2 * angle)};
}
// A helix of radius 50 mm at 25 mm/s between z 25 and 15 mm.
WorldPose ldelta_path(double t) {
  const double angle = t / 2.0;
  return {50.0 * std::cos(angle), 50.0 * std::sin(angle), 25.0 - t, 0, 0, 0};
}
// A helix of radius 2 in at 1 in/s between z -12 and -13 in.
WorldPose rdelta_path(double t) {
  const double angle = t / 2.0;
  return {2.0 * std::cos(angle), 2.0 * std::sin(angle), -12.0 - 0.1 * t, 0, 0, 0};
}

// genhexkins' pins keep its defaults: they are the hexapod simulator's numbers.
const Case kHexapod{"linuxcnc-hexapod-sim.toml", "genhexkins", {}, hexapod_path, 6};
const Case kLdelta{"linuxcnc-ldelta.toml",
                   "lineardeltakins",
                   {{"lineardeltakins.R", 130.25}, {"lineardeltakins.L", 269.0}},
                   ldelta_path,
                   3};
const Case kRdelta{"linuxcnc-rdelta.toml",
                   "rotarydeltakins",
                   {{"rotarydeltakins.platformradius", 10.0},
                    {"rotarydeltakins.thighlength", 10.0},
                    {"rotarydeltakins.shinlength", 18.0},
                    {"rotarydeltakins.footradius", 5.0}},
                   rdelta_path,
                   3};

// What a case's benchmarks share: both modules and the path with pkmkins' joints along it.
struct Loaded {
  LinuxcncModule reference;
  pkm::linuxcnc::KinsAdapter pkmkins;
  std::vector<WorldPose> path;
  std::vector<std::vector<double>> joints;
};

Loaded& loaded(const Case& which) {
  static std::map<const Case*, std::unique_ptr<Loaded>> cache;
  std::unique_ptr<Loaded>& entry = cache[&which];
  if (!entry) {
    entry = std::make_unique<Loaded>(Loaded{
        load_module(which.module, which.geometry),
        pkm::linuxcnc::KinsAdapter(pkm::load_machine(std::string(PKM_SOURCE_DIR) +
                                                     "/examples/machines/" + which.machine_file),
                                   std::nullopt),
        {},
        {}});
    for (int k = 0; k < 10000; ++k) {
      entry->path.push_back(which.pose_at(k * 0.001));
      std::vector<double> joints(9);
      entry->pkmkins.inverse(entry->path.back(), joints.data());
      entry->joints.push_back(joints);
    }
  }
  return *entry;
}

void pkmkins_inverse(benchmark::State& state, const Case* which) {
  Loaded& data = loaded(*which);
  pkm::linuxcnc::KinsAdapter& adapter = data.pkmkins;
  double joints[9];
  std::size_t k = 0;
  for (auto _ : state) {
    adapter.inverse(data.path[k], joints);
    benchmark::DoNotOptimize(joints);
    k = (k + 1) % data.path.size();
  }
}

void linuxcnc_inverse(benchmark::State& state, const Case* which) {
  const Loaded& data = loaded(*which);
  if (data.reference.inverse == nullptr) {
    state.SkipWithError(data.reference.error.c_str());
    return;
  }
  double joints[9];
  unsigned long iflags = 0, fflags = 0;
  std::size_t k = 0;
  double worst = 0.0;  // machine units or deg: the module and pkmkins give the same joints
  for (auto _ : state) {
    data.reference.inverse(&data.path[k], joints, &iflags, &fflags);
    for (int n = 0; n < which->joints; ++n) {
      worst = std::max(worst, std::abs(joints[n] - data.joints[k][static_cast<std::size_t>(n)]));
    }
    k = (k + 1) % data.path.size();
  }
  state.counters["worst_vs_pkmkins"] = worst;
}

void pkmkins_forward(benchmark::State& state, const Case* which) {
  Loaded& data = loaded(*which);
  pkm::linuxcnc::KinsAdapter& adapter = data.pkmkins;
  WorldPose pose = data.path[0];
  std::size_t k = 0;
  double iterations = 0.0;
  for (auto _ : state) {
    adapter.forward(data.joints[k].data(), pose);  // seeded with the previous pose
    benchmark::DoNotOptimize(pose);
    iterations += adapter.counters().fk_iterations;
    k = (k + 1) % data.path.size();
    if (k == 0) pose = data.path[0];
  }
  state.counters["iterations_per_call"] = iterations / static_cast<double>(state.iterations());
}

void linuxcnc_forward(benchmark::State& state, const Case* which) {
  const Loaded& data = loaded(*which);
  if (data.reference.inverse == nullptr) {
    state.SkipWithError(data.reference.error.c_str());
    return;
  }
  WorldPose pose = data.path[0];
  unsigned long iflags = 0, fflags = 0;
  std::size_t k = 0;
  double worst = 0.0;  // machine units or deg: the module's forward of pkmkins' joints
  for (auto _ : state) {
    data.reference.forward(data.joints[k].data(), &pose, &fflags, &iflags);
    const WorldPose& want = data.path[k];
    worst = std::max({worst, std::abs(pose.x - want.x), std::abs(pose.y - want.y),
                      std::abs(pose.z - want.z), std::abs(pose.a - want.a),
                      std::abs(pose.b - want.b), std::abs(pose.c - want.c)});
    k = (k + 1) % data.path.size();
    if (k == 0) pose = data.path[0];
  }
  state.counters["worst_vs_path"] = worst;
}

BENCHMARK_CAPTURE(pkmkins_inverse, hexapod, &kHexapod);
BENCHMARK_CAPTURE(linuxcnc_inverse, hexapod_genhexkins, &kHexapod);
BENCHMARK_CAPTURE(pkmkins_forward, hexapod, &kHexapod);
BENCHMARK_CAPTURE(linuxcnc_forward, hexapod_genhexkins, &kHexapod);
BENCHMARK_CAPTURE(pkmkins_inverse, ldelta, &kLdelta);
BENCHMARK_CAPTURE(linuxcnc_inverse, ldelta_lineardeltakins, &kLdelta);
BENCHMARK_CAPTURE(pkmkins_forward, ldelta, &kLdelta);
BENCHMARK_CAPTURE(linuxcnc_forward, ldelta_lineardeltakins, &kLdelta);
BENCHMARK_CAPTURE(pkmkins_inverse, rdelta, &kRdelta);
BENCHMARK_CAPTURE(linuxcnc_inverse, rdelta_rotarydeltakins, &kRdelta);
BENCHMARK_CAPTURE(pkmkins_forward, rdelta, &kRdelta);
BENCHMARK_CAPTURE(linuxcnc_forward, rdelta_rotarydeltakins, &kRdelta);

}  // namespace

BENCHMARK_MAIN();
