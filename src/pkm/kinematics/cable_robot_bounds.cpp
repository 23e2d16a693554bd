// The cable robot's derivative bounds and reach over a cell (derivative_bounds.hpp): each
// cable's Hessian over a ball, each cable's clearance of its anchor, and the wrench-feasibility
// margin, the tensions' room within tension_limits, bounded over a cell. The arguments are in
// docs/kinematics.md ("Cable robot: bounds") and docs/cable-machines.md ("The wrench-feasible
// workspace").
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {

namespace {

// The distribution's own tolerance on a limit (tension_distribution.cpp: 1e-9 of its scale, the
// largest of 1 + |load| and 1 + |max| in N): inverse() holds a pose whose least-violating
// tensions pass a limit by less, so a margin proves a refusal only below minus this.
double held_tolerance_N(const WrenchVector& load_N, double max_N) {
  return 1e-9 * (1.0 + std::max(load_N.lpNorm<Eigen::Infinity>(), std::abs(max_N)));
}

// The dual side of the margin, over a cell where column i of the structure matrix A0 moves by at
// most delta_i: for a unit wrench direction y and s_i = y . a_i, tensions in [lo + m, hi - m]
// give y . (A t + w) >= y . w + lo P - hi N + m (P + N) (P, N the sums of the positive and
// negative s_i's sizes), which is positive past m_y = (hi N - lo P - y . w) / (P + N): no
// tensions there hold the effector, so m <= m_y (weak duality). Each s_i moves by at most delta_i
// over the cell; the numerator falls as s_i grows (lo, hi >= 0), so it is largest at s_i -
// delta_i. The least m_y over the candidates y: those normal to k - 1 cables (a dual vertex of
// the margin's LP: the cables strictly within their limits at the optimum are orthogonal to y).
double dual_margin_bound(const StructureMatrix& a0, const WrenchVector& load_N,
                         const TensionVector& delta, double lo, double hi) {
  const int k = static_cast<int>(a0.rows()), n = static_cast<int>(a0.cols());
  const auto bound_for = [&](const Eigen::Vector3d& direction) {
    const double length = direction.norm();
    if (!(length > 1e-9)) return static_cast<double>(INFINITY);
    const WrenchVector y = (direction / length).head(k);
    double numerator = -y.dot(load_N), widest = 0.0, narrowest = 0.0;
    for (int i = 0; i < n; ++i) {
      const double s = y.dot(a0.col(i)), low_s = s - delta[i];
      numerator += low_s > 0.0 ? -lo * low_s : -hi * low_s;
      widest += std::abs(s) + delta[i];
      narrowest += std::max(0.0, std::abs(s) - delta[i]);
    }
    if (numerator <= 0.0) return numerator / widest;
    return narrowest > 0.0 ? numerator / narrowest : static_cast<double>(INFINITY);
  };
  const auto column = [&](int i) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    c.head(k) = a0.col(i);
    return c;
  };
  // Each candidate also tilted towards or away from the cables it is normal to, by a few times
  // their turn: a cable with s_i = 0 costs max * delta_i, one with s_i >= delta_i costs min's.
  double best = INFINITY;
  const auto try_tilted = [&](const Eigen::Vector3d& unit_normal, int i, int j) {
    const double turn = std::max(delta[i], j >= 0 ? delta[j] : 0.0);
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d y = sign * unit_normal;
      best = std::min(best, bound_for(y));
      if (!std::isfinite(turn)) continue;
      for (const double scale : {1.5, 3.0}) {
        for (int tilt = 0; tilt < (j >= 0 ? 4 : 2); ++tilt) {
          Eigen::Vector3d tilted = y + (tilt & 1 ? -1.0 : 1.0) * scale * turn * column(i);
          if (j >= 0) tilted += (tilt & 2 ? -1.0 : 1.0) * scale * turn * column(j);
          best = std::min(best, bound_for(tilted));
        }
      }
    }
  };
  for (int i = 0; i < n; ++i) {
    if (k == 2) {
      const Eigen::Vector3d across(-a0(1, i), a0(0, i), 0.0);
      if (across.norm() > 1e-9) try_tilted(across.normalized(), i, -1);
      continue;
    }
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector3d normal = column(i).cross(column(j));
      if (normal.norm() > 1e-9) try_tilted(normal.normalized(), i, j);
    }
  }
  return best;
}

