// The pkmkins LinuxCNC kinematics module without LinuxCNC: a machine file's kinematics answering
// LinuxCNC's kinematicsInverse / kinematicsForward / kinematicsHome in LinuxCNC's units (the
// world length unit of [TRAJ] LINEAR_UNITS, mm or inch, and degrees), forward seeded with the
// previous pose, the counters the module shows on HAL pins, where the machine file is found and
// what in LinuxCNC's INI may contradict it. It includes no LinuxCNC header
// (apps/pkmkins/pkmkins.cpp is the thin RTAPI/HAL shim), so it is unit-tested without LinuxCNC.
//
// Nothing here allocates after construction: inverse, forward, home and the failure message run
// in LinuxCNC's servo thread.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "pkm/linuxcnc/ini_file.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::linuxcnc {

// LinuxCNC's EmcPose, field for field, without its header: x y z in the world length unit, a b c
// in degrees, u v w (unused by pkmkit's machines, left as given).
struct WorldPose {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  double a = 0.0;
  double b = 0.0;
  double c = 0.0;
  double u = 0.0;
  double v = 0.0;
  double w = 0.0;
};
static_assert(sizeof(WorldPose) == 9 * sizeof(double), "WorldPose must stay EmcPose's layout");

// "mm" or "inch" (LinuxCNC's LINEAR_UNITS also says "in"); nullopt for anything else.
std::optional<machine::LengthUnit> parse_world_unit(std::string_view text);

// What the module shows on its HAL pins (genhexkins' pins, plus the inverse's).
struct KinsCounters {
  int fk_status = 0;         // last forward: its StatusCode (0 ok)
  int fk_iterations = 0;     // Newton iterations of the last forward (0: closed form)
  unsigned fk_failures = 0;  // forward calls that failed, since load
  unsigned ik_failures = 0;  // inverse calls that failed, since load
  int ik_failed_joint = -1;  // joint (0-based, LinuxCNC's numbering) of the last failed
                             // inverse; -1 when it named none; back to -1 on success
  int ik_status = 0;         // last inverse: its StatusCode (0 ok)
};

// The machine file a KinsAdapter was loaded from, for checking it against the INI.
struct MachineFileSource {
  std::string path;
  std::string sha256;  // of its bytes (machine_fingerprint.hpp)
};

class KinsAdapter {
 public:
  // world_unit: LinuxCNC's length unit; the machine file's own when not given. `source`: where
  // the machine came from (empty when it was not read from a file).
  KinsAdapter(machine::Machine machine, std::optional<machine::LengthUnit> world_unit,
              MachineFileSource source = {});

  const machine::Machine& machine() const { return machine_; }
  int joint_count() const { return joint_count_; }
  machine::LengthUnit world_unit() const { return world_unit_; }
  const KinsCounters& counters() const { return counters_; }
  const MachineFileSource& source() const { return source_; }

  // Pose <-> world: mm and rad inside, the world unit and degrees at LinuxCNC's side.
  geometry::Pose to_pose(const WorldPose& world) const;
  // Writes x..c; u v w are left as they are in `world`.
  void to_world(const geometry::Pose& pose, WorldPose& world) const;
  // Joint n: mm or rad inside; the world unit (linear) or degrees (rotary) at LinuxCNC's side.
  double joint_to_world(int joint, double internal) const;
  double joint_from_world(int joint, double value) const;

  // IK with the machine file's joint limits and work envelope. Writes joint_count() values to
  // `joints` on success and leaves them untouched on failure (so LinuxCNC keeps the last good
  // ones); records the failure for failure_message().
  kinematics::Status inverse(const WorldPose& world, double* joints);
  // FK of joint_count() values, seeded with `world_inout` (LinuxCNC passes the previous pose),
  // or the last pose forward found when that is not finite; the machine falls back to its home
  // pose when the seed leads astray. Coordinates the machine does not control are left as
  // seeded. On failure `world_inout` is left as it was.
  kinematics::Status forward(const double* joints, WorldPose& world_inout);
  // The machine file's home pose and its joints.
  void home(WorldPose& world, double* joints) const;

  // The last failed inverse as a sentence for LinuxCNC's error channel, e.g. "pkmkins: inverse
  // kinematics refused x 1.0000 y 2.0000 z 30.0000 in a 0.0000 b 0.0000 c 0.0000 deg: joint 3
  // 'leg3' = 36.2100 in passes its max 36.0000 in". Written into `buffer` (no allocation);
  // returns it.
  const char* failure_message(char* buffer, std::size_t size) const;
  // Whether the inverse failure just recorded should be printed: the first of a run of failures,
  // then every `kReportEvery`-th while they go on, so that a servo thread failing every cycle
  // does not flood the log.
  bool should_report_failure() const;
  static constexpr unsigned kReportEvery = 1000;

 private:
  machine::Machine machine_;
  MachineFileSource source_;
  machine::LengthUnit world_unit_;
  double mm_per_world_unit_;
  int joint_count_;
  geometry::Pose last_forward_;
  kinematics::ForwardTrack
      forward_track_;  // LinuxCNC calls forward once a servo period along the path
  // The last failed inverse: the pose, its status, the joint values IK found (when it got that
  // far: a joint limit), and how many failures in a row it ends.
  geometry::Pose failed_pose_;
  kinematics::Status failed_status_;
  kinematics::JointVector failed_joints_;
  unsigned failures_in_a_row_ = 0;
  KinsCounters counters_;
};

// Loads the machine file; throws MachineFileError (file:line:key) when it does not load.
KinsAdapter load_kins(const std::filesystem::path& machine_file,
                      std::optional<machine::LengthUnit> world_unit);

// What in LinuxCNC's INI file contradicts the module as loaded: a machine file changed since
// `pkm export linuxcnc` wrote the INI ([KINS] PKM_MACHINE_SHA256, machine_fingerprint.hpp),
// [KINS] JOINTS other than the machine file's number of joints, [TRAJ] LINEAR_UNITS other than
// the world unit (the first of a repeated key, as LinuxCNC reads it). "file:line: " and a sentence
// naming both and the fix, or "" when they agree (or the INI does not say).
std::string ini_mismatch(const KinsAdapter& kins, const IniFile& ini);

// Where the module finds its machine file: `name` as given when absolute, else relative to the
// INI file's directory (`ini_file_name`, LinuxCNC's INI_FILE_NAME, when set), else to `cwd` (the
// linuxcnc script starts in the INI's directory).
std::filesystem::path resolve_machine_file(std::string_view name, const char* ini_file_name,
                                           const std::filesystem::path& cwd);

}  // namespace pkm::linuxcnc
