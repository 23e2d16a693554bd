#include "pkm/linuxcnc/config_export.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "pkm/files/atomic_file.hpp"
#include "pkm/linuxcnc/machine_fingerprint.hpp"

namespace pkm::linuxcnc {

namespace {

// Six significant digits past the point, trailing zeros dropped: "12.5", "0.000125".
std::string number(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", value + 0.0);
  std::string s = text;
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  if (s == "-0") s = "0";
  return s;
}

// A limit written to the INI, rounded towards the bound's inside: speeds and accelerations and
// the axes' max rounded down, the axes' min up.
std::string number_down(double value) {
  return number(std::floor(value * 1e6) / 1e6);
}
std::string number_up(double value) {
  return number(std::ceil(value * 1e6) / 1e6);
}

char axis_letter(int axis) {
  return "XYZABC"[axis];
}

// Pose coordinate (mm, rad) in the machine file's units (length unit, deg).
double axis_in_file(const machine::Machine& machine, int axis, double value) {
  return machine.axis_to_file(axis, value);
}

// The coordinates LinuxCNC moves: those the model controls, and Z always (a plotter's Z is the
// pen's channel, or ignored, but G-code programs write it).
geometry::Dof moved_axes(const machine::Machine& machine) {
  return machine.kinematics().dof().with(2);
}

struct Header {
  std::string text;
  void line(const std::string& s) { text += s.empty() ? "#\n" : "# " + s + "\n"; }
};

std::string units_name(const machine::Machine& machine) {
  return machine.units() == machine::LengthUnit::inch ? "inch" : "mm";
}

// The rate (velocity or acceleration) of an axis in the INI's units (length unit or deg per s).
double rate_in_file(const machine::Machine& machine, int axis, double internal) {
  return axis < 3 ? internal / machine.mm_per_unit() : geometry::radians_to_degrees(internal);
}

std::string joint_name(const machine::Machine& machine, int joint) {
  return "joint " + std::to_string(joint) + " '" +
         machine.joints()[static_cast<std::size_t>(joint)].name + "'";
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value + 0.0);
  return text;
}

// The speed pkm plan allows a move along `axis` at the worst cell centre the bound met: the
// joints' rates there are the largest sampled.
double plan_speed_at_worst(const machine::Machine& machine, const bounds::JointRateBound& bound,
                           int axis) {
  double speed = machine.cartesian().max_feed_mm_per_s();
  for (int i = 0; i < bound.sampled_slope.rows(); ++i) {
    const double rate = bound.sampled_slope(i, axis);
    const double max_velocity = 0.99 * machine.joints()[static_cast<std::size_t>(i)].max_velocity;
    if (rate > 0.0) speed = std::min(speed, max_velocity / rate);
  }
  return speed;
}

std::vector<std::string> cost_lines(const machine::Machine& machine, const LinuxcncConfig& config) {
  std::vector<std::string> lines;
  const double unit = machine.mm_per_unit();
  const std::string u = machine.length_unit();
  const double max_feed = machine.cartesian().max_feed_mm_per_s();
  const double max_acceleration = machine.cartesian().max_acceleration_mm_per_s2;
  for (const int axis : config.moved.axes()) {
    const std::string name(1, axis_letter(axis));
    const int limiting = config.limits.velocity_limiting[static_cast<std::size_t>(axis)];
    const std::string by = limiting >= 0 ? "set by " + joint_name(machine, limiting)
                                         : (axis < 3 ? "the machine's own" : "no joint");
    const double v = config.limits.velocity[axis], a = config.limits.acceleration[axis];
    if (axis >= 3) {
      lines.push_back(name + ": " + fixed(rate_in_file(machine, axis, v), 2) + " deg/s, " +
                      fixed(rate_in_file(machine, axis, a), 1) + " deg/s^2 (" + by + ")");
      continue;
    }
    std::string line = name + ": " + fixed(v * 60.0 / unit, 1) + " " + u +
                       "/min = " + fixed(100.0 * v / max_feed, 1) + " % of max_feed " +
                       fixed(max_feed * 60.0 / unit, 0) + " (" + by + "); " + fixed(a / unit, 1) +
                       " " + u + "/s^2 = " + fixed(100.0 * a / max_acceleration, 1) +
                       " % of max_acceleration";
    if (machine.kinematics().dof().controls(axis)) {
      line += "; pkm plan, a move along " + name + ": " +
              fixed(plan_speed_along(machine, machine.home(), axis) * 60.0 / unit, 0) +
              " at home, " +
              fixed(plan_speed_at_worst(machine, config.bound, axis) * 60.0 / unit, 0) + " " + u +
              "/min where the joints' velocities alone allow least (sampled)";
    }
    lines.push_back(line);
  }
  return lines;
}

void bound_comments(Header& h, const LinuxcncConfig& config) {
  const bounds::JointRateBound& b = config.bound;
  h.line("Speeds and accelerations. LinuxCNC's planner holds each [AXIS_x] limit per axis but");
  h.line("not the joints' limits (LinuxCNC issue #97), so the [AXIS_x] and [TRAJ] limits below");
  h.line("are chosen so that no joint passes its MAX_VELOCITY or MAX_ACCELERATION anywhere in the");
  h.line("work envelope: |dq_i/dt| <= sum_j max|J_ij| v_j and |d2q_i/dt2| <= sum_j max|J_ij| a_j");
  h.line("+ max|H_i| |v|^2, with max|J_ij| and max|H_i| over the envelope " +
         std::string(b.proven ? "BOUNDED (cells, each" : "SAMPLED ONLY (this model has no"));
  h.line(b.proven ? "from its centre plus a Hessian bound times its radius; docs/linuxcnc.md)."
                  : "Hessian bound: a grid of the envelope, NOT a proof; docs/linuxcnc.md).");
  h.line("Cells: " + std::to_string(b.cells) +
         ", proven outside the joint limits: " + std::to_string(b.excluded) +
         ", left unbounded at the edge of reach: " + number(100.0 * b.uncovered) +
         " % of the volume; " + number(config.bound_seconds) + " s.");
  if (config.shrink < 1.0) {
    h.line("The axis limits are the work envelope shrunk about home to " +
           number(100.0 * config.shrink) + " %: beyond, a joint moves more than " +
           number(bounds::kMaxSlopeGrowth) + " times as fast per unit of");
    h.line("tool motion as at home (the edge of reach), or the bound is not finite.");
  }
  h.line("What it costs (exported vs the machine file's [cartesian] limits, and vs the feed");
  h.line("pkm plan allows per move, which follows each move's own joint rates):");
  for (const std::string& line : config.cost) h.line("  " + line);
}

std::string traj_section(const machine::Machine& machine, const LinuxcncConfig& config) {
  const double unit = machine.mm_per_unit();
  std::string letters;
  for (const int axis : config.moved.axes()) {
    letters += std::string(letters.empty() ? "" : " ") + axis_letter(axis);
  }
  const double v = config.limits.linear_velocity / unit;
  const double a = config.limits.linear_acceleration / unit;
  std::string s = "[TRAJ]\nCOORDINATES = " + letters + "\nLINEAR_UNITS = " + units_name(machine) +
                  "\nANGULAR_UNITS = degree\n";
  // The forward kinematics' seed once every joint is homed: the machine's home pose (x y z a b c).
  const geometry::Vector6d home = machine.home().as_vector();
  s += "HOME =";
  for (int axis = 0; axis < geometry::kPoseSize; ++axis)
    s += " " + number(axis_in_file(machine, axis, home[axis]));
  s += "\n";
  s += "DEFAULT_LINEAR_VELOCITY = " + number_down(v) + "\nMAX_LINEAR_VELOCITY = " + number_down(v) +
       "\nDEFAULT_LINEAR_ACCELERATION = " + number_down(a) +
       "\nMAX_LINEAR_ACCELERATION = " + number_down(a) + "\n";
  double angular = 0.0;
  bool any_angle = false;
  for (const int axis : config.moved.axes()) {
    if (axis < 3) continue;
    const double w = rate_in_file(machine, axis, config.limits.velocity[axis]);
    angular = any_angle ? std::min(angular, w) : w;
    any_angle = true;
  }
  if (any_angle) {
    s += "DEFAULT_ANGULAR_VELOCITY = " + number_down(angular) +
         "\nMAX_ANGULAR_VELOCITY = " + number_down(angular) + "\n";
  }
  return s + "NO_FORCE_HOMING = 0\n\n";
}

// Z on a machine that does not control it: the pen's channel (or ignored), limits wide enough for
// any job's pen heights.
constexpr double kFreeZRangeMm = 100.0;

std::string axis_sections(const machine::Machine& machine, const LinuxcncConfig& config) {
  std::string s;
  for (const int axis : config.moved.axes()) {
    const bool controlled = machine.kinematics().dof().controls(axis);
    const double low = controlled ? axis_in_file(machine, axis, config.envelope.box.min[axis])
                                  : -kFreeZRangeMm / machine.mm_per_unit();
    const double high = controlled ? axis_in_file(machine, axis, config.envelope.box.max[axis])
                                   : kFreeZRangeMm / machine.mm_per_unit();
    s += "[AXIS_" + std::string(1, axis_letter(axis)) + "]\n";
    if (!controlled) {
      s += machine.tool().z == machine::ToolZ::pen
               ? "# Z moves no joint: it is the pen's channel (pen-up in the HAL files)\n"
               : "# Z moves no joint: the machine ignores it\n";
    } else {
      const std::string from = config.envelope.from_file.controls(axis)
                                   ? "[cartesian] min/max"
                                   : "the reachable extent along lines through home";
      s += config.shrink < 1.0
               ? "# limits: " + from + " (" +
                     number(axis_in_file(machine, axis, config.requested.box.min[axis])) + " .. " +
                     number(axis_in_file(machine, axis, config.requested.box.max[axis])) +
                     "), shrunk about home to " + number(100.0 * config.shrink) +
                     " % (see the header)\n"
               : "# limits: " + from + "\n";
    }
    s += "MIN_LIMIT = " + number_up(low) + "\nMAX_LIMIT = " + number_down(high) + "\n";
    s +=
        "MAX_VELOCITY = " + number_down(rate_in_file(machine, axis, config.limits.velocity[axis])) +
        "\nMAX_ACCELERATION = " +
        number_down(rate_in_file(machine, axis, config.limits.acceleration[axis])) + "\n\n";
  }
  return s;
}

std::string joint_sections(const machine::Machine& machine,
                           const kinematics::JointVector& home_joints, bool sim) {
  std::string s;
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const machine::JointSpec& joint = machine.joints()[static_cast<std::size_t>(i)];
    const auto file = [&](double v) { return number(machine.joint_to_file(i, v)); };
    const double home = machine.joint_to_file(i, home_joints[i]);
    s += "[JOINT_" + std::to_string(i) + "]\n# " + joint.name + " (" + machine.joint_file_unit(i) +
         "); HOME: the joint at the machine's home pose\n";
    s += std::string("TYPE = ") +
         (joint.kind == kinematics::JointKind::rotary ? "ANGULAR" : "LINEAR") + "\n";
    s += "MIN_LIMIT = " + file(joint.min) + "\nMAX_LIMIT = " + file(joint.max) + "\n";
    s += "MAX_VELOCITY = " + file(joint.max_velocity) +
         "\nMAX_ACCELERATION = " + file(joint.max_acceleration) + "\n";
    // Following errors: 1 mm (or 1 deg) at full speed, a quarter of it at rest.
    const double ferror =
        joint.kind == kinematics::JointKind::rotary ? 1.0 : 1.0 / machine.mm_per_unit();
    s += "FERROR = " + number(ferror) + "\nMIN_FERROR = " + number(0.25 * ferror) + "\n";
    if (!sim) {
      s += "# Homing: with HOME_SEARCH_VEL 0 the joint takes HOME_OFFSET where it stands when you\n"
           "# home: stand the machine at its home pose first. With home switches, set\n"
           "# HOME_SEARCH_VEL, HOME_LATCH_VEL and HOME_OFFSET (the switch's joint value).\n";
    }
    s += "HOME = " + number(home) + "\nHOME_OFFSET = " + number(home) +
         "\nHOME_SEARCH_VEL = 0\nHOME_LATCH_VEL = 0\nHOME_USE_INDEX = NO\nHOME_SEQUENCE = 0\n\n";
  }
  return s;
}

