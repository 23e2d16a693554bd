// Stewart/Gough hexapod: six telescopic legs between base joints (world frame) and platform
// joints (platform frame). The tool tip is at (0, 0, -tool_length) in the platform frame. Its
// assembly mode: the platform's tilt below 90 deg and each platform joint on home's side of the
// base plane, with one bound over a box of poses that certify and workspace share.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <optional>

#include "pkm/kinematics/assembly_mode_bounds.hpp"
#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/leg_limits.hpp"
#include "pkm/kinematics/mechanism_sketch.hpp"
#include "pkm/kinematics/model_config.hpp"

namespace pkm::kinematics {

struct HexapodGeometry {
  std::array<Eigen::Vector3d, 6> base_mm;      // base joint centres, world frame
  std::array<Eigen::Vector3d, 6> platform_mm;  // platform joint centres, platform frame
  double tool_length_mm = 0.0;
  // Added to each leg's geometric length (joint centre to joint centre) to give its joint reading.
  std::array<double, 6> leg_offset_mm{};

  // Platform joint `leg` measured from the tool tip, platform frame: where R acts (mm).
  Eigen::Vector3d platform_from_tip_mm(std::size_t leg) const {
    return platform_mm[leg] + Eigen::Vector3d(0.0, 0.0, tool_length_mm);
  }

