// A machine as a firmware with its own kinematics can hold it (docs/firmware.md): the machine
// itself where its model is one of the firmware's forms exactly, else (only when asked) the
// nearest machine of that form, fitted over the workspace, with the tool error that costs.
#pragma once

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/kinematics/firmware_form.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::firmware {

// swivel_arm_cable_robot: a CableRobotForm with Maslow 4's swivel arms or riding tie points
// (kinematics::has_swivel_arms), which a Hangprinter's or a winch's firmware cannot hold.
enum class FormKind {
  wall_plotter,
  linear_delta,
  rotary_delta,
  cable_robot,
  swivel_arm_cable_robot
};
FormKind form_kind(const kinematics::FormGeometry& geometry);
const char* form_kind_name(FormKind kind);  // "two-cable wall plotter"

// What following the approximation costs: the firmware's joints for a pose are the form's
// inverse kinematics; the machine as built goes where its own forward kinematics takes them.
struct ApproximationCost {
  int samples = 0;  // workspace poses compared
  double worst_tool_error_mm = 0.0;
  geometry::Pose worst_at;  // machine coordinates, mm
  double rms_tool_error_mm = 0.0;
  double worst_before_fit_mm = 0.0;  // the form's nearest geometry before the fit
  // Workspace poses the machine reaches where the form's inverse kinematics or the machine's
  // forward kinematics of the form's joints fails: the firmware cannot go there.
  int unreached = 0;
};

struct FirmwareMachine {
  machine::Machine machine;       // its model is in the form
  kinematics::FirmwareForm form;  // form.losses: what the firmware cannot hold (empty: exact)
  std::optional<ApproximationCost> cost;  // set when the machine was approximated
  // The machine as built, which an approximation's cost is measured on (none: `machine` itself).
  std::shared_ptr<const machine::Machine> as_built;
  const machine::Machine& built() const { return as_built ? *as_built : machine; }
};

// A machine a target cannot express: says which of its forms the model is not, or what the
// form would lose, with the numbers.
class ExportRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `machine` as a firmware whose forms are `accepted` (by `target`, for messages) holds it.
// Exact: the machine as it is. With losses: ExportRefused listing them, unless `approximate`,
// which fits the form's geometry to the machine's joints over the workspace and measures the cost.
FirmwareMachine firmware_machine(const machine::Machine& machine,
                                 const std::vector<FormKind>& accepted, const std::string& target,
                                 bool approximate);

// What following `form_model` (a model whose firmware_form() is exact) costs on `machine` at
// `samples`: the firmware's joints by the form's own equations, driven through the machine's
// forward kinematics (ApproximationCost; worst_before_fit_mm left 0).
ApproximationCost approximation_cost(const machine::Machine& machine,
                                     const kinematics::Kinematics& form_model,
                                     const std::vector<geometry::Pose>& samples);

// `machine` with its model replaced by `form_model` (name: "..., nearest <what>"), the rest kept.
machine::Machine nearest_machine(const machine::Machine& machine,
                                 std::unique_ptr<kinematics::Kinematics> form_model,
                                 const std::string& what);

// Poses over the machine's reach (a grid of about `per_axis` points along each controlled axis
// over the reachable extent, kept where the machine's inverse kinematics and limits accept them),
// mm and rad: where round trips and approximations are measured.
std::vector<geometry::Pose> workspace_samples(const machine::Machine& machine, int per_axis = 15);

}  // namespace pkm::firmware
