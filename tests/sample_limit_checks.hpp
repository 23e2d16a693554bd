// Sinks that hold planned samples to the machine's limits by finite differences, independently of
// the planner's own bounds: each joint's velocity and acceleration (JointLimitCheck), and on a
// hanging cable machine the cables' tensions under the tool's acceleration (TensionCheck).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/machine/machine.hpp"
#include "pkm/motion/planner.hpp"

namespace pkm::test {

// Each joint's velocity (q_k - q_{k-1}) / dt and acceleration 2 (v_k - v_{k-1}) / (dt_{k-1} +
// dt_k) from successive samples (dt: their time stamps' differences, the servo period but for the
// plan's last sample), against max_velocity and max_acceleration times (1 + tolerance). Joint
// values are compared as the kinematics gives them (mm or rad, continuous: no model here wraps a
// rotary joint). Also counts samples that are not numbers or not later than the one before.
class JointLimitCheck final : public motion::SampleSink {
 public:
  explicit JointLimitCheck(const machine::Machine& machine, double tolerance = 1e-9)
      : machine_(machine), tolerance_(tolerance) {}

  void write(const motion::Sample& sample) override {
    window_[0] = window_[1];
    window_[1] = window_[2];
    window_[2] = sample;
    ++samples;
    if (!sample.joints.allFinite() || !sample.pose.allFinite() || !std::isfinite(sample.time_s)) {
      ++not_numbers;
    }
    if (samples >= 2) check_velocity(window_[1], window_[2]);
    if (samples >= 3) check_acceleration(window_[0], window_[1], window_[2]);
  }

  long samples = 0;
  long over = 0;          // velocities and accelerations over their limits
  long not_numbers = 0;   // samples with a NaN or infinite value
  long out_of_order = 0;  // samples not later than the one before
  // The largest share of its limit any joint's velocity and acceleration reached, and where.
  double velocity_share = 0.0, acceleration_share = 0.0;
  std::string velocity_at, acceleration_at;
  std::string first_over;  // the first sample over a limit, with its numbers

 private:
  void check_velocity(const motion::Sample& before, const motion::Sample& at) {
    const double dt = at.time_s - before.time_s;
    if (!(dt > 0.0)) {
      ++out_of_order;
      return;
    }
    for (int j = 0; j < at.joints.size(); ++j) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(j)];
      const double velocity = (at.joints[j] - before.joints[j]) / dt;
      note(std::abs(velocity) / joint.max_velocity, velocity_share, velocity_at, at, j, "velocity",
           velocity, joint.max_velocity);
    }
  }

  void check_acceleration(const motion::Sample& before, const motion::Sample& at,
                          const motion::Sample& after) {
    const double dt0 = at.time_s - before.time_s, dt1 = after.time_s - at.time_s;
    if (!(dt0 > 0.0) || !(dt1 > 0.0)) return;
    for (int j = 0; j < at.joints.size(); ++j) {
      const machine::JointSpec& joint = machine_.joints()[static_cast<std::size_t>(j)];
      const double v0 = (at.joints[j] - before.joints[j]) / dt0;
      const double v1 = (after.joints[j] - at.joints[j]) / dt1;
      const double acceleration = 2.0 * (v1 - v0) / (dt0 + dt1);
      note(std::abs(acceleration) / joint.max_acceleration, acceleration_share, acceleration_at, at,
           j, "acceleration", acceleration, joint.max_acceleration);
    }
  }

  void note(double share, double& worst, std::string& worst_at, const motion::Sample& at, int j,
            const char* what, double value, double limit) {
    const bool is_over = !(share <= 1.0 + tolerance_);
    if (!(share <= worst) || is_over) {
      std::ostringstream text;
      text.precision(10);
      text << "sample " << samples - 1 << " (t = " << at.time_s << " s, line " << at.line
           << "): joint '" << machine_.joints()[static_cast<std::size_t>(j)].name << "' " << what
           << " " << value << " against " << limit << " (" << share << " of it)";
      if (!(share <= worst)) {
        worst = share;
        worst_at = text.str();
      }
      if (is_over && over++ == 0) first_over = text.str();
    }
  }

  const machine::Machine& machine_;
  double tolerance_;
  motion::Sample window_[3];
};

// Checks each sample's tensions under its acceleration, by finite differences of the sampled
// positions (the samples before and after it), against the limits [min_N, max_N], from the
// statics of the machine alone: the planner's own bound is not used.
class TensionCheck final : public motion::SampleSink {
 public:
  TensionCheck(const kinematics::CablePlotterKinematics& kinematics, double min_N, double max_N)
      : kinematics_(kinematics), min_N_(min_N), max_N_(max_N) {}

  void write(const motion::Sample& sample) override {
    window_[0] = window_[1];
    window_[1] = window_[2];
    window_[2] = sample;
    if (++count_ >= 3) check(window_[0], window_[1], window_[2]);
  }

  long outside = 0;               // samples with a tension outside [min_N, max_N]
  double worst_margin_N = 1e300;  // the least distance of a tension to its nearer limit
  double lowest_N = 1e300, highest_N = -1e300;
  std::string first_outside;
  long checked = 0;

