// RepRapFirmware's flex compensation for the cable robot (HangprinterKinematics with M666 F1:
// FlexDistances, StaticForces' box-constrained least squares, SpringK; docs/kinematics.md,
// "Cable robot"): the forces RRF plans for each line at a pose and the stretch they give it. The
// joint is then the unstretched length, which those forces stretch to the straight one. The forces
// are RRF's, not pkmkit's tension distribution, so that the firmware and pkmkit pay out the same
// line; the distribution still decides whether the pose is held.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "pkm/kinematics/cable_robot.hpp"

namespace pkm::kinematics {

namespace {

using CableSquare =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, kMaxJoints>;
// Where each force sits: free, or held at its lower or upper limit.
enum class Bound { free, lower, upper };
// More working-set changes than this: the active set cycles (it cannot for a strictly convex
// problem; a guard, not a limit met).
constexpr int kMostSetChanges = 8 * kMaxJoints + 16;

double mechanical_advantage(const RobotCable& cable) {
  return cable.spool ? cable.spool->mechanical_advantage : 1.0;
}

// Minimises 1/2 t'Ht - f't within [low, high] from t = low (feasible): a primal active set, which
// ends at the unique minimum of a strictly convex quadratic (H = A'A + ridge I). On the stack.
void box_least_squares(const CableSquare& h, const CableVector& f, double low, double high,
                       CableVector& t) {
  const int n = static_cast<int>(f.size());
  Bound bound[kMaxJoints];
  for (int i = 0; i < n; ++i) bound[i] = Bound::lower;
  t.setConstant(n, low);
  const double tolerance = 1e-12 * (1.0 + f.cwiseAbs().maxCoeff() + high);
  for (int change = 0; change < kMostSetChanges; ++change) {
    int free[kMaxJoints];
    int k = 0;
    for (int i = 0; i < n; ++i) {
      if (bound[i] == Bound::free) free[k++] = i;
    }
    double step[kMaxJoints] = {};
    double largest = 0.0;
    if (k > 0) {
      CableSquare sub(k, k);
      CableVector rhs(k);
      for (int a = 0; a < k; ++a) {
        rhs[a] = f[free[a]] - h.row(free[a]).dot(t);
        for (int b = 0; b < k; ++b) sub(a, b) = h(free[a], free[b]);
      }
      // The free forces' Newton step with the bound ones held: H_FF d = f_F - (H t)_F.
      const CableVector delta = sub.ldlt().solve(rhs);
      for (int a = 0; a < k; ++a) {
        step[free[a]] = delta[a];
        largest = std::max(largest, std::abs(delta[a]));
      }
    }
    if (largest > tolerance) {
      double alpha = 1.0;
      int blocking = -1;
      for (int i = 0; i < n; ++i) {
        if (step[i] < 0.0 && (low - t[i]) / step[i] < alpha) {
          alpha = (low - t[i]) / step[i];
          blocking = i;
        } else if (step[i] > 0.0 && (high - t[i]) / step[i] < alpha) {
          alpha = (high - t[i]) / step[i];
          blocking = i;
        }
      }
      for (int i = 0; i < n; ++i) t[i] += alpha * step[i];
      if (blocking >= 0) {
        bound[blocking] = step[blocking] < 0.0 ? Bound::lower : Bound::upper;
        t[blocking] = step[blocking] < 0.0 ? low : high;
      }
      continue;
    }
    // At the working set's minimum: release the bound force whose gradient pulls it inside most.
    const CableVector gradient = h * t - f;
    int release = -1;
    double worst = tolerance;
    for (int i = 0; i < n; ++i) {
      const double inward = bound[i] == Bound::lower   ? -gradient[i]
                            : bound[i] == Bound::upper ? gradient[i]
                                                       : 0.0;
      if (inward > worst) {
        worst = inward;
        release = i;
      }
    }
    if (release < 0) return;
    bound[release] = Bound::free;
  }
}

}  // namespace

void CableRobotKinematics::planned_forces(const Eigen::Vector3d& tool_mm,
                                          CableVector& force_N) const {
  // StaticForces (Qp): the weight m g along +z asked of the lines, A t = m g z (A's columns the
  // unit vectors from the mover to each anchor), in least squares with a ridge, each force within
  // M666 I X: minimise |A t - w|^2 + ridge |t|^2.
  const int n = cable_count();
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxJoints> a(3, n);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d tie;
    if (!tie_point(i, tool_mm, tie)) tie = tool_mm + geometry_.cables[i].attach_mm;
    const Eigen::Vector3d along = geometry_.cables[i].anchor_mm - tie;
    const double length = along.norm();
    a.col(i) = length > 0.0 ? Eigen::Vector3d(along / length) : Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d weight(0.0, 0.0, geometry_.effector_mass_kg * kRrfGravity_m_per_s2);
  CableSquare h = a.transpose() * a;
  h.diagonal().array() += kRrfForceRidge;
  const CableVector f = a.transpose() * weight;
  box_least_squares(h, f, geometry_.tension_min_N, geometry_.tension_max_N, force_N);
}

void CableRobotKinematics::stretch(const Eigen::Vector3d& tool_mm, const CableVector& length_mm,
                                   CableVector& stretch_mm) const {
  // FlexDistances: a line of U strands from its spool, each as long as the straight length, plus
  // its guy wire, is a spring of stiffness S / (length U + guy wire); the stretch RRF takes off
  // the line position is the force over that stiffness times U.
  CableVector force;
  planned_forces(tool_mm, force);
  stretch_mm.resize(cable_count());
  for (int i = 0; i < cable_count(); ++i) {
    const RobotCable& cable = geometry_.cables[i];
    const double advantage = mechanical_advantage(cable);
    const double spring =
        geometry_.line_stiffness_N / (length_mm[i] * advantage + cable.guy_wire_mm);
    stretch_mm[i] = force[i] / (spring * advantage);
  }
}

void CableRobotKinematics::flex_jacobian(const Eigen::Vector3d& tool_mm,
                                         CableJacobian& d_length) const {
  constexpr double kStep_mm = 1e-2;
  for (int axis = 0; axis < coordinates(); ++axis) {
    const auto difference = [&](double h) {
      Eigen::Vector3d plus = tool_mm, minus = tool_mm;
      plus[axis] += h;
      minus[axis] -= h;
      CableVector length_plus, length_minus;
      if (!lengths(plus, length_plus, nullptr).ok() ||
          !lengths(minus, length_minus, nullptr).ok()) {
        return CableVector(d_length.col(axis));
      }
      return CableVector((length_plus - length_minus) / (2.0 * h));
    };
    const CableVector coarse = difference(kStep_mm);
    const CableVector fine = difference(kStep_mm / 2.0);
    d_length.col(axis) = (4.0 * fine - coarse) / 3.0;
  }
}

}  // namespace pkm::kinematics
