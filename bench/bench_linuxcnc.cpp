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
#include <ctime>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/kinematics/lanes.hpp"
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
    entry = std::make_unique<Loaded>(
        Loaded{load_module(which.module, which.geometry),
               pkm::linuxcnc::KinsAdapter(
                   pkm::machine::load_machine(std::string(PKM_SOURCE_DIR) + "/examples/machines/" +
                                              which.machine_file),
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

// ---- Side by side: pkm and genhexkins timed alternately in the same benchmark, the ratio reported
// (x_genhexkins: genhexkins' time per pose over pkm's; above 1 pkm is faster), CPU time of this
// thread, so that the load of a shared machine weighs on both alike. Every figure of issue 16's
// kinematics targets, in one run.

double thread_cpu_ns() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return 1e9 * static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec);
}

// A stretch of samples: what one benchmark iteration does with each side.
constexpr std::size_t kStretch = 1000;

// genhexkins' inverse and forward (seeded with the previous pose) over samples [first, first +
// kStretch) of the hexapod path.
void genhexkins_inverse_stretch(const Loaded& hexapod, std::size_t first) {
  double joints[9];
  unsigned long iflags = 0, fflags = 0;
  for (std::size_t k = first; k < first + kStretch; ++k) {
    hexapod.reference.inverse(&hexapod.path[k], joints, &iflags, &fflags);
    benchmark::DoNotOptimize(joints);
  }
}
void genhexkins_forward_stretch(const Loaded& hexapod, std::size_t first) {
  WorldPose pose = hexapod.path[first];
  unsigned long iflags = 0, fflags = 0;
  for (std::size_t k = first; k < first + kStretch; ++k) {
    hexapod.reference.forward(hexapod.joints[k].data(), &pose, &fflags, &iflags);
    benchmark::DoNotOptimize(pose);
  }
}

// Runs `pkm(first)` and `reference(first)` on successive stretches of the path, each timed on its
// own; reports ns per pose of both and their ratio.
template <class Pkm, class Reference>
void alternate(benchmark::State& state, std::size_t samples, Pkm pkm, Reference reference,
               const char* ratio_name) {
  double pkm_ns = 0.0, reference_ns = 0.0;
  std::size_t first = 0;
  for (auto _ : state) {
    const double start = thread_cpu_ns();
    pkm(first);
    const double middle = thread_cpu_ns();
    state.PauseTiming();
    const double reference_start = thread_cpu_ns();
    reference(first);
    reference_ns += thread_cpu_ns() - reference_start;
    state.ResumeTiming();
    pkm_ns += middle - start;
    first = first + 2 * kStretch <= samples ? first + kStretch : 0;
  }
  const double poses = static_cast<double>(state.iterations()) * static_cast<double>(kStretch);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kStretch));
  state.counters["pkm_ns"] = pkm_ns / poses;
  state.counters["reference_ns"] = reference_ns / poses;
  state.counters[ratio_name] = reference_ns / pkm_ns;
}

// A machine of pkm's own (examples/machines), its path in mm and rad, and its joints along it.
struct PkmCase {
  pkm::machine::Machine machine;
  std::vector<pkm::geometry::Pose> path;
  std::vector<pkm::kinematics::JointVector> joints;
};

