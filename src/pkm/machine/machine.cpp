#include "pkm/machine/machine.hpp"

#include <toml++/toml.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "pkm/kinematics/registry.hpp"
#include "pkm/machine/toml_config.hpp"

namespace pkm {

Machine::Machine(std::string name, std::string source, LengthUnit units,
                 std::unique_ptr<Kinematics> kinematics, std::vector<JointSpec> joints,
                 CartesianLimits cartesian, Pose home)
    : name_(std::move(name)),
      source_(std::move(source)),
      units_(units),
      kinematics_(std::move(kinematics)),
      joints_(std::move(joints)),
      cartesian_(cartesian),
      home_(home),
      home_assembly_mode_(kinematics_->assembly_mode(home)) {
  for (const JointSpec& joint : joints_) joint_names_.push_back(joint.name);
}

Machine::Machine(const Machine& other)
    : name_(other.name_),
      source_(other.source_),
      units_(other.units_),
      kinematics_(other.kinematics_->clone()),
      joints_(other.joints_),
      joint_names_(other.joint_names_),
      cartesian_(other.cartesian_),
      home_(other.home_),
      tool_(other.tool_),
      home_assembly_mode_(other.home_assembly_mode_) {}

Machine& Machine::operator=(const Machine& other) {
  if (this != &other) *this = Machine(other);
  return *this;
}

Status Machine::check_joint_limits(const JointVector& joints) const {
  for (int i = 0; i < static_cast<int>(joints_.size()); ++i) {
    if (joints[i] < joints_[i].min || joints[i] > joints_[i].max) {
      return Status::failure(StatusCode::joint_limit, i);
    }
  }
  return Status::success();
}

Status Machine::inverse(const Pose& pose, JointVector& joints) const {
  const Status status = kinematics_->inverse(pose, joints);
  if (!status.ok()) return status;
  if (home_assembly_mode_ != 0 && kinematics_->assembly_mode(pose) != home_assembly_mode_) {
    return Status::failure(StatusCode::other_assembly);
  }
  return check_joint_limits(joints);
}

Status Machine::forward(const JointVector& joints, Pose& pose_inout) const {
  if (joints.size() != static_cast<int>(joints_.size())) {
    return Status::failure(StatusCode::invalid_input);
  }
  if (!all_finite(joints)) return Status::failure(StatusCode::invalid_input);
  const Status limits = check_joint_limits(joints);
  if (!limits.ok()) return limits;
  Pose solved = pose_inout;
  Status status = kinematics_->forward(joints, solved);
  const auto wrong_mode = [&] {
    return status.ok() && home_assembly_mode_ != 0 &&
           kinematics_->assembly_mode(solved) != home_assembly_mode_;
  };
  if (status.code == StatusCode::branch_changed || status.code == StatusCode::not_converged ||
      wrong_mode()) {
    // A seed across a singularity from the answer leads FK astray (or to the mirror-image pose);
    // home is on the machine's side by definition, so it is the seed of last resort.
    solved = home_;
    status = kinematics_->forward(joints, solved);
    if (wrong_mode()) status = Status::failure(StatusCode::branch_changed);
  }
  if (status.ok()) pose_inout = solved;
  return status;
}

namespace {

constexpr std::string_view kAxisLetters = "XYZABCUVW";

JointSpec read_joint(const ModelConfig& table, JointKind kind, double mm_per_unit) {
  JointSpec joint;
  joint.name = table.string("name");
  joint.kind = kind;
  // Rotary joints are in degrees in the file and radians inside.
  const double scale = kind == JointKind::rotary ? degrees_to_radians(1.0) : mm_per_unit;
  joint.min = table.number("min") * scale;
  joint.max = table.number("max") * scale;
  joint.max_velocity = table.number("max_velocity") * scale;
  joint.max_acceleration = table.number("max_acceleration") * scale;
  if (!(joint.min < joint.max)) table.fail("max", "must be greater than min");
  if (!(joint.max_velocity > 0.0)) table.fail("max_velocity", "must be positive");
  if (!(joint.max_acceleration > 0.0)) table.fail("max_acceleration", "must be positive");
  return joint;
}

Pose read_home(const TomlSection& cartesian, const Kinematics& kinematics) {
  const std::vector<double> values = cartesian.number_list("home");
  if (values.size() < 2 || values.size() > 6) {
    cartesian.fail("home", "needs 2 to 6 numbers: x y [z [a b c]] in mm and deg");
  }
  Vector6d pose = Vector6d::Zero();
  for (std::size_t i = 0; i < values.size(); ++i) {
    pose[static_cast<int>(i)] =
        i < 3 ? values[i] * cartesian.mm_per_file_unit() : degrees_to_radians(values[i]);
  }
  for (int axis = static_cast<int>(values.size()); axis < kPoseSize; ++axis) {
    if (kinematics.dof().controls(axis)) {
      cartesian.fail("home", "this machine controls " + std::string(kAxisNames[axis]) +
                                 ", so home needs a value for it");
    }
  }
  return Pose::from_vector(pose);
}

// The optional [tool] table: the pen channel of machines that do not move in Z.
ToolChannel read_tool(const TomlSection& tool, const Kinematics& kinematics) {
  ToolChannel channel;
  const std::string z = tool.string("z");
  if (z == "pen") {
    channel.z = ToolZ::pen;
  } else if (z == "ignore") {
    channel.z = ToolZ::ignore;
  } else {
    tool.fail("z", "must be \"pen\" or \"ignore\", not \"" + z + "\"");
  }
  if (kinematics.dof().controls(2)) {
    tool.fail("z", "this machine moves in Z itself; a [tool] channel is for machines that do not");
  }
  channel.down_below_mm = tool.length_or("down_below", 0.0);
  if (tool.has("down")) channel.down_command = tool.string("down");
  if (tool.has("up")) channel.up_command = tool.string("up");
  channel.delay_s = tool.number_or("delay", 0.0);
  if (!(channel.delay_s >= 0.0 && channel.delay_s <= 60.0)) {
    tool.fail("delay", "must be between 0 and 60 s");
  }
  for (const auto* key : {"down", "up"}) {
    const std::string& command = key[0] == 'd' ? channel.down_command : channel.up_command;
    if (command.find_first_of("\n\r") != std::string::npos) {
      tool.fail(key, "must be one line of G-code");
    }
  }
  return channel;
}

}  // namespace

Machine parse_machine(std::string_view toml_text, const std::string& source_name) {
  toml::table document;
  try {
    document = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& error) {
    throw MachineFileError(source_name, static_cast<int>(error.source().begin.line), "(syntax)",
                           std::string(error.description()));
  }
  auto tracker = std::make_shared<KeyTracker>(source_name);
  LengthUnit units = LengthUnit::mm;
  double mm_per_unit = 1.0;
  {
    const TomlSection unit_reader(document, "", tracker, 1.0, {});
    if (unit_reader.has("units")) {
      const std::string unit_name = unit_reader.string("units");
      if (unit_name == "inch") {
        units = LengthUnit::inch;
        mm_per_unit = 25.4;
      } else if (unit_name != "mm") {
        unit_reader.fail("units", "must be \"mm\" or \"inch\", not \"" + unit_name + "\"");
      }
    }
  }
  TomlSection root(document, "", tracker, mm_per_unit, {});
  const std::string name = root.string("name");

  const auto joint_tables = root.table_list("joints");
  std::vector<std::string> joint_names;
  for (const auto& table : joint_tables) {
    const std::string joint_name = table->string("name");
    if (joint_name.empty()) table->fail("name", "must not be empty");
    for (const std::string& seen : joint_names) {
      if (seen == joint_name) table->fail("name", "joint '" + joint_name + "' is named twice");
    }
    joint_names.push_back(joint_name);
  }
  root.set_joint_names(joint_names);

  TomlSection kinematics_section = root.section("kinematics");
  std::unique_ptr<Kinematics> kinematics = make_kinematics(kinematics_section);
  if (kinematics->joint_count() != static_cast<int>(joint_tables.size())) {
    root.fail("joints", "the " + std::string(kinematics->type()) + " kinematics here has " +
                            std::to_string(kinematics->joint_count()) + " joints; the file lists " +
                            std::to_string(joint_tables.size()) + " [[joints]] tables");
  }

  std::vector<JointSpec> joints;
  std::string letters_used;
  for (std::size_t i = 0; i < joint_tables.size(); ++i) {
    const ModelConfig& table = *joint_tables[i];
    JointSpec joint = read_joint(table, kinematics->joint_kind(static_cast<int>(i)), mm_per_unit);
    if (table.has("axis")) {
      const std::string letter = table.string("axis");
      if (letter.size() != 1 ||
          kAxisLetters.find(static_cast<char>(
              std::toupper(static_cast<unsigned char>(letter[0])))) == std::string_view::npos) {
        table.fail("axis", "must be one letter of X Y Z A B C U V W");
      }
      joint.axis_letter = static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    } else {
      joint.axis_letter = kAxisLetters[i];
    }
    if (letters_used.find(joint.axis_letter) != std::string::npos) {
      table.fail("axis", std::string("letter ") + joint.axis_letter + " is used by two joints");
    }
    letters_used += joint.axis_letter;
    joints.push_back(joint);
  }

  const TomlSection cartesian_section = root.section("cartesian");
  CartesianLimits cartesian;
  cartesian.max_feed_mm_per_min = cartesian_section.length("max_feed");
  cartesian.max_acceleration_mm_per_s2 = cartesian_section.length("max_acceleration");
  if (!(cartesian.max_feed_mm_per_min > 0.0))
    cartesian_section.fail("max_feed", "must be positive");
  if (!(cartesian.max_acceleration_mm_per_s2 > 0.0)) {
    cartesian_section.fail("max_acceleration", "must be positive");
  }
  const Pose home = read_home(cartesian_section, *kinematics);

  ToolChannel tool;
  if (root.has("tool")) tool = read_tool(root.section("tool"), *kinematics);

  tracker->check_all_read();
  Machine machine(name, source_name, units, std::move(kinematics), std::move(joints), cartesian,
                  home);
  machine.set_tool(std::move(tool));
  JointVector home_joints;
  const Status home_status = machine.inverse(home, home_joints);
  if (!home_status.ok()) {
    cartesian_section.fail("home", "is not a usable pose: " + machine.describe(home_status));
  }
  return machine;
}

Machine load_machine(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw MachineFileError(path.string(), 0, "(file)", "cannot open the machine file");
  std::ostringstream text;
  text << file.rdbuf();
  return parse_machine(text.str(), path.string());
}

std::vector<AxisExtent> reachable_extent(const Machine& machine) {
  std::vector<AxisExtent> extents;
  const Vector6d home = machine.home().as_vector();
  JointVector joints;
  const auto reachable = [&](int axis, double offset) {
    Vector6d pose = home;
    pose[axis] += offset;
    return machine.inverse(Pose::from_vector(pose), joints).ok();
  };
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    AxisExtent extent{axis, home[axis], home[axis]};
    // Angles are bounded by a half turn; lengths by a kilometre.
    const double limit = axis < 3 ? 1e6 : 3.14159265358979323846;
    const double first_step = axis < 3 ? 1.0 : 1e-3;
    const double resolution = axis < 3 ? 1e-6 : 1e-9;
    for (const double sign : {-1.0, 1.0}) {
      double inside = 0.0;
      double outside = first_step;
      while (outside < limit && reachable(axis, sign * outside)) {
        inside = outside;
        outside *= 2.0;
      }
      if (outside >= limit) {
        outside = limit;
        if (reachable(axis, sign * limit)) inside = limit;
      }
      while (outside - inside > resolution && inside < limit) {
        const double middle = 0.5 * (inside + outside);
        (reachable(axis, sign * middle) ? inside : outside) = middle;
      }
      (sign < 0 ? extent.min : extent.max) = home[axis] + sign * inside;
    }
    extents.push_back(extent);
  }
  return extents;
}

}  // namespace pkm
