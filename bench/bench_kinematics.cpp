// IK and FK per model: ns per pose, single calls and batches, FK warm-started along a path.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm {
namespace {

constexpr int kPoses = 1024;

// "hexapod-bit+limits": the paper's hexapod with 30 deg joints and 40 mm legs (the cost of the
// joint-angle and interference checks on every pose; without the keys they cost a flag test).
machine::Machine load(const std::string& file) {
  const std::filesystem::path examples = std::filesystem::path(PKM_SOURCE_DIR) / "examples";
  if (file != "hexapod-bit+limits") return machine::load_machine(examples / "machines" / file);
  std::ifstream in(examples / "machines" / "hexapod-bit.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string toml = text.str();
  const std::string key = "tool_length = 30.0";
  toml.replace(toml.find(key), key.size(), key + "\nmax_joint_angle = 30\nleg_diameter = 40");
  return machine::parse_machine(toml, "hexapod-bit+limits");
}

// A small helix about home, 0.1 mm apart (a 1 ms servo step at 6 m/min), with a slow tilt on
// machines that control orientation: the poses FK meets along a tool path.
std::vector<geometry::Pose> path_about_home(const machine::Machine& machine) {
  std::vector<geometry::Pose> poses;
  const geometry::Dof dof = machine.kinematics().dof();
  const double radius_mm = 10.0;
  for (int i = 0; i < kPoses; ++i) {
    const double phase = 0.1 * i / radius_mm;
    geometry::Vector6d values = machine.home().as_vector();
    int used = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!dof.controls(axis)) continue;
      if (used == 0) values[axis] += radius_mm * (std::cos(phase) - 1.0);
      if (used == 1) values[axis] += radius_mm * std::sin(phase);
      if (used == 2) values[axis] += 0.01 * i;
      ++used;
    }
    if (dof.any_rotation()) {
      values[3] += geometry::degrees_to_radians(3.0) * std::sin(phase);
      values[4] += geometry::degrees_to_radians(3.0) * (1.0 - std::cos(phase));
    }
    poses.push_back(geometry::Pose::from_vector(values));
  }
  return poses;
}

void inverse_single(benchmark::State& state, const std::string& file) {
  const machine::Machine machine = load(file);
  const std::vector<geometry::Pose> poses = path_about_home(machine);
  kinematics::JointVector joints;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(machine.kinematics().inverse(poses[i], joints));
    benchmark::DoNotOptimize(joints.data());
    i = (i + 1) % poses.size();
  }
  state.SetItemsProcessed(state.iterations());
}

void inverse_batch(benchmark::State& state, const std::string& file) {
  const machine::Machine machine = load(file);
  const std::vector<geometry::Pose> poses = path_about_home(machine);
  std::vector<kinematics::JointVector> joints(poses.size());
  std::vector<kinematics::Status> statuses(poses.size());
  for (auto _ : state) {
    machine.kinematics().inverse_batch(poses, joints, statuses);
    benchmark::DoNotOptimize(joints.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(poses.size()));
}

// The paper's fixed-attitude mode: the tool axis stays put along the path, so the batch computes
// the rotation once.
void inverse_batch_fixed_attitude(benchmark::State& state, const std::string& file) {
  const machine::Machine machine = load(file);
  std::vector<geometry::Pose> poses = path_about_home(machine);
  for (geometry::Pose& pose : poses) pose.orientation_rad = machine.home().orientation_rad;
  std::vector<kinematics::JointVector> joints(poses.size());
  std::vector<kinematics::Status> statuses(poses.size());
  for (auto _ : state) {
    machine.kinematics().inverse_batch(poses, joints, statuses);
    benchmark::DoNotOptimize(joints.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(poses.size()));
}

void forward_along_path(benchmark::State& state, const std::string& file) {
  const machine::Machine machine = load(file);
  const std::vector<geometry::Pose> poses = path_about_home(machine);
  std::vector<kinematics::JointVector> joints(poses.size());
  std::vector<kinematics::Status> statuses(poses.size());
  machine.kinematics().inverse_batch(poses, joints, statuses);
  std::vector<geometry::Pose> solved(poses.size());
  int64_t succeeded = 0;
  int64_t iterations = 0;
  for (auto _ : state) {
    machine.kinematics().forward_path(joints, poses.front(), solved, statuses);
    for (const kinematics::Status& status : statuses) {
      succeeded += status.ok() ? 1 : 0;
      iterations += status.iterations;
    }
    benchmark::DoNotOptimize(solved.data());
  }
  const int64_t attempted = state.iterations() * static_cast<int64_t>(poses.size());
  state.SetItemsProcessed(attempted);
  state.counters["success_pct"] =
      100.0 * static_cast<double>(succeeded) / static_cast<double>(attempted);
  state.counters["newton_steps"] = static_cast<double>(iterations) / static_cast<double>(attempted);
}

void forward_from_home(benchmark::State& state, const std::string& file) {
  const machine::Machine machine = load(file);
  std::vector<geometry::Pose> poses = path_about_home(machine);
  std::vector<kinematics::JointVector> joints(poses.size());
  std::vector<kinematics::Status> statuses(poses.size());
  machine.kinematics().inverse_batch(poses, joints, statuses);
  std::size_t i = 0;
  int64_t succeeded = 0;
  for (auto _ : state) {
    geometry::Pose pose = machine.home();
    succeeded += machine.kinematics().forward(joints[i], pose).ok() ? 1 : 0;
    benchmark::DoNotOptimize(pose);
    i = (i + 1) % poses.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["success_pct"] =
      100.0 * static_cast<double>(succeeded) / static_cast<double>(state.iterations());
}

const char* const kMachines[] = {"hektor.toml", "matrix-mill.toml", "triaglide.toml",
                                 "linear-delta.toml", "hexaglide.toml", "hexapod-bit.toml",
                                 "hexapod-bit+limits", "mach3-formula.toml", "linuxcnc-rdelta.toml",
                                 // Cable machines as built: pulleys; a gondola; a sled and chain.
                                 "hektor-pulleys.toml", "makelangelo.toml", "maslow-frame.toml"};

const bool kRegistered = [] {
  for (const char* file : kMachines) {
    const std::string name = std::string(file).substr(0, std::string(file).find('.'));
    benchmark::RegisterBenchmark(("inverse/" + name).c_str(), inverse_single, std::string(file));
    benchmark::RegisterBenchmark(("inverse_batch/" + name).c_str(), inverse_batch,
                                 std::string(file));
    benchmark::RegisterBenchmark(("inverse_batch_fixed_attitude/" + name).c_str(),
                                 inverse_batch_fixed_attitude, std::string(file));
    benchmark::RegisterBenchmark(("forward_path/" + name).c_str(), forward_along_path,
                                 std::string(file));
    benchmark::RegisterBenchmark(("forward_from_home/" + name).c_str(), forward_from_home,
                                 std::string(file));
  }
  return true;
}();

}  // namespace
}  // namespace pkm

BENCHMARK_MAIN();