std::string ini_text(const machine::Machine& machine, const LinuxcncConfig& config,
                     const ExportOptions& options, const kinematics::JointVector& home_joints) {
  const std::string stem = std::filesystem::path(options.machine_file_name).stem().string();
  Header h;
  h.line(config.ini_name + ": LinuxCNC 2.9 configuration of \"" + machine.name() + "\",");
  h.line("written by pkm export linuxcnc" + std::string(options.sim ? " --sim" : "") + " from " +
         options.machine_file_name + " (copied beside this file).");
  h.line("Kinematics: pkmkins, the machine file's own model (docs/linuxcnc.md).");
  h.line("");
  bound_comments(h, config);
  std::string s =
      h.text + "\n[EMC]\nVERSION = 1.1\nMACHINE = " + machine.name() + "\nDEBUG = 0\n\n";
  s += "[DISPLAY]\nDISPLAY = axis\nPOSITION_OFFSET = RELATIVE\nPOSITION_FEEDBACK = ACTUAL\n";
  s += "# feed override above 100 % would not pass the bound (the planner clips at MAX_VELOCITY)\n";
  s += "MAX_FEED_OVERRIDE = 1.0\nMAX_LINEAR_VELOCITY = " +
       number_down(config.limits.linear_velocity / machine.mm_per_unit()) +
       "\nPROGRAM_PREFIX = .\nCYCLE_TIME = 0.100\n\n";
  s += "[TASK]\nTASK = milltask\nCYCLE_TIME = 0.010\n\n";
  s += "[RS274NGC]\nPARAMETER_FILE = " + stem + ".var\n\n";
  s += "[EMCMOT]\nEMCMOT = motmod\nCOMM_TIMEOUT = 1.0\nSERVO_PERIOD = 1000000\n\n";
  s += "[EMCIO]\nEMCIO = io\nCYCLE_TIME = 0.100\nTOOL_TABLE = " + stem + ".tbl\n\n";
  s += "[HAL]\nHALFILE = " + stem +
       ".hal\nHALFILE = " + std::string(options.sim ? "sim.hal" : "hardware.hal") + "\n\n";
  s += "[KINS]\nKINEMATICS = pkmkins machine=" + options.machine_file_name +
       "\nPKM_MACHINE = " + options.machine_file_name + "\n# The SHA-256 of " +
       options.machine_file_name +
       " as exported: the limits here are made from it, so pkmkins\n# refuses the file once it "
       "differs (export again)\n" +
       std::string(kMachineFingerprintKey) + " = " + sha256_hex(options.machine_text) +
       "\nJOINTS = " + std::to_string(machine.joints().size()) + "\n\n";
  s += traj_section(machine, config) + axis_sections(machine, config) +
       joint_sections(machine, home_joints, options.sim);
  return s;
}

