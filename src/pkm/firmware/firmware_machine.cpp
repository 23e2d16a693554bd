#include "pkm/firmware/firmware_machine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/calibration/geometry_fit.hpp"

namespace pkm::firmware {
namespace {

struct KindOf {
  FormKind operator()(const kinematics::WallPlotterForm&) const { return FormKind::wall_plotter; }
  FormKind operator()(const kinematics::LinearDeltaForm&) const { return FormKind::linear_delta; }
  FormKind operator()(const kinematics::RotaryDeltaForm&) const { return FormKind::rotary_delta; }
};

std::string accepted_names(const std::vector<FormKind>& accepted) {
  std::string text;
  for (std::size_t i = 0; i < accepted.size(); ++i) {
    if (i > 0) text += i + 1 == accepted.size() ? " or " : ", ";
    text += std::string("a ") + form_kind_name(accepted[i]);
  }
  return text;
}

std::string refusal(const machine::Machine& machine, const kinematics::FirmwareForm& form,
                    const std::string& target) {
  std::string text = machine.source() + ": " + target + "'s " + form_name(form.geometry) +
                     " kinematics cannot hold this machine exactly:";
  for (const std::string& loss : form.losses) text += "\n  - " + loss;
  text += "\n--approximate writes the nearest " + std::string(form_name(form.geometry)) +
          " it can hold, fitted over the workspace, and states the worst tool error that costs";
  return text;
}

// The parameters of each form's model that a fit may move: those the firmware has.
std::vector<std::string> form_parameters(FormKind kind) {
  switch (kind) {
    case FormKind::wall_plotter:
      return {"anchor_*", "cable_offset_*"};
    case FormKind::linear_delta:
      return {"rail*.origin.*", "rail*.strut"};
    case FormKind::rotary_delta:
      break;
  }
  return {"*"};
}

// The tool position (mm) the machine as built reaches on the joints `form_model` gives for `pose`;
// none where either model refuses.
std::optional<double> tool_error_mm(const machine::Machine& machine,
                                    const kinematics::Kinematics& form_model,
                                    const geometry::Pose& pose) {
  kinematics::JointVector joints(form_model.joint_count());
  if (!form_model.inverse(pose, joints).ok()) return std::nullopt;
  geometry::Pose reached = pose;
  if (!machine.kinematics().forward(joints, reached).ok()) return std::nullopt;
  return (reached.position_mm - pose.position_mm).norm();
}

// The worst and root-mean-square tool errors of following `form_model` over `samples`.
ApproximationCost measure_cost(const machine::Machine& machine,
                               const kinematics::Kinematics& form_model,
                               const std::vector<geometry::Pose>& samples) {
  ApproximationCost cost;
  double sum_squares = 0.0;
  for (const geometry::Pose& pose : samples) {
    const std::optional<double> error = tool_error_mm(machine, form_model, pose);
    if (!error) continue;
    ++cost.samples;
    sum_squares += *error * *error;
    if (*error >= cost.worst_tool_error_mm) {
      cost.worst_tool_error_mm = *error;
      cost.worst_at = pose;
    }
  }
  if (cost.samples > 0) cost.rms_tool_error_mm = std::sqrt(sum_squares / cost.samples);
  return cost;
}

// The form's geometry fitted to the machine's joints over its workspace.
FirmwareMachine approximate(const machine::Machine& machine, const kinematics::FirmwareForm& form,
                            const std::string& target) {
  const std::vector<geometry::Pose> samples = workspace_samples(machine);
  if (samples.size() < 8) {
    throw ExportRefused(machine.source() + ": too few workspace poses (" +
                        std::to_string(samples.size()) + ") to fit a " + form_name(form.geometry) +
                        " for " + target);
  }
  std::unique_ptr<kinematics::Kinematics> model =
      kinematics::make_form_kinematics(form.geometry, form.passthrough);
  const double worst_before = measure_cost(machine, *model, samples).worst_tool_error_mm;
  std::vector<calibration::Measurement> measurements;
  for (const geometry::Pose& pose : samples) {
    calibration::Measurement measurement;
    measurement.joints.resize(machine.kinematics().joint_count());
    if (!machine.kinematics().inverse(pose, measurement.joints).ok()) continue;
    measurement.pose = pose.as_vector();
    for (const int axis : machine.kinematics().dof().axes()) measurement.measured[axis] = true;
    measurements.push_back(std::move(measurement));
  }
  calibration::FitOptions options;
  options.parameters = form_parameters(form_kind(form.geometry));
  (void)calibration::fit_geometry(*model, machine.home(), measurements, options);
  std::optional<kinematics::FirmwareForm> fitted = model->firmware_form();
  if (!fitted || !fitted->losses.empty()) {
    throw ExportRefused(machine.source() + ": the fitted " + form_name(form.geometry) +
                        " is not one " + target + " holds");
  }
  fitted->losses = form.losses;
  fitted->unchecked = form.unchecked;
  ApproximationCost cost = measure_cost(machine, *model, samples);
  cost.worst_before_fit_mm = worst_before;
  machine::Machine nearest(machine.name() + " (nearest " + form_name(form.geometry) + ")",
                           machine.source(), machine.units(), std::move(model), machine.joints(),
                           machine.cartesian(), machine.home());
  nearest.set_tool(machine.tool());
  nearest.set_homing(machine.homing());
  nearest.set_controller(machine.controller());
  return FirmwareMachine{std::move(nearest), std::move(*fitted), cost};
}

}  // namespace

FormKind form_kind(const kinematics::FormGeometry& geometry) {
  return std::visit(KindOf{}, geometry);
}

const char* form_kind_name(FormKind kind) {
  switch (kind) {
    case FormKind::wall_plotter:
      return "two-cable wall plotter";
    case FormKind::linear_delta:
      return "linear delta";
    case FormKind::rotary_delta:
      return "rotary delta";
  }
  return "?";
}

FirmwareMachine firmware_machine(const machine::Machine& machine,
                                 const std::vector<FormKind>& accepted, const std::string& target,
                                 bool approximate_if_needed) {
  const std::optional<kinematics::FirmwareForm> form = machine.kinematics().firmware_form();
  if (!form ||
      std::find(accepted.begin(), accepted.end(), form_kind(form->geometry)) == accepted.end()) {
    throw ExportRefused(machine.source() + ": " + target + " has kinematics for " +
                        accepted_names(accepted) + "; this machine's model is " +
                        std::string(machine.kinematics().type()) +
                        (form ? std::string(" (a ") + form_name(form->geometry) + ")" : ""));
  }
  if (form->losses.empty()) return FirmwareMachine{machine, *form, std::nullopt};
  if (!approximate_if_needed) throw ExportRefused(refusal(machine, *form, target));
  return approximate(machine, *form, target);
}

std::vector<geometry::Pose> workspace_samples(const machine::Machine& machine, int per_axis) {
  const machine::PoseBox box = machine::reach_box(machine);
  const std::vector<int> axes = box.axes.axes();
  std::vector<geometry::Pose> samples;
  std::vector<int> index(axes.size(), 0);
  kinematics::JointVector joints(machine.kinematics().joint_count());
  // Six controlled coordinates at 15 points each would be 11 million poses.
  const int steps = std::max(axes.size() > 3 ? std::min(per_axis, 5) : per_axis, 2);
  while (true) {
    geometry::Vector6d values = machine.home().as_vector();
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const int axis = axes[k];
      const double fraction = static_cast<double>(index[k]) / (steps - 1);
      values[axis] = box.min[axis] + fraction * (box.max[axis] - box.min[axis]);
    }
    const geometry::Pose pose = geometry::Pose::from_vector(values);
    if (machine.inverse(pose, joints).ok()) samples.push_back(pose);
    std::size_t k = 0;
    while (k < axes.size() && ++index[k] == steps) index[k++] = 0;
    if (k == axes.size()) break;
  }
  return samples;
}

}  // namespace pkm::firmware
