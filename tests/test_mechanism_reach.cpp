// How far the leg limits' values move over a ball of poses (bounds::mechanism_reach): every pose
// sampled in the ball keeps each joint angle and each clearance within the reach of its value at
// the centre, and the clearance's bound from where the legs are closest is tighter than the rate
// alone (what lets the workspace and the certified check decide legs near each other).
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "pkm/bounds/inverse_hessian.hpp"
#include "pkm/bounds/mechanism_rate.hpp"
#include "test_support.hpp"

namespace pkm::bounds {
namespace {

machine::Machine with_leg_limits(const std::string& example, const std::string& keys) {
  std::ifstream file(test::example_machine_path(example));
  std::stringstream text;
  text << file.rdbuf();
  std::string toml = text.str();
  const std::string section = "[kinematics]\n";
  toml.replace(toml.find(section), section.size(), section + keys + "\n");
  return machine::parse_machine(toml, example);
}

// Returns how many clearances the closest-point bound made tighter than the rate.
int check_reach(const machine::Machine& machine, int balls) {
  const kinematics::Kinematics& model = machine.kinematics();
  const double scale = pose_angle_scale_mm(model);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(1.0, 60.0);
  int tighter = 0;
  for (int ball = 0; ball < balls; ++ball) {
    geometry::Vector6d centre = machine.home().as_vector();
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (model.dof().controls(axis))
        centre[axis] += axis < 3 ? 150.0 * unit(rng) : 0.15 * unit(rng);
    }
    const double radius = size(rng);
    kinematics::JointVector joints;
    kinematics::JointJacobian jacobian;
    if (!model.inverse_and_jacobian(geometry::Pose::from_vector(centre), joints, jacobian).ok())
      continue;
    const auto hessians = inverse_hessian_bounds(model, centre, radius, scale, kinematics::Chord{});
    if (!hessians) continue;
    const kinematics::LegMotion motion =
        leg_motion(model, joints, jacobian, *hessians, radius, scale);
    std::vector<kinematics::MechanismLimit> at_centre, at_sample;
    model.mechanism_limits(geometry::Pose::from_vector(centre), at_centre);
    const std::optional<kinematics::LegEnds> ends =
        legs_at(model, geometry::Pose::from_vector(centre), joints);
    EXPECT_TRUE(ends.has_value());
    if (!ends) return tighter;
    std::vector<Reach> reach;
    for (const kinematics::MechanismLimit& value : at_centre) {
      reach.push_back(mechanism_reach(value, motion, radius, &*ends));
      const double spread = mechanism_rate(value, motion) * radius;
      EXPECT_LE(reach.back().down, spread + 1e-12);
      if (value.code == kinematics::StatusCode::interference && reach.back().down < 0.9 * spread)
        ++tighter;
    }
    for (int sample = 0; sample < 200; ++sample) {
      // A pose of the scaled ball: |dx|^2 + (scale |da|)^2 <= radius^2.
      geometry::Vector6d step = geometry::Vector6d::Zero();
      for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
        if (model.dof().controls(axis)) step[axis] = unit(rng) * (axis < 3 ? 1.0 : 1.0 / scale);
      }
      geometry::Vector6d scaled = step;
      scaled.tail<3>() *= scale;
      // Outside the ball: onto its surface, where the farthest poses are.
      const geometry::Vector6d pose = centre + radius * step / std::max(1.0, scaled.norm());
      kinematics::JointVector sample_joints;
      if (!model.inverse_and_jacobian(geometry::Pose::from_vector(pose), sample_joints, jacobian)
               .ok())
        continue;
      at_sample.clear();
      model.mechanism_limits(geometry::Pose::from_vector(pose), at_sample);
      EXPECT_EQ(at_sample.size(), at_centre.size());
      if (at_sample.size() != at_centre.size()) return tighter;
      for (std::size_t k = 0; k < at_centre.size(); ++k) {
        EXPECT_GE(at_sample[k].value, at_centre[k].value - reach[k].down - 1e-9)
            << "ball " << ball << " value " << k;
        EXPECT_LE(at_sample[k].value, at_centre[k].value + reach[k].up + 1e-9)
            << "ball " << ball << " value " << k;
      }
    }
  }
  return tighter;
}

TEST(MechanismReach, HexapodValuesStayWithinTheirReachOverTheBall) {
  const machine::Machine machine =
      with_leg_limits("hexapod-bit.toml", "max_joint_angle = 60\nleg_diameter = 250");
  EXPECT_GT(check_reach(machine, 150), 100);
}

TEST(MechanismReach, GlideValuesStayWithinTheirReachOverTheBall) {
  const machine::Machine machine =
      with_leg_limits("triaglide.toml", "max_joint_angle = 80\nleg_diameter = 30");
  EXPECT_GT(check_reach(machine, 150), 10);
}

}  // namespace
}  // namespace pkm::bounds