// comp's out is true while in1 > in0: the commanded Z above down_below, or below down_above.
std::string pen_hal(const machine::Machine& machine) {
  const machine::ToolChannel& tool = machine.tool();
  if (tool.z != machine::ToolZ::pen) return "";
  const std::string height = number(tool.pen_height_mm / machine.mm_per_unit());
  const std::string z = "axis.z.pos-cmd";
  return std::string("\n# The pen: up while the commanded Z is ") +
         (tool.down_above ? "below" : "above") + " the machine file's [tool] " + tool.height_key() +
         "\nloadrt comp names=pen-up\naddf pen-up servo-thread\n" +
         (tool.down_above ? "setp pen-up.in1 " + height + "\nnet pen-z " + z + " => pen-up.in0\n"
                          : "setp pen-up.in0 " + height + "\nnet pen-z " + z + " => pen-up.in1\n") +
         "net pen-up pen-up.out\n";
}

std::string main_hal(const machine::Machine& machine, const std::string& name) {
  return "# " + name +
         ": motion, the pkmkins kinematics and the servo thread (pkm export linuxcnc)\n"
         "loadrt [KINS]KINEMATICS\n"
         "loadrt [EMCMOT]EMCMOT servo_period_nsec=[EMCMOT]SERVO_PERIOD "
         "num_joints=[KINS]JOINTS\n"
         "addf motion-command-handler servo-thread\naddf motion-controller servo-thread\n"
         "\n# No tool changer: every tool change is done at once\n"
         "net tool-prepare-loop iocontrol.0.tool-prepare => iocontrol.0.tool-prepared\n"
         "net tool-change-loop iocontrol.0.tool-change => iocontrol.0.tool-changed\n" +
         pen_hal(machine);
}

