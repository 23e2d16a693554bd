// Pass-through joints: joints that copy a pose coordinate the mechanism itself does not move (a
// matrix mill's rotary A and C, a plotter's pen on a real Z axis). They follow the model's own
// joints, in the order the machine file lists them.
#pragma once

#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

class PassThroughAxes {
 public:
  PassThroughAxes() = default;
  // Throws std::invalid_argument for an axis out of 0..5, one the mechanism moves, or a repeat.
  PassThroughAxes(std::vector<int> axes, geometry::Dof mechanism);

  // The optional `passthrough` key: a list of axis names, each one `allowed` lets through.
  static PassThroughAxes read(const ModelConfig& config, geometry::Dof mechanism,
                              geometry::Dof allowed);

  const std::vector<int>& axes() const { return axes_; }
  int count() const { return static_cast<int>(axes_.size()); }
  geometry::Dof add_to(geometry::Dof mechanism) const;
  // Joint `first + k` is axis k's: linear for x y z (mm), rotary for a b c (rad).
  JointKind kind(int k) const { return axes_[k] < 3 ? JointKind::linear : JointKind::rotary; }

  void inverse(const geometry::Pose& pose, JointVector& joints, int first) const;
  void forward(const JointVector& joints, int first, geometry::Pose& pose) const;
  void jacobian(JointJacobian& d_joints_d_pose, int first) const;
  // The `passthrough` key read() reads; nothing when there are none.
  void write(ModelConfigWriter& out) const;

 private:
  std::vector<int> axes_;
};

}  // namespace pkm::kinematics
