#include "pkm/firmware/klipper_winch.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "pkm/firmware/klipper.hpp"
#include "pkm/firmware/klipper_import.hpp"
#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine_writer.hpp"

namespace pkm::firmware {
namespace {

// winch.py reads stepper_a .. stepper_z: the first three always, the rest while they exist.
constexpr int kMaxSteppers = 26;
constexpr int kRequiredSteppers = 3;
// pkmkit's spatial cable robot needs a fourth cable (a pose in x y z from the lines alone).
constexpr int kPkmkitSpatialCables = 4;
// A home farther than this from x = y = z = 0 (mm) is not where Klipper's winch starts.
constexpr double kHomeTolerance_mm = 1e-9;

std::string stepper_name(int i) {
  return std::string("stepper_") + static_cast<char>('a' + i);
}

std::string option(const std::string& key, double value, const std::string& comment) {
  return key + ": " + klipper_number(value) + "  # " + comment + "\n";
}

// The machine as Klipper's winch can run it, or why not.
const kinematics::CableRobotForm& winch_form(const FirmwareMachine& firmware) {
  const machine::Machine& machine = firmware.machine;
  const auto& form = std::get<kinematics::CableRobotForm>(firmware.form.geometry);
  const std::string& source = machine.source();
  if (form.planar) {
    throw ExportRefused(source +
                        ": klipper's winch moves the tool in x y z; this cable robot is planar "
                        "(its cables hold x y only), so Klipper would drive z through the cables");
  }
  if (form.flex_compensation) {
    throw ExportRefused(source +
                        ": klipper's winch pays out each line's straight length; this machine's "
                        "joints are the lines' unstretched lengths (flex_compensation), which "
                        "Klipper has no setting for");
  }
  if (firmware.form.passthrough.count() > 0) {
    throw ExportRefused(source + ": klipper's winch moves x y z only; this machine has " +
                        std::to_string(firmware.form.passthrough.count()) +
                        " pass-through joint(s) it would not drive");
  }
  if (form.anchors_mm.size() > static_cast<std::size_t>(kMaxSteppers)) {
    throw ExportRefused(source + ": klipper's winch reads at most 26 steppers (stepper_a .. " +
                        "stepper_z); this machine has " + std::to_string(form.anchors_mm.size()) +
                        " cables");
  }
  const Eigen::Vector3d home = machine.home().position_mm;
  if (home.norm() > kHomeTolerance_mm) {
    throw ExportRefused(
        source + ": klipper's winch has no homing: it takes the tool at x 0 y 0 z 0 when it " +
        "starts and after G28, and this machine's home is x " + klipper_number(home.x()) + " y " +
        klipper_number(home.y()) + " z " + klipper_number(home.z()) +
        " mm. Move the machine file's frame so that home is its origin (the anchors less home)");
  }
  return form;
}

}  // namespace

ExportedFile write_klipper_winch(const FirmwareMachine& firmware, const ExportContext& context) {
  const kinematics::CableRobotForm& form = winch_form(firmware);
  const machine::Machine& machine = firmware.machine;
  ExportedFile file;
  file.text += header_comment(firmware, context, "# ");
  file.text +=
      "# Klipper's winch (klippy/kinematics/winch.py). Merge into printer.cfg, or [include] this\n"
      "# file: Klipper merges sections of one name, so your pins stay yours. Each stepper's\n"
      "# coordinate is its line's length from its anchor to the tool. Klipper neither homes a\n"
      "# winch nor checks its limits: it takes the tool at x 0 y 0 z 0 (this machine's home) when\n"
      "# it starts and after G28, and runs any move; check the G-code with pkm check first.\n\n";
  file.text += "[printer]\nkinematics: winch\n";
  file.text += option("max_velocity", machine.cartesian().max_feed_mm_per_s(),
                      "mm/s: the machine's max_feed");
  file.text += option("max_accel", machine.cartesian().max_acceleration_mm_per_s2,
                      "mm/s^2: the machine's max_acceleration");
  for (std::size_t i = 0; i < form.anchors_mm.size(); ++i) {
    const int index = static_cast<int>(i);
    const Eigen::Vector3d& anchor = form.anchors_mm[i];
    file.text += "\n[" + stepper_name(index) + "]  # cable " + std::to_string(index + 1) + "\n";
    file.text += option("anchor_x", anchor.x(), "mm: the anchor less the line's tie point");
    file.text += option("anchor_y", anchor.y(), "mm");
    file.text += option("anchor_z", anchor.z(), "mm");
    file.text += klipper_steps(machine.joints()[i], stepper_name(index), file.warnings);
  }
  return file;
}

namespace {

std::vector<Eigen::Vector3d> read_anchors(KlipperConfig& config) {
  std::vector<Eigen::Vector3d> anchors;
  for (int i = 0; i < kMaxSteppers; ++i) {
    const std::string section = stepper_name(i);
    if (i >= kRequiredSteppers && config.section(section) == nullptr) break;
    anchors.emplace_back(config.required(section, "anchor_x"), config.required(section, "anchor_y"),
                         config.required(section, "anchor_z"));
  }
  if (anchors.size() < static_cast<std::size_t>(kPkmkitSpatialCables)) {
    config.fail("stepper_c", "anchor_x",
                "Klipper's winch runs on 3 lines with the tool hanging below them, but pkmkit's "
                "cable robot in x y z needs 4 or more ([stepper_d]): not imported");
  }
  return anchors;
}

}  // namespace

machine::ImportedMachine read_klipper_winch(KlipperConfig& config, const std::string& source) {
  machine::ImportedMachine imported;
  imported.source = source;
  imported.origin = "Imported by `pkm import klipper` from " + source + " (kinematics winch).";
  imported.name = "Klipper winch (" + source.substr(source.find_last_of('/') + 1) + ")";
  const double max_velocity = config.required("printer", "max_velocity");
  const double max_accel = config.required("printer", "max_accel");
  const std::vector<Eigen::Vector3d> anchors = read_anchors(config);

  // Klipper's axis limits (get_status) are the anchors' box; pkmkit's work envelope likewise.
  Eigen::Vector3d low = anchors.front(), high = anchors.front();
  for (const Eigen::Vector3d& anchor : anchors) {
    low = low.cwiseMin(anchor);
    high = high.cwiseMax(anchor);
  }
  kinematics::CableRobotForm form;
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    form.anchors_mm.push_back(anchors[i]);
    form.cable_offsets_mm.push_back(0.0);
    machine::ImportedJoint joint;
    joint.name = stepper_name(static_cast<int>(i));
    // A line inside the anchors' box is at most as long as the way to its farthest corner.
    const Eigen::Vector3d far = (anchors[i] - low).cwiseMax(high - anchors[i]);
    joint.min = 0.0;
    joint.max = far.norm();
    joint.home = anchors[i].norm();
    joint.max_velocity = max_velocity;  // a line never runs faster than the tool
    joint.max_acceleration = max_accel;
    joint.steps_per_unit = klipper_steps_per_mm(config, joint.name, imported.notes);
    imported.joints.push_back(joint);
  }
  const std::unique_ptr<kinematics::Kinematics> model = kinematics::make_form_kinematics(form);
  imported.kinematics_section = machine::kinematics_toml(*model, machine::LengthUnit::mm);
  imported.max_feed_per_min = 60.0 * max_velocity;
  imported.max_acceleration = max_accel;
  imported.home = std::vector<double>{0.0, 0.0, 0.0};
  imported.envelope_min = std::vector<double>{low.x(), low.y(), low.z()};
  imported.envelope_max = std::vector<double>{high.x(), high.y(), high.z()};
  imported.notes.push_back(
      "each line's reading is Klipper's stepper coordinate, its length from its anchor; Klipper "
      "starts (and 'homes') with the tool at x 0 y 0 z 0, pkmkit's home");
  imported.notes.push_back(
      "Klipper checks no limits on a winch: the work envelope is the anchors' box (Klipper's "
      "axis_minimum and axis_maximum), each line from 0 to its farthest corner of it, at the "
      "tool's max_velocity and max_accel (a line's acceleration can exceed the tool's on a curve)");
  for (const std::string& note : config.unread()) imported.notes.push_back(note);
  return imported;
}

}  // namespace pkm::firmware
