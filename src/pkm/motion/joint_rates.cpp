#include "pkm/motion/joint_rates.hpp"

namespace pkm::motion {

void JointRates::add(double time_s, const kinematics::JointVector& joints) {
  const double interval_s = time_s - last_time_s_;
  if (samples_ == 0) {
    velocity_ = kinematics::JointVector::Zero(joints.size());
    acceleration_ = kinematics::JointVector::Zero(joints.size());
  }
  has_velocity_ = samples_ > 0 && interval_s > 0.0;
  has_acceleration_ = has_velocity_ && samples_ > 1;
  if (has_velocity_) {
    // Velocities are averages over their intervals: their change spans the midpoints.
    const double spacing_s = 0.5 * (interval_s + last_interval_s_);
    for (int i = 0; i < joints.size(); ++i) {
      const double velocity = (joints[i] - last_joints_[i]) / interval_s;
      if (has_acceleration_) acceleration_[i] = (velocity - velocity_[i]) / spacing_s;
      velocity_[i] = velocity;
    }
  }
  last_joints_ = joints;
  if (interval_s > 0.0) last_interval_s_ = interval_s;
  last_time_s_ = time_s;
  ++samples_;
}

}  // namespace pkm::motion
