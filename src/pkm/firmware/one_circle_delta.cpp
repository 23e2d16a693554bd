#include "pkm/firmware/one_circle_delta.hpp"

#include <cmath>

#include "pkm/calibration/parameter_fit.hpp"
#include "pkm/firmware/fit_residuals.hpp"

namespace pkm::firmware {
namespace {

// The fitted values: the common radius; then per tower its angle (rad), rod and carriage offset.
constexpr int kParameters = 10;

kinematics::LinearDeltaForm form_of(std::span<const double> p) {
  kinematics::LinearDeltaForm form;
  for (int i = 0; i < 3; ++i) {
    const double angle = p[1 + 3 * i];
    form.towers[i].column_mm = p[0] * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    form.towers[i].rod_mm = p[2 + 3 * i];
    form.towers[i].carriage_offset_mm = p[3 + 3 * i];
  }
  return form;
}

struct Sample {
  Eigen::Vector3d tool;
  Eigen::Vector3d joints;  // the machine's own
};

// Each sample's form readings less the machine's (mm).
class CircleResiduals final : public MillimetreResiduals {
 public:
  explicit CircleResiduals(std::vector<Sample> samples)
      : MillimetreResiduals(3), samples_(std::move(samples)) {}

  int count() const override { return 3 * static_cast<int>(samples_.size()); }
  bool evaluate(std::span<const double> parameters, double* residuals) const override {
    const kinematics::LinearDeltaForm form = form_of(parameters);
    for (const Sample& sample : samples_) {
      for (int i = 0; i < 3; ++i) {
        const kinematics::LinearDeltaTower& tower = form.towers[i];
        const double under_root =
            tower.rod_mm * tower.rod_mm - (sample.tool.head<2>() - tower.column_mm).squaredNorm();
        if (!(under_root > 0.0)) return false;
        *residuals++ =
            sample.tool.z() + std::sqrt(under_root) + tower.carriage_offset_mm - sample.joints[i];
      }
    }
    return true;
  }
  std::string nominal_failure_hint() const override {
    return "a tower's rod does not reach a workspace pose";
  }

 private:
  std::vector<Sample> samples_;
};

// The machine's joints at the poses each start tower's rod reaches with a millimetre to spare
// (a rod at the edge of its reach would end the fit's first step).
std::vector<Sample> fit_samples(const machine::Machine& machine,
                                const std::vector<geometry::Pose>& poses,
                                const kinematics::LinearDeltaForm& start) {
  std::vector<Sample> samples;
  kinematics::JointVector joints(machine.kinematics().joint_count());
  for (const geometry::Pose& pose : poses) {
    if (!machine.kinematics().inverse(pose, joints).ok()) continue;
    bool inside = true;
    for (const kinematics::LinearDeltaTower& tower : start.towers)
      inside = inside && (pose.position_mm.head<2>() - tower.column_mm).norm() < tower.rod_mm - 1.0;
    if (inside) samples.push_back({pose.position_mm, joints.head<3>()});
  }
  return samples;
}

}  // namespace

bool towers_on_one_circle(const kinematics::LinearDeltaForm& form) {
  double low = form.towers[0].column_mm.norm(), high = low;
  for (const kinematics::LinearDeltaTower& tower : form.towers) {
    low = std::min(low, tower.column_mm.norm());
    high = std::max(high, tower.column_mm.norm());
  }
  return high - low <= kOneCircleTolerance_mm;
}

FirmwareMachine nearest_delta_on_one_circle(const FirmwareMachine& exact,
                                            const std::string& setting) {
  const machine::Machine& machine = exact.built();
  const auto& form = std::get<kinematics::LinearDeltaForm>(exact.form.geometry);
  const std::vector<geometry::Pose> poses = workspace_samples(machine);
  std::vector<double> start(kParameters, 0.0);
  for (int i = 0; i < 3; ++i) {
    const kinematics::LinearDeltaTower& tower = form.towers[i];
    start[0] += tower.column_mm.norm() / 3.0;
    start[1 + 3 * i] = std::atan2(tower.column_mm.y(), tower.column_mm.x());
    start[2 + 3 * i] = tower.rod_mm;
    start[3 + 3 * i] = tower.carriage_offset_mm;
  }
  const kinematics::LinearDeltaForm start_form = form_of(start);
  const CircleResiduals residuals(fit_samples(machine, poses, start_form));
  if (residuals.count() < 3 * 8) {
    throw ExportRefused(machine.source() + ": too few workspace poses (" +
                        std::to_string(residuals.count() / 3) + ") to fit a delta " + setting +
                        " holds");
  }
  std::vector<int> free(kParameters);
  for (int k = 0; k < kParameters; ++k) free[k] = k;
  const kinematics::LinearDeltaForm fitted =
      form_of(calibration::least_squares(residuals, start, free).fitted);
  std::unique_ptr<kinematics::Kinematics> model =
      kinematics::make_form_kinematics(fitted, exact.form.passthrough);
  ApproximationCost cost = approximation_cost(machine, *model, poses);
  cost.worst_before_fit_mm =
      approximation_cost(
          machine, *kinematics::make_form_kinematics(start_form, exact.form.passthrough), poses)
          .worst_tool_error_mm;
  kinematics::FirmwareForm held = exact.form;
  held.geometry = fitted;
  held.losses.push_back("the towers' columns at different radii from the origin (" + setting +
                        " is one radius)");
  return FirmwareMachine{nearest_machine(machine, std::move(model), "delta on one circle"),
                         std::move(held), cost, std::make_shared<const machine::Machine>(machine)};
}

}  // namespace pkm::firmware
