#include "pkm/kinematics/hexapod.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/lanes.hpp"

namespace pkm::kinematics {

namespace {
constexpr std::array<const char*, 3> kComponent = {"x", "y", "z"};

static_assert(sizeof(geometry::Pose) == geometry::kPoseSize * sizeof(double),
              "poses are read as 6 doubles");

// The squared lengths of the six legs (mm^2), from the tool position (mm) and the sines and
// cosines of A B C: one pose (T = double) or four (T = lanes::Lanes4). `platform` and `base` are
// the model's 3x6 column-major joint matrices (platform joints from the tool tip).
template <class T>
[[gnu::always_inline]] inline void squared_leg_lengths(const double* platform, const double* base,
                                                       const T (&position)[3], const T (&sines)[3],
                                                       const T (&cosines)[3], T (&squared)[6]) {
  T r[9];
  lanes::rotation_abc(sines, cosines, r);
  for (int leg = 0; leg < 6; ++leg) {
    const double* joint = platform + 3 * leg;
    const double* b = base + 3 * leg;
    T strut[3];  // tool side less base side
    for (int k = 0; k < 3; ++k) {
      const T from_base = position[k] - b[k];
      lanes::row_times_add(r + 3 * k, joint, from_base, strut[k]);
    }
    lanes::squared_norm(strut, squared[leg]);
  }
}

#if PKM_HAS_AVX2_LANES
// One pose's leg lengths (mm): the scalar arithmetic with the sines, cosines and square roots in
// vector registers.
PKM_AVX2 void leg_lengths_one_avx2(const double* platform, const double* base,
                                   const double* offsets, const geometry::Pose& pose,
                                   double* lengths) {
  double sines[3], cosines[3];
  lanes::sin_cos_3_avx2(pose.orientation_rad.data(), sines, cosines);
  const double position[3] = {pose.position_mm.x(), pose.position_mm.y(), pose.position_mm.z()};
  double squared[6];
  squared_leg_lengths(platform, base, position, sines, cosines, squared);
  lanes::sqrt_6_avx2(squared, lengths);
  for (int leg = 0; leg < 6; ++leg) lengths[leg] += offsets[leg];
}

// The leg lengths of one block of four poses from `first` on (`used` of them its own), with
// their statuses.
PKM_AVX2 void leg_lengths_block(const double* platform, const double* base, const double* offsets,
                                const lanes::PoseChunk& chunk, std::size_t block,
                                std::span<const geometry::Pose> poses, std::size_t first,
                                std::span<JointVector> joints, std::span<Status> statuses) {
  using lanes::Lanes4;
  const std::size_t used = chunk.used[block];
  const Lanes4 position[3] = {chunk.coordinates[block][0], chunk.coordinates[block][1],
                              chunk.coordinates[block][2]};
  Lanes4 lengths[6];
  squared_leg_lengths(platform, base, position, chunk.sines[block], chunk.cosines[block], lengths);
  int finite = 0b1111;  // bit k: pose k's legs are finite, so the pose is
  for (int leg = 0; leg < 6; ++leg) {
    lengths[leg] = lanes::sqrt(lengths[leg]) + offsets[leg];
    finite &= lanes::lanes_finite(lengths[leg]);
  }
  // A non-finite coordinate makes a leg non-finite; a finite pose far enough away can too.
  const bool all_valid = used == lanes::kLanes && finite == 0b1111;
  for (std::size_t k = 0; k < used; ++k) {
    const std::size_t i = first + k;
    statuses[i] = all_valid || all_finite(poses[i]) ? Status::success()
                                                    : Status::failure(StatusCode::invalid_input);
    joints[i].resize(6);
  }
  if (all_valid) {
    double* const rows[lanes::kLanes] = {joints[first].data(), joints[first + 1].data(),
                                         joints[first + 2].data(), joints[first + 3].data()};
    lanes::store_6_by_4(lengths, rows);
    return;
  }
  for (std::size_t k = 0; k < used; ++k) {
    if (!statuses[first + k].ok()) continue;
    for (int leg = 0; leg < 6; ++leg) joints[first + k][leg] = lengths[leg][k];
  }
}

// inverse_without_leg_limits of every pose, four at a time; a last partial block repeats its last
// pose in the spare lanes.
PKM_AVX2 void leg_lengths_avx2(const double* platform, const double* base, const double* offsets,
                               std::span<const geometry::Pose> poses, std::span<JointVector> joints,
                               std::span<Status> statuses) {
  lanes::PoseChunk chunk;
  for (std::size_t first = 0; first < poses.size();) {
    lanes::load_pose_chunk(poses[first].position_mm.data(), poses.size() - first, true, chunk);
    for (std::size_t block = 0; block < chunk.blocks; ++block) {
      leg_lengths_block(platform, base, offsets, chunk, block, poses, first, joints, statuses);
      first += chunk.used[block];
    }
  }
}
#endif
}  // namespace

HexapodGeometry HexapodGeometry::semi_regular(double base_radius_mm, double platform_radius_mm,
                                              double side_ratio, double tool_length_mm) {
  if (!(base_radius_mm > 0.0) || !(platform_radius_mm > 0.0)) {
    throw std::invalid_argument("hexagon radii must be positive");
  }
  if (!(side_ratio > 0.0) || !(side_ratio <= 1.0)) {
    throw std::invalid_argument("side_ratio (short:long side) must be in (0, 1]");
  }
  // Short and long sides subtend 2h and 120 deg - 2h; chord ratio sin(h) / sin(60 deg - h) = k.
  const double half_short_angle = std::atan(std::numbers::sqrt3 * side_ratio / (2.0 + side_ratio));
  const double third = 2.0 * std::numbers::pi / 3.0;
  HexapodGeometry geometry;
  geometry.tool_length_mm = tool_length_mm;
  for (int pair = 0; pair < 3; ++pair) {
    const double base_centre = third * pair;
    const double platform_before = base_centre - third / 2.0;  // platform pair on the left
    const double platform_after = base_centre + third / 2.0;   // platform pair on the right
    const double base_angles[2] = {base_centre - half_short_angle, base_centre + half_short_angle};
    const double platform_angles[2] = {platform_before + half_short_angle,
                                       platform_after - half_short_angle};
    for (int k = 0; k < 2; ++k) {
      geometry.base_mm[2 * pair + k] = {base_radius_mm * std::cos(base_angles[k]),
                                        base_radius_mm * std::sin(base_angles[k]), 0.0};
      geometry.platform_mm[2 * pair + k] = {platform_radius_mm * std::cos(platform_angles[k]),
                                            platform_radius_mm * std::sin(platform_angles[k]), 0.0};
    }
  }
  return geometry;
}

HexapodKinematics::HexapodKinematics(const HexapodGeometry& geometry,
                                     const LegLimitSettings& leg_limits)
    : leg_limits_(leg_limits, 6), geometry_(geometry) {
  update_derived();
}

void HexapodKinematics::update_derived() {
  if (!std::isfinite(geometry_.tool_length_mm)) {
    throw std::invalid_argument("tool_length must be finite");
  }
  for (int i = 0; i < 6; ++i) {
    if (!geometry_.base_mm[i].allFinite() || !geometry_.platform_mm[i].allFinite() ||
        !std::isfinite(geometry_.leg_offset_mm[i])) {
      throw std::invalid_argument("leg " + std::to_string(i + 1) + " has a non-finite joint");
    }
    platform_from_tip_mm_.col(i) = geometry_.platform_from_tip_mm(i);
    base_mm_.col(i) = geometry_.base_mm[i];
    leg_offset_mm_[i] = geometry_.leg_offset_mm[i];
  }
  // The base plane: the direction in which the base joints spread least. A base on one line (or
  // a point) has no plane, and no mirror image in it.
  const Eigen::Vector3d mean = base_mm_.rowwise().mean();
  const Eigen::Matrix<double, 3, 6> spread = base_mm_.colwise() - mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(spread * spread.transpose());
  const Eigen::Vector3d extent = axes.eigenvalues();  // ascending
  base_normal_ = extent[1] > 1e-12 * extent[2] ? Eigen::Vector3d(axes.eigenvectors().col(0))
                                               : Eigen::Vector3d::Zero();
  if (base_normal_.z() < 0.0) base_normal_ = -base_normal_;
  // A level base (every joint at one z, as most are) has the z axis itself: exactly.
  if (base_normal_ != Eigen::Vector3d::Zero() && (spread.row(2).array() == 0.0).all()) {
    base_normal_ = Eigen::Vector3d::UnitZ();
  }
  update_home_side();
}

void HexapodKinematics::update_home_side() {
  home_side_.fill(0.0);
  if (!home_ || !all_finite(*home_)) return;
  const LegEnds ends = leg_ends(*home_);
  const double size = (base_mm_.colwise() - base_mm_.rowwise().mean()).colwise().norm().maxCoeff();
  for (std::size_t leg = 0; leg < 6; ++leg) {
    const auto i = static_cast<Eigen::Index>(leg);
    const double rise = base_normal_.dot(ends.platform.col(i) - base_mm_.col(i));
    // A leg (all but) in the base plane at home tells no side.
    if (std::abs(rise) > 1e-9 * size) home_side_[leg] = rise > 0.0 ? 1.0 : -1.0;
  }
}

Eigen::Vector3d HexapodKinematics::normal_in_platform(const Eigen::Vector3d& abc_rad) const {
  if (base_normal_ == Eigen::Vector3d::UnitZ()) {
    // The last row of Rz(c) Ry(b) Rx(a): no c, two sines and cosines (the per-sample path).
    const double cos_b = std::cos(abc_rad.y());
    return {-std::sin(abc_rad.y()), cos_b * std::sin(abc_rad.x()), cos_b * std::cos(abc_rad.x())};
  }
  return geometry::rotation_from_abc(abc_rad).transpose() * base_normal_;
}

HexapodKinematics::BaseSide HexapodKinematics::base_side(const geometry::Pose& pose) const {
  BaseSide side;
  if (!home_) return side;
  const Eigen::Vector3d tilted = normal_in_platform(pose.orientation_rad);
  const double height = base_normal_.dot(pose.position_mm);
  for (int leg = 0; leg < 6; ++leg) {
    if (home_side_[static_cast<std::size_t>(leg)] == 0.0) continue;
    const double rise =
        height + tilted.dot(platform_from_tip_mm_.col(leg)) - base_normal_.dot(base_mm_.col(leg));
    const double margin = home_side_[static_cast<std::size_t>(leg)] * rise;
    if (!(margin >= side.margin_mm)) side = {margin, leg};
  }
  return side;
}

HexapodKinematics::BaseSideBound HexapodKinematics::base_side_bound(
    const geometry::Vector6d& centre, const geometry::Vector6d& half) const {
  BaseSideBound bound;
  if (!home_) return bound;
  const geometry::Pose middle = geometry::Pose::from_vector(centre);
  const Eigen::Vector3d tilted = normal_in_platform(middle.orientation_rad);
  const double height = base_normal_.dot(middle.position_mm);
  const double moves = base_normal_.cwiseAbs().dot(half.head<3>().cwiseAbs());
  const double turns = half.tail<3>().cwiseAbs().sum();
  for (int leg = 0; leg < 6; ++leg) {
    const double side = home_side_[static_cast<std::size_t>(leg)];
    if (side == 0.0) continue;
    const double margin = side * (height + tilted.dot(platform_from_tip_mm_.col(leg)) -
                                  base_normal_.dot(base_mm_.col(leg)));
    const double change = moves + platform_from_tip_mm_.col(leg).norm() * turns;
    if (!(margin - change >= bound.low)) bound = {margin - change, margin + change, leg};
  }
  return bound;
}

Status HexapodKinematics::inverse_without_leg_limits(const geometry::Pose& pose,
                                                     JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  joints.resize(6);
#if PKM_HAS_AVX2_LANES
  if (lanes::avx2_enabled()) {
    leg_lengths_one_avx2(platform_from_tip_mm_.data(), base_mm_.data(), leg_offset_mm_.data(), pose,
                         joints.data());
    return Status::success();
  }
#endif
  double sines[3], cosines[3];
  lanes::sin_cos_3(pose.orientation_rad.data(), sines, cosines);
  const double position[3] = {pose.position_mm.x(), pose.position_mm.y(), pose.position_mm.z()};
  double squared[6];
  squared_leg_lengths(platform_from_tip_mm_.data(), base_mm_.data(), position, sines, cosines,
                      squared);
  for (int leg = 0; leg < 6; ++leg) joints[leg] = std::sqrt(squared[leg]) + leg_offset_mm_[leg];
  return Status::success();
}

Status HexapodKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  const Status status = inverse_without_leg_limits(pose, joints);
  if (!status.ok() || !leg_limits_.active()) return status;
  return leg_limits_.check(leg_ends(pose));
}