std::string sim_hal(const machine::Machine& machine) {
  std::string s =
      "# sim.hal: no hardware. Each joint's command is its feedback; E-stop always released.\n"
      "# The joints read 0 until homed; homing (HOME_SEARCH_VEL 0, all at once) sets each to its\n"
      "# HOME_OFFSET, the joint at the machine's home pose, without a move. LinuxCNC runs the\n"
      "# forward kinematics only once every joint is homed, seeded with [TRAJ] HOME.\n"
      "net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in\n";
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const std::string j = std::to_string(i);
    s += "net j" + j + "-pos joint." + j + ".motor-pos-cmd => joint." + j + ".motor-pos-fb\n";
  }
  return s;
}

std::string hardware_hal(const machine::Machine& machine) {
  std::string s =
      "# hardware.hal: WIRE YOUR MACHINE HERE. Every line marked WIRE names a signal with one\n"
      "# end only: connect the other end to your drives' pins (a step generator such as\n"
      "# stepgen, a Mesa card's hm2 pins, a servo amplifier). Until then nothing moves and the\n"
      "# feedback stays at 0: LinuxCNC reports a following error on the first move.\n"
      "# WIRE: replace this line by your E-stop chain (it releases E-stop unconditionally).\n"
      "net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in\n";
  for (int i = 0; i < static_cast<int>(machine.joints().size()); ++i) {
    const std::string j = "joint." + std::to_string(i);
    const std::string n = "j" + std::to_string(i);
    s += "\n# " + joint_name(machine, i) + " (" + machine.joint_file_unit(i) + ")\n";
    s += "net " + n + "-pos-cmd " + j + ".motor-pos-cmd  # WIRE: to the drive's position command\n";
    s += "net " + n + "-pos-fb " + j + ".motor-pos-fb  # WIRE: from its position feedback\n";
    s += "net " + n + "-enable " + j + ".amp-enable-out  # WIRE: to the drive's enable\n";
    s += "net " + n + "-home-sw " + j + ".home-sw-in  # WIRE: from the home switch, if any\n";
  }
  if (machine.tool().z == machine::ToolZ::pen) {
    s += "\n# WIRE: pen-up (bit, true while the pen is up) to the pen's servo or solenoid output\n";
  }
  return s;
}

}  // namespace

