#include "pkm/machine/tension_region.hpp"

#include <algorithm>
#include <limits>

#include "pkm/kinematics/hanging_cables.hpp"

namespace pkm::machine {

void GridRegion::add(const Eigen::Vector2d& at_mm) {
  ++points;
  min_mm = min_mm.cwiseMin(at_mm);
  max_mm = max_mm.cwiseMax(at_mm);
}

namespace {

void record_extremes(const kinematics::CableStatics& statics, const Eigen::Vector2d& at,
                     TensionRegion& region) {
  for (int cable = 0; cable < 2; ++cable) {
    const std::size_t c = static_cast<std::size_t>(cable);
    if (statics.lowest_N[c] < region.lowest_N) {
      region.lowest_N = statics.lowest_N[c];
      region.lowest_at_mm = at;
      region.lowest_cable = cable;
    }
    if (statics.highest_N[c] > region.highest_N) {
      region.highest_N = statics.highest_N[c];
      region.highest_at_mm = at;
      region.highest_cable = cable;
    }
  }
}

// The joints at a pose where a cable would push (no balance to solve): the straight distances
// from the pulley centres, enough to tell whether the joints' limits reach the point.
kinematics::JointVector straight_joints(const Machine& machine,
                                        const kinematics::HangingCables& cables,
                                        const geometry::Pose& pose) {
  kinematics::JointVector joints =
      kinematics::JointVector::Zero(static_cast<Eigen::Index>(machine.joints().size()));
  for (int c = 0; c < 2; ++c) {
    const auto cable = static_cast<std::size_t>(c);
    joints[c] = (pose.position_mm.head<2>() - cables.cable_geometry().anchors_mm[cable]).norm() +
                cables.cable_geometry().cable_offsets_mm[cable];
  }
  for (Eigen::Index j = 2; j < joints.size(); ++j) {
    const JointSpec& spec = machine.joints()[static_cast<std::size_t>(j)];
    joints[j] = std::clamp(0.0, spec.min, spec.max);  // pass-through joints: any value
  }
  return joints;
}

// One point into the region's tallies: only where the joints reach it, tensions aside.
void classify(const Machine& machine, const kinematics::HangingCables& cables,
              const kinematics::Kinematics& unlimited, const geometry::Pose& pose,
              TensionRegion& region) {
  const Eigen::Vector2d at = pose.position_mm.head<2>();
  kinematics::JointVector joints;
  const kinematics::Status status = unlimited.inverse(pose, joints);
  const bool pushes = (status.code == kinematics::StatusCode::tension ||
                       status.code == kinematics::StatusCode::unreachable) &&
                      (status.joint == 0 || status.joint == 1);
  if (!status.ok() && !pushes) return;  // no balance (the cables in line, above the anchors)
  if (pushes) joints = straight_joints(machine, cables, pose);
  if (!machine.check_envelope(pose).ok() || !machine.check_joint_limits(joints).ok()) return;
  region.reached.add(at);
  if (pushes) {
    region.slack[static_cast<std::size_t>(status.joint)].add(at);
    return;
  }
  kinematics::CableStatics statics;
  if (!cables.statics(pose, Eigen::Vector2d::Zero(), statics).ok()) return;
  record_extremes(statics, at, region);
  bool within = true;
  for (std::size_t c = 0; c < 2; ++c) {
    if (statics.lowest_N[c] < cables.tension_min_N()) {
      region.slack[c].add(at);
      within = false;
    }
    if (statics.highest_N[c] > cables.tension_max_N()) {
      region.over_max[c].add(at);
      within = false;
    }
  }
  if (within) region.within.add(at);
}

}  // namespace

std::optional<TensionRegion> tension_region(const Machine& machine, int columns, int rows) {
  const kinematics::HangingCables* cables = machine.kinematics().hanging_cables();
  if (cables == nullptr || !(cables->effector_mass_kg() > 0.0)) return std::nullopt;
  const std::unique_ptr<kinematics::Kinematics> unlimited = cables->without_tension_limits();
  const Eigen::Vector2d left = cables->cable_geometry().anchors_mm[0];
  const Eigen::Vector2d right = cables->cable_geometry().anchors_mm[1];
  TensionRegion region;
  region.columns = columns;
  region.rows = rows;
  region.min_mm = Eigen::Vector2d(std::min(left.x(), right.x()), reach_box(machine).min[1]);
  region.max_mm = Eigen::Vector2d(std::max(left.x(), right.x()), std::max(left.y(), right.y()));
  const Eigen::Vector2d cell =
      (region.max_mm - region.min_mm).cwiseQuotient(Eigen::Vector2d(columns, rows));
  geometry::Pose pose = machine.home();
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < columns; ++column) {
      pose.position_mm.head<2>() =
          region.min_mm + cell.cwiseProduct(Eigen::Vector2d(column + 0.5, row + 0.5));
      classify(machine, *cables, *unlimited, pose, region);
    }
  }
  return region;
}

}  // namespace pkm::machine
