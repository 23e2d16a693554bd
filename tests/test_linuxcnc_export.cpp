// pkm export linuxcnc: the INI and HAL text of a hand-checked machine, every example machine,
// the joint-rate bound against dense sampling with the inverse kinematics (joint velocities and
// accelerations at the exported axis limits stay within the joints' limits), bad inputs.
#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/linuxcnc/config_export.hpp"
#include "pkm/linuxcnc/kins_adapter.hpp"
#include "pkm/linuxcnc/machine_fingerprint.hpp"
#include "test_support.hpp"

namespace pkm::linuxcnc {
namespace {

// joint = C * axis with C_xy = 0.01: joint x moves 1.01 mm per mm of x and y together.
constexpr const char* kSmallMatrix = R"(name = "small matrix"
units = "mm"
[kinematics]
type = "matrix"
matrix = [[1.0, 0.01, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
[[joints]]
name = "jx"
min = -10.0
max = 300.0
max_velocity = 100.0
max_acceleration = 1000.0
axis = "X"
[[joints]]
name = "jy"
min = -10.0
max = 200.0
max_velocity = 50.0
max_acceleration = 500.0
axis = "Y"
[[joints]]
name = "jz"
min = -200.0
max = 10.0
max_velocity = 20.0
max_acceleration = 200.0
axis = "Z"
[cartesian]
max_feed = 12000.0
max_acceleration = 800.0
home = [100.0, 50.0, -10.0]
min = [0.0, 0.0, -100.0]
max = [200.0, 100.0, 0.0]
)";

ExportOptions options_for(const std::string& file_name, const std::string& text, bool sim) {
  ExportOptions options;
  options.sim = sim;
  options.machine_file_name = file_name;
  options.machine_text = text;
  return options;
}

const ConfigFile& file_named(const LinuxcncConfig& config, const std::string& name) {
  for (const ConfigFile& file : config.files) {
    if (file.name == name) return file;
  }
  throw std::runtime_error("no file " + name);
}

// The text of INI section `name` ("[AXIS_X]") up to the next section.
std::string section(const std::string& ini, const std::string& name) {
  const std::size_t start = ini.find("\n" + name + "\n");
  if (start == std::string::npos) return "";
  const std::size_t end = ini.find("\n[", start + 1);
  return ini.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

bool has_line(const std::string& text, const std::string& line) {
  return ("\n" + text + "\n").find("\n" + line + "\n") != std::string::npos;
}

TEST(LinuxcncExport, HandCheckedMatrixMachine) {
  const machine::Machine machine = machine::parse_machine(kSmallMatrix, "small.toml");
  const LinuxcncConfig config =
      make_linuxcnc_config(machine, options_for("small.toml", kSmallMatrix, true));
  // The split by hand: alone, X could have 100 mm/s (jx), Y 50 (jy), Z 20 (jz). All grow as the
  // same share t of that: jx runs out first, at 100 t + 0.01 * 50 t = 100, t = 100 / 100.5,
  // fixing X and Y (both move jx); Z goes on to t = 1. Accelerations, alone: X 800 (the machine's
  // max_acceleration), Y 500, Z 200; jy and jz run out at t = 1 (jx keeps 995 of its 1000). No
  // curvature: the model is linear. LinuxCNC gets the accelerations divided by its planner's
  // overshoot (1.5: what it reaches in parabolic blends).
  const double v = 1.0, a = 1.0 / kPlannerAccelerationOvershoot;
  EXPECT_NEAR(config.limits.velocity[0], 100.0 * 100.0 / 100.5 * v, 1e-9);
  EXPECT_NEAR(config.limits.velocity[1], 50.0 * 100.0 / 100.5 * v, 1e-9);
  EXPECT_NEAR(config.limits.velocity[2], 20.0 * v, 1e-9);
  EXPECT_NEAR(config.limits.acceleration[0], 800.0 * a, 1e-9);
  EXPECT_NEAR(config.limits.acceleration[1], 500.0 * a, 1e-9);
  EXPECT_NEAR(config.limits.acceleration[2], 200.0 * a, 1e-9);
  EXPECT_NEAR(config.limits.linear_velocity,
              std::hypot(100.0 * 100.0 / 100.5, 50.0 * 100.0 / 100.5, 20.0) * v, 1e-9);
  EXPECT_DOUBLE_EQ(config.shrink, 1.0);
  EXPECT_TRUE(config.bound.proven);

  const std::string ini = file_named(config, "small.ini").text;
  EXPECT_TRUE(has_line(section(ini, "[KINS]"), "KINEMATICS = pkmkins machine=small.toml"));
  EXPECT_TRUE(has_line(section(ini, "[KINS]"), "PKM_MACHINE = small.toml"));
  EXPECT_TRUE(has_line(section(ini, "[KINS]"), "JOINTS = 3"));
  const std::string traj = section(ini, "[TRAJ]");
  EXPECT_TRUE(has_line(traj, "COORDINATES = X Y Z"));
  EXPECT_TRUE(has_line(traj, "LINEAR_UNITS = mm"));
  EXPECT_TRUE(has_line(traj, "MAX_LINEAR_VELOCITY = 113.030665"));     // the three, down
  EXPECT_TRUE(has_line(traj, "MAX_LINEAR_ACCELERATION = 642.91005"));  // the three
  const std::string x = section(ini, "[AXIS_X]");
  EXPECT_TRUE(has_line(x, "MIN_LIMIT = 0"));
  EXPECT_TRUE(has_line(x, "MAX_LIMIT = 200"));
  EXPECT_TRUE(has_line(x, "MAX_VELOCITY = 99.502487"));  // 99.5024875..., down
  EXPECT_TRUE(has_line(x, "MAX_ACCELERATION = 533.333333"));
  EXPECT_TRUE(has_line(section(ini, "[AXIS_Z]"), "MAX_VELOCITY = 20"));
  EXPECT_TRUE(has_line(section(ini, "[AXIS_Z]"), "MIN_LIMIT = -100"));
  const std::string j0 = section(ini, "[JOINT_0]");
  EXPECT_TRUE(has_line(j0, "TYPE = LINEAR"));
  EXPECT_TRUE(has_line(j0, "MIN_LIMIT = -10"));
  EXPECT_TRUE(has_line(j0, "MAX_LIMIT = 300"));
  EXPECT_TRUE(has_line(j0, "MAX_VELOCITY = 100"));
  EXPECT_TRUE(has_line(j0, "MAX_ACCELERATION = 1000"));
  EXPECT_TRUE(has_line(j0, "HOME = 100.5"));  // 100 + 0.01 * 50
  EXPECT_TRUE(has_line(j0, "HOME_OFFSET = 100.5"));
  EXPECT_TRUE(has_line(j0, "HOME_SEARCH_VEL = 0"));
  EXPECT_TRUE(has_line(j0, "HOME_SEQUENCE = 0"));
  EXPECT_TRUE(has_line(section(ini, "[JOINT_2]"), "HOME = -10"));
  EXPECT_TRUE(has_line(section(ini, "[HAL]"), "HALFILE = sim.hal"));

  const std::string sim = file_named(config, "sim.hal").text;
  EXPECT_TRUE(has_line(sim, "net j0-pos joint.0.motor-pos-cmd => joint.0.motor-pos-fb"));
  EXPECT_EQ(sim.find("\nsets "), std::string::npos);       // a signal with a writer takes no value
  EXPECT_TRUE(has_line(traj, "HOME = 100 50 -10 0 0 0"));  // FK's seed once homed
  const std::string hal = file_named(config, "small.hal").text;
  EXPECT_TRUE(has_line(hal, "loadrt [KINS]KINEMATICS"));
  EXPECT_TRUE(has_line(hal, "addf motion-controller servo-thread"));
  EXPECT_EQ(file_named(config, "small.toml").text, kSmallMatrix);
}

TEST(LinuxcncExport, HardwareConfigMarksWhatToWire) {
  const machine::Machine machine = machine::parse_machine(kSmallMatrix, "small.toml");
  const LinuxcncConfig config =
      make_linuxcnc_config(machine, options_for("small.toml", kSmallMatrix, false));
  const std::string hardware = file_named(config, "hardware.hal").text;
  EXPECT_TRUE(
      has_line(section(file_named(config, "small.ini").text, "[HAL]"), "HALFILE = hardware.hal"));
  for (const std::string pin : {"motor-pos-cmd", "motor-pos-fb", "amp-enable-out"}) {
    for (int joint = 0; joint < 3; ++joint) {
      const std::string name = "joint." + std::to_string(joint) + "." + pin;
      const std::size_t at = hardware.find(name);
      ASSERT_NE(at, std::string::npos) << name;
      EXPECT_NE(hardware.substr(at, hardware.find('\n', at) - at).find("# WIRE"), std::string::npos)
          << name;
    }
  }
  EXPECT_EQ(hardware.find("=> joint.0.motor-pos-fb"), std::string::npos);  // no loopback
}

TEST(LinuxcncExport, APenThatDrawsAboveItsHeightIsUpBelowIt) {
  // comp's out (pen-up) is true while in1 > in0: for down_above = 45 the height is in1 and the
  // commanded Z in0, so the pen is up below Z 45 (down_below puts them the other way round).
  std::ifstream in(PKM_SOURCE_DIR "/examples/machines/linuxcnc-polargraph-2366.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = text.substr(0, text.find("[tool]")) +
         "[tool]\nz = \"pen\"\ndown_above = 45.0\ndown = \"M3\"\nup = \"M5\"\n";
  const machine::Machine machine = machine::parse_machine(text, "polargraph.toml");
  const LinuxcncConfig config =
      make_linuxcnc_config(machine, options_for("polargraph.toml", text, true));
  const std::string hal = file_named(config, "polargraph.hal").text;
  EXPECT_TRUE(has_line(hal, "setp pen-up.in1 45")) << hal;
  EXPECT_TRUE(has_line(hal, "net pen-z axis.z.pos-cmd => pen-up.in0")) << hal;
  EXPECT_TRUE(has_line(hal,
                       "# The pen: up while the commanded Z is below the machine file's "
                       "[tool] down_above"));
}

TEST(LinuxcncExport, InchMachineSpeaksInches) {
  const machine::Machine machine =
      machine::load_machine(PKM_SOURCE_DIR "/tests/data/hektor-inch.toml");
  const LinuxcncConfig config = make_linuxcnc_config(machine, options_for("h.toml", "", true));
  const std::string ini = file_named(config, "h.ini").text;
  EXPECT_TRUE(has_line(section(ini, "[TRAJ]"), "LINEAR_UNITS = inch"));
  EXPECT_TRUE(has_line(section(ini, "[JOINT_0]"), "MAX_LIMIT = 180"));
  EXPECT_TRUE(has_line(section(ini, "[JOINT_0]"), "MAX_VELOCITY = 60"));
  // The exported speed in the INI is the bound's mm/s in inches.
  const std::string x = section(ini, "[AXIS_X]");
  const double inches = config.limits.velocity[0] / 25.4;
  EXPECT_NE(x.find("MAX_VELOCITY = " + std::to_string(inches).substr(0, 4)), std::string::npos)
      << x;
}

// Every example machine's configuration, made once for the tests below.
const LinuxcncConfig& example_config(const std::string& file) {
  static std::map<std::string, LinuxcncConfig> made;
  auto found = made.find(file);
  if (found == made.end()) {
    const machine::Machine machine = test::load_example(file);
    found =
        made.emplace(file, make_linuxcnc_config(machine, options_for(file, "text", true))).first;
  }
  return found->second;
}

TEST(LinuxcncExport, EveryExampleMachineExports) {
  for (const std::string& file : test::example_machine_files()) {
    SCOPED_TRACE(file);
    const machine::Machine machine = test::load_example(file);
    const LinuxcncConfig& config = example_config(file);
    const std::string stem = std::filesystem::path(file).stem().string();
    const std::string ini = file_named(config, stem + ".ini").text;
    EXPECT_TRUE(
        has_line(section(ini, "[KINS]"), "JOINTS = " + std::to_string(machine.joints().size())));
    EXPECT_EQ(ini.find("nan"), std::string::npos);
    EXPECT_EQ(ini.find("inf"), std::string::npos);
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (!config.moved.controls(axis)) continue;
      EXPECT_GT(config.limits.velocity[axis], 0.0) << axis;
      EXPECT_GT(config.limits.acceleration[axis], 0.0) << axis;
      EXPECT_LE(config.envelope.box.min[axis], machine.home().as_vector()[axis]);
      EXPECT_GE(config.envelope.box.max[axis], machine.home().as_vector()[axis]);
    }
    EXPECT_GT(config.shrink, 0.0);
    // Proven wherever post's deviation argument has a Hessian bound for the model (not formula
    // machines, nor a model added since without one: those are sampled, and say so).
    const bool hessian_bound =
        bounds::inverse_hessian_bounds(machine.kinematics(), machine.home().as_vector(), 0.0,
                                       bounds::pose_angle_scale_mm(machine.kinematics()), {})
            .has_value();
    EXPECT_EQ(config.bound.proven, hessian_bound);
    if (machine.kinematics().type() == "formula") {
      EXPECT_FALSE(config.bound.proven);
    }
  }
}

// Where LinuxCNC may take the tool: every axis within its exported velocity, and its
// acceleration times the planner's overshoot (kPlannerAccelerationOvershoot), in any combination.
// At a pose p, joint i's rate is J_i v, largest for v_j = sign(J_ij) V_j; its acceleration
// J_i a + v^T H_i v (the second term by central differences of the IK along v), largest for
// a_j = sign(J_ij) A_j. Both must stay within the joint's limits wherever the machine reaches.
struct Worst {
  double velocity = 0.0;      // largest joint rate met, as a share of its limit
  double acceleration = 0.0;  // ... joint acceleration
  long poses = 0;
};

void check_pose(const machine::Machine& machine, const LinuxcncConfig& config,
                const geometry::Vector6d& pose, Worst& worst) {
  const kinematics::Kinematics& model = machine.kinematics();
  kinematics::JointVector q, ahead, behind;
  kinematics::JointJacobian jacobian;
  if (!machine.inverse(geometry::Pose::from_vector(pose), q).ok()) return;
  ASSERT_TRUE(model.jacobian(geometry::Pose::from_vector(pose), jacobian).ok());
  ++worst.poses;
  for (int i = 0; i < model.joint_count(); ++i) {
    geometry::Vector6d v = geometry::Vector6d::Zero(), a = geometry::Vector6d::Zero();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      const double sign = jacobian(i, axis) < 0.0 ? -1.0 : 1.0;
      v[axis] = sign * config.limits.velocity[axis];
      a[axis] = sign * config.limits.acceleration[axis] * kPlannerAccelerationOvershoot;
    }
    const machine::JointSpec& spec = machine.joints()[static_cast<std::size_t>(i)];
    const double rate = std::abs(jacobian.row(i).dot(v));
    EXPECT_LE(rate, spec.max_velocity * (1.0 + 1e-9))
        << machine.format_pose(geometry::Pose::from_vector(pose));
    worst.velocity = std::max(worst.velocity, rate / spec.max_velocity);
    const double dt = 1e-3;
    if (!model.inverse(geometry::Pose::from_vector(pose + dt * v), ahead).ok() ||
        !model.inverse(geometry::Pose::from_vector(pose - dt * v), behind).ok()) {
      continue;
    }
    const double curving = (ahead[i] - 2.0 * q[i] + behind[i]) / (dt * dt);
    const double acceleration = std::abs(jacobian.row(i).dot(a)) + std::abs(curving);
    EXPECT_LE(acceleration, spec.max_acceleration * (1.0 + 1e-6) + 1e-6)
        << machine.format_pose(geometry::Pose::from_vector(pose)) << " joint " << i;
    worst.acceleration = std::max(worst.acceleration, acceleration / spec.max_acceleration);
  }
}

class ExportedLimits : public ::testing::TestWithParam<std::string> {};

TEST_P(ExportedLimits, KeepEveryJointWithinItsLimitsAcrossTheEnvelope) {
  const machine::Machine machine = test::load_example(GetParam());
  const LinuxcncConfig& config = example_config(GetParam());
  const machine::PoseBox& box = config.envelope.box;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Worst worst;
  const std::vector<int> axes = machine.kinematics().dof().axes();
  // The corners of the envelope (where the rates peak on most machines), then random poses.
  for (long corner = 0; corner < (1L << axes.size()); ++corner) {
    geometry::Vector6d pose = machine.home().as_vector();
    for (std::size_t k = 0; k < axes.size(); ++k) {
      pose[axes[k]] = (corner >> k) & 1 ? box.max[axes[k]] : box.min[axes[k]];
    }
    check_pose(machine, config, pose, worst);
  }
  for (int sample = 0; sample < 4000; ++sample) {
    geometry::Vector6d pose = machine.home().as_vector();
    for (const int axis : axes)
      pose[axis] = box.min[axis] + unit(rng) * (box.max[axis] - box.min[axis]);
    check_pose(machine, config, pose, worst);
  }
  EXPECT_GT(worst.poses, 1000);
  // The bound is not vacuous: somewhere a joint comes within a factor of one of its limits (the
  // rotary delta's speeds are set by its joints' acceleration: velocity share 0.11, acceleration
  // 0.39).
  EXPECT_GT(std::max(worst.velocity, worst.acceleration), 0.3);
  RecordProperty("worst_velocity_share", std::to_string(worst.velocity));
  RecordProperty("worst_acceleration_share", std::to_string(worst.acceleration));
}

INSTANTIATE_TEST_SUITE_P(Examples, ExportedLimits,
                         ::testing::Values("hektor.toml", "maslow.toml", "linear-delta.toml",
                                           "linuxcnc-ldelta.toml", "triaglide-fanned.toml",
                                           "hexapod-bit.toml", "linuxcnc-hexapod-sim.toml",
                                           "hexaglide.toml", "matrix-mill.toml",
                                           "linuxcnc-xyzac-trt.toml", "linuxcnc-rdelta.toml"),
                         [](const auto& param_info) { return test::test_name(param_info.param); });

// The envelope's sides from the file where it gives them, the reach box where it does not; the
// INI says which.
TEST(LinuxcncExport, EnvelopeFromTheFileOrTheReach) {
  const machine::Machine given = machine::parse_machine(kSmallMatrix, "small.toml");
  const bounds::EnvelopeBox from_file = bounds::work_envelope(given);
  EXPECT_EQ(from_file.from_file, geometry::Dof::translation());
  EXPECT_EQ(from_file.box.axes, geometry::Dof::translation());
  EXPECT_EQ(from_file.box.min.head<3>(), Eigen::Vector3d(0.0, 0.0, -100.0));
  EXPECT_EQ(from_file.box.max.head<3>(), Eigen::Vector3d(200.0, 100.0, 0.0));
  const std::string ini =
      file_named(make_linuxcnc_config(given, options_for("small.toml", kSmallMatrix, true)),
                 "small.ini")
          .text;
  EXPECT_TRUE(has_line(section(ini, "[AXIS_Y]"), "# limits: [cartesian] min/max"));

  std::string text = kSmallMatrix;
  text.replace(text.find("min = [0.0, 0.0, -100.0]\n"), 25, "");
  text.replace(text.find("max = [200.0, 100.0, 0.0]\n"), 26, "");
  const machine::Machine reached = machine::parse_machine(text, "reach.toml");
  const bounds::EnvelopeBox from_reach = bounds::work_envelope(reached);
  EXPECT_EQ(from_reach.from_file, geometry::Dof());
  const machine::PoseBox reach = machine::reach_box(reached);
  EXPECT_EQ(from_reach.box.min, reach.min);
  EXPECT_EQ(from_reach.box.max, reach.max);
  // jz runs -200..10 with z = jz: the reach along z from home (-10) is the joint's range.
  EXPECT_NEAR(from_reach.box.min[2], -200.0, 1e-3);
  EXPECT_NEAR(from_reach.box.max[2], 10.0, 1e-3);
  const std::string reach_ini =
      file_named(make_linuxcnc_config(reached, options_for("reach.toml", text, true)), "reach.ini")
          .text;
  EXPECT_TRUE(has_line(section(reach_ini, "[AXIS_Z]"),
                       "# limits: the reachable extent along lines through home"));
}

TEST(LinuxcncExport, RefusesAMachineWithNoFiniteReach) {
  std::string text = kSmallMatrix;
  text.replace(text.find("min = [0.0, 0.0, -100.0]\n"), 25, "");
  text.replace(text.find("max = [200.0, 100.0, 0.0]\n"), 26, "");
  text.replace(text.find("min = -10.0\nmax = 300.0"), 23, "min = -9e5\nmax = 9e5");
  const machine::Machine machine = machine::parse_machine(text, "far.toml");
  try {
    make_linuxcnc_config(machine, options_for("far.toml", text, true));
    FAIL() << "exported";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("reach along x is not finite"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("[cartesian] min and max for x"), std::string::npos);
  }
}

std::filesystem::path scratch(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("pkm-lcnc-" + name + "-" + std::to_string(::getpid()));
}

TEST(LinuxcncExport, WritesTheDirectoryWholeAndRefusesOneInUse) {
  const machine::Machine machine = machine::parse_machine(kSmallMatrix, "small.toml");
  const LinuxcncConfig config =
      make_linuxcnc_config(machine, options_for("small.toml", kSmallMatrix, true));
  const std::filesystem::path dir = scratch("write");
  std::filesystem::remove_all(dir);
  write_config_directory(dir, config, false);
  for (const ConfigFile& file : config.files) {
    std::ifstream in(dir / file.name);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(), file.text) << file.name;
  }
  // Not empty now: refused, and nothing changes; --force replaces the files.
  std::ofstream(dir / "mine.txt") << "keep";
  try {
    write_config_directory(dir, config, false);
    FAIL() << "written";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("exists and is not empty"), std::string::npos);
    EXPECT_NE(std::string(error.what()).find("--force"), std::string::npos);
  }
  std::filesystem::remove(dir / "small.ini");
  write_config_directory(dir, config, true);
  EXPECT_TRUE(std::filesystem::exists(dir / "small.ini"));
  EXPECT_TRUE(std::filesystem::exists(dir / "mine.txt"));
  std::filesystem::remove_all(dir);