LinuxcncConfig make_linuxcnc_config(const machine::Machine& machine, const ExportOptions& options) {
  LinuxcncConfig config;
  const std::string stem = std::filesystem::path(options.machine_file_name).stem().string();
  config.ini_name = stem + ".ini";
  config.moved = moved_axes(machine);
  kinematics::JointVector home_joints;
  if (const kinematics::Status status = machine.inverse(machine.home(), home_joints);
      !status.ok()) {
    throw std::runtime_error("the machine's home is not a pose it can take: " +
                             machine.explain(machine.home(), status));
  }
  config.requested = bounds::work_envelope(machine);
  const auto start = std::chrono::steady_clock::now();
  bounds::FittedEnvelope fitted =
      bounds::fit_envelope(machine, config.requested, options.bound_options);
  config.envelope = fitted.box;
  config.shrink = fitted.shrink;
  config.bound = std::move(fitted.bound);
  config.bound_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  config.limits = axis_rate_limits(machine, config.bound, config.moved);
  config.cost = cost_lines(machine, config);
  config.files.push_back({config.ini_name, ini_text(machine, config, options, home_joints)});
  config.files.push_back({stem + ".hal", main_hal(machine, stem + ".hal")});
  // hardware.hal is where the user wires the machine: kept when there is one.
  config.files.push_back(options.sim ? ConfigFile{"sim.hal", sim_hal(machine), false}
                                     : ConfigFile{"hardware.hal", hardware_hal(machine), true});
  config.files.push_back({options.machine_file_name, options.machine_text});
  config.files.push_back({stem + ".tbl", "T1 P1 D0 Z0 ;no tool length\n", true});
  config.files.push_back({stem + ".var", "5220\t1.000000\n", true});
  return config;
}

