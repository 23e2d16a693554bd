#include "pkm/firmware/firmware_machine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pkm/calibration/parameter_fit.hpp"
#include "pkm/firmware/fit_residuals.hpp"

namespace pkm::firmware {
namespace {

bool is_cable_robot(FormKind kind) {
  return kind == FormKind::cable_robot || kind == FormKind::swivel_arm_cable_robot;
}

struct KindOf {
  FormKind operator()(const kinematics::WallPlotterForm&) const { return FormKind::wall_plotter; }
  FormKind operator()(const kinematics::LinearDeltaForm&) const { return FormKind::linear_delta; }
  FormKind operator()(const kinematics::RotaryDeltaForm&) const { return FormKind::rotary_delta; }
  FormKind operator()(const kinematics::CableRobotForm& form) const {
    return kinematics::has_swivel_arms(form) ? FormKind::swivel_arm_cable_robot
                                             : FormKind::cable_robot;
  }
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
  if (is_cable_robot(form_kind(form.geometry))) {
    // A swivel arm's error grows towards the frame's edges and with z; fixed tie points fitted
    // over the sheet would spread it everywhere. Not offered: the joint-space output is exact.
    return text +
           "\npkmkit does not approximate a cable robot (--approximate refuses it too): drive this "
           "machine with pkmkit's joint-space output (pkm post)";
  }
  text += "\n--approximate writes the nearest " + std::string(form_name(form.geometry)) +
          " it can hold, fitted over the workspace, and states the worst tool error that costs";
  return text;
}

// What a straight-cable firmware (a Hangprinter's, a winch's) would lose of Maslow 4's belts.
std::vector<std::string> swivel_arm_losses(const kinematics::CableRobotForm& form) {
  std::vector<std::string> losses;
  const double arm = *std::max_element(form.swivel_arms_mm.begin(), form.swivel_arms_mm.end());
  if (arm != 0.0) {
    losses.push_back(kinematics::loss_text(
        "swivel_arm %.3f mm: each cable is tied at the end of an arm that turns to point at its "
        "anchor (Maslow 4), not at a point fixed on the effector",
        arm));
  }
  if (form.cables_follow_z) {
    losses.push_back(
        "cables_follow_z: the tie points ride on the tool's z (Maslow 4's arms on its spindle), "
        "so a cable's length changes with z");
  }
  return losses;
}

// The parameters of each form's model that a fit may move: those the firmware has, less the
// joints' offsets, which the machine's home pins (below).
bool fitted_parameter(FormKind kind, const std::string& name) {
  switch (kind) {
    case FormKind::wall_plotter:
      return name.rfind("anchor_", 0) == 0;
    case FormKind::linear_delta:
      return name.find(".origin.x") != std::string::npos ||
             name.find(".origin.y") != std::string::npos ||
             name.find(".strut") != std::string::npos;
    case FormKind::rotary_delta:
    case FormKind::cable_robot:  // not approximated (firmware_machine refuses first)
    case FormKind::swivel_arm_cable_robot:
      break;
  }
  return false;
}

// Per joint of the form, the parameter that shifts its reading alone and the sign of that shift:
// a cord's offset (+1), a rail origin's height (-1: the reading counts up from it).
struct JointOffset {
  int parameter = 0;
  double sign = 1.0;
};
std::vector<JointOffset> joint_offsets(FormKind kind, const kinematics::Kinematics& model) {
  std::vector<JointOffset> offsets;
  const std::vector<kinematics::Parameter> parameters = model.parameters();
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string& name = parameters[k].name;
    if (kind == FormKind::wall_plotter && name.rfind("cable_offset_", 0) == 0)
      offsets.push_back({static_cast<int>(k), 1.0});
    if (kind == FormKind::linear_delta && name.find(".origin.z") != std::string::npos)
      offsets.push_back({static_cast<int>(k), -1.0});
  }
  return offsets;
}

// The firmware and the machine agree at home, however the firmware homes (a switch whose reading
// the export writes, or the pose declared there): each joint's offset moved so that the form's
// reading at home is the machine's. Updates `values` and the model; false where the form does not
// reach home.
bool pin_at_home(kinematics::Kinematics& model, const std::vector<JointOffset>& offsets,
                 const geometry::Pose& home, const kinematics::JointVector& home_joints,
                 std::vector<double>& values) {
  model.set_parameters(values);
  kinematics::JointVector form_joints(model.joint_count());
  if (!model.inverse(home, form_joints).ok()) return false;
  for (std::size_t j = 0; j < offsets.size(); ++j) {
    const Eigen::Index joint = static_cast<Eigen::Index>(j);
    values[offsets[j].parameter] += offsets[j].sign * (home_joints[joint] - form_joints[joint]);
  }
  model.set_parameters(values);
  return true;
}

// Where the machine goes, to first order, on the joints the form's model gives for each sample,
// less the sample (mm, over the controlled coordinates): the firmware's joints against the
// machine's own, through the inverse of the machine's Jacobian there. A cord nearly level moves
// the tool far for a small change of its length: the fit weighs it so.
class ToolResiduals final : public MillimetreResiduals {
 public:
  struct Sample {
    geometry::Pose pose;
    kinematics::JointVector joints;  // the machine's own
    Eigen::MatrixXd tool_per_joint;  // d pose / d joints over the controlled coordinates
  };