LegEnds HexapodKinematics::leg_ends(const geometry::Pose& pose) const {
  LegEnds ends;
  ends.rotation = geometry::rotation_from_abc(pose.orientation_rad);
  ends.inner = base_mm_;
  ends.platform = (ends.rotation * platform_from_tip_mm_).colwise() + pose.position_mm;
  return ends;
}

void HexapodKinematics::set_home(const geometry::Pose& home) {
  if (leg_limits_.active() && all_finite(home)) leg_limits_.set_home(leg_ends(home));
  home_ = home;
  update_home_side();
}

void HexapodKinematics::mechanism_limits(const geometry::Pose& pose,
                                         std::vector<MechanismLimit>& out) const {
  if (leg_limits_.active() && all_finite(pose)) leg_limits_.append_values(leg_ends(pose), out);
}

std::string HexapodKinematics::why_refused(const geometry::Pose& pose, const Status& status) const {
  if (!all_finite(pose)) return {};

  return leg_limits_.why(leg_ends(pose), status, "leg");
}

void HexapodKinematics::inverse_batch(std::span<const geometry::Pose> poses,
                                      std::span<JointVector> joints,
                                      std::span<Status> statuses) const {
  if (joints.size() < poses.size() || statuses.size() < poses.size()) {
    throw std::invalid_argument("inverse_batch: output spans shorter than the input");
  }
#if PKM_HAS_AVX2_LANES
  if (lanes::avx2_enabled()) {
    leg_lengths_avx2(platform_from_tip_mm_.data(), base_mm_.data(), leg_offset_mm_.data(), poses,
                     joints, statuses);
    if (leg_limits_.active()) {
      for (std::size_t i = 0; i < poses.size(); ++i) {
        if (statuses[i].ok()) statuses[i] = leg_limits_.check(leg_ends(poses[i]));
      }
    }
    return;
  }
#endif
  // Along a path with a fixed tool attitude (the paper's "fixed attitude mode") the rotated
  // platform, less the base, is the same for every pose: each leg is then one vector sum and a
  // norm. The rotation's sines and cosines are most of the cost of a pose with a varying attitude.
  Eigen::Vector3d rotation_angles = Eigen::Vector3d::Constant(std::nan(""));
  Eigen::Matrix<double, 3, 6> rotated_from_base;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const geometry::Pose& pose = poses[i];
    if (!all_finite(pose)) {
      statuses[i] = Status::failure(StatusCode::invalid_input);
      continue;
    }
    if (pose.orientation_rad != rotation_angles) {
      rotation_angles = pose.orientation_rad;
      rotated_from_base =
          geometry::rotation_from_abc(rotation_angles) * platform_from_tip_mm_ - base_mm_;
    }
    joints[i] = (rotated_from_base.colwise() + pose.position_mm).colwise().norm().transpose() +
                leg_offset_mm_;
    statuses[i] = leg_limits_.active() ? leg_limits_.check(leg_ends(pose)) : Status::success();
  }
}