// The wrench-feasibility margin's [low, high] over a cell whose structure matrix's columns move
// by at most `delta` (the argument above reach_over_cell). The dual bound first, which needs no
// distribution: where it proves a cell refused, the low side is not needed (-infinity).
std::array<double, 2> wrench_over_cell(const CableRobotKinematics& model,
                                       const geometry::Vector6d& centre,
                                       const TensionVector& delta) {
  const CableRobotGeometry& g = model.geometry();
  const geometry::Pose pose = geometry::Pose::from_vector(centre);
  const StructureMatrix structure = model.structure_matrix(pose);
  if (structure.size() == 0) return {-INFINITY, INFINITY};
  const WrenchVector load = model.wrench_N(Eigen::Vector3d::Zero());
  const double tolerance = held_tolerance_N(load, g.tension_max_N);
  const double dual =
      dual_margin_bound(structure, load, delta, g.tension_min_N, g.tension_max_N) + 2.0 * tolerance;
  // At a single pose (no turn) the low side is the margin itself: computed, whatever the dual.
  if (dual < 0.0 && delta.sum() > 0.0) return {-INFINITY, dual};
  const std::optional<CableRobotKinematics::WrenchMargin> at_centre = model.wrench_margin(pose);
  if (!at_centre) return {-INFINITY, dual};
  std::array<double, 2> wrench{-INFINITY, dual};
  const double sigma = at_centre->smallest_singular;
  if (sigma > 0.0) {
    const double largest = std::max(std::abs(g.tension_min_N), std::abs(g.tension_max_N));
    wrench[1] = std::min(dual, at_centre->upper_N + largest * delta.sum() / sigma + tolerance);
  }
  const double sigma_cell = sigma - delta.norm();
  if (!(sigma_cell > 0.0)) return wrench;
  const auto low_from = [&](const TensionVector& t, double residual_N) {
    const double room = std::min((t.array() - g.tension_min_N).minCoeff(),
                                 (g.tension_max_N - t.array()).minCoeff());
    return room - (residual_N + delta.dot(t.cwiseAbs())) / sigma_cell;
  };
  wrench[0] = low_from(at_centre->tension_N, at_centre->residual_N);
  // The widest tensions sit mid-range, and each N of them is unbalanced by the cables' turn:
  // tensions nearest min + m / 2 that keep half the room may leave less unbalanced.
  if (wrench[0] <= 0.0 && at_centre->margin_N > 0.0) {
    const double half = 0.5 * at_centre->margin_N;
    const double low = g.tension_min_N + half, high = g.tension_max_N - half;
    const TensionDistribution lighter = distribute_tensions(
        structure, load, TensionTargets::uniform(model.cable_count(), low, high, low));
    if (lighter.held()) {
      wrench[0] = std::max(wrench[0], low_from(lighter.tension_N, lighter.equilibrium_residual_N));
    }
  }
  return wrench;
}

// A cable over its pulley (cable_robot_pulley.cpp), its tie point within `radius_mm` of `tie`:
// the shortest span over the ball, or 0 where no bound holds. The distance from the tie point to
// the pulley's centre is its distance from the circle the centre swivels on, 1-Lipschitz; so are
// the axis distance and the height along the axis. Where the wrap stays within [0, pi] (the tie
// point beyond the plane through the anchor normal to the axis, or 2 r or more from the axis) the
// Hessian is (m m^T) / s + (sin(theta) / rho) n n^T with 0 <= sin(theta) / rho <= 1 / s
// (rho = r (1 - cos theta) + s sin theta >= s sin theta): between 0 and (I - u u^T) / s.
double shortest_span(const RobotCable& cable, const Eigen::Vector3d& tie, double radius_mm) {
  PulleyPath path;
  if (!pulley_path(cable, tie, path).ok()) return 0.0;
  const double r = cable.pulley_radius_mm, nearest = path.rim_distance_mm - radius_mm;
  const bool within_half_turn =
      path.along_axis_mm + radius_mm <= 0.0 || path.axis_distance_mm - radius_mm >= 2.0 * r;
  if (!within_half_turn || !(nearest > r) || !(path.axis_distance_mm > radius_mm)) return 0.0;
  return std::sqrt((nearest - r) * (nearest + r));
}

}  // namespace

