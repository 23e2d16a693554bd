// Marlin's POLARGRAPH (docs/firmware-marlin.md): the X stepper's belt runs from
// (X_MIN_POS, Y_MAX_POS), the Y stepper's from (X_MAX_POS, Y_MAX_POS); a stepper's position is the
// belt's length from there to the pen; Z is the pen's own axis; moves are clamped to the
// rectangle X_MIN_POS..X_MAX_POS, Y_MIN_POS..Y_MAX_POS and refused where a belt would pass
// POLARGRAPH_MAX_BELT_LEN + 1 mm.
#include <algorithm>
#include <cmath>

#include "pkm/firmware/marlin_forms.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

// Fitted anchors level within this (mm) are written level: half of it is the most it moves one.
constexpr double kLevelTolerance_mm = 1e-6;
// Marlin's position_is_reachable takes a belt up to POLARGRAPH_MAX_BELT_LEN + 1 mm.
constexpr double kBeltSlack_mm = 1.0;

struct PolargraphSettings {
  StepperJoints joints{0, 1, -1};
  double x_min = 0, x_max = 0, y_max = 0, y_min = 0, belt = 0;
};

PolargraphSettings polargraph_settings(const FirmwareMachine& fm) {
  const auto& form = std::get<kinematics::WallPlotterForm>(fm.form.geometry);
  const std::string& source = fm.machine.source();
  PolargraphSettings s;
  for (int k = 0; k < fm.form.passthrough.count(); ++k) {
    if (fm.form.passthrough.axes()[k] != 2 || k > 0) {
      throw ExportRefused(source +
                          ": Marlin's POLARGRAPH passes Z through to the pen; this "
                          "machine passes through other axes too");
    }
    s.joints[2] = 2;
  }
  const Eigen::Vector2d& a = form.anchors_mm[0];
  const Eigen::Vector2d& b = form.anchors_mm[1];
  if (std::abs(a.y() - b.y()) > kLevelTolerance_mm) {
    throw ExportRefused(
        source +
        ": Marlin's POLARGRAPH puts both motors at Y_MAX_POS (level); this machine's "
        "anchors are at y " +
        marlin_number(a.y()) + " and " + marlin_number(b.y()) +
        " mm, and Marlin has no setting that turns its frame");
  }
  // pkmkit lists the left anchor first (cable_plotter refuses the other order), as Marlin's X
  // stepper is the left motor.
  if (a.x() >= b.x()) throw ExportRefused(source + ": the first anchor is not left of the second");
  s.x_min = a.x();
  s.x_max = b.x();
  s.y_max = 0.5 * (a.y() + b.y());
  const WorkBox box = work_box(fm.machine);
  s.y_min = box.min.y();
  s.belt = 1e300;
  for (int k = 0; k < 2; ++k) {
    s.belt = std::min(s.belt, fm.machine.joints()[k].max - form.cable_offsets_mm[k]);
  }
  s.belt -= kBeltSlack_mm;
  return s;
}

void polargraph_warnings(const FirmwareMachine& fm, const PolargraphSettings& s,
                         std::vector<std::string>& warnings) {
  const WorkBox box = work_box(fm.machine);
  if (box.min.x() < s.x_min - 1e-6 || box.max.x() > s.x_max + 1e-6 ||
      box.max.y() > s.y_max + 1e-6) {
    warnings.push_back("Marlin clamps X to " + marlin_number(s.x_min) + ".." +
                       marlin_number(s.x_max) + " and Y to at most " + marlin_number(s.y_max) +
                       " mm (between and below its motors); the machine reaches X " +
                       marlin_number(box.min.x()) + ".." + marlin_number(box.max.x()) +
                       ", Y up to " + marlin_number(box.max.y()) +
                       " mm (M211 S0 turns the clamp off)");
  }
  for (const machine::JointSpec& joint : fm.machine.joints()) {
    if (joint.home_switch) {
      warnings.push_back(
          "Marlin's G28 sets the pen at MANUAL_X_HOME_POS, MANUAL_Y_HOME_POS when "
          "its X and Y endstops trip; joint '" +
          joint.name + "''s home switch (a belt length) has no Marlin setting");
      break;
    }
  }
}

std::string polargraph_defines(const FirmwareMachine& fm, const PolargraphSettings& s) {
  const Eigen::Vector3d home = fm.machine.home().position_mm;
  std::string text;
  text += define_line("X_MIN_POS", marlin_number(s.x_min), "mm: the left motor's x (X stepper)");
  text += define_line("X_MAX_POS", marlin_number(s.x_max), "mm: the right motor's x (Y stepper)");
  text += define_line("Y_MAX_POS", marlin_number(s.y_max), "mm: both motors' y");
  text += define_line("Y_MIN_POS", marlin_number(s.y_min), "mm: the lowest pen y");
  text += define_line("X_BED_SIZE", marlin_number(s.x_max - s.x_min), "mm");
  text += define_line("Y_BED_SIZE", marlin_number(s.y_max - s.y_min), "mm");
  text += define_line("POLARGRAPH_MAX_BELT_LEN", marlin_number(s.belt),
                      "mm: Marlin takes belts up to this + 1 mm, the joints' max");
  text += define_line("MANUAL_X_HOME_POS", marlin_number(home.x()), "mm: the pen after G28");
  text += define_line("MANUAL_Y_HOME_POS", marlin_number(home.y()), "mm");
  if (s.joints[2] >= 0) {
    const machine::JointSpec& z = fm.machine.joints()[2];
    text += define_line("MANUAL_Z_HOME_POS", marlin_number(home.z()), "mm");
    text += define_line("Z_MIN_POS", marlin_number(z.min), "mm: the pen's axis");
    text += define_line("Z_MAX_POS", marlin_number(z.max), "mm");
  }
  return text;
}

}  // namespace