Status HexapodKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  if (joints.size() != 6) return Status::failure(StatusCode::invalid_input);
  if (!leg_limits_.active())
    return solve_forward_newton(*this, joints, pose_inout, forward_options_);
  geometry::Pose solved = pose_inout;
  Status status = solve_forward_newton(WithoutLegLimits<HexapodKinematics>(*this), joints, solved,
                                       forward_options_);
  if (status.ok()) {
    const int iterations = status.iterations;
    status = leg_limits_.check(leg_ends(solved));
    status.iterations = iterations;
  }
  if (status.ok()) pose_inout = solved;
  return status;
}

Status HexapodKinematics::inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                                               JointJacobian& d_joints_d_pose) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  Eigen::Matrix3d rotation;
  std::array<Eigen::Matrix3d, 3> rotation_derivatives;
  geometry::rotation_and_derivatives_abc(pose.orientation_rad, rotation, rotation_derivatives);
  joints.resize(6);
  d_joints_d_pose.resize(6, geometry::kPoseSize);
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d leg =
        pose.position_mm + rotation * platform_from_tip_mm_.col(i) - base_mm_.col(i);
    const double length = leg.norm();
    if (length == 0.0) return Status::failure(StatusCode::singular, i);
    joints[i] = length + leg_offset_mm_[i];
    const Eigen::Vector3d unit = leg / length;
    d_joints_d_pose.block<1, 3>(i, 0) = unit.transpose();
    for (int k = 0; k < 3; ++k) {
      d_joints_d_pose(i, 3 + k) = unit.dot(rotation_derivatives[k] * platform_from_tip_mm_.col(i));
    }
  }
  return Status::success();
}

