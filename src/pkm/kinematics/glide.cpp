#include "pkm/kinematics/glide.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "pkm/kinematics/closed_form_text.hpp"
#include "pkm/kinematics/lanes.hpp"

namespace pkm::kinematics {

namespace {
// A strut closer than this (relative) to perpendicular to its rail is at a singularity: the
// carriage's motion no longer moves the platform.
constexpr double kMinRelativeDiscriminant = 1e-12;

constexpr std::array<const char*, 3> kComponent = {"x", "y", "z"};

static_assert(sizeof(geometry::Pose) == geometry::kPoseSize * sizeof(double),
              "poses are read as 6 doubles");

// The carriage reading `along` (mm) where the strut's foot projects onto the rail, and the
// discriminant (mm^2) whose root is how far either way of it the carriage sits: one pose (T =
// double) or four (T = lanes::Lanes4). `rotation` is row-major R, or null for a translating
// platform.
template <class T>
[[gnu::always_inline]] inline void rail_solution(const GlideRail& rail, const T* rotation,
                                                 const T (&position)[3], T& along,
                                                 T& discriminant) {
  T foot[3];
  if (rotation != nullptr) {
    T turned[3];
    lanes::rotate(rotation, rail.attach_mm.data(), turned);
    for (int k = 0; k < 3; ++k) foot[k] = position[k] + turned[k] - rail.origin_mm[k];
  } else {
    for (int k = 0; k < 3; ++k) foot[k] = position[k] + rail.attach_mm[k] - rail.origin_mm[k];
  }
  along = rail.direction[0] * foot[0] + rail.direction[1] * foot[1] + rail.direction[2] * foot[2];
  // strut^2 less the foot's squared distance from the rail, from its component across the rail:
  // along^2 - |foot|^2 would cancel two large squares where the foot is far along the rail.
  T across[3];
  for (int k = 0; k < 3; ++k) across[k] = foot[k] - along * rail.direction[k];
  discriminant = rail.strut_mm * rail.strut_mm -
                 (across[0] * across[0] + across[1] * across[1] + across[2] * across[2]);
}

// The singular margin of a rail: a discriminant at or below it is refused.
double singular_discriminant(const GlideRail& rail) {
  return kMinRelativeDiscriminant * rail.strut_mm * rail.strut_mm;
}

// Why rail `i` with this discriminant has no carriage reading (ok where it has one).
Status rail_status(const GlideRail& rail, int i, double discriminant) {
  // Written to refuse NaN too: a pose far enough away overflows the squares (inf - inf).
  if (!(discriminant >= 0.0)) return Status::failure(StatusCode::unreachable, i);
  if (discriminant <= singular_discriminant(rail)) return Status::failure(StatusCode::singular, i);
  return Status::success();
}

// Every rail's `along` and discriminant for one pose (`part`: its controlled coordinates), and
// the first rail's refusal, if any. At most six rails.
[[gnu::always_inline]] inline Status rails_before_roots(std::span<const GlideRail> rails,
                                                        const double* rotation,
                                                        const geometry::Pose& part, double* along,
                                                        double* discriminant) {
  const double position[3] = {part.position_mm.x(), part.position_mm.y(), part.position_mm.z()};
  for (std::size_t i = 0; i < rails.size(); ++i) {
    rail_solution(rails[i], rotation, position, along[i], discriminant[i]);
    const Status status = rail_status(rails[i], static_cast<int>(i), discriminant[i]);
    if (!status.ok()) return status;
  }
  return Status::success();
}

#if PKM_HAS_AVX2_LANES
// One pose's rail readings, four rails at a time in vector lanes: rail_solution's arithmetic,
// operation for operation (no fused multiply-add), so bit for bit the scalar path's readings;
// the first rail without a reading refuses, as rails_before_roots does.
PKM_AVX2 Status rail_readings_one_avx2(const GlideKinematics::RailsSideBySide& side,
                                       std::span<const GlideRail> rails, bool rotates,
                                       const geometry::Pose& part, JointVector& joints) {
  static_assert(kMaxJoints >= 8, "two blocks of four rails' readings fit in a JointVector");
  using lanes::Lanes4;
  double rotation[9] = {};
  if (rotates) {
    double sines[3], cosines[3];
    lanes::sin_cos_3_avx2(part.orientation_rad.data(), sines, cosines);
    lanes::rotation_abc(sines, cosines, rotation);
  }
  const int rail_count = static_cast<int>(rails.size());
  alignas(32) double discriminant[GlideKinematics::RailsSideBySide::kSlots];
  int refused = 0;  // bit i: rail i has no reading
  for (int first = 0; first < rail_count; first += lanes::kLanes) {
    Lanes4 foot[3];
    for (int k = 0; k < 3; ++k) {
      const Lanes4 turned =
          rotates ? rotation[3 * k] * _mm256_load_pd(side.attach_mm[0] + first) +
                        rotation[3 * k + 1] * _mm256_load_pd(side.attach_mm[1] + first) +
                        rotation[3 * k + 2] * _mm256_load_pd(side.attach_mm[2] + first)
                  : _mm256_load_pd(side.attach_mm[k] + first);
      foot[k] = part.position_mm[k] + turned - _mm256_load_pd(side.origin_mm[k] + first);
    }
    const Lanes4 direction[3] = {_mm256_load_pd(side.direction[0] + first),
                                 _mm256_load_pd(side.direction[1] + first),
                                 _mm256_load_pd(side.direction[2] + first)};
    const Lanes4 along = direction[0] * foot[0] + direction[1] * foot[1] + direction[2] * foot[2];
    Lanes4 across[3];
    for (int k = 0; k < 3; ++k) across[k] = foot[k] - along * direction[k];
    const Lanes4 disc = _mm256_load_pd(side.strut_squared_mm2 + first) -
                        (across[0] * across[0] + across[1] * across[1] + across[2] * across[2]);
    _mm256_store_pd(discriminant + first, disc);
    refused |= lanes::lanes_not_above(disc, _mm256_load_pd(side.singular_mm2 + first)) << first;
    // Spare lanes land in the joints' spare capacity, where pass-through joints go next.
    _mm256_storeu_pd(joints.data() + first,
                     along + _mm256_load_pd(side.branch + first) * lanes::sqrt(disc));
  }
  refused &= (1 << rail_count) - 1;
  if (refused == 0) return Status::success();
  const int i = std::countr_zero(static_cast<unsigned>(refused));  // the first refusing rail
  return rail_status(rails[static_cast<std::size_t>(i)], i, discriminant[i]);
}

// The rails' readings of one block of four poses from `first` on (statuses: invalid input, a
// rail's refusal, or ok); pass-through joints and leg limits are the caller's. Uncontrolled
// coordinates read as 0.
PKM_AVX2 void rail_readings_block(std::span<const GlideRail> rails, geometry::Dof dof,
                                  const lanes::PoseChunk& chunk, std::size_t block,
                                  std::span<const geometry::Pose> poses, std::size_t first,
                                  std::span<JointVector> joints, std::span<Status> statuses,
                                  int joint_count) {
  using lanes::Lanes4;
  const int rail_count = static_cast<int>(rails.size());
  Lanes4 position[3];
  for (int axis = 0; axis < 3; ++axis) {
    position[axis] = dof.controls(axis) ? chunk.coordinates[block][axis] : lanes::zero();
  }
  Lanes4 rotation[9] = {};
  if (dof.any_rotation()) lanes::rotation_abc(chunk.sines[block], chunk.cosines[block], rotation);
  Lanes4 along[6], discriminant[6], reading[6];
  int refused = 0;  // bit k: pose k has a rail without a reading
  for (int i = 0; i < rail_count; ++i) {
    const GlideRail& rail = rails[static_cast<std::size_t>(i)];
    rail_solution(rail, dof.any_rotation() ? rotation : nullptr, position, along[i],
                  discriminant[i]);
    refused |= lanes::lanes_not_above(discriminant[i], singular_discriminant(rail));
    reading[i] = along[i] + rail.branch * lanes::sqrt(discriminant[i]);
  }
  for (std::size_t k = 0; k < chunk.used[block]; ++k) {
    const std::size_t p = first + k;
    Status& status = statuses[p];
    status = all_finite(poses[p]) ? Status::success() : Status::failure(StatusCode::invalid_input);
    for (int i = 0; status.ok() && (refused >> k & 1) != 0 && i < rail_count; ++i) {
      status = rail_status(rails[static_cast<std::size_t>(i)], i, discriminant[i][k]);
    }
    if (!status.ok()) continue;
    joints[p].resize(joint_count);
    for (int i = 0; i < rail_count; ++i) joints[p][i] = reading[i][k];
  }
}

// rail_readings_block over every pose, a chunk of blocks at a time; a last partial block repeats
// its last pose in the spare lanes.
PKM_AVX2 void rail_readings_avx2(std::span<const GlideRail> rails, geometry::Dof dof,
                                 std::span<const geometry::Pose> poses,
                                 std::span<JointVector> joints, std::span<Status> statuses,
                                 int joint_count) {
  lanes::PoseChunk chunk;
  for (std::size_t first = 0; first < poses.size();) {
    lanes::load_pose_chunk(poses[first].position_mm.data(), poses.size() - first,
                           dof.any_rotation(), chunk);
    for (std::size_t block = 0; block < chunk.blocks; ++block) {
      rail_readings_block(rails, dof, chunk, block, poses, first, joints, statuses, joint_count);
      first += chunk.used[block];
    }
  }
}
#endif
}  // namespace

GlideKinematics::GlideKinematics(std::vector<GlideRail> rails, geometry::Dof dof,
                                 PassThroughAxes passthrough, const LegLimitSettings& leg_limits)
    : rails_(std::move(rails)), dof_(dof), passthrough_(std::move(passthrough)) {
  leg_limits_ = LegLimits(leg_limits, static_cast<int>(rails_.size()));
  validate(rails_, dof_);
  update_side_by_side();
  if (passthrough_.count() > 0 && dof_.any_rotation()) {
    throw std::invalid_argument("only a translating glide carries pass-through joints");
  }
  for (const int axis : passthrough_.axes()) {
    if (dof_.controls(axis)) {
      throw std::invalid_argument("the rails move " + std::string(geometry::kAxisNames[axis]) +
                                  " themselves");
    }
  }
}

void GlideKinematics::validate(std::vector<GlideRail>& rails, geometry::Dof dof) {
  const int count = static_cast<int>(rails.size());
  if (dof == geometry::Dof::all()) {
    if (count != 6) throw std::invalid_argument("a glide with orientation needs exactly 6 rails");
  } else if (dof.any_rotation() || dof.count() != count || count < 2 || count > 3) {
    throw std::invalid_argument("a translating glide needs 2 or 3 rails, one per controlled axis");
  }
  for (int i = 0; i < count; ++i) {
    GlideRail& rail = rails[i];
    const std::string which = "rail " + std::to_string(i + 1);
    if (!rail.origin_mm.allFinite() || !rail.attach_mm.allFinite() || !rail.direction.allFinite() ||
        !std::isfinite(rail.strut_mm)) {
      throw std::invalid_argument(which + " has a non-finite value");
    }
    const double norm = rail.direction.norm();
    if (norm == 0.0) throw std::invalid_argument(which + ": direction is the zero vector");
    rail.direction /= norm;
    if (!(rail.strut_mm > 0.0)) throw std::invalid_argument(which + ": strut must be positive");
    if (rail.branch != 1 && rail.branch != -1) {
      throw std::invalid_argument(which + ": branch must be +1 or -1");
    }
  }
}

geometry::Pose GlideKinematics::controlled_part(const geometry::Pose& pose) const {
  geometry::Pose part;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!dof_.controls(axis)) continue;
    if (axis < 3) {
      part.position_mm[axis] = pose.position_mm[axis];
    } else {
      part.orientation_rad[axis - 3] = pose.orientation_rad[axis - 3];
    }
  }
  return part;
}

