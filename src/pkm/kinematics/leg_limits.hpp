// Joint-angle and leg-interference limits of the models whose legs run between two joints (a
// hexapod's legs, a glide's struts): each leg is a straight cylinder between its inner joint (on
// the base, or on a carriage) and its platform joint. A joint end allows the leg at most
// `max_joint_angle` from its neutral axis; two legs whose axes come closer than `leg_diameter`
// touch. Read from the machine file's [kinematics] (docs/machine-file.md, "Joint angles and leg
// interference"); a model without the keys checks nothing and pays one test of a flag.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

// The two ends of a leg: 0 the inner one (base joint, carriage joint), 1 the platform joint.
inline constexpr int kInnerEnd = 0;
inline constexpr int kPlatformEnd = 1;

struct LegLimitSettings {
  // Per end (kInnerEnd, kPlatformEnd), rad; infinity: that end is not checked.
  std::array<double, 2> max_joint_angle_rad{std::numeric_limits<double>::infinity(),
                                            std::numeric_limits<double>::infinity()};
  double leg_diameter_mm = 0.0;  // 0: legs are not checked against each other
  // The neutral axes as the file gives them, one for every leg: the inner end's in the world
  // frame, the platform end's in the platform frame, each the direction (inner joint towards
  // platform joint) of a leg centred in that joint. Absent: each leg's direction at home.
  std::optional<Eigen::Vector3d> inner_axis, platform_axis;

  bool checks_angles() const {
    return max_joint_angle_rad[0] < std::numeric_limits<double>::infinity() ||
           max_joint_angle_rad[1] < std::numeric_limits<double>::infinity();
  }
  bool any() const { return checks_angles() || leg_diameter_mm > 0.0; }
};

// Reads max_joint_angle, leg_diameter and the two axis keys (`inner_axis_key`: "base_joint_axis"
// for a hexapod, "carriage_joint_axis" for a glide). Fails at the key for values out of range.
LegLimitSettings read_leg_limit_settings(const ModelConfig& config, const char* inner_axis_key);
// Writes them as read_leg_limit_settings reads them: the angles in deg (one number where both
// ends share it), the diameter, and the axes only where the file named them.
void write_leg_limit_settings(const LegLimitSettings& settings, const char* inner_axis_key,
                              ModelConfigWriter& out);

// The legs of one pose: the joint centres in the world frame and the platform's rotation.
struct LegEnds {
  using Points = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6>;
  Points inner;     // base joints, carriage joints
  Points platform;  // platform joints
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

class LegLimits {
 public:
  LegLimits() = default;
  LegLimits(const LegLimitSettings& settings, int legs);

  // False without any of the keys: nothing to check, nothing to set.
  bool active() const { return active_; }
  // Neutral axes the file did not give, from the legs at home; leg pairs whose joint centres
  // lie closer than the diameter at either end at home are neighbours sharing a joint and are
  // not checked against each other. Until called, no angle and no pair is checked.
  void set_home(const LegEnds& at_home);

  // The first end (leg order, inner end first) past its angle, else the first pair (i < j in
  // lexicographic order) closer than the diameter: joint_angle (joint = the leg) or interference
  // (joint = the first leg).
  Status check(const LegEnds& ends) const;
  // Every checked quantity at the pose, appended to `out`.
  void append_values(const LegEnds& ends, std::vector<MechanismLimit>& out) const;
  // "the platform joint of leg 3 is at 31.2 deg from its axis, beyond max_joint_angle 30 deg",
  // "legs 2 and 5 are 31.4 mm apart, closer than leg_diameter 40 mm"; empty when `status` is
  // neither failure.
  std::string why(const LegEnds& ends, const Status& status, const char* leg_word) const;

  const LegLimitSettings& settings() const { return settings_; }
  bool homed() const { return homed_; }
  // The neutral axis (unit) of `leg`'s `end`: the inner end's in the world frame, the platform
  // end's in the platform frame. Set by set_home.
  const Eigen::Vector3d& neutral_axis(int leg, int end) const {
    return axes_[static_cast<std::size_t>(end)][static_cast<std::size_t>(leg)];
  }
  // cos(max_joint_angle) of an end; -1 where the end is not checked.
  double cos_max_joint_angle(int end) const { return cos_max_[static_cast<std::size_t>(end)]; }

 private:
  // Unit neutral axis of `leg`'s `end`, in the world frame at `rotation`.
  Eigen::Vector3d axis_in_world(int leg, int end, const Eigen::Matrix3d& rotation) const;
  bool pair_checked(int i, int j) const { return (checked_pairs_ >> pair_bit(i, j)) & 1u; }
  static int pair_bit(int i, int j) { return i * 6 + j; }

  LegLimitSettings settings_;
  int legs_ = 0;
  bool active_ = false;
  bool homed_ = false;
  std::array<double, 2> cos_max_{-1.0, -1.0};
  std::array<std::vector<Eigen::Vector3d>, 2> axes_;  // per end, per leg (platform end: platform
                                                      // frame)
  std::uint64_t checked_pairs_ = 0;
};

// A legged model seen without its leg limits: what forward kinematics iterates on (a Newton step
// may pass a pose the joints do not allow on its way to one they do; the answer is checked after).
// `Model` gives inverse_without_leg_limits; everything else is the model's own.
// It refers to the model it is made from; a clone owns a copy of it, so it may outlive that one.
template <class Model>
class WithoutLegLimits final : public Kinematics {
 public:
  explicit WithoutLegLimits(const Model& model) : model_(model) {}
  explicit WithoutLegLimits(std::shared_ptr<const Model> owned)
      : owned_(std::move(owned)), model_(*owned_) {}
  std::string_view type() const override { return model_.type(); }
  int joint_count() const override { return model_.joint_count(); }
  geometry::Dof dof() const override { return model_.dof(); }
  JointKind joint_kind(int joint) const override { return model_.joint_kind(joint); }
  int passthrough_axis(int joint) const override { return model_.passthrough_axis(joint); }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override {
    return model_.inverse_without_leg_limits(pose, joints);
  }
  Status forward(const JointVector&, geometry::Pose&) const override {
    return Status::failure(StatusCode::invalid_input);
  }
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override {
    return model_.jacobian(pose, d_joints_d_pose);
  }
  Status inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                              JointJacobian& d_joints_d_pose) const override {
    return model_.inverse_and_jacobian(pose, joints, d_joints_d_pose);
  }
  std::vector<Parameter> parameters() const override { return model_.parameters(); }
  void set_parameters(std::span<const double>) override {}
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<WithoutLegLimits>(std::make_shared<const Model>(model_));
  }

 private:
  std::shared_ptr<const Model> owned_;  // empty unless cloned
  const Model& model_;
};

// Shortest distance (mm) between the segments [p0, p1] and [q0, q1].
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                        const Eigen::Vector3d& q0, const Eigen::Vector3d& q1);

}  // namespace pkm::kinematics
