#include "pkm/linuxcnc/kins_adapter.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "pkm/linuxcnc/machine_fingerprint.hpp"
#include "pkm/text/text_file.hpp"

namespace pkm::linuxcnc {

namespace {

// A value as printed with `decimals` decimals, without the "-0.000" of a hair below zero.
double shown(double value, int decimals) {
  return std::abs(value) < 0.5 * std::pow(10.0, -decimals) ? 0.0 : value;
}

// StatusCode::ok is 0: the pins show the code itself.
int status_number(const kinematics::Status& status) {
  return static_cast<int>(status.code);
}

// Appends printf-style text at `used` within `size`, never past it (no allocation).
void append(char* buffer, std::size_t size, std::size_t& used, const char* format, ...)
    __attribute__((format(printf, 4, 5)));
void append(char* buffer, std::size_t size, std::size_t& used, const char* format, ...) {
  if (used >= size) return;
  va_list arguments;
  va_start(arguments, format);
  const int written = std::vsnprintf(buffer + used, size - used, format, arguments);
  va_end(arguments);
  if (written > 0) used += static_cast<std::size_t>(written);
  if (used >= size) used = size - 1;
}

}  // namespace

std::optional<machine::LengthUnit> parse_world_unit(std::string_view text) {
  if (text == "mm" || text == "metric") return machine::LengthUnit::mm;
  if (text == "inch" || text == "in" || text == "imperial") return machine::LengthUnit::inch;
  return std::nullopt;
}

KinsAdapter::KinsAdapter(machine::Machine machine, std::optional<machine::LengthUnit> world_unit,
                         MachineFileSource source)
    : machine_(std::move(machine)),
      source_(std::move(source)),
      world_unit_(world_unit.value_or(machine_.units())),
      mm_per_world_unit_(world_unit_ == machine::LengthUnit::inch ? 25.4 : 1.0),
      joint_count_(static_cast<int>(machine_.joints().size())),
      last_forward_(machine_.home()),
      failed_joints_(joint_count_) {}

geometry::Pose KinsAdapter::to_pose(const WorldPose& world) const {
  geometry::Pose pose;
  pose.position_mm = Eigen::Vector3d(world.x, world.y, world.z) * mm_per_world_unit_;
  pose.orientation_rad =
      Eigen::Vector3d(geometry::degrees_to_radians(world.a), geometry::degrees_to_radians(world.b),
                      geometry::degrees_to_radians(world.c));
  return pose;
}

void KinsAdapter::to_world(const geometry::Pose& pose, WorldPose& world) const {
  world.x = pose.position_mm.x() / mm_per_world_unit_;
  world.y = pose.position_mm.y() / mm_per_world_unit_;
  world.z = pose.position_mm.z() / mm_per_world_unit_;
  world.a = geometry::radians_to_degrees(pose.orientation_rad.x());
  world.b = geometry::radians_to_degrees(pose.orientation_rad.y());
  world.c = geometry::radians_to_degrees(pose.orientation_rad.z());
}

double KinsAdapter::joint_to_world(int joint, double internal) const {
  return machine_.joints()[static_cast<std::size_t>(joint)].kind == kinematics::JointKind::rotary
             ? geometry::radians_to_degrees(internal)
             : internal / mm_per_world_unit_;
}

double KinsAdapter::joint_from_world(int joint, double value) const {
  return machine_.joints()[static_cast<std::size_t>(joint)].kind == kinematics::JointKind::rotary
             ? geometry::degrees_to_radians(value)
             : value * mm_per_world_unit_;
}

kinematics::Status KinsAdapter::inverse(const WorldPose& world, double* joints) {
  const geometry::Pose pose = to_pose(world);
  kinematics::JointVector solved(joint_count_);
  const kinematics::Status status = machine_.inverse(pose, solved);
  counters_.ik_status = status_number(status);
  if (!status.ok()) {
    ++counters_.ik_failures;
    ++failures_in_a_row_;
    counters_.ik_failed_joint = status.joint;
    failed_pose_ = pose;
    failed_status_ = status;
    failed_joints_ = solved;
    return status;
  }
  failures_in_a_row_ = 0;
  counters_.ik_failed_joint = -1;
  for (int i = 0; i < joint_count_; ++i) joints[i] = joint_to_world(i, solved[i]);
  return status;
}

kinematics::Status KinsAdapter::forward(const double* joints, WorldPose& world_inout) {
  kinematics::JointVector internal(joint_count_);
  for (int i = 0; i < joint_count_; ++i) internal[i] = joint_from_world(i, joints[i]);
  geometry::Pose pose = to_pose(world_inout);
  const bool seeded = kinematics::all_finite(pose);
  if (!seeded) pose = last_forward_;
  const kinematics::Status status = machine_.forward(internal, pose, forward_track_);
  counters_.fk_status = status_number(status);
  counters_.fk_iterations = status.iterations;
  if (!status.ok()) {
    ++counters_.fk_failures;
    return status;
  }
  last_forward_ = pose;
  WorldPose solved = world_inout;
  to_world(pose, solved);
  // LinuxCNC's own values of the coordinates the machine does not control stay bit for bit (a
  // trip through mm and rad would change their last digit).
  const geometry::Dof dof = machine_.kinematics().dof();
  double* const out[geometry::kPoseSize] = {&world_inout.x, &world_inout.y, &world_inout.z,
                                            &world_inout.a, &world_inout.b, &world_inout.c};
  const double in[geometry::kPoseSize] = {solved.x, solved.y, solved.z,
                                          solved.a, solved.b, solved.c};
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (dof.controls(axis) || !seeded) *out[axis] = in[axis];
  }
  return status;
}