Status GlideKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  const Status status = inverse_without_leg_limits(pose, joints);
  if (!status.ok() || !leg_limits_.active()) return status;
  return leg_limits_.check(leg_ends(pose, joints));
}

LegEnds GlideKinematics::leg_ends(const geometry::Pose& pose, const JointVector& joints) const {
  const geometry::Pose part = controlled_part(pose);
  LegEnds ends;
  if (dof_.any_rotation()) ends.rotation = geometry::rotation_from_abc(part.orientation_rad);
  ends.inner.resize(3, rail_count());
  ends.platform.resize(3, rail_count());
  for (int i = 0; i < rail_count(); ++i) {
    const GlideRail& rail = rails_[static_cast<std::size_t>(i)];
    ends.inner.col(i) = rail.origin_mm + joints[i] * rail.direction;
    ends.platform.col(i) = part.position_mm + ends.rotation * rail.attach_mm;
  }
  return ends;
}

void GlideKinematics::set_home(const geometry::Pose& home) {
  JointVector joints;
  if (leg_limits_.active() && inverse_without_leg_limits(home, joints).ok()) {
    leg_limits_.set_home(leg_ends(home, joints));
  }
}

void GlideKinematics::mechanism_limits(const geometry::Pose& pose,
                                       std::vector<MechanismLimit>& out) const {
  JointVector joints;
  if (leg_limits_.active() && inverse_without_leg_limits(pose, joints).ok()) {
    leg_limits_.append_values(leg_ends(pose, joints), out);
  }
}