 private:
  void check(const motion::Sample& before, const motion::Sample& at, const motion::Sample& after) {
    const double dt0 = at.time_s - before.time_s, dt1 = after.time_s - at.time_s;
    if (!(dt0 > 0.0) || !(dt1 > 0.0)) return;
    const Eigen::Vector2d v0 = (at.pose.head<2>() - before.pose.head<2>()) / dt0;
    const Eigen::Vector2d v1 = (after.pose.head<2>() - at.pose.head<2>()) / dt1;
    const Eigen::Vector2d acceleration = 2.0 * (v1 - v0) / (dt0 + dt1);
    kinematics::CableStatics statics;
    const kinematics::Status status =
        kinematics_.statics(geometry::Pose::from_vector(at.pose), acceleration, statics);
    ++checked;
    double margin = -1.0;
    if (status.ok()) {
      for (int cable = 0; cable < 2; ++cable) {
        const std::size_t c = static_cast<std::size_t>(cable);
        lowest_N = std::min(lowest_N, statics.lowest_N[c]);
        highest_N = std::max(highest_N, statics.highest_N[c]);
        margin = cable == 0 ? 1e300 : margin;
        margin = std::min({margin, statics.lowest_N[c] - min_N_, max_N_ - statics.highest_N[c]});
      }
    }
    worst_margin_N = std::min(worst_margin_N, margin);
    if (margin < 0.0 && outside++ == 0) {
      std::ostringstream text;
      text << "t = " << at.time_s << " s, line " << at.line << ", x " << at.pose[0] << " y "
           << at.pose[1] << " mm, acceleration " << acceleration.transpose()
           << " mm/s^2: " << statics.lowest_N[0] << ".." << statics.highest_N[0] << " N, "
           << statics.lowest_N[1] << ".." << statics.highest_N[1] << " N";
      first_outside = text.str();
    }
  }

  const kinematics::CablePlotterKinematics& kinematics_;
  double min_N_, max_N_;
  motion::Sample window_[3];
  long count_ = 0;
};

// The tool tip's acceleration 2 (v_k - v_{k-1}) / (dt_{k-1} + dt_k) from successive samples'
// positions (x y, and z where the machine moves it), against [cartesian] max_acceleration times
// (1 + tolerance), plus what rounding the positions can make of it. The planner uses the whole
// limit, so the check allows for what the finite difference itself adds: a second difference of
// positions near 1,500 mm over 1 ms errs by up to 4 eps 1500 mm / (1 ms)^2 = 1.3e-6 mm/s^2
// (1.3e-8 of the Maslow's 100 mm/s^2), and on a curve of curvature k at speed v with the speed
// changing it passes the acceleration by a share of order (v h k)^2 / 12 (2e-7 measured on
// Dragon.nc's arcs): 1e-5 by default.
class ToolAccelerationCheck final : public motion::SampleSink {
 public:
  explicit ToolAccelerationCheck(const machine::Machine& machine, double tolerance = 1e-5)
      : limit_(machine.cartesian().max_acceleration_mm_per_s2),
        moves_z_(machine.kinematics().dof().controls(2)),
        tolerance_(tolerance) {}

  void write(const motion::Sample& sample) override {
    window_[0] = window_[1];
    window_[1] = window_[2];
    window_[2] = sample;
    if (++count_ >= 3) check(window_[0], window_[1], window_[2]);
  }

  long over = 0;
  double share = 0.0;  // the largest share of the limit reached
  std::string worst_at, first_over;

 private:
  Eigen::Vector3d position(const motion::Sample& sample) const {
    Eigen::Vector3d p = sample.pose.head<3>();
    if (!moves_z_) p.z() = 0.0;
    return p;
  }

  void check(const motion::Sample& before, const motion::Sample& at, const motion::Sample& after) {
    const double dt0 = at.time_s - before.time_s, dt1 = after.time_s - at.time_s;
    if (!(dt0 > 0.0) || !(dt1 > 0.0)) return;
    const Eigen::Vector3d v0 = (position(at) - position(before)) / dt0;
    const Eigen::Vector3d v1 = (position(after) - position(at)) / dt1;
    const double acceleration = (2.0 * (v1 - v0) / (dt0 + dt1)).norm();
    const double here = acceleration / limit_;
    const double magnitude =
        std::max({position(before).cwiseAbs().maxCoeff(), position(at).cwiseAbs().maxCoeff(),
                  position(after).cwiseAbs().maxCoeff()});
    const double rounding = 4.0 * std::numeric_limits<double>::epsilon() * magnitude /
                            (std::min(dt0, dt1) * 0.5 * (dt0 + dt1)) / limit_;
    const bool is_over = !(here <= 1.0 + tolerance_ + rounding);
    if (!(here <= share) || is_over) {
      std::ostringstream text;
      text.precision(10);
      text << "t = " << at.time_s << " s, line " << at.line << ": tool acceleration "
           << acceleration << " mm/s^2 against " << limit_ << " (" << here << " of it)";
      if (!(here <= share)) {
        share = here;
        worst_at = text.str();
      }
      if (is_over && over++ == 0) first_over = text.str();
    }
  }

  double limit_;
  bool moves_z_;
  double tolerance_;
  motion::Sample window_[3];
  long count_ = 0;
};

// Passes every sample on to each of the sinks.
class FanOut final : public motion::SampleSink {
 public:
  explicit FanOut(std::vector<motion::SampleSink*> sinks) : sinks_(std::move(sinks)) {}
  void write(const motion::Sample& sample) override {
    for (motion::SampleSink* sink : sinks_) {
      if (sink != nullptr) sink->write(sample);
    }
  }

 private:
  std::vector<motion::SampleSink*> sinks_;
};

}  // namespace pkm::test