  struct Home {
    geometry::Pose pose;
    kinematics::JointVector joints;  // the machine's own
    std::vector<JointOffset> offsets;
  };

  ToolResiduals(const kinematics::Kinematics& model, std::vector<Sample> samples, Home home)
      : MillimetreResiduals(static_cast<int>(model.dof().count())),
        model_(model.clone()),
        samples_(std::move(samples)),
        home_(std::move(home)) {}

  // `parameters` with the joints' offsets pinned at home.
  bool pinned(std::span<const double> parameters, std::vector<double>& values) const {
    values.assign(parameters.begin(), parameters.end());
    try {
      return pin_at_home(*model_, home_.offsets, home_.pose, home_.joints, values);
    } catch (const std::invalid_argument&) {
      return false;
    }
  }

  int count() const override {
    return samples_.empty()
               ? 0
               : static_cast<int>(samples_.size() * samples_.front().tool_per_joint.rows());
  }
  bool evaluate(std::span<const double> parameters, double* residuals) const override {
    std::vector<double> pinned_values;
    if (!pinned(parameters, pinned_values)) return false;
    kinematics::JointVector values(model_->joint_count());
    for (const Sample& sample : samples_) {
      if (!model_->inverse(sample.pose, values).ok()) return false;
      const Eigen::VectorXd moved = sample.tool_per_joint * (values - sample.joints);
      for (Eigen::Index k = 0; k < moved.size(); ++k) *residuals++ = moved[k];
    }
    return true;
  }
  std::string nominal_failure_hint() const override {
    return "the form's inverse kinematics refuses a workspace pose";
  }

 private:
  std::unique_ptr<kinematics::Kinematics> model_;
  std::vector<Sample> samples_;
  Home home_;
};

// The fit's samples: the poses both the machine and the form's nearest geometry reach, with the
// machine's joints and Jacobian there.
std::vector<ToolResiduals::Sample> fit_samples(const machine::Machine& machine,
                                               const kinematics::Kinematics& model,
                                               const std::vector<geometry::Pose>& poses) {
  const kinematics::Kinematics& built = machine.kinematics();
  const std::vector<int> axes = built.dof().axes();
  std::vector<ToolResiduals::Sample> samples;
  kinematics::JointVector form_joints(model.joint_count());
  for (const geometry::Pose& pose : poses) {
    ToolResiduals::Sample sample{pose, kinematics::JointVector(built.joint_count()), {}};
    kinematics::JointJacobian jacobian(built.joint_count(), geometry::kPoseSize);
    if (!built.inverse_and_jacobian(pose, sample.joints, jacobian).ok()) continue;
    if (!model.inverse(pose, form_joints).ok()) continue;
    Eigen::MatrixXd controlled(built.joint_count(), static_cast<Eigen::Index>(axes.size()));
    for (std::size_t k = 0; k < axes.size(); ++k)
      controlled.col(static_cast<Eigen::Index>(k)) = jacobian.col(axes[k]);
    sample.tool_per_joint = controlled.completeOrthogonalDecomposition().pseudoInverse();
    samples.push_back(std::move(sample));
  }
  return samples;
}

// The form's parameters fitted to the machine over `poses` (least squares, Ceres).
void fit_form(kinematics::Kinematics& model, FormKind kind, const machine::Machine& machine,
              const std::vector<geometry::Pose>& poses) {
  std::vector<double> nominal;
  std::vector<int> free;
  const std::vector<kinematics::Parameter> parameters = model.parameters();
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    nominal.push_back(parameters[k].value);
    if (fitted_parameter(kind, parameters[k].name)) free.push_back(static_cast<int>(k));
  }
  ToolResiduals::Home home{machine.home(),
                           kinematics::JointVector(machine.kinematics().joint_count()),
                           joint_offsets(kind, model)};
  if (!machine.kinematics().inverse(home.pose, home.joints).ok()) return;
  const ToolResiduals residuals(model, fit_samples(machine, model, poses), home);
  if (residuals.count() == 0) return;
  std::vector<double> fitted;
  if (!residuals.pinned(calibration::least_squares(residuals, nominal, free).fitted, fitted) &&
      !residuals.pinned(nominal, fitted)) {
    return;
  }
  model.set_parameters(fitted);
}

// The joints a firmware computes for `pose` from the form `form_model` answers (`form`): a wall
// plotter's cords by firmware_form.hpp's equation, without the model's check of its balance,
// which no firmware makes (a pen beyond an anchor still gets its cords' lengths); the other forms'
// models check nothing a firmware does not. False where the equations have no value.
bool firmware_joints(const kinematics::Kinematics& form_model, const kinematics::FirmwareForm& form,
                     const geometry::Pose& pose, kinematics::JointVector& joints) {
  const auto* plotter = std::get_if<kinematics::WallPlotterForm>(&form.geometry);
  if (plotter == nullptr) return form_model.inverse(pose, joints).ok();
  for (int cable = 0; cable < 2; ++cable) {
    joints[cable] = (pose.position_mm.head<2>() - plotter->anchors_mm[cable]).norm() +
                    plotter->cable_offsets_mm[cable];
  }
  form.passthrough.inverse(pose, joints, 2);
  return true;
}