std::string GlideKinematics::leg_limits_why(const geometry::Pose& pose,
                                            const Status& status) const {
  JointVector joints;
  if (!leg_limits_.active() || !inverse_without_leg_limits(pose, joints).ok()) return {};
  return leg_limits_.why(leg_ends(pose, joints), status, "strut");
}

Status GlideKinematics::inverse_without_leg_limits(const geometry::Pose& pose,
                                                   JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  const geometry::Pose part = controlled_part(pose);
  joints.resize(joint_count());
  Status status;
#if PKM_HAS_AVX2_LANES
  if (lanes::avx2_enabled()) {
    status = rail_readings_one_avx2(side_by_side_, rails_, dof_.any_rotation(), part, joints);
  } else
#endif
  {
    double rotation[9] = {};
    if (dof_.any_rotation()) {
      double sines[3], cosines[3];
      lanes::sin_cos_3(part.orientation_rad.data(), sines, cosines);
      lanes::rotation_abc(sines, cosines, rotation);
    }
    double along[6] = {}, discriminant[6] = {};
    status = rails_before_roots(rails_, dof_.any_rotation() ? rotation : nullptr, part, along,
                                discriminant);
    for (int i = 0; status.ok() && i < rail_count(); ++i) {
      joints[i] =
          along[i] + rails_[static_cast<std::size_t>(i)].branch * std::sqrt(discriminant[i]);
    }
  }
  if (!status.ok()) return status;
  passthrough_.inverse(pose, joints, rail_count());
  return Status::success();
}