void KinsAdapter::home(WorldPose& world, double* joints) const {
  to_world(machine_.home(), world);
  kinematics::JointVector solved(joint_count_);
  // The machine file's loader refuses a home pose the machine cannot take: this succeeds.
  machine_.inverse(machine_.home(), solved);
  for (int i = 0; i < joint_count_; ++i) joints[i] = joint_to_world(i, solved[i]);
}

bool KinsAdapter::should_report_failure() const {
  return failures_in_a_row_ == 1 ||
         (failures_in_a_row_ > 0 && failures_in_a_row_ % kReportEvery == 0);
}

const char* KinsAdapter::failure_message(char* buffer, std::size_t size) const {
  if (size == 0) return buffer;
  buffer[0] = '\0';
  std::size_t used = 0;
  const char* unit = world_unit_ == machine::LengthUnit::inch ? "in" : "mm";
  const int decimals = world_unit_ == machine::LengthUnit::inch ? 4 : 3;  // as pkm's explanations
  WorldPose world;
  to_world(failed_pose_, world);
  append(buffer, size, used, "pkmkins: inverse kinematics refused x %.*f y %.*f z %.*f %s",
         decimals, shown(world.x, decimals), decimals, shown(world.y, decimals), decimals,
         shown(world.z, decimals), unit);
  append(buffer, size, used, " a %.3f b %.3f c %.3f deg: ", shown(world.a, 3), shown(world.b, 3),
         shown(world.c, 3));
  const int joint = failed_status_.joint;
  if (joint >= 0 && joint < joint_count_) {
    const machine::JointSpec& spec = machine_.joints()[static_cast<std::size_t>(joint)];
    const char* joint_unit = spec.kind == kinematics::JointKind::rotary ? "deg" : unit;
    append(buffer, size, used, "joint %d '%s' ", joint, spec.name.c_str());
    const double found = failed_joints_[joint];
    if (failed_status_.code == kinematics::StatusCode::joint_limit && std::isfinite(found)) {
      const bool below = found < spec.min;
      append(buffer, size, used, "= %.4f %s passes its %s %.4f %s", joint_to_world(joint, found),
             joint_unit, below ? "min" : "max", joint_to_world(joint, below ? spec.min : spec.max),
             joint_unit);
    } else {
      const std::string_view why = kinematics::status_name(failed_status_.code);
      append(buffer, size, used, "%.*s", static_cast<int>(why.size()), why.data());
    }
  } else if (failed_status_.code == kinematics::StatusCode::outside_envelope &&
             failed_status_.axis >= 0) {
    const int axis = failed_status_.axis;
    const double found = failed_pose_.as_vector()[axis];
    const bool below = found < machine_.cartesian().envelope_min[axis];
    const double limit =
        below ? machine_.cartesian().envelope_min[axis] : machine_.cartesian().envelope_max[axis];
    const double limit_shown =
        axis < 3 ? limit / mm_per_world_unit_ : geometry::radians_to_degrees(limit);
    append(buffer, size, used, "%.*s passes the work envelope's %s %.4f %s",
           static_cast<int>(geometry::kAxisNames[axis].size()), geometry::kAxisNames[axis].data(),
           below ? "min" : "max", limit_shown, axis < 3 ? unit : "deg");
  } else {
    const std::string_view why = kinematics::status_name(failed_status_.code);
    append(buffer, size, used, "%.*s", static_cast<int>(why.size()), why.data());
  }
  if (failures_in_a_row_ > 1) append(buffer, size, used, " (%u in a row)", failures_in_a_row_);
  return buffer;
}