  // An empty directory is used as it is.
  std::filesystem::create_directory(dir);
  write_config_directory(dir, config, false);
  EXPECT_TRUE(std::filesystem::exists(dir / "sim.hal"));
  std::filesystem::remove_all(dir);
}

TEST(LinuxcncExport, UnwritablePlaceLeavesNothing) {
  const machine::Machine machine = machine::parse_machine(kSmallMatrix, "small.toml");
  const LinuxcncConfig config =
      make_linuxcnc_config(machine, options_for("small.toml", kSmallMatrix, true));
  const std::filesystem::path file = scratch("a-file");
  std::ofstream(file) << "x";
  try {
    write_config_directory(file / "config", config, false);
    FAIL() << "written";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("cannot create the directory"), std::string::npos)
        << error.what();
  }
  try {
    write_config_directory(file, config, false);
    FAIL() << "written";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("is not a directory"), std::string::npos);
  }
  std::filesystem::remove(file);
  // A failure while writing leaves no half directory: the files go to a temporary first.
  const std::filesystem::path parent = scratch("parent");
  std::filesystem::create_directories(parent);
  LinuxcncConfig broken = config;
  // (a directory where the configuration already has a file of that name)
  broken.files.push_back({broken.files.front().name + "/x.hal", "x"});
  EXPECT_THROW(write_config_directory(parent / "config", broken, false), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(parent));
  std::filesystem::remove_all(parent);
}