// The hexapod simulator's path in pkm's units, or a machine's own: 10 s of a helix at 25 mm/s
// about home, 1 ms apart, tilting by a few degrees where the machine controls orientation.
PkmCase& pkm_case(const std::string& file) {
  static std::map<std::string, std::unique_ptr<PkmCase>> cache;
  std::unique_ptr<PkmCase>& entry = cache[file];
  if (entry) return *entry;
  entry = std::make_unique<PkmCase>(PkmCase{
      pkm::machine::load_machine(std::string(PKM_SOURCE_DIR) + "/examples/machines/" + file),
      {},
      {}});
  if (file == kHexapod.machine_file) {
    const Loaded& hexapod = loaded(kHexapod);
    for (const WorldPose& world : hexapod.path)
      entry->path.push_back(hexapod.pkmkins.to_pose(world));
  } else {
    const pkm::geometry::Dof dof = entry->machine.kinematics().dof();
    for (int k = 0; k < 10000; ++k) {
      const double angle = k * 0.001 / 2.0;  // 25 mm/s on a 50 mm radius
      pkm::geometry::Vector6d values = entry->machine.home().as_vector();
      values[0] += 50.0 * (std::cos(angle) - 1.0);
      values[1] += 50.0 * std::sin(angle);
      values[2] -= 1.0 * k * 0.001;
      if (dof.any_rotation()) {
        values[3] += pkm::geometry::degrees_to_radians(3.0) * std::sin(angle);
        values[4] += pkm::geometry::degrees_to_radians(2.0) * std::cos(angle);
        values[5] += pkm::geometry::degrees_to_radians(4.0) * std::sin(2.0 * angle);
      }
      entry->path.push_back(pkm::geometry::Pose::from_vector(values));
    }
  }
  entry->joints.resize(entry->path.size());
  std::vector<pkm::kinematics::Status> statuses(entry->path.size());
  entry->machine.kinematics().inverse_batch(entry->path, entry->joints, statuses);
  for (const pkm::kinematics::Status& status : statuses) {
    if (!status.ok()) throw std::runtime_error(file + ": the benchmark's path leaves the reach");
  }
  return *entry;
}

bool genhexkins_missing(benchmark::State& state) {
  const Loaded& hexapod = loaded(kHexapod);
  if (hexapod.reference.inverse != nullptr) return false;
  state.SkipWithError(hexapod.reference.error.c_str());
  return true;
}

// IK one pose at a time (the model's inverse), against genhexkins' inverse.
void ik_single_vs_genhexkins(benchmark::State& state, const char* file) {
  if (genhexkins_missing(state)) return;
  PkmCase& pkm_side = pkm_case(file);
  const Loaded& hexapod = loaded(kHexapod);
  pkm::kinematics::JointVector joints;
  alternate(
      state, pkm_side.path.size(),
      [&](std::size_t first) {
        for (std::size_t k = first; k < first + kStretch; ++k) {
          benchmark::DoNotOptimize(pkm_side.machine.kinematics().inverse(pkm_side.path[k], joints));
          benchmark::DoNotOptimize(joints.data());
        }
      },
      [&](std::size_t first) { genhexkins_inverse_stretch(hexapod, first); }, "x_genhexkins");
}

// IK through inverse_batch, the attitude varying from pose to pose, against genhexkins' inverse.
void ik_batch_vs_genhexkins(benchmark::State& state, const char* file) {
  if (genhexkins_missing(state)) return;
  PkmCase& pkm_side = pkm_case(file);
  const Loaded& hexapod = loaded(kHexapod);
  std::vector<pkm::kinematics::JointVector> joints(kStretch);
  std::vector<pkm::kinematics::Status> statuses(kStretch);
  alternate(
      state, pkm_side.path.size(),
      [&](std::size_t first) {
        pkm_side.machine.kinematics().inverse_batch(
            std::span<const pkm::geometry::Pose>(pkm_side.path).subspan(first, kStretch), joints,
            statuses);
        benchmark::DoNotOptimize(joints.data());
      },
      [&](std::size_t first) { genhexkins_inverse_stretch(hexapod, first); }, "x_genhexkins");
}

// Warm FK along the path (Machine::forward with a track, each sample seeded with the previous
// solution), against genhexkins' forward seeded with its previous solution.
void fk_path_vs_genhexkins(benchmark::State& state, const char* file) {
  if (genhexkins_missing(state)) return;
  PkmCase& pkm_side = pkm_case(file);
  const Loaded& hexapod = loaded(kHexapod);
  long steps = 0, failures = 0;
  alternate(
      state, pkm_side.path.size(),
      [&](std::size_t first) {
        pkm::kinematics::ForwardTrack track;
        pkm::geometry::Pose pose = pkm_side.path[first];
        for (std::size_t k = first; k < first + kStretch; ++k) {
          const pkm::kinematics::Status status =
              pkm_side.machine.forward(pkm_side.joints[k], pose, track);
          steps += status.iterations;
          failures += status.ok() ? 0 : 1;
        }
        benchmark::DoNotOptimize(pose);
      },
      [&](std::size_t first) { genhexkins_forward_stretch(hexapod, first); }, "x_genhexkins");
  const double poses = static_cast<double>(state.iterations()) * static_cast<double>(kStretch);
  state.counters["newton_steps"] = static_cast<double>(steps) / poses;
  state.counters["success_pct"] = 100.0 * (1.0 - static_cast<double>(failures) / poses);
}