// A straight cable of length l from its tie point to its anchor: Hessian (I - u u^T) / l, u its
// direction. A swivel arm's cable, sqrt((rho - s)^2 + dz^2) with rho the plan distance from the
// arm's axis to the anchor: Hessian n n^T / l + (rho - s) / (rho l) t t^T, n, t and u
// orthonormal, dominated by (I - u u^T) / l (docs/kinematics.md). l is 1-Lipschitz (its gradient
// is u), so l >= l(centre) - r on the ball; u turns at most r / l_min, so the sine between u and
// the chord v is at most its centre's plus r / l_min: |H[v, v]| <= |v|^2 sine^2 / l_min.
std::optional<HessianBounds> CableRobotKinematics::own_hessian_bounds(
    const geometry::Vector6d& centre, double radius_mm, double /*angle_scale_mm*/,
    const Chord& chord) const {
  // With flex compensation a joint is the length less its stretch under RRF's forces, which turn
  // with the pose through a clamped least-squares solve: no bound on their derivatives here.
  if (geometry_.flex_compensation) return std::nullopt;
  const Eigen::Vector3d tool = tool_point(geometry::Pose::from_vector(centre));
  Eigen::Vector3d v = chord.position;
  if (geometry_.planar && !geometry_.cables_follow_z) v.z() = 0.0;  // z does not move the cables
  HessianBounds bounds;
  for (int i = 0; i < cable_count(); ++i) {
    const RobotCable& cable = geometry_.cables[i];
    const Eigen::Vector3d axis = tool + cable.attach_mm;
    const double plan = (cable.anchor_mm - axis).head<2>().norm();
    Eigen::Vector3d tie;
    const bool arm_clear = cable.swivel_arm_mm == 0.0 || plan - radius_mm > cable.swivel_arm_mm;
    if (!arm_clear || !tie_point(i, tool, tie)) {
      bounds.add(INFINITY, INFINITY);
      continue;
    }
    if (cable.pulley_radius_mm > 0.0) {
      // Over a pulley: the same bound with the span for the length (shortest_span()).
      PulleyPath path;
      const double span = shortest_span(cable, tie, radius_mm);
      if (!(span > 0.0) || !pulley_path(cable, tie, path).ok()) {
        bounds.add(INFINITY, INFINITY);
        continue;
      }
      const double v_norm = v.norm();
      const double sine_at_centre = v_norm > 0.0 ? v.cross(path.direction).norm() / v_norm : 0.0;
      const double sine = std::min(1.0, sine_at_centre + radius_mm / span);
      bounds.add(1.0 / span, v_norm * v_norm * sine * sine / span);
      continue;
    }
    const Eigen::Vector3d along = cable.anchor_mm - tie;
    const double length = along.norm(), shortest = length - radius_mm;
    if (!(shortest > 0.0)) {
      bounds.add(INFINITY, INFINITY);
      continue;
    }
    const double v_norm = v.norm();
    const double sine_at_centre = v_norm > 0.0 ? v.cross(along).norm() / (v_norm * length) : 0.0;
    const double sine = std::min(1.0, sine_at_centre + radius_mm / shortest);
    bounds.add(1.0 / shortest, v_norm * v_norm * sine * sine / shortest);
  }
  return bounds;
}

std::optional<CableRobotKinematics::WrenchMargin> CableRobotKinematics::wrench_margin(
    const geometry::Pose& pose) const {
  const StructureMatrix structure = structure_matrix(pose);
  if (structure.size() == 0) return std::nullopt;
  // The tensions nearest the limits' middle within the narrowest box [middle - s, middle + s]
  // that holds the effector: the distribution's least-violating tensions for min = max = middle.
  // Their room within the limits is the margin (an LP's optimum, as the distribution's bisection
  // finds it).
  const double low = geometry_.tension_min_N, high = geometry_.tension_max_N;
  const double middle = 0.5 * (low + high);
  const WrenchVector load = wrench_N(Eigen::Vector3d::Zero());
  const TensionDistribution narrowest = distribute_tensions(
      structure, load, TensionTargets::uniform(cable_count(), middle, middle, middle));
  if (narrowest.outcome == TensionOutcome::unbalanced) return std::nullopt;
  WrenchMargin result;
  result.tension_N = narrowest.tension_N;
  result.margin_N = std::min((result.tension_N.array() - low).minCoeff(),
                             (high - result.tension_N.array()).minCoeff());
  result.upper_N = result.margin_N + held_tolerance_N(load, high);
  result.residual_N = narrowest.equilibrium_residual_N;
  using Normal = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;
  const Normal normal = structure * structure.transpose();
  const double smallest = Eigen::SelfAdjointEigenSolver<Normal>(normal, Eigen::EigenvaluesOnly)
                              .eigenvalues()
                              .minCoeff();
  result.smallest_singular = std::sqrt(std::max(smallest, 0.0));
  return result;
}