// Every file under `directory` (names relative to it, '/'-separated) and its bytes.
std::map<std::string, std::string> tree_of(const std::filesystem::path& directory) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(directory)) {
    if (entry.is_directory()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    files[std::filesystem::relative(entry.path(), directory).generic_string()] = text.str();
  }
  return files;
}

// Names in `parent` other than `keep`: what an export left beside its directory.
std::vector<std::string> beside(const std::filesystem::path& parent, const std::string& keep) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(parent)) {
    if (entry.path().filename() != keep) names.push_back(entry.path().filename().string());
  }
  return names;
}

// The small matrix with its X joint's speed changed: another configuration of the same name.
LinuxcncConfig changed_small_config() {
  std::string text = kSmallMatrix;
  text.replace(text.find("max_velocity = 100.0"), 20, "max_velocity = 80.0");
  return make_linuxcnc_config(machine::parse_machine(text, "small.toml"),
                              options_for("small.toml", text, true));
}

TEST(LinuxcncExport, ForceReplacesTheConfigurationWholeAndKeepsTheUsersFiles) {
  const LinuxcncConfig old_config =
      make_linuxcnc_config(machine::parse_machine(kSmallMatrix, "small.toml"),
                           options_for("small.toml", kSmallMatrix, true));
  const LinuxcncConfig new_config = changed_small_config();
  ASSERT_NE(file_named(old_config, "small.ini").text, file_named(new_config, "small.ini").text);
  const std::filesystem::path parent = scratch("force");
  const std::filesystem::path dir = parent / "config";
  std::filesystem::remove_all(parent);
  std::filesystem::create_directories(parent);
  write_config_directory(dir, old_config, false);
  // What LinuxCNC and the user put there since: offsets, a tool, their own HAL file and macros.
  std::ofstream(dir / "small.var") << "5220\t1.000000\n5221\t12.5\n";
  std::ofstream(dir / "small.tbl") << "T1 P1 D3 Z-12.7 ;3 mm end mill\n";
  std::ofstream(dir / "custom.hal") << "net spindle-on motion.spindle-on\n";
  std::filesystem::create_directories(dir / "macros");
  std::ofstream(dir / "macros" / "o100.ngc") << "o100 sub\no100 endsub\n";
  std::map<std::string, std::string> expected;
  for (const ConfigFile& file : new_config.files) expected[file.name] = file.text;
  expected["small.var"] = "5220\t1.000000\n5221\t12.5\n";
  expected["small.tbl"] = "T1 P1 D3 Z-12.7 ;3 mm end mill\n";
  expected["custom.hal"] = "net spindle-on motion.spindle-on\n";
  expected["macros/o100.ngc"] = "o100 sub\no100 endsub\n";

  const KeptFiles kept = write_config_directory(dir, new_config, true);
  EXPECT_EQ(tree_of(dir), expected);
  EXPECT_EQ(kept.state, (std::vector<std::string>{"small.tbl", "small.var"}));
  std::vector<std::string> others = kept.others;
  std::sort(others.begin(), others.end());
  EXPECT_EQ(others, (std::vector<std::string>{"custom.hal", "macros/o100.ngc"}));
  EXPECT_EQ(beside(parent, "config"), std::vector<std::string>{});  // no staging, no old copy
  std::filesystem::remove_all(parent);
}

