// Joint velocities and accelerations of a sampled path by finite differences, the one measure the
// plan report's peaks and the plan's page both use: a velocity is the average over the interval
// since the previous sample, an acceleration the change of two successive velocities over the
// spacing of their intervals' midpoints. Fixed-size state: nothing allocates per sample.
#pragma once

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::motion {

class JointRates {
 public:
  // The next sample (time in s, joints in mm or rad). A sample at the time of the previous one
  // gives no new velocity.
  void add(double time_s, const kinematics::JointVector& joints);

  // Whether the last add() gave velocities (from the second sample on), and accelerations
  // (from the third); the values are unspecified otherwise.
  bool has_velocity() const { return has_velocity_; }
  bool has_acceleration() const { return has_acceleration_; }
  const kinematics::JointVector& velocity() const { return velocity_; }  // mm/s or rad/s
  const kinematics::JointVector& acceleration() const {
    return acceleration_;
  }  // mm/s^2 or rad/s^2

 private:
  kinematics::JointVector last_joints_, velocity_, acceleration_;
  double last_time_s_ = 0.0, last_interval_s_ = 0.0;
  long samples_ = 0;
  bool has_velocity_ = false, has_acceleration_ = false;
};

}  // namespace pkm::motion