  // The semi-regular hexagons of the literature: joints on circles of the given radii, in pairs
  // whose short side is `side_ratio` times the long side; the platform's pairs sit 60 deg from
  // the base's so that each base pair feeds two different platform pairs. Base pair k is centred
  // at 120*k deg from +X; leg 2k joins that pair's first joint, leg 2k+1 its second.
  static HexapodGeometry semi_regular(double base_radius_mm, double platform_radius_mm,
                                      double side_ratio, double tool_length_mm);
};

class HexapodKinematics final : public Kinematics,
                                public MechanismSketch,
                                public DerivativeBounds,
                                public AssemblyModeBounds {
 public:
  explicit HexapodKinematics(const HexapodGeometry& geometry,
                             const LegLimitSettings& leg_limits = {});

  std::string_view type() const override { return "hexapod"; }
  int joint_count() const override { return 6; }
  geometry::Dof dof() const override { return geometry::Dof::all(); }
  // The legs' lengths, then the leg limits (max_joint_angle, leg_diameter) where the file sets
  // them.
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  Status inverse_without_leg_limits(const geometry::Pose& pose, JointVector& joints) const;
  // jacobian and inverse_and_jacobian do not check the leg limits: they serve the iterations of
  // forward kinematics, whose answer forward() checks.
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  Status inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                              JointJacobian& d_joints_d_pose) const override;
  // +1 while the platform is tilted less than 90 deg from the base (cos A cos B > 0, the z of its
  // normal) and every platform joint stays on home's side of the base plane (base_side below),
  // -1 otherwise: an upside-down platform (B = 180) and the mirror image of the machine in its
  // base plane (the platform below the base, same leg lengths) are other assembly modes, which
  // the machine cannot reach from home without passing a singularity (with the platform in the
  // base plane every leg lies in it and nothing holds the platform up or down).
  int assembly_mode(const geometry::Pose& pose) const override;
  // How far the platform stands on home's side of the base plane (mm): the least over the legs
  // of (platform joint - base joint) . n, n the normal of the plane through the base joints,
  // signed by that leg's side at home. Legs in the plane at home, or a base whose joints lie on
  // one line, take no part (+infinity without any leg, and before set_home).
  using BaseSide = BasePlaneMargin;
  BaseSide base_side(const geometry::Pose& pose) const;
  BasePlaneMargin base_plane_margin(const geometry::Pose& pose) const override {
    return base_side(pose);
  }
  // Bounds on base_side's margin over every pose within centre +- half (mm, rad), and the leg of
  // the least low bound: (n . position) moves by at most sum |n_k| half_k over the box, and a
  // platform joint at distance q from the tool tip by at most q (|half a| + |half b| + |half c|)
  // (the angular speed of R = Rz Ry Rx is at most the sum of its angles' speeds).
  struct BaseSideBound {
    double low = INFINITY, high = INFINITY;
    int leg = -1;
  };
  BaseSideBound base_side_bound(const geometry::Vector6d& centre,
                                const geometry::Vector6d& half) const;
  // A lower bound on cos a cos b (the z of the platform's normal) over centre +- half: each
  // cosine is least at the end of its interval farther from 0 (-1 once an interval reaches pi).
  static double tilt_low(const geometry::Vector6d& centre, const geometry::Vector6d& half);
  std::string why_refused(const geometry::Pose& pose, const Status& status) const override;
  void set_home(const geometry::Pose& home) override;
  bool has_mechanism_limits() const override { return leg_limits_.active(); }
  void mechanism_limits(const geometry::Pose& pose,
                        std::vector<MechanismLimit>& out) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<HexapodKinematics>(*this);
  }
  // Four poses at a time where AVX2 runs (lanes.hpp); elsewhere pose by pose, the rotation
  // computed once while the attitude stays (the paper's fixed-attitude mode).
  void inverse_batch(std::span<const geometry::Pose> poses, std::span<JointVector> joints,
                     std::span<Status> statuses) const override;

  // base, platform, tool_length, leg_offsets, then the leg limits.
  void write_config(ModelConfigWriter& out) const override;
  const LegLimitSettings* leg_limit_settings() const override {
    return leg_limits_.active() ? &leg_limits_.settings() : nullptr;
  }
  // The drawing: the base hexagon; the legs, the platform's hexagon and the tool.
  const MechanismSketch* sketch() const override { return this; }
  void fixed_parts(std::span<const JointTravel> travel,
                   std::vector<SketchLine>& out) const override;
  void moving_parts(const geometry::Pose& pose, const JointVector& joints,
                    std::vector<SketchLine>& out) const override;

  // The proofs' capabilities (hexapod_bounds.cpp): the legs' Hessian and third-derivative
  // bounds, the legs; the assembly mode over a box (tilt_low, base_side_bound).
  const DerivativeBounds* derivative_bounds() const override { return this; }
  std::optional<HessianBounds> own_hessian_bounds(const geometry::Vector6d& centre,
                                                  double radius_mm, double angle_scale_mm,
                                                  const Chord& chord) const override;
  std::optional<double> farthest_platform_point_mm() const override;
  LegMotion leg_motion(const JointVector& joints, const JointJacobian& jacobian,
                       const HessianBounds& hessians, double radius, double scale) const override;
  std::optional<LegEnds> legs_at(const geometry::Pose& pose,
                                 const JointVector& joints) const override;
  const AssemblyModeBounds* assembly_mode_bounds() const override { return this; }
  bool has_mode_over_box() const override { return true; }
  std::optional<ModeShortfall> mode_over_box(int home_mode, const geometry::Vector6d& centre,
                                             const geometry::Vector6d& half) const override;
  // Reach box (kinematics.hpp; hexapod_reach.cpp).
  std::optional<Eigen::AlignedBox3d> tool_position_box(const JointVector& joint_min,
                                                       const JointVector& joint_max) const override;

  const HexapodGeometry& geometry() const { return geometry_; }
  const LegLimits& leg_limits() const { return leg_limits_; }
  // The legs' joint centres at a pose (what the leg limits judge).
  LegEnds leg_ends(const geometry::Pose& pose) const;

 private:
  void update_derived();
  // home_side_ from home_ (none without a home).
  void update_home_side();
  // The base plane's normal in the platform frame at these angles: R^T n.
  Eigen::Vector3d normal_in_platform(const Eigen::Vector3d& abc_rad) const;
  LegLimits leg_limits_;
  HexapodGeometry geometry_;
  // Columns: platform joints measured from the tool tip, platform frame (platform + (0, 0,
  // tool_length)); base joints, world frame; leg offsets. Matrix form lets Eigen do the six legs
  // as one product.
  Eigen::Matrix<double, 3, 6> platform_from_tip_mm_;
  Eigen::Matrix<double, 3, 6> base_mm_;
  Eigen::Matrix<double, 6, 1> leg_offset_mm_;
  // The base plane's unit normal (zero where the base joints lie on one line), and each leg's
  // side of it at home: +1, -1, or 0 (in the plane, or no home yet).
  Eigen::Vector3d base_normal_ = Eigen::Vector3d::Zero();
  std::array<double, 6> home_side_{};
  std::optional<geometry::Pose> home_;
};

std::unique_ptr<Kinematics> make_hexapod_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