TEST(LinuxcncExport, FailedForceLeavesTheOldConfigurationByteForByte) {
  const LinuxcncConfig old_config =
      make_linuxcnc_config(machine::parse_machine(kSmallMatrix, "small.toml"),
                           options_for("small.toml", kSmallMatrix, true));
  const std::filesystem::path parent = scratch("force-fails");
  const std::filesystem::path dir = parent / "config";
  std::filesystem::remove_all(parent);
  std::filesystem::create_directories(parent);
  write_config_directory(dir, old_config, false);
  std::ofstream(dir / "custom.hal") << "net spindle-on motion.spindle-on\n";
  const std::map<std::string, std::string> before = tree_of(dir);

  // A failure after every new file is written (a file where a later one needs a directory):
  // the files were once replaced one at a time, so the INI here was already the new one.
  LinuxcncConfig broken = changed_small_config();
  broken.files.push_back({"small.hal/x.hal", "x"});
  EXPECT_THROW(write_config_directory(dir, broken, true), std::runtime_error);
  EXPECT_EQ(tree_of(dir), before);
  EXPECT_EQ(beside(parent, "config"), std::vector<std::string>{});

  // The user's directory where the configuration writes a file: refused, naming it.
  std::filesystem::create_directories(dir / "sim.hal.d");
  LinuxcncConfig clash = changed_small_config();
  clash.files.push_back({"sim.hal.d", "a file now"});
  try {
    write_config_directory(dir, clash, true);
    FAIL() << "replaced";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what())
                  .find("its sim.hal.d is a directory where the configuration writes a file"),
              std::string::npos)
        << error.what();
  }
  EXPECT_EQ(tree_of(dir), before);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "sim.hal.d"));
  EXPECT_EQ(beside(parent, "config"), std::vector<std::string>{});
  std::filesystem::remove_all(parent);
}