// Over the cell (positions within R of the centre): each column u_i of the structure matrix
// moves by at most delta_i = R / (l_i - R) (its Hessian's norm 1 / l over the cell), so the
// centre's tensions t0 leave at most e = |A0 t0 + w| + sum delta_i |t0_i| of the load unbalanced
// anywhere, which tensions changing by at most e / sigma_cell (the least-norm correction,
// sigma_cell >= sigma0 - sqrt(sum delta_i^2) the structure matrix's smallest singular value over
// the cell) balance: the margin is at least the centre's less that. Conversely, tensions within
// [min, max] holding the effector anywhere in the cell (|t_i| <= T = max(|min|, |max|)) hold it
// at the centre after a change of at most T sum delta_i / sigma0, so where the margin anywhere
// is >= 0 it is at most the centre's plus that.
void CableRobotKinematics::reach_over_cell(const geometry::Vector6d& centre,
                                           double /*scaled_radius*/, double position_radius_mm,
                                           double /*angle_scale_mm*/,
                                           std::span<std::array<double, 2>> margins) const {
  const double r = position_radius_mm;
  const Eigen::Vector3d tool = tool_point(geometry::Pose::from_vector(centre));
  TensionVector delta(cable_count());
  bool directions_bounded = true;
  for (int i = 0; i < cable_count(); ++i) {
    const RobotCable& cable = geometry_.cables[i];
    const Eigen::Vector3d axis = tool + cable.attach_mm;
    double clearance = 0.0;  // 1-Lipschitz in the tool's position, either way
    PulleyPath path;
    if (cable.pulley_radius_mm > 0.0) {
      // The nearer of its tie point's distance from the pulley's rim (from the circle its centre
      // swivels on, less r) and from the swivel axis (where the pulley has no plane).
      pulley_path(cable, axis, path);
      clearance = std::min(path.rim_distance_mm - cable.pulley_radius_mm,
                           path.axis_distance_mm - kShortestRobotCable_mm);
      const double span = shortest_span(cable, axis, r);
      margins[static_cast<std::size_t>(i)] = {clearance - r, clearance + r};
      directions_bounded = directions_bounded && span > 0.0;
      delta[i] = span > 0.0 ? r / span : INFINITY;
      continue;
    }
    if (cable.swivel_arm_mm > 0.0) {
      clearance = (cable.anchor_mm - axis).head<2>().norm() - cable.swivel_arm_mm;
    } else {
      clearance = (cable.anchor_mm - axis).norm() - kShortestRobotCable_mm;
    }
    margins[static_cast<std::size_t>(i)] = {clearance - r, clearance + r};
    Eigen::Vector3d tie;
    const double length =
        clearance - r > 0.0 && tie_point(i, tool, tie) ? (cable.anchor_mm - tie).norm() : 0.0;
    directions_bounded = directions_bounded && length > r;
    delta[i] = length > r ? r / (length - r) : INFINITY;
  }
  if (!geometry_.tension_limited) return;
  margins[static_cast<std::size_t>(cable_count())] =
      directions_bounded ? wrench_over_cell(*this, centre, delta)
                         : std::array<double, 2>{-INFINITY, INFINITY};
}

ReachMargin CableRobotKinematics::reach_margin(int index) const {
  if (index < cable_count()) {
    const std::string cable = "cable " + std::to_string(index + 1);
    if (geometry_.cables[static_cast<std::size_t>(index)].swivel_arm_mm > 0.0) {
      return {cable + "'s clearance of its anchor (its arm's plan distance to it less the arm)",
              false, Status::failure(StatusCode::unreachable, index)};
    }
    if (geometry_.cables[static_cast<std::size_t>(index)].pulley_radius_mm > 0.0) {
      return {cable +
                  "'s clearance of its pulley (its tie point's distance from the pulley's rim "
                  "or from its swivel axis, the nearer)",
              false, Status::failure(StatusCode::unreachable, index)};
    }
    return {cable + "'s length (clear of its anchor)", false,
            Status::failure(StatusCode::singular, index)};
  }
  return {"the tensions' room within tension_limits [" +
              formatted_number("%.3f", geometry_.tension_min_N) + ", " +
              formatted_number("%.3f", geometry_.tension_max_N) +
              "] N (how far from both limits tensions holding the " +
              formatted_number("%.3f", geometry_.effector_mass_kg) +
              " kg effector can keep every cable)",
          true, Status::failure(StatusCode::tension)};
}

}  // namespace pkm::kinematics