namespace {

bool is_empty_directory(const std::filesystem::path& directory) {
  return std::filesystem::is_directory(directory) &&
         std::filesystem::directory_iterator(directory) == std::filesystem::directory_iterator();
}

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path,
                       const std::error_code& error) {
  throw std::runtime_error("cannot " + what + " " + path.string() + ": " + error.message());
}

}  // namespace

KeptFiles write_config_directory(const std::filesystem::path& directory,
                                 const LinuxcncConfig& config, bool force) {
  return write_config_directory(directory, config.files, force);
}

namespace {

// Writes `file` under `directory`, making the directories its name has; each made is added to
// `tree` when there is one (a staging directory), so that a signal removes it with its files.
// Each is listed before it is made: a signal between the two would leave the tree non-empty, and
// so in place.
void write_config_file(const std::filesystem::path& directory, const ConfigFile& file,
                       files::TemporaryTree* tree) {
  const std::filesystem::path path = directory / file.name;
  std::vector<std::filesystem::path> made;
  for (std::filesystem::path parent = path.parent_path();
       parent != directory && !std::filesystem::exists(parent); parent = parent.parent_path()) {
    made.push_back(parent);
  }
  if (tree) {
    for (auto it = made.rbegin(); it != made.rend(); ++it) tree->add_directory(*it);
  }
  std::error_code error;
  std::filesystem::create_directories(path.parent_path(), error);
  if (error) fail("create the directory", path.parent_path(), error);
  if (tree) tree->add_file(path);
  files::write_file_atomically(path, file.text);
}

std::filesystem::path staging_path(const std::filesystem::path& target) {
  return target.parent_path() /
         ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
}

[[noreturn]] void refuse_replacing(const std::filesystem::path& directory, const std::string& name,
                                   const std::string& why) {
  throw std::runtime_error("cannot replace the configuration in " + directory.string() + ": its " +
                           name + " " + why + "; move it away and export again");
}

// A file of the old configuration in the new one as it is: a hard link (the same file), else a
// copy.
void carry_file(const std::filesystem::directory_entry& entry, const std::filesystem::path& to) {
  std::error_code error;
  if (entry.is_symlink(error)) {
    std::filesystem::copy_symlink(entry.path(), to, error);
  } else {
    std::filesystem::create_hard_link(entry.path(), to, error);
    if (error) std::filesystem::copy_file(entry.path(), to, error);
  }
  if (error) fail("carry over", entry.path(), error);
}

// A configuration directory holds a few dozen files; more, and `-o` names something else (a home
// directory) that --force should not rebuild.
constexpr std::size_t kMaxCarriedFiles = 10000;

// Carries what the old configuration directory `from` holds and the new one `to` does not (the
// user's files and directories, and the state files kept) into `to`, listing each in `tree`.
// `relative`: `from` within the old directory ("" at its top).
void carry_over(const std::filesystem::path& old_root, const std::filesystem::path& from,
                const std::filesystem::path& to, const std::filesystem::path& relative,
                files::TemporaryTree& tree, KeptFiles& kept) {
  namespace fs = std::filesystem;
  for (const fs::directory_entry& entry : fs::directory_iterator(from)) {
    const fs::path target = to / entry.path().filename();
    const std::string name = (relative / entry.path().filename()).generic_string();
    std::error_code error;
    const fs::file_status there = fs::symlink_status(target, error);
    const bool is_directory = entry.is_directory(error) && !entry.is_symlink(error);
    if (is_directory) {
      if (fs::exists(there) && !fs::is_directory(there))
        refuse_replacing(old_root, name, "is a directory where the configuration writes a file");
      if (!fs::exists(there)) {
        tree.add_directory(target);  // listed first, as write_config_file's
        if (!fs::create_directory(target, entry.path(), error) && error)
          fail("create the directory", target, error);
      }
      carry_over(old_root, entry.path(), target, relative / entry.path().filename(), tree, kept);
      continue;
    }
    if (fs::is_directory(there))
      refuse_replacing(old_root, name, "is a file where the configuration writes a directory");
    if (fs::exists(there)) continue;  // replaced by the new configuration's
    if (!entry.is_regular_file(error) && !entry.is_symlink(error))
      refuse_replacing(old_root, name, "is not a regular file, a link or a directory");
    const auto& state = kept.state;
    const bool own = std::find(state.begin(), state.end(), name) == state.end();
    if (own && kept.others.size() == kMaxCarriedFiles) {
      throw std::runtime_error(
          "cannot replace the configuration in " + old_root.string() + ": it holds more than " +
          std::to_string(kMaxCarriedFiles) +
          " files the export does not write (is it a LinuxCNC configuration?); give another "
          "directory");
    }
    tree.add_file(target);  // listed first, as write_config_file's
    carry_file(entry, target);
    if (own) kept.others.push_back(name);
  }
}

// `force` over an existing, non-empty directory: the new one built beside it, then swapped in.
KeptFiles replace_config_directory(const std::filesystem::path& directory,
                                   const std::vector<ConfigFile>& files) {
  namespace fs = std::filesystem;
  std::error_code error;
  // Through a link to a configuration directory, the directory it names is replaced.
  const fs::path old_root = fs::canonical(directory, error);
  if (error) fail("resolve", directory, error);
  const fs::path here = fs::current_path(error);
  if (!error && std::mismatch(old_root.begin(), old_root.end(), here.begin(), here.end()).first ==
                    old_root.end()) {
    throw std::runtime_error(directory.string() +
                             " is the current directory (or holds it): --force replaces it as a "
                             "whole, which would leave this shell in the removed one; run it from "
                             "outside, e.g. from " +
                             old_root.parent_path().string());
  }
  files::TemporaryTree staging(staging_path(old_root));
  fs::permissions(staging.root(), fs::status(old_root).permissions(), error);
  KeptFiles kept;
  for (const ConfigFile& file : files) {
    if (file.keep_existing && fs::is_regular_file(old_root / file.name, error)) {
      kept.state.push_back(file.name);
      continue;
    }
    write_config_file(staging.root(), file, &staging);
  }
  carry_over(old_root, old_root, staging.root(), "", staging, kept);
  staging.replace(old_root);
  return kept;
}

}  // namespace

KeptFiles write_config_directory(const std::filesystem::path& directory,
                                 const std::vector<ConfigFile>& files, bool force) {
  namespace fs = std::filesystem;
  std::error_code error;
  const bool exists = fs::exists(directory, error);
  if (exists && !fs::is_directory(directory)) {
    throw std::runtime_error(directory.string() + " exists and is not a directory");
  }
  if (exists && !is_empty_directory(directory)) {
    if (!force) {
      throw std::runtime_error(directory.string() +
                               " exists and is not empty: give another directory, or --force "
                               "to replace the configuration in it");
    }
    return replace_config_directory(directory, files);
  }
  const fs::path target = directory.has_filename() ? directory : directory.parent_path();
  if (!target.parent_path().empty() && !fs::exists(target.parent_path())) {
    fs::create_directories(target.parent_path(), error);  // as mkdir -p
    if (error) fail("create the directory", target.parent_path(), error);
  }
  files::TemporaryTree staging(staging_path(target));
  for (const ConfigFile& file : files) write_config_file(staging.root(), file, &staging);
  staging.commit_to(target);
  return {};
}

}  // namespace pkm::linuxcnc