TEST(LinuxcncExport, ForceThroughALinkReplacesTheDirectoryItNames) {
  const LinuxcncConfig config = changed_small_config();
  const std::filesystem::path parent = scratch("force-link");
  std::filesystem::remove_all(parent);
  std::filesystem::create_directories(parent / "real");
  std::ofstream(parent / "real" / "small.ini") << "old";
  std::filesystem::create_directory_symlink("real", parent / "link");
  write_config_directory(parent / "link", config, true);
  EXPECT_TRUE(std::filesystem::is_symlink(parent / "link"));
  EXPECT_EQ(tree_of(parent / "real").at("small.ini"), file_named(config, "small.ini").text);
  std::filesystem::remove_all(parent);
}

// Swapping the directory a shell stands in would leave the shell in the removed one.
TEST(LinuxcncExport, ForceRefusesTheCurrentDirectory) {
  const LinuxcncConfig config = changed_small_config();
  const std::filesystem::path dir = scratch("force-here");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "sub");
  std::ofstream(dir / "small.ini") << "old";
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir / "sub");
  std::string message;
  try {
    write_config_directory("..", config, true);
  } catch (const std::runtime_error& error) {
    message = error.what();
  }
  std::filesystem::current_path(before);
  EXPECT_NE(message.find(".. is the current directory (or holds it): --force replaces it as a "
                         "whole"),
            std::string::npos)
      << message;
  EXPECT_EQ(tree_of(dir).at("small.ini"), "old");
  std::filesystem::remove_all(dir);
}