// The tool position (mm) the machine as built reaches on the joints `form_model` gives for `pose`;
// none where either model refuses.
std::optional<double> tool_error_mm(const machine::Machine& machine,
                                    const kinematics::Kinematics& form_model,
                                    const kinematics::FirmwareForm& form,
                                    const geometry::Pose& pose) {
  kinematics::JointVector joints(form_model.joint_count());
  if (!firmware_joints(form_model, form, pose, joints)) return std::nullopt;
  geometry::Pose reached = pose;
  if (!machine.kinematics().forward(joints, reached).ok()) return std::nullopt;
  return (reached.position_mm - pose.position_mm).norm();
}

}  // namespace

ApproximationCost approximation_cost(const machine::Machine& machine,
                                     const kinematics::Kinematics& form_model,
                                     const std::vector<geometry::Pose>& samples) {
  // Asked once: the answer carries its texts and is the same at every pose.
  const std::optional<kinematics::FirmwareForm> form = form_model.firmware_form();
  if (!form) throw std::invalid_argument("approximation_cost: the model is no firmware form");
  ApproximationCost cost;
  double sum_squares = 0.0;
  for (const geometry::Pose& pose : samples) {
    const std::optional<double> error = tool_error_mm(machine, form_model, *form, pose);
    if (!error) {
      ++cost.unreached;
      continue;
    }
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

machine::Machine nearest_machine(const machine::Machine& machine,
                                 std::unique_ptr<kinematics::Kinematics> form_model,
                                 const std::string& what) {
  machine::Machine nearest(machine.name() + ", nearest " + what, machine.source(), machine.units(),
                           std::move(form_model), machine.joints(), machine.cartesian(),
                           machine.home());
  nearest.set_tool(machine.tool());
  nearest.set_homing(machine.homing());
  nearest.set_controller(machine.controller());
  return nearest;
}

namespace {

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
  const double worst_before = approximation_cost(machine, *model, samples).worst_tool_error_mm;
  fit_form(*model, form_kind(form.geometry), machine, samples);
  std::optional<kinematics::FirmwareForm> fitted = model->firmware_form();
  if (!fitted || !fitted->losses.empty()) {
    throw ExportRefused(machine.source() + ": the fitted " + form_name(form.geometry) +
                        " is not one " + target + " holds");
  }
  fitted->losses = form.losses;
  fitted->unchecked = form.unchecked;
  ApproximationCost cost = approximation_cost(machine, *model, samples);
  cost.worst_before_fit_mm = worst_before;
  return FirmwareMachine{nearest_machine(machine, std::move(model), form_name(form.geometry)),
                         std::move(*fitted), cost,
                         std::make_shared<const machine::Machine>(machine)};
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
    case FormKind::cable_robot:
      return "cable robot";
    case FormKind::swivel_arm_cable_robot:
      return "cable robot on swivel arms (Maslow 4)";
  }
  return "?";
}

FirmwareMachine firmware_machine(const machine::Machine& machine,
                                 const std::vector<FormKind>& accepted, const std::string& target,
                                 bool approximate_if_needed) {
  std::optional<kinematics::FirmwareForm> form = machine.kinematics().firmware_form();
  const auto accepts = [&](FormKind kind) {
    return std::find(accepted.begin(), accepted.end(), kind) != accepted.end();
  };
  if (form && form_kind(form->geometry) == FormKind::swivel_arm_cable_robot &&
      !accepts(FormKind::swivel_arm_cable_robot) && accepts(FormKind::cable_robot)) {
    // A straight-cable firmware holds the belts less their arms: refused with what it would lose.
    kinematics::CableRobotForm straight = std::get<kinematics::CableRobotForm>(form->geometry);
    form->losses = swivel_arm_losses(straight);
    straight.swivel_arms_mm.clear();
    straight.cables_follow_z = false;
    form->geometry = straight;
    throw ExportRefused(refusal(machine, *form, target));
  }
  if (!form ||
      std::find(accepted.begin(), accepted.end(), form_kind(form->geometry)) == accepted.end()) {
    throw ExportRefused(machine.source() + ": " + target + " has kinematics for " +
                        accepted_names(accepted) + "; this machine's model is " +
                        std::string(machine.kinematics().type()) +
                        (form ? std::string(" (a ") + form_name(form->geometry) + ")" : ""));
  }
  if (form->losses.empty()) return FirmwareMachine{machine, *form, std::nullopt, nullptr};
  if (!approximate_if_needed || is_cable_robot(form_kind(form->geometry)))
    throw ExportRefused(refusal(machine, *form, target));
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