double HexapodKinematics::tilt_low(const geometry::Vector6d& centre,
                                   const geometry::Vector6d& half) {
  const auto least_cos = [&](int axis) {
    const double lo = centre[axis] - std::abs(half[axis]), hi = centre[axis] + std::abs(half[axis]);
    if (!(lo > -std::numbers::pi && hi < std::numbers::pi)) return -1.0;
    return std::min(std::cos(lo), std::cos(hi));
  };
  const double a = least_cos(3), b = least_cos(4);
  return a > 0.0 && b > 0.0 ? a * b : -1.0;
}

int HexapodKinematics::assembly_mode(const geometry::Pose& pose) const {
  if (!(base_side(pose).margin_mm > 0.0)) return -1;
  // Every machine tilts less than 90 deg about X and Y: no cosine needed there.
  constexpr double kQuarterTurn = std::numbers::pi / 2.0;
  if (std::abs(pose.orientation_rad.x()) < kQuarterTurn &&
      std::abs(pose.orientation_rad.y()) < kQuarterTurn) {
    return 1;
  }
  const double normal_z = std::cos(pose.orientation_rad.x()) * std::cos(pose.orientation_rad.y());
  return normal_z > 0.0 ? 1 : -1;
}

Status HexapodKinematics::jacobian(const geometry::Pose& pose,
                                   JointJacobian& d_joints_d_pose) const {
  JointVector joints;
  return inverse_and_jacobian(pose, joints, d_joints_d_pose);
}