void GlideKinematics::inverse_batch(std::span<const geometry::Pose> poses,
                                    std::span<JointVector> joints,
                                    std::span<Status> statuses) const {
#if PKM_HAS_AVX2_LANES
  if (lanes::avx2_enabled()) {
    if (joints.size() < poses.size() || statuses.size() < poses.size()) {
      throw std::invalid_argument("inverse_batch: output spans shorter than the input");
    }
    rail_readings_avx2(rails_, dof_, poses, joints, statuses, joint_count());
    for (std::size_t p = 0; p < poses.size(); ++p) {
      if (!statuses[p].ok()) continue;
      passthrough_.inverse(poses[p], joints[p], rail_count());
      if (leg_limits_.active()) statuses[p] = leg_limits_.check(leg_ends(poses[p], joints[p]));
    }
    return;
  }
#endif
  Kinematics::inverse_batch(poses, joints, statuses);
}

Status GlideKinematics::inverse_and_jacobian(const geometry::Pose& pose, JointVector& joints,
                                             JointJacobian& d_joints_d_pose) const {
  const Status status = inverse_without_leg_limits(pose, joints);
  if (!status.ok()) return status;
  const geometry::Pose part = controlled_part(pose);
  const bool rotates = dof_.any_rotation();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  std::array<Eigen::Matrix3d, 3> rotation_derivatives{};
  if (rotates)
    geometry::rotation_and_derivatives_abc(part.orientation_rad, rotation, rotation_derivatives);
  d_joints_d_pose.setZero(joint_count(), geometry::kPoseSize);
  for (int i = 0; i < rail_count(); ++i) {
    const GlideRail& rail = rails_[i];
    const Eigen::Vector3d foot = part.position_mm + rotation * rail.attach_mm - rail.origin_mm;
    // |foot - q*direction| = strut; differentiating gives dq = strut_vector . dfoot / (strut .
    // dir).
    const Eigen::Vector3d strut_vector = foot - joints[i] * rail.direction;
    const Eigen::Vector3d gradient = strut_vector / strut_vector.dot(rail.direction);
    for (int axis = 0; axis < 3; ++axis) {
      if (dof_.controls(axis)) d_joints_d_pose(i, axis) = gradient[axis];
    }
    if (rotates) {
      for (int k = 0; k < 3; ++k) {
        d_joints_d_pose(i, 3 + k) = gradient.dot(rotation_derivatives[k] * rail.attach_mm);
      }
    }
  }
  passthrough_.jacobian(d_joints_d_pose, rail_count());
  return Status::success();
}

Status GlideKinematics::jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const {
  JointVector joints;
  return inverse_and_jacobian(pose, joints, d_joints_d_pose);
}

int GlideKinematics::assembly_mode(const geometry::Pose& pose) const {
  if (dof_.any_rotation()) return 0;
  JointVector joints;
  if (!inverse_without_leg_limits(pose, joints).ok()) return 0;
  return mode_of_tip(controlled_part(pose).position_mm, joints);
}

