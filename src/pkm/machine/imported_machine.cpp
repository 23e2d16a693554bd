#include "pkm/machine/imported_machine.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <memory>

#include "pkm/kinematics/registry.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"
#include "pkm/machine/toml_config.hpp"

namespace pkm::machine {
namespace {

// The model of the section, made by the registry as a machine file's would be.
std::unique_ptr<kinematics::Kinematics> make_model(const ImportedMachine& config,
                                                   const std::string& output_name) {
  toml::table document;
  try {
    document = toml::parse(config.kinematics_section, output_name);
  } catch (const toml::parse_error& error) {
    throw MachineFileError(output_name, static_cast<int>(error.source().begin.line), "(syntax)",
                           std::string(error.description()));
  }
  std::vector<std::string> names;
  for (const ImportedJoint& joint : config.joints) names.push_back(joint.name);
  auto tracker = std::make_shared<KeyTracker>(output_name);
  const TomlSection section(*document["kinematics"].as_table(), "kinematics", tracker,
                            config.inch ? 25.4 : 1.0, names);
  return kinematics::make_kinematics(section);
}

// The pose of the joints' HOME values by the model's forward kinematics, in the config's units.
std::vector<double> home_through_forward(const ImportedMachine& config,
                                         const std::string& output_name) {
  const std::unique_ptr<kinematics::Kinematics> model = make_model(config, output_name);
  const double mm_per_unit = config.inch ? 25.4 : 1.0;
  kinematics::JointVector joints(static_cast<Eigen::Index>(config.joints.size()));
  for (std::size_t i = 0; i < config.joints.size(); ++i) {
    const ImportedJoint& joint = config.joints[i];
    joints[static_cast<Eigen::Index>(i)] =
        joint.angular ? geometry::degrees_to_radians(joint.home) : joint.home * mm_per_unit;
  }
  geometry::Pose pose = geometry::Pose::from_mm_deg(0.0, 0.0, config.home_seed_z * mm_per_unit);
  const kinematics::Status status = model->forward(joints, pose);
  if (!status.ok()) {
    throw ImportedMachineError("the joints' homes have no pose (" +
                               kinematics::describe(status, {}) + "); give the pose they home to");
  }
  const geometry::Vector6d values = pose.as_vector();
  std::vector<double> home;
  for (int axis = 0; axis < config.pose_size; ++axis) {
    const double value =
        axis < 3 ? values[axis] / mm_per_unit : geometry::radians_to_degrees(values[axis]);
    // Rounding noise of the solution (1e-14) would read as a real offset in the file.
    home.push_back(std::abs(value) < 1e-9 ? 0.0 : value);
  }
  return home;
}

std::string number_list(const std::vector<double>& values) {
  std::string text;
  for (const double value : values) text += (text.empty() ? "" : ", ") + toml_number(value);
  return "[" + text + "]";
}

std::string joints_text(const ImportedMachine& config) {
  std::string text;
  for (const ImportedJoint& joint : config.joints) {
    text += "\n[[joints]]\nname = " + toml_string(joint.name) + "\n";
    text += "min = " + toml_number(joint.min) + "\nmax = " + toml_number(joint.max) + "\n";
    text += "max_velocity = " + toml_number(joint.max_velocity) + "\n";
    text += "max_acceleration = " + toml_number(joint.max_acceleration) + "\n";
    if (joint.steps_per_unit)
      text += "steps_per_unit = " + toml_number(*joint.steps_per_unit) + "\n";
  }
  return text;
}

}  // namespace

std::string machine_file_text(const ImportedMachine& config, const std::string& output_name) {
  const std::vector<double> home =
      config.home ? *config.home : home_through_forward(config, output_name);
  std::string text = "# " + config.origin + "\n";
  for (const std::string& note : config.notes) text += "# - " + note + "\n";
  text += "name = " + toml_string(config.name) + "\n";
  text += std::string("units = \"") + (config.inch ? "inch" : "mm") + "\"\n\n";
  text += config.kinematics_section;
  text += joints_text(config);
  text += "\n[cartesian]\nmax_feed = " + toml_number(config.max_feed_per_min) + "\n";
  text += "max_acceleration = " + toml_number(config.max_acceleration) + "\n";
  text += "home = " + number_list(home) + "\n";
  if (config.envelope_min && config.envelope_max) {
    text += "min = " + number_list(*config.envelope_min) + "\n";
    text += "max = " + number_list(*config.envelope_max) + "\n";
  }
  try {
    (void)parse_machine(text, output_name);
  } catch (const MachineFileError& error) {
    throw ImportedMachineError(std::string("pkmkit refuses the imported machine (") + error.what() +
                               ")");
  }
  return text;
}

}  // namespace pkm::machine