ExportedFile write_marlin_polargraph(const FirmwareMachine& fm, const ExportContext& context) {
  const PolargraphSettings settings = polargraph_settings(fm);
  ExportedFile file;
  polargraph_warnings(fm, settings, file.warnings);
  file.text = marlin_preamble(fm, context, "POLARGRAPH");
  file.text += polargraph_defines(fm, settings);
  file.text += marlin_motion_defines(fm, settings.joints);
  return file;
}

machine::ImportedMachine read_marlin_polargraph(const MarlinDefines& defines) {
  for (const char* name :
       {"X_MIN_POS", "X_MAX_POS", "Y_MIN_POS", "Y_MAX_POS", "POLARGRAPH_MAX_BELT_LEN"}) {
    if (!defines.enabled(name)) {
      defines.missing(name, "POLARGRAPH", "the polargraph's motors and reach come from it");
    }
  }
  const double x_min = defines.number("X_MIN_POS"), x_max = defines.number("X_MAX_POS");
  const double y_min = defines.number("Y_MIN_POS"), y_max = defines.number("Y_MAX_POS");
  const double belt = defines.number("POLARGRAPH_MAX_BELT_LEN");
  if (x_max <= x_min) {
    throw FirmwareFileError(defines.source() + ":" + std::to_string(defines.line("X_MAX_POS")) +
                            ": X_MAX_POS: not right of X_MIN_POS (the motors' x)");
  }
  const bool has_z = defines.enabled("Z_MIN_POS") && defines.enabled("Z_MAX_POS");
  const MarlinJointNames names = read_joint_names(defines, {"left", "right", "z"});
  const StepperRates rates = read_stepper_rates(defines, names, "POLARGRAPH");
  machine::ImportedMachine imported = imported_base(
      defines, {"POLARGRAPH", "X_MIN_POS", "X_MAX_POS", "Y_MIN_POS", "Y_MAX_POS", "X_BED_SIZE",
                "Y_BED_SIZE", "POLARGRAPH_MAX_BELT_LEN", "MANUAL_X_HOME_POS", "MANUAL_Y_HOME_POS",
                "MANUAL_Z_HOME_POS", "Z_MIN_POS", "Z_MAX_POS"});
  kinematics::WallPlotterForm form;
  form.anchors_mm = {Eigen::Vector2d(x_min, y_max), Eigen::Vector2d(x_max, y_max)};
  kinematics::PassThroughAxes passthrough;
  if (has_z) passthrough = kinematics::PassThroughAxes({2}, geometry::Dof::planar_xy());
  imported.kinematics_section = machine::kinematics_toml(
      *kinematics::make_form_kinematics(form, passthrough), machine::LengthUnit::mm);
  const int joint_count = has_z ? 3 : 2;
  imported.joints.resize(joint_count);
  for (int k = 0; k < joint_count; ++k) {
    machine::ImportedJoint& joint = imported.joints[k];
    joint.name = names.names[k];
    joint.min = k < 2 ? 0.0 : defines.number("Z_MIN_POS");
    joint.max = k < 2 ? belt + kBeltSlack_mm : defines.number("Z_MAX_POS");
    joint.max_velocity = rates.feed_mm_per_s[k];
    joint.max_acceleration = rates.acceleration_mm_per_s2[k];
    if (rates.steps_per_mm) joint.steps_per_unit = (*rates.steps_per_mm)[k];
  }
  const double home_x =
      defines.optional_number("MANUAL_X_HOME_POS").value_or(0.5 * (x_min + x_max));
  const double home_y =
      defines.optional_number("MANUAL_Y_HOME_POS").value_or(0.5 * (y_min + y_max));
  if (!defines.enabled("MANUAL_X_HOME_POS") || !defines.enabled("MANUAL_Y_HOME_POS")) {
    imported.warnings.push_back(
        "no MANUAL_X_HOME_POS / MANUAL_Y_HOME_POS: home is the drawing "
        "area's centre; give the pen's position after G28");
    imported.notes.push_back(imported.warnings.back());
  }
  imported.pose_size = has_z ? 3 : 2;
  imported.home =
      has_z ? std::vector<double>{home_x, home_y,
                                  defines.optional_number("MANUAL_Z_HOME_POS").value_or(0.0)}
            : std::vector<double>{home_x, home_y};
  imported.envelope_min = std::vector<double>{x_min, y_min};
  imported.envelope_max = std::vector<double>{x_max, y_max};
  if (has_z) {
    imported.envelope_min->push_back(imported.joints[2].min);
    imported.envelope_max->push_back(imported.joints[2].max);
  }
  imported.max_feed_per_min = 60.0 * std::min(rates.feed_mm_per_s[0], rates.feed_mm_per_s[1]);
  imported.max_acceleration =
      defines.optional_number("DEFAULT_ACCELERATION")
          .value_or(std::min(rates.acceleration_mm_per_s2[0], rates.acceleration_mm_per_s2[1]));
  imported.notes.push_back(
      "belts from (X_MIN_POS, Y_MAX_POS) and (X_MAX_POS, Y_MAX_POS); a "
      "joint's max is POLARGRAPH_MAX_BELT_LEN + 1 mm (Marlin's reach test), its min 0 (Marlin has "
      "none)");
  imported.notes.push_back(
      "the envelope is Marlin's clamp rectangle X_MIN_POS..X_MAX_POS, "
      "Y_MIN_POS..Y_MAX_POS");
  return imported;
}

}  // namespace pkm::firmware