// The pkmkins module's calls as LinuxCNC's servo thread makes them (units converted, the
// machine's limits), against genhexkins'.
void pkmkins_ik_vs_genhexkins(benchmark::State& state) {
  if (genhexkins_missing(state)) return;
  Loaded& hexapod = loaded(kHexapod);
  double joints[9];
  alternate(
      state, hexapod.path.size(),
      [&](std::size_t first) {
        for (std::size_t k = first; k < first + kStretch; ++k) {
          hexapod.pkmkins.inverse(hexapod.path[k], joints);
          benchmark::DoNotOptimize(joints);
        }
      },
      [&](std::size_t first) { genhexkins_inverse_stretch(hexapod, first); }, "x_genhexkins");
}
void pkmkins_fk_vs_genhexkins(benchmark::State& state) {
  if (genhexkins_missing(state)) return;
  Loaded& hexapod = loaded(kHexapod);
  alternate(
      state, hexapod.path.size(),
      [&](std::size_t first) {
        WorldPose pose = hexapod.path[first];
        for (std::size_t k = first; k < first + kStretch; ++k) {
          hexapod.pkmkins.forward(hexapod.joints[k].data(), pose);
          benchmark::DoNotOptimize(pose);
        }
      },
      [&](std::size_t first) { genhexkins_forward_stretch(hexapod, first); }, "x_genhexkins");
}

// The same with the vector paths off: what a CPU without AVX2 gets.
void ik_batch_scalar_vs_genhexkins(benchmark::State& state, const char* file) {
  const bool previous = pkm::kinematics::lanes::set_avx2_enabled(false);
  ik_batch_vs_genhexkins(state, file);
  pkm::kinematics::lanes::set_avx2_enabled(previous);
}

BENCHMARK_CAPTURE(ik_single_vs_genhexkins, hexapod, "linuxcnc-hexapod-sim.toml");
BENCHMARK_CAPTURE(ik_batch_vs_genhexkins, hexapod, "linuxcnc-hexapod-sim.toml");
BENCHMARK_CAPTURE(ik_batch_scalar_vs_genhexkins, hexapod, "linuxcnc-hexapod-sim.toml");
BENCHMARK_CAPTURE(fk_path_vs_genhexkins, hexapod, "linuxcnc-hexapod-sim.toml");
BENCHMARK(pkmkins_ik_vs_genhexkins);
BENCHMARK(pkmkins_fk_vs_genhexkins);
BENCHMARK_CAPTURE(ik_single_vs_genhexkins, hexaglide, "hexaglide.toml");
BENCHMARK_CAPTURE(ik_batch_vs_genhexkins, hexaglide, "hexaglide.toml");
BENCHMARK_CAPTURE(fk_path_vs_genhexkins, hexaglide, "hexaglide.toml");
BENCHMARK_CAPTURE(ik_single_vs_genhexkins, ldelta, "linuxcnc-ldelta.toml");
BENCHMARK_CAPTURE(ik_batch_vs_genhexkins, ldelta, "linuxcnc-ldelta.toml");
BENCHMARK_CAPTURE(fk_path_vs_genhexkins, ldelta, "linuxcnc-ldelta.toml");
BENCHMARK_CAPTURE(ik_single_vs_genhexkins, linear_delta, "linear-delta.toml");
BENCHMARK_CAPTURE(ik_batch_vs_genhexkins, linear_delta, "linear-delta.toml");
BENCHMARK_CAPTURE(fk_path_vs_genhexkins, linear_delta, "linear-delta.toml");

// ---- Each side on its own, LinuxCNC's lineardeltakins and rotarydeltakins too.
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