int GlideKinematics::mode_of_tip(const Eigen::Vector3d& tip_mm, const JointVector& joints) const {
  std::array<Eigen::Vector3d, 3> strut;
  for (int i = 0; i < rail_count(); ++i) {
    strut[i] = tip_mm + rails_[i].attach_mm - rails_[i].origin_mm - joints[i] * rails_[i].direction;
  }
  double orientation = 0.0;
  if (rail_count() == 3) {
    orientation = strut[0].dot(strut[1].cross(strut[2]));
  } else {
    int plane[2] = {0, 1};
    for (int axis = 0, n = 0; axis < 3; ++axis) {
      if (dof_.controls(axis)) plane[n++] = axis;
    }
    orientation = strut[0][plane[0]] * strut[1][plane[1]] - strut[0][plane[1]] * strut[1][plane[0]];
  }
  return orientation >= 0.0 ? 1 : -1;
}

namespace {

// The two intersections of three spheres (carriage i's at `centre[i]`, radius strut i).
Status intersect_spheres(const std::array<Eigen::Vector3d, 3>& centre,
                         const std::array<double, 3>& radius,
                         std::array<Eigen::Vector3d, 2>& candidates) {
  const Eigen::Vector3d span_12 = centre[1] - centre[0];
  const double d = span_12.norm();
  if (d == 0.0) return Status::failure(StatusCode::singular);
  const Eigen::Vector3d ex = span_12 / d;
  const Eigen::Vector3d span_13 = centre[2] - centre[0];
  const double i = ex.dot(span_13);
  Eigen::Vector3d ey = span_13 - i * ex;
  const double j = ey.norm();
  if (j <= 1e-9 * d) return Status::failure(StatusCode::singular);
  ey /= j;
  const Eigen::Vector3d ez = ex.cross(ey);
  const double x = (radius[0] * radius[0] - radius[1] * radius[1] + d * d) / (2.0 * d);
  const double y =
      (radius[0] * radius[0] - radius[2] * radius[2] + i * i + j * j) / (2.0 * j) - i * x / j;
  const double z_squared = radius[0] * radius[0] - x * x - y * y;
  if (z_squared < 0.0) return Status::failure(StatusCode::unreachable);
  const double z = std::sqrt(z_squared);
  candidates = {centre[0] + x * ex + y * ey + z * ez, centre[0] + x * ex + y * ey - z * ez};
  return Status::success();
}

// Two rails: the spheres of the first two carriages cut the plane of the two controlled axes
// (`dof`) in circles; their two intersections, the third coordinate 0.
Status intersect_circles(const std::array<Eigen::Vector3d, 3>& centre,
                         const std::array<double, 3>& radius, geometry::Dof dof,
                         std::array<Eigen::Vector3d, 2>& candidates) {
  std::array<int, 2> plane{};
  int off_plane = 0;
  for (int axis = 0, n = 0; axis < 3; ++axis) {
    if (dof.controls(axis)) {
      plane[n++] = axis;
    } else {
      off_plane = axis;
    }
  }
  std::array<Eigen::Vector2d, 2> centre_2d;
  std::array<double, 2> radius_2d{};
  for (int k = 0; k < 2; ++k) {
    centre_2d[k] = {centre[k][plane[0]], centre[k][plane[1]]};
    const double in_plane_squared =
        radius[k] * radius[k] - centre[k][off_plane] * centre[k][off_plane];
    if (in_plane_squared < 0.0) return Status::failure(StatusCode::unreachable, k);
    radius_2d[k] = std::sqrt(in_plane_squared);
  }
  const Eigen::Vector2d span = centre_2d[1] - centre_2d[0];
  const double d = span.norm();
  if (d == 0.0) return Status::failure(StatusCode::singular);
  const double along =
      (radius_2d[0] * radius_2d[0] - radius_2d[1] * radius_2d[1] + d * d) / (2.0 * d);
  const double across_squared = radius_2d[0] * radius_2d[0] - along * along;
  if (across_squared < 0.0) return Status::failure(StatusCode::unreachable);
  const Eigen::Vector2d ex = span / d;
  const Eigen::Vector2d ey(-ex.y(), ex.x());
  const double across = std::sqrt(across_squared);
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d point = centre_2d[0] + along * ex + (k == 0 ? across : -across) * ey;
    candidates[k] = Eigen::Vector3d::Zero();
    candidates[k][plane[0]] = point.x();
    candidates[k][plane[1]] = point.y();
  }
  return Status::success();
}

}  // namespace