TEST(LinuxcncExport, IniRecordsTheMachineFilesSha256) {
  const LinuxcncConfig config =
      make_linuxcnc_config(machine::parse_machine(kSmallMatrix, "small.toml"),
                           options_for("small.toml", kSmallMatrix, true));
  const std::string kins = section(file_named(config, "small.ini").text, "[KINS]");
  EXPECT_TRUE(has_line(kins, "PKM_MACHINE_SHA256 = " + sha256_hex(kSmallMatrix))) << kins;
}

// The fingerprint's round trip: pkmkins (KinsAdapter, as the module loads) accepts the exported
// machine file beside its INI, and refuses it, at the INI's line, once it has changed.
TEST(LinuxcncExport, PkmkinsRefusesAMachineFileChangedSinceTheExport) {
  const LinuxcncConfig config =
      make_linuxcnc_config(machine::parse_machine(kSmallMatrix, "small.toml"),
                           options_for("small.toml", kSmallMatrix, true));
  const std::filesystem::path dir = scratch("fingerprint");
  std::filesystem::remove_all(dir);
  write_config_directory(dir, config, false);
  const IniFile ini = IniFile::read(dir / "small.ini");
  EXPECT_EQ(ini_mismatch(load_kins(dir / "small.toml", std::nullopt), ini), "");

  // A joint limit changed in the copy beside the INI (the INI's limits still say 300 mm).
  std::string text = kSmallMatrix;
  text.replace(text.find("max = 300.0"), 11, "max = 250.0");
  std::ofstream(dir / "small.toml") << text;
  const KinsAdapter kins = load_kins(dir / "small.toml", std::nullopt);
  const IniEntry& recorded = *ini.find("KINS", "PKM_MACHINE_SHA256");
  const std::string file = (dir / "small.toml").string();
  EXPECT_EQ(ini_mismatch(kins, ini),
            (dir / "small.ini").string() + ":" + std::to_string(recorded.where.line) +
                ": machine file " + file +
                " changed since `pkm export linuxcnc` wrote this configuration (its SHA-256 is "
                "now " +
                sha256_hex(text) + "; [KINS] PKM_MACHINE_SHA256 = " + sha256_hex(kSmallMatrix) +
                " is the file the INI's joint and axis limits were made from): export again, `pkm "
                "export linuxcnc -m " +
                file + " -o " + dir.string() + " --sim --force`, or put the exported file back");
  // A comment is a change too: the check is of the bytes, as `sha256sum` sees them.
  std::ofstream(dir / "small.toml") << kSmallMatrix << "# checked\n";
  EXPECT_NE(ini_mismatch(load_kins(dir / "small.toml", std::nullopt), ini), "");
  std::filesystem::remove_all(dir);
}

TEST(LinuxcncExport, Sha256IsTheStandardOne) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace pkm::linuxcnc