std::vector<Parameter> HexapodKinematics::parameters() const {
  std::vector<Parameter> result;
  for (int i = 0; i < 6; ++i) {
    const std::string prefix = "leg" + std::to_string(i + 1) + ".";
    for (int k = 0; k < 3; ++k) {
      result.push_back({prefix + "base." + kComponent[k],
                        geometry_.base_mm[i][k],
                        "mm",
                        {"a base joint", BuiltTolerance::machine_size}});
    }
    for (int k = 0; k < 3; ++k) {
      result.push_back({prefix + "platform." + kComponent[k],
                        geometry_.platform_mm[i][k],
                        "mm",
                        {"a platform joint", BuiltTolerance::machine_size}});
    }
    result.push_back({prefix + "offset",
                      geometry_.leg_offset_mm[i],
                      "mm",
                      {"a leg's zero", BuiltTolerance::machine_size}});
  }
  result.push_back({"tool_length",
                    geometry_.tool_length_mm,
                    "mm",
                    {"the tool's length", BuiltTolerance::machine_size}});
  return result;
}

void HexapodKinematics::set_parameters(std::span<const double> values) {
  constexpr std::size_t kPerLeg = 7;
  if (values.size() != 6 * kPerLeg + 1) {
    throw std::invalid_argument("hexapod takes " + std::to_string(6 * kPerLeg + 1) + " parameters");
  }
  HexapodGeometry geometry = geometry_;
  for (int i = 0; i < 6; ++i) {
    const double* v = values.data() + kPerLeg * i;
    geometry.base_mm[i] = {v[0], v[1], v[2]};
    geometry.platform_mm[i] = {v[3], v[4], v[5]};
    geometry.leg_offset_mm[i] = v[6];
  }
  geometry.tool_length_mm = values[6 * kPerLeg];
  const HexapodGeometry previous = geometry_;
  geometry_ = geometry;
  try {
    update_derived();
  } catch (...) {
    geometry_ = previous;
    update_derived();
    throw;
  }
}