Status GlideKinematics::forward_translating(const JointVector& joints,
                                            geometry::Pose& pose_inout) const {
  // Sphere i: the tip lies at distance strut_i from carriage_i - attach_i.
  std::array<Eigen::Vector3d, 3> centre;
  std::array<double, 3> radius{};
  for (int i = 0; i < rail_count(); ++i) {
    centre[i] = rails_[i].origin_mm + joints[i] * rails_[i].direction - rails_[i].attach_mm;
    radius[i] = rails_[i].strut_mm;
  }
  std::array<Eigen::Vector3d, 2> candidates;
  const Status intersected = rail_count() == 3
                                 ? intersect_spheres(centre, radius, candidates)
                                 : intersect_circles(centre, radius, dof_, candidates);
  if (!intersected.ok()) return intersected;
  geometry::Pose best;
  const Status picked = pick_candidate(joints, candidates, pose_inout, best);
  if (!picked.ok()) return picked;
  // The closed form loses a few digits to cancellation; Newton from it restores full precision.
  const Status polished = solve_forward_newton(WithoutLegLimits<GlideKinematics>(*this), joints,
                                               best, forward_options_);
  if (!polished.ok()) return polished;
  pose_inout = best;
  return Status::success();
}

Status GlideKinematics::pick_candidate(const JointVector& joints,
                                       const std::array<Eigen::Vector3d, 2>& candidates,
                                       const geometry::Pose& seed_pose,
                                       geometry::Pose& picked) const {
  // Both intersections satisfy the strut lengths; only those whose carriages sit on the
  // configured branch reproduce the joint readings. Where both do, the one in the seed's assembly
  // mode (the side of the struts' plane the platform hangs on, which the joints move with) wins,
  // however far the seed is; nearest only breaks a tie. A seed the rails cannot reach has no
  // mode: then the candidate on the seed's side of the spheres' centres.
  const double scale = 1.0 + joints.cwiseAbs().maxCoeff();
  const Eigen::Vector3d seed = controlled_part(seed_pose).position_mm;
  std::array<geometry::Pose, 2> trials{seed_pose, seed_pose};
  std::array<bool, 2> valid{};
  for (int k = 0; k < 2; ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      if (dof_.controls(axis)) trials[k].position_mm[axis] = candidates[k][axis];
    }
    JointVector check;
    valid[k] = inverse_without_leg_limits(trials[k], check).ok() &&
               (check - joints).cwiseAbs().maxCoeff() <= 1e-6 * scale;
  }
  if (!valid[0] && !valid[1]) return Status::failure(StatusCode::unreachable);
  int chosen = valid[0] ? 0 : 1;
  if (valid[0] && valid[1]) {
    // The seed's mode costs an IK: only asked where there is a choice.
    int seed_mode = assembly_mode(seed_pose);
    if (seed_mode == 0) {
      const double seed_side =
          (seed - 0.5 * (candidates[0] + candidates[1])).dot(candidates[0] - candidates[1]);
      seed_mode = mode_of_tip(seed_side >= 0.0 ? candidates[0] : candidates[1], joints);
    }
    const auto score = [&](int k) {
      return (mode_of_tip(candidates[k], joints) == seed_mode ? 0.0 : 1e300) +
             (candidates[k] - seed).norm();
    };
    chosen = score(1) < score(0) ? 1 : 0;
  }
  picked = trials[chosen];
  return Status::success();
}

Status GlideKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  if (joints.size() != joint_count() || !all_finite(joints) || !all_finite(pose_inout)) {
    return Status::failure(StatusCode::invalid_input);
  }
  geometry::Pose pose = pose_inout;
  Status status;
  if (!dof_.any_rotation()) {
    // The pass-through coordinates are the joints themselves; the rails solve the rest.
    passthrough_.forward(joints, rail_count(), pose);
    status = forward_translating(joints, pose);
  } else {
    status = solve_forward_newton(WithoutLegLimits<GlideKinematics>(*this), joints, pose,
                                  forward_options_);
  }
  if (status.ok() && leg_limits_.active()) {
    const int iterations = status.iterations;
    status = leg_limits_.check(leg_ends(pose, joints));
    status.iterations = iterations;
  }
  if (status.ok()) pose_inout = pose;
  return status;
}