KinsAdapter load_kins(const std::filesystem::path& machine_file,
                      std::optional<machine::LengthUnit> world_unit) {
  std::string text;
  try {
    text = text::read_text_file(machine_file, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw machine::MachineFileError(machine_file.string(), error.what());
  }
  machine::Machine machine = machine::parse_machine(text, machine_file.string());
  return KinsAdapter(std::move(machine), world_unit, {machine_file.string(), sha256_hex(text)});
}

std::string ini_mismatch(const KinsAdapter& kins, const IniFile& ini) {
  const auto located = [](const IniEntry& entry) {
    return entry.where.file + ":" + std::to_string(entry.where.line) + ": ";
  };
  if (!kins.source().sha256.empty()) {
    std::string changed = machine_file_changed(kins.source().path, kins.source().sha256, ini);
    if (!changed.empty()) return changed;
  }
  const char* unit = kins.world_unit() == machine::LengthUnit::inch ? "inch" : "mm";
  if (const IniEntry* joints = ini.find("KINS", "JOINTS");
      joints != nullptr && joints->value != std::to_string(kins.joint_count())) {
    return located(*joints) + "[KINS] JOINTS = " + joints->value + " but the machine file has " +
           std::to_string(kins.joint_count()) +
           " joints: set JOINTS = " + std::to_string(kins.joint_count());
  }
  if (const IniEntry* units = ini.find("TRAJ", "LINEAR_UNITS")) {
    const std::optional<machine::LengthUnit> ini_unit = parse_world_unit(units->value);
    if (ini_unit && *ini_unit != kins.world_unit()) {
      return located(*units) + "[TRAJ] LINEAR_UNITS = " + units->value + " but pkmkins works in " +
             unit + ": add units=" + (*ini_unit == machine::LengthUnit::inch ? "inch" : "mm") +
             " to [KINS] KINEMATICS (the default is the machine file's units)";
    }
  }
  return {};
}

std::filesystem::path resolve_machine_file(std::string_view name, const char* ini_file_name,
                                           const std::filesystem::path& cwd) {
  const std::filesystem::path file(name);
  if (file.is_absolute()) return file;
  if (ini_file_name != nullptr && *ini_file_name != '\0') {
    const std::filesystem::path ini(ini_file_name);
    const std::filesystem::path ini_dir = ini.has_parent_path() ? ini.parent_path() : cwd;
    return (ini_dir.is_absolute() ? ini_dir : cwd / ini_dir) / file;
  }
  return cwd / file;
}

}  // namespace pkm::linuxcnc
