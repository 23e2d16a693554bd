#include "pkm/firmware/klipper_fit.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace pkm::firmware {
namespace {

constexpr int kParameters = 10;  // radius; then per tower angle (rad), rod, carriage offset
using Parameters = Eigen::Matrix<double, kParameters, 1>;

kinematics::LinearDeltaForm form_of(const Parameters& p) {
  kinematics::LinearDeltaForm form;
  for (int i = 0; i < 3; ++i) {
    const double angle = p[1 + 3 * i];
    form.towers[i].column_mm = p[0] * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    form.towers[i].rod_mm = p[2 + 3 * i];
    form.towers[i].carriage_offset_mm = p[3 + 3 * i];
  }
  return form;
}

// A joint reading of the form (firmware_form.hpp); NaN where the rod cannot reach.
double reading(const kinematics::LinearDeltaTower& tower, const Eigen::Vector3d& tool) {
  const double horizontal2 = (tool.head<2>() - tower.column_mm).squaredNorm();
  return tool.z() + std::sqrt(tower.rod_mm * tower.rod_mm - horizontal2) + tower.carriage_offset_mm;
}

struct Sample {
  Eigen::Vector3d tool;
  Eigen::Vector3d joints;
};

Eigen::VectorXd residuals(const Parameters& p, const std::vector<Sample>& samples) {
  const kinematics::LinearDeltaForm form = form_of(p);
  Eigen::VectorXd r(3 * static_cast<Eigen::Index>(samples.size()));
  for (std::size_t k = 0; k < samples.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      r[3 * static_cast<Eigen::Index>(k) + i] =
          reading(form.towers[i], samples[k].tool) - samples[k].joints[i];
    }
  }
  return r;
}

// Gauss-Newton on the joints' residuals, forward-difference Jacobian: ten smooth parameters
// near their start (the machine's own towers, radii averaged).
Parameters fit(Parameters p, const std::vector<Sample>& samples) {
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::VectorXd r = residuals(p, samples);
    Eigen::MatrixXd jacobian(r.size(), kParameters);
    for (int j = 0; j < kParameters; ++j) {
      Parameters moved = p;
      const double step = 1e-7 * std::max(1.0, std::abs(p[j]));
      moved[j] += step;
      jacobian.col(j) = (residuals(moved, samples) - r) / step;
    }
    const Parameters delta = jacobian.colPivHouseholderQr().solve(-r);
    if (!delta.allFinite()) break;
    p += delta;
    if (delta.norm() < 1e-12) break;
  }
  return p;
}

std::vector<Sample> joint_samples(const machine::Machine& machine) {
  std::vector<Sample> samples;
  kinematics::JointVector joints(machine.kinematics().joint_count());
  for (const geometry::Pose& pose : workspace_samples(machine)) {
    if (!machine.kinematics().inverse(pose, joints).ok()) continue;
    samples.push_back({pose.position_mm, joints.head<3>()});
  }
  return samples;
}

ApproximationCost tool_cost(const machine::Machine& machine,
                            const kinematics::Kinematics& form_model,
                            const std::vector<Sample>& samples) {
  ApproximationCost cost;
  double sum_squares = 0.0;
  kinematics::JointVector joints(form_model.joint_count());
  for (const Sample& sample : samples) {
    geometry::Pose pose = machine.home();
    pose.position_mm = sample.tool;
    if (!form_model.inverse(pose, joints).ok()) continue;
    geometry::Pose reached = pose;
    if (!machine.kinematics().forward(joints, reached).ok()) continue;
    const double error = (reached.position_mm - sample.tool).norm();
    ++cost.samples;
    sum_squares += error * error;
    if (error >= cost.worst_tool_error_mm) {
      cost.worst_tool_error_mm = error;
      cost.worst_at = pose;
    }
  }
  if (cost.samples > 0) cost.rms_tool_error_mm = std::sqrt(sum_squares / cost.samples);
  return cost;
}

}  // namespace

FirmwareMachine klipper_nearest_delta(const FirmwareMachine& exact) {
  const machine::Machine& machine = exact.machine;
  const auto& form = std::get<kinematics::LinearDeltaForm>(exact.form.geometry);
  const std::vector<Sample> samples = joint_samples(machine);
  if (samples.size() < 8) {
    throw ExportRefused(machine.source() + ": too few workspace poses (" +
                        std::to_string(samples.size()) + ") to fit a delta klipper can hold");
  }
  Parameters start;
  start[0] = 0.0;
  for (int i = 0; i < 3; ++i) {
    const kinematics::LinearDeltaTower& tower = form.towers[i];
    start[0] += tower.column_mm.norm() / 3.0;
    start[1 + 3 * i] = std::atan2(tower.column_mm.y(), tower.column_mm.x());
    start[2 + 3 * i] = tower.rod_mm;
    start[3 + 3 * i] = tower.carriage_offset_mm;
  }
  // The fit reads every sample's joints from the start: those a start tower's rod only just
  // reaches (within 1 mm of horizontal) are left to the cost.
  std::vector<Sample> fitted_samples;
  const kinematics::LinearDeltaForm start_form = form_of(start);
  for (const Sample& sample : samples) {
    bool inside = true;
    for (const kinematics::LinearDeltaTower& tower : start_form.towers) {
      inside = inside && (sample.tool.head<2>() - tower.column_mm).norm() < tower.rod_mm - 1.0;
    }
    if (inside) fitted_samples.push_back(sample);
  }
  const kinematics::LinearDeltaForm fitted = form_of(fit(start, fitted_samples));
  std::unique_ptr<kinematics::Kinematics> model =
      kinematics::make_form_kinematics(fitted, exact.form.passthrough);
  ApproximationCost cost = tool_cost(machine, *model, samples);
  cost.worst_before_fit_mm =
      tool_cost(machine, *kinematics::make_form_kinematics(start_form, exact.form.passthrough),
                samples)
          .worst_tool_error_mm;
  kinematics::FirmwareForm held = exact.form;
  held.geometry = fitted;
  held.losses.push_back(
      "the towers' columns at different radii from the origin (klipper's delta "
      "has one delta_radius)");
  machine::Machine nearest(machine.name() + " (nearest klipper delta)", machine.source(),
                           machine.units(), std::move(model), machine.joints(), machine.cartesian(),
                           machine.home());
  nearest.set_tool(machine.tool());
  nearest.set_homing(machine.homing());
  nearest.set_controller(machine.controller());
  return FirmwareMachine{std::move(nearest), std::move(held), cost};
}

}  // namespace pkm::firmware