std::vector<Parameter> GlideKinematics::parameters() const {
  std::vector<Parameter> result;
  for (std::size_t i = 0; i < rails_.size(); ++i) {
    const GlideRail& rail = rails_[i];
    const std::string prefix = "rail" + std::to_string(i + 1) + ".";
    for (int k = 0; k < 3; ++k)
      result.push_back({prefix + "origin." + kComponent[k],
                        rail.origin_mm[k],
                        "mm",
                        {"a rail's origin", BuiltTolerance::machine_size}});
    for (int k = 0; k < 3; ++k)
      result.push_back({prefix + "direction." + kComponent[k],
                        rail.direction[k],
                        "",
                        {"a rail direction's component", BuiltTolerance::absolute, 0.02}});
    result.push_back({prefix + "strut",
                      rail.strut_mm,
                      "mm",
                      {"a strut's length", BuiltTolerance::machine_size}});
    for (int k = 0; k < 3; ++k)
      result.push_back({prefix + "attach." + kComponent[k],
                        rail.attach_mm[k],
                        "mm",
                        {"a point on the platform", BuiltTolerance::machine_size}});
  }
  return result;
}

void GlideKinematics::set_parameters(std::span<const double> values) {
  constexpr std::size_t kPerRail = 10;
  if (values.size() != kPerRail * rails_.size()) {
    throw std::invalid_argument("glide takes " + std::to_string(kPerRail * rails_.size()) +
                                " parameters");
  }
  std::vector<GlideRail> rails = rails_;
  for (std::size_t i = 0; i < rails.size(); ++i) {
    const double* v = values.data() + kPerRail * i;
    rails[i].origin_mm = {v[0], v[1], v[2]};
    rails[i].direction = {v[3], v[4], v[5]};
    rails[i].strut_mm = v[6];
    rails[i].attach_mm = {v[7], v[8], v[9]};
  }
  validate(rails, dof_);
  rails_ = std::move(rails);
  update_side_by_side();
}

void GlideKinematics::update_side_by_side() {
  for (int slot = 0; slot < RailsSideBySide::kSlots; ++slot) {
    const GlideRail& rail = rails_[std::min(static_cast<std::size_t>(slot), rails_.size() - 1)];
    for (int k = 0; k < 3; ++k) {
      side_by_side_.origin_mm[k][slot] = rail.origin_mm[k];
      side_by_side_.direction[k][slot] = rail.direction[k];
      side_by_side_.attach_mm[k][slot] = rail.attach_mm[k];
    }
    side_by_side_.strut_squared_mm2[slot] = rail.strut_mm * rail.strut_mm;
    side_by_side_.branch[slot] = rail.branch;
    side_by_side_.singular_mm2[slot] = singular_discriminant(rail);
  }
}

std::unique_ptr<Kinematics> make_glide_kinematics(const ModelConfig& config) {
  std::vector<GlideRail> rails;
  for (const auto& rail_config : config.table_list("rails")) {
    GlideRail rail;
    rail.origin_mm = rail_config->length_vector3("origin");
    const std::vector<double> direction = rail_config->number_list("direction");
    if (direction.size() != 3) rail_config->fail("direction", "needs 3 numbers [x, y, z]");
    rail.direction = {direction[0], direction[1], direction[2]};
    rail.strut_mm = rail_config->length("strut");
    rail.attach_mm = rail_config->length_vector3("attach");
    const double branch = rail_config->number_or("branch", 1.0);
    if (branch != 1.0 && branch != -1.0) rail_config->fail("branch", "must be 1 or -1");
    rail.branch = static_cast<int>(branch);
    if (rail.direction.norm() == 0.0) rail_config->fail("direction", "must not be zero");
    if (!(rail.strut_mm > 0.0)) rail_config->fail("strut", "must be a positive length");
    rails.push_back(rail);
  }
  const bool orientation = config.boolean_or("orientation", false);
  geometry::Dof dof;
  if (orientation) {
    if (rails.size() != 6) {
      config.fail("rails", "orientation = true needs exactly 6 rails, found " +
                               std::to_string(rails.size()));
    }
    if (config.has("axes")) config.fail("axes", "only a translating glide chooses its axes");
    if (config.has("passthrough")) {
      config.fail("passthrough", "a hexaglide moves all six axes itself; nothing passes through");
    }
    dof = geometry::Dof::all();
  } else if (config.has("axes")) {
    for (const std::string& name : config.string_list("axes")) {
      const int axis = geometry::axis_index(name);
      if (axis < 0 || axis > 2) config.fail("axes", "'" + name + "' is not one of x, y, z");
      dof = dof.with(axis);
    }
  } else {
    dof = rails.size() == 2 ? geometry::Dof::planar_xy() : geometry::Dof::translation();
  }
  if (!orientation &&
      (static_cast<int>(rails.size()) != dof.count() || rails.size() < 2 || rails.size() > 3)) {
    config.fail("rails", "a translating glide needs one rail per axis (2 or 3), found " +
                             std::to_string(rails.size()) + " rails for " +
                             std::to_string(dof.count()) + " axes");
  }
  // A pen on a real Z axis of a biglide, or a rotary axis under a delta, follows the program.
  PassThroughAxes passthrough;
  if (!orientation) passthrough = PassThroughAxes::read(config, dof, geometry::Dof::all());
  const LegLimitSettings leg_limits = read_leg_limit_settings(config, "carriage_joint_axis");
  try {
    return std::make_unique<GlideKinematics>(std::move(rails), dof, std::move(passthrough),
                                             leg_limits);
  } catch (const std::invalid_argument& error) {
    config.fail("rails", error.what());
  }
}

