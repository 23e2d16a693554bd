// The assembly mode over a ball, whatever the model (assembly_mode.hpp).
#include "pkm/bounds/assembly_mode.hpp"

namespace pkm::bounds {

bool has_assembly_bound(const kinematics::Kinematics& model, int home_mode) {
  return home_mode == 0 || model.assembly_mode_bounds() != nullptr;
}

std::optional<kinematics::ModeBound> assembly_mode_over_ball(const kinematics::Kinematics& model,
                                                             int home_mode,
                                                             const geometry::Vector6d& centre,
                                                             const kinematics::JointVector& joints,
                                                             std::span<const double> joint_speed) {
  if (home_mode == 0) return kinematics::ModeBound{1.0, 0.0};
  const kinematics::AssemblyModeBounds* modes = model.assembly_mode_bounds();
  if (modes == nullptr) return std::nullopt;
  return modes->mode_over_ball(home_mode, centre, joints, joint_speed);
}

}  // namespace pkm::bounds