std::unique_ptr<Kinematics> make_hexapod_kinematics(const ModelConfig& config) {
  const bool explicit_joints = config.has("base") || config.has("platform");
  const bool shorthand =
      config.has("base_radius") || config.has("platform_radius") || config.has("side_ratio");
  if (explicit_joints && shorthand) {
    config.fail(config.has("base_radius") ? "base_radius" : "side_ratio",
                "give either base/platform joint lists or the base_radius/platform_radius/"
                "side_ratio shorthand, not both");
  }
  const double tool_length = config.length("tool_length");
  HexapodGeometry geometry;
  if (shorthand) {
    try {
      geometry = HexapodGeometry::semi_regular(config.length("base_radius"),
                                               config.length("platform_radius"),
                                               config.number("side_ratio"), tool_length);
    } catch (const std::invalid_argument& error) {
      config.fail("side_ratio", error.what());
    }
  } else {
    const auto base = config.length_vector3_list("base");
    const auto platform = config.length_vector3_list("platform");
    if (base.size() != 6) config.fail("base", "needs exactly 6 points [x, y, z]");
    if (platform.size() != 6) config.fail("platform", "needs exactly 6 points [x, y, z]");
    for (int i = 0; i < 6; ++i) {
      geometry.base_mm[i] = base[i];
      geometry.platform_mm[i] = platform[i];
    }
    geometry.tool_length_mm = tool_length;
  }
  const LegLimitSettings leg_limits = read_leg_limit_settings(config, "base_joint_axis");
  if (config.has("leg_offsets")) {
    const std::vector<double> offsets = config.length_list("leg_offsets");
    if (offsets.size() != 6) config.fail("leg_offsets", "needs exactly 6 lengths");
    for (int i = 0; i < 6; ++i) geometry.leg_offset_mm[i] = offsets[i];
  }
  try {
    return std::make_unique<HexapodKinematics>(geometry, leg_limits);
  } catch (const std::invalid_argument& error) {
    config.fail(shorthand ? "base_radius" : "base", error.what());
  }
}

void HexapodKinematics::write_config(ModelConfigWriter& out) const {
  out.length_vector3_list("base", geometry_.base_mm);
  out.length_vector3_list("platform", geometry_.platform_mm);
  out.length("tool_length", geometry_.tool_length_mm);
  out.length_list("leg_offsets", geometry_.leg_offset_mm);
  write_leg_limit_settings(leg_limits_.settings(), "base_joint_axis", out);
}

void HexapodKinematics::fixed_parts(std::span<const JointTravel> /*travel*/,
                                    std::vector<SketchLine>& out) const {
  sketch_loop(out, SketchPart::frame, {geometry_.base_mm.begin(), geometry_.base_mm.end()});
}

void HexapodKinematics::moving_parts(const geometry::Pose& pose, const JointVector& /*joints*/,
                                     std::vector<SketchLine>& out) const {
  const Eigen::Matrix3d rotation = geometry::rotation_from_abc(pose.orientation_rad);
  const Eigen::Vector3d up(0.0, 0.0, geometry_.tool_length_mm);
  const Eigen::Vector3d centre = pose.position_mm + rotation * up;
  std::vector<Eigen::Vector3d> platform_joints;
  for (std::size_t i = 0; i < 6; ++i) {
    platform_joints.push_back(pose.position_mm + rotation * geometry_.platform_from_tip_mm(i));
    out.push_back({SketchPart::link, geometry_.base_mm[i], platform_joints.back()});
  }
  sketch_loop(out, SketchPart::platform, platform_joints);
  out.push_back({SketchPart::tool, centre, pose.position_mm});
}

}  // namespace pkm::kinematics