void GlideKinematics::write_config(ModelConfigWriter& out) const {
  const bool orientation = dof_.any_rotation();
  out.boolean("orientation", orientation);
  if (!orientation) out.axis_list("axes", dof_);
  passthrough_.write(out);
  write_leg_limit_settings(leg_limits_.settings(), "carriage_joint_axis", out);
  for (const GlideRail& rail : rails_) {
    ModelConfigWriter& entry = out.table_list_entry("rails");
    entry.length_vector3("origin", rail.origin_mm);
    entry.vector3("direction", rail.direction);
    entry.length("strut", rail.strut_mm);
    entry.length_vector3("attach", rail.attach_mm);
    entry.whole_number("branch", rail.branch);
  }
}

std::optional<std::vector<std::string>> GlideKinematics::joint_formulas() const {
  if (dof_.any_rotation()) {
    throw std::invalid_argument("a glide that turns its platform has no formula in x y z alone");
  }
  static constexpr const char* kAxes[] = {"x", "y", "z"};
  std::vector<std::string> formulas;
  for (const GlideRail& rail : rails_) {
    // w = tip + attach - origin per axis (uncontrolled axes are 0); q = d.w + branch sqrt(...).
    std::string w[3];
    for (int k = 0; k < 3; ++k) {
      const double offset = rail.attach_mm[k] - rail.origin_mm[k];
      w[k] = dof_.controls(k) ? shifted_coordinate(kAxes[k], offset) : plain_decimal(offset);
    }
    std::string along;
    for (int k = 0; k < 3; ++k) {
      if (rail.direction[k] == 0.0) continue;
      along += (along.empty() ? "" : " + ") + std::string("(") + plain_decimal(rail.direction[k]) +
               "*" + w[k] + ")";
    }
    if (along.empty()) along = "0";
    const std::string squares = "(" + w[0] + "^2) + (" + w[1] + "^2) + (" + w[2] + "^2)";
    formulas.push_back("(" + along + ") " + (rail.branch > 0 ? "+" : "-") + " sqrt(((" + along +
                       ")^2) - (" + squares + ") + " +
                       plain_decimal(rail.strut_mm * rail.strut_mm) + ")");
  }
  return formulas;
}

void GlideKinematics::fixed_parts(std::span<const JointTravel> travel,
                                  std::vector<SketchLine>& out) const {
  for (std::size_t i = 0; i < rails_.size(); ++i) {
    const GlideRail& rail = rails_[i];
    out.push_back({SketchPart::frame, rail.origin_mm + travel[i].min * rail.direction,
                   rail.origin_mm + travel[i].max * rail.direction});
  }
}

void GlideKinematics::moving_parts(const geometry::Pose& pose, const JointVector& joints,
                                   std::vector<SketchLine>& out) const {
  const Eigen::Matrix3d rotation = geometry::rotation_from_abc(pose.orientation_rad);
  std::vector<Eigen::Vector3d> ends;
  for (std::size_t i = 0; i < rails_.size(); ++i) {
    const GlideRail& rail = rails_[i];
    const Eigen::Vector3d carriage = rail.origin_mm + joints[static_cast<int>(i)] * rail.direction;
    ends.push_back(pose.position_mm + rotation * rail.attach_mm);
    out.push_back({SketchPart::link, carriage, ends.back()});
  }
  if (ends.size() == 2) {
    out.push_back({SketchPart::platform, ends[0], ends[1]});
  } else {
    sketch_loop(out, SketchPart::platform, ends);
  }
  for (const Eigen::Vector3d& end : ends) out.push_back({SketchPart::tool, end, pose.position_mm});
}

}  // namespace pkm::kinematics
