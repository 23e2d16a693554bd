// Dexterity and joint-speed maps (plane_maps.hpp).
#include "pkm/workspace/plane_maps.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "pkm/bounds/inverse_hessian.hpp"

namespace pkm::workspace {

double characteristic_length_mm(const kinematics::Kinematics& model) {
  return 0.5 * bounds::pose_angle_scale_mm(model);
}

double dexterity(const kinematics::JointJacobian& jacobian, geometry::Dof dof, double length_mm) {
  Eigen::MatrixXd scaled(jacobian.rows(), dof.count());
  int column = 0;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!dof.controls(axis)) continue;
    scaled.col(column++) = jacobian.col(axis) / (axis >= 3 ? length_mm : 1.0);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled);
  const auto& values = svd.singularValues();
  if (values.size() == 0 || !(values[0] > 0.0)) return 0.0;
  return values[values.size() - 1] / values[0];
}

double joint_speed_per_tool_speed(const machine::Machine& machine,
                                  const kinematics::JointJacobian& jacobian) {
  const kinematics::Kinematics& model = machine.kinematics();
  double worst = 0.0;
  for (int joint = 0; joint < model.joint_count(); ++joint) {
    if (model.passthrough_axis(joint) >= 0) continue;
    const double per_mm = jacobian.block(joint, 0, 1, 3).norm();
    const bool rotary =
        machine.joints()[static_cast<std::size_t>(joint)].kind == kinematics::JointKind::rotary;
    worst = std::max(worst, rotary ? geometry::radians_to_degrees(per_mm) : per_mm);
  }
  return worst;
}

std::vector<PlaneMap> plane_maps(const machine::Machine& machine, const Workspace& ws, int points) {
  std::vector<PlaneMap> maps;
  if (!ws.extent || points < 2) return maps;
  const kinematics::Kinematics& model = machine.kinematics();
  const Eigen::Vector3d lo = ws.extent->min(), hi = ws.extent->max();
  const double longer = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(longer > 0.0)) return maps;
  const double step = longer / (points - 1);
  PlaneMap dex{"dexterity", machine.home().position_mm.z(), {lo.x(), lo.y()}, step, {}, {}};
  dex.dims = {static_cast<int>(std::floor((hi.x() - lo.x()) / step)) + 1,
              static_cast<int>(std::floor((hi.y() - lo.y()) / step)) + 1};
  PlaneMap speed = dex;
  speed.name = "joint_speed_per_tool_speed";
  const double length = characteristic_length_mm(model);
  const Eigen::Vector3d orientation = 0.5 * (ws.orientation_min_rad + ws.orientation_max_rad);
  kinematics::JointVector joints;
  kinematics::JointJacobian jacobian;
  for (int j = 0; j < dex.dims[1]; ++j) {
    for (int i = 0; i < dex.dims[0]; ++i) {
      geometry::Pose pose = machine.home();
      pose.position_mm.x() = lo.x() + i * step;
      pose.position_mm.y() = lo.y() + j * step;
      for (int k = 0; k < 3; ++k) {
        if (model.dof().controls(3 + k)) pose.orientation_rad[k] = orientation[k];
      }
      double d = NAN, s = NAN;
      if (machine.inverse(pose, joints).ok() && model.jacobian(pose, jacobian).ok()) {
        d = dexterity(jacobian, model.dof(), length);
        s = joint_speed_per_tool_speed(machine, jacobian);
      }
      dex.values.push_back(d);
      speed.values.push_back(s);
    }
  }
  maps.push_back(std::move(dex));
  maps.push_back(std::move(speed));
  return maps;
}

}  // namespace pkm::workspace
