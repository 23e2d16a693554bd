// The tension distribution: Goldfarb and Idnani's dual active-set method (Math. Programming 27,
// 1983) for the projection of the preferred tensions onto {t : A t = -w, min <= t <= max}, and a
// bisection on a widened box for the least-violating tensions where that set is empty. All on
// fixed-capacity Eigen types and arrays: nothing allocates but a refusal's violations list.
#include "pkm/kinematics/tension_distribution.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pkm::kinematics {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Relative to the largest singular value: smaller ones are rank lost (cables in line).
constexpr double kRankTolerance = 1e-12;
// A new bound's normal closer than this (sine of the angle) to the active normals' span is
// dependent on them: the dual method then steps in the multipliers only.
constexpr double kDependentNormal = 1e-10;
// Bisection on the least violation stops at this fraction of the problem's tension scale.
constexpr double kViolationResolution = 1e-12;

// V (n x rank) and the active normals [V, sign_j e_j] (n x (rank + active)): the active bounds'
// normals are independent of V's and of each other, so rank + active <= n; the capacity allows
// for rank + kMaxCables.
using EquilibriumNormals =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCables, kMaxWrenchRows>;
using ActiveNormals = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxCables,
                                    kMaxWrenchRows + kMaxCables>;
using DualVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxWrenchRows + kMaxCables, 1>;
using SquareWrench =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxWrenchRows, kMaxWrenchRows>;

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

void validate(const Eigen::Ref<const Eigen::MatrixXd>& structure,
              const Eigen::Ref<const Eigen::VectorXd>& wrench_N, const TensionTargets& targets) {
  const Eigen::Index n = structure.cols();
  if (structure.rows() < 1 || n < 1) {
    throw std::invalid_argument("tension distribution: the structure matrix is empty");
  }
  if (structure.rows() > kMaxWrenchRows || n > kMaxCables) {
    throw std::invalid_argument("tension distribution: a " + std::to_string(structure.rows()) +
                                " x " + std::to_string(n) + " structure matrix; at most " +
                                std::to_string(kMaxWrenchRows) + " wrench rows and " +
                                std::to_string(kMaxCables) + " cables");
  }
  if (wrench_N.size() != structure.rows()) {
    throw std::invalid_argument(
        format("tension distribution: the wrench has %g rows, the structure matrix %g",
               static_cast<double>(wrench_N.size()), static_cast<double>(structure.rows())));
  }
  if (targets.min_N.size() != n || targets.max_N.size() != n || targets.preferred_N.size() != n) {
    throw std::invalid_argument("tension distribution: " + std::to_string(n) +
                                " cables, but min, max and preferred "
                                "tensions for " +
                                std::to_string(targets.min_N.size()) + ", " +
                                std::to_string(targets.max_N.size()) + " and " +
                                std::to_string(targets.preferred_N.size()));
  }
  if (!structure.allFinite() || !wrench_N.allFinite() || !targets.preferred_N.allFinite() ||
      !targets.min_N.allFinite()) {
    throw std::invalid_argument(
        "tension distribution: the structure matrix, wrench, min and preferred tensions must be "
        "finite");
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (std::isnan(targets.max_N[i]) || targets.max_N[i] < targets.min_N[i]) {
      throw std::invalid_argument(
          format("tension distribution: cable %g's limits [%g, %g] N need min <= max",
                 static_cast<double>(i + 1), targets.min_N[i], targets.max_N[i]));
    }
  }
}

// A t = -w as V^T t = c with V's columns an orthonormal basis of A's row space; `residual` is
// how far -w is from A's column space (0: some tensions balance it).
struct Equilibrium {
  EquilibriumNormals normals;  // V: n x rank
  WrenchVector values;         // c
  double residual_N = 0.0;
};

Equilibrium equilibrium_constraints(const StructureMatrix& structure,
                                    const WrenchVector& wrench_N) {
  const Eigen::JacobiSVD<StructureMatrix> svd(structure, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& sigma = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < sigma.size() && sigma[rank] > kRankTolerance * sigma[0]) ++rank;
  const SquareWrench u = svd.matrixU().leftCols(rank);
  const WrenchVector projected = u.transpose() * (-wrench_N);
  Equilibrium equilibrium;
  equilibrium.normals = svd.matrixV().leftCols(rank);
  equilibrium.values = projected.cwiseQuotient(sigma.head(rank));
  equilibrium.residual_N = (-wrench_N - u * projected).norm();
  return equilibrium;
}

struct ActiveBound {
  Eigen::Index cable;
  double sign;        // +1: t >= min active, -1: t <= max active (the normal is sign e_cable)
  double multiplier;  // >= 0
};

// The active bounds in the order they were added (the normals' column order), on the stack: at
// most one per cable (a cable's two bounds have dependent normals).
struct ActiveSet {
  std::array<ActiveBound, kMaxCables> bounds;
  std::size_t count = 0;

  std::size_t size() const { return count; }
  ActiveBound& operator[](std::size_t j) { return bounds[j]; }
  const ActiveBound& operator[](std::size_t j) const { return bounds[j]; }
  const ActiveBound* begin() const { return bounds.data(); }
  const ActiveBound* end() const { return bounds.data() + count; }
  void push_back(const ActiveBound& bound) {
    if (count == bounds.size()) {
      throw std::logic_error("tension distribution: more active bounds than cables");
    }
    bounds[count++] = bound;
  }
  void erase(std::size_t j) {
    std::copy(bounds.begin() + static_cast<std::ptrdiff_t>(j + 1),
              bounds.begin() + static_cast<std::ptrdiff_t>(count),
              bounds.begin() + static_cast<std::ptrdiff_t>(j));
    --count;
  }
};

struct BoxSolution {
  bool feasible = false;
  TensionVector tension_N;
  ActiveSet active;
  int iterations = 0;
};

// The most violated bound of `t` among those not active: its cable and sign, and its slack
// (negative where violated); sign 0 when none is violated by more than `tolerance`.
ActiveBound most_violated(const TensionVector& t, const TensionVector& lo, const TensionVector& hi,
                          double tolerance, double& slack) {
  ActiveBound worst{-1, 0.0, 0.0};
  slack = -tolerance;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (lo[i] - t[i] > -slack) {
      worst = {i, 1.0, 0.0};
      slack = t[i] - lo[i];
    }
    if (t[i] - hi[i] > -slack) {
      worst = {i, -1.0, 0.0};
      slack = hi[i] - t[i];
    }
  }
  return worst;
}

struct StepDirections {
  TensionVector primal;  // z: the new bound's normal projected off the active normals
  DualVector dual;       // r: that normal in the active normals' coordinates (N^T N)^-1 N^T n
};

// The active normals N = [V, sign_j e_j] (orthonormal equilibrium rows, then the active bounds)
// by a Householder QR: z = n - Q Q^T n, r = R^-1 Q^T n.
StepDirections step_directions(const EquilibriumNormals& v, const ActiveSet& active,
                               const ActiveBound& adding) {
  const Eigen::Index n = v.rows(), rank = v.cols();
  ActiveNormals normals = ActiveNormals::Zero(n, rank + static_cast<Eigen::Index>(active.size()));
  normals.leftCols(rank) = v;
  for (std::size_t j = 0; j < active.size(); ++j) {
    normals(active[j].cable, rank + static_cast<Eigen::Index>(j)) = active[j].sign;
  }
  const Eigen::Index q = normals.cols();
  StepDirections directions{TensionVector::Zero(n), DualVector::Zero(q)};
  directions.primal[adding.cable] = adding.sign;
  if (q == 0) return directions;
  const Eigen::HouseholderQR<ActiveNormals> qr(normals);
  const ActiveNormals basis = qr.householderQ() * ActiveNormals::Identity(n, q);
  const DualVector along = basis.transpose() * directions.primal;
  directions.primal -= basis * along;
  directions.dual = qr.matrixQR().topLeftCorner(q, q).triangularView<Eigen::Upper>().solve(along);
  return directions;
}

// Goldfarb-Idnani with H = I. Adds the most violated bound; steps along z (the bound's normal
// projected off the active normals) and in the multipliers; drops the active bound whose
// multiplier reaches zero first. Finite: the dual objective never decreases and no active set
// repeats (Goldfarb and Idnani, theorem 3). A bound whose normal is dependent on the active ones
// with no multiplier to drop proves the box and the equilibrium disjoint.
BoxSolution solve_in_box(const Equilibrium& equilibrium, const TensionVector& lo,
                         const TensionVector& hi, const TensionVector& preferred,
                         double tolerance) {
  const EquilibriumNormals& v = equilibrium.normals;
  const Eigen::Index n = preferred.size(), rank = v.cols();
  BoxSolution solution;
  TensionVector t = preferred + v * (equilibrium.values - v.transpose() * preferred);
  const int cap = 100 * static_cast<int>(n + rank) + 100;
  for (;;) {
    double slack = 0.0;
    ActiveBound adding = most_violated(t, lo, hi, tolerance, slack);
    if (adding.sign == 0.0) break;
    for (;;) {
      if (++solution.iterations > cap) {
        throw std::runtime_error("tension distribution: the active-set method did not finish");
      }
      const StepDirections directions = step_directions(v, solution.active, adding);
      const TensionVector& z = directions.primal;
      const DualVector& r = directions.dual;
      double dual_step = kInfinity;
      std::size_t dropping = 0;
      for (std::size_t j = 0; j < solution.active.size(); ++j) {
        const double rate = r[rank + static_cast<Eigen::Index>(j)];
        if (rate > kDependentNormal && solution.active[j].multiplier / rate < dual_step) {
          dual_step = solution.active[j].multiplier / rate;
          dropping = j;
        }
      }
      const double z_squared = z.squaredNorm();
      const double primal_step =
          z_squared > kDependentNormal * kDependentNormal ? -slack / z_squared : kInfinity;
      const double step = std::min(dual_step, primal_step);
      if (step == kInfinity) {
        solution.tension_N = t;
        return solution;  // infeasible
      }
      if (primal_step < kInfinity) {
        t += step * z;
        slack += step * z_squared;
      }
      for (std::size_t j = 0; j < solution.active.size(); ++j) {
        solution.active[j].multiplier -= step * r[rank + static_cast<Eigen::Index>(j)];
      }
      adding.multiplier += step;
      if (primal_step <= dual_step) {
        solution.active.push_back(adding);
        break;
      }
      solution.active.erase(dropping);
    }
  }
  solution.feasible = true;
  solution.tension_N = t;
  return solution;
}

// The KKT system of the final active set solved afresh (active tensions at their bounds, the rest
// closest to preferred on the equilibrium): removes the rounding the steps accumulated.
TensionVector polished(const Equilibrium& equilibrium, const BoxSolution& solution,
                       const TensionVector& lo, const TensionVector& hi,
                       const TensionVector& preferred) {
  TensionVector t = preferred;
  std::array<bool, kMaxCables> fixed{};
  for (const ActiveBound& bound : solution.active) {
    t[bound.cable] = bound.sign > 0.0 ? lo[bound.cable] : hi[bound.cable];
    fixed[static_cast<std::size_t>(bound.cable)] = true;
  }
  std::array<Eigen::Index, kMaxCables> free{};
  std::size_t free_count = 0;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (!fixed[static_cast<std::size_t>(i)]) free[free_count++] = i;
  }
  const EquilibriumNormals& v = equilibrium.normals;
  if (free_count == 0 || v.cols() == 0) return t;
  StructureMatrix free_rows(v.cols(), static_cast<Eigen::Index>(free_count));
  for (std::size_t k = 0; k < free_count; ++k) {
    free_rows.col(static_cast<Eigen::Index>(k)) = v.row(free[k]).transpose();
  }
  // min |x - p_free| subject to free_rows x = c - (fixed part): the least-norm correction.
  const WrenchVector rhs = equilibrium.values - v.transpose() * t;
  const TensionVector correction =
      Eigen::CompleteOrthogonalDecomposition<StructureMatrix>(free_rows).solve(rhs);
  for (std::size_t k = 0; k < free_count; ++k) {
    t[free[k]] += correction[static_cast<Eigen::Index>(k)];
  }
  return t;
}

double tension_scale(const WrenchVector& wrench_N, const TensionTargets& targets) {
  double scale = 1.0 + wrench_N.lpNorm<Eigen::Infinity>() +
                 targets.min_N.lpNorm<Eigen::Infinity>() +
                 targets.preferred_N.lpNorm<Eigen::Infinity>();
  for (Eigen::Index i = 0; i < targets.max_N.size(); ++i) {
    if (std::isfinite(targets.max_N[i])) scale = std::max(scale, 1.0 + std::abs(targets.max_N[i]));
  }
  return scale;
}

double largest_violation(const TensionVector& t, const TensionTargets& targets) {
  return std::max(0.0, std::max((targets.min_N - t).maxCoeff(), (t - targets.max_N).maxCoeff()));
}

// The least s for which the box [min - s, max + s] meets the equilibrium, by bisection (the box
// grows with s, so feasibility is monotone), and the tensions closest to preferred in that box.
BoxSolution least_violating(const Equilibrium& equilibrium, const TensionTargets& targets,
                            double scale, double tolerance, int& iterations) {
  const TensionVector& p = targets.preferred_N;
  const TensionVector on_equilibrium =
      p + equilibrium.normals * (equilibrium.values - equilibrium.normals.transpose() * p);
  double infeasible = 0.0, feasible = largest_violation(on_equilibrium, targets) + tolerance;
  const TensionVector ones = TensionVector::Ones(p.size());
  BoxSolution best = solve_in_box(equilibrium, targets.min_N - feasible * ones,
                                  targets.max_N + feasible * ones, p, tolerance);
  iterations += best.iterations;
  while (feasible - infeasible > kViolationResolution * scale) {
    const double widening = 0.5 * (infeasible + feasible);
    BoxSolution trial = solve_in_box(equilibrium, targets.min_N - widening * ones,
                                     targets.max_N + widening * ones, p, tolerance);
    iterations += trial.iterations;
    if (trial.feasible) {
      feasible = widening, best = std::move(trial);
    } else {
      infeasible = widening;
    }
  }
  best.tension_N = polished(equilibrium, best, targets.min_N - feasible * ones,
                            targets.max_N + feasible * ones, p);
  return best;
}

std::vector<CableViolation> violations_of(const TensionVector& t, const TensionTargets& targets,
                                          double tolerance) {
  std::vector<CableViolation> violations;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    if (targets.min_N[i] - t[i] > tolerance) {
      violations.push_back(
          {static_cast<int>(i), t[i], targets.min_N[i], true, targets.min_N[i] - t[i]});
    } else if (t[i] - targets.max_N[i] > tolerance) {
      violations.push_back(
          {static_cast<int>(i), t[i], targets.max_N[i], false, t[i] - targets.max_N[i]});
    }
  }
  std::stable_sort(
      violations.begin(), violations.end(),
      [](const CableViolation& a, const CableViolation& b) { return a.excess_N > b.excess_N; });
  return violations;
}

}  // namespace

TensionTargets TensionTargets::uniform(int cables, double min_N, double max_N, double preferred_N) {
  if (cables < 0 || cables > kMaxCables) {
    throw std::invalid_argument("tension distribution: " + std::to_string(cables) +
                                " cables; at most " + std::to_string(kMaxCables));
  }
  return {TensionVector::Constant(cables, min_N), TensionVector::Constant(cables, max_N),
          TensionVector::Constant(cables, preferred_N)};
}

TensionTargets TensionTargets::middle(int cables, double min_N, double max_N) {
  if (!std::isfinite(min_N) || !std::isfinite(max_N)) {
    throw std::invalid_argument(
        format("tension distribution: the middle of [%g, %g] N needs finite limits; give a "
               "preferred tension",
               min_N, max_N));
  }
  return uniform(cables, min_N, max_N, 0.5 * (min_N + max_N));
}

TensionDistribution distribute_tensions(const Eigen::Ref<const Eigen::MatrixXd>& structure_in,
                                        const Eigen::Ref<const Eigen::VectorXd>& wrench_in,
                                        const TensionTargets& targets) {
  validate(structure_in, wrench_in, targets);
  const StructureMatrix structure = structure_in;
  const WrenchVector wrench_N = wrench_in;
  const double scale = tension_scale(wrench_N, targets);
  const double tolerance = 1e-12 * scale;
  const Equilibrium equilibrium = equilibrium_constraints(structure, wrench_N);
  TensionDistribution result;
  BoxSolution solution =
      solve_in_box(equilibrium, targets.min_N, targets.max_N, targets.preferred_N, tolerance);
  result.iterations = solution.iterations;
  if (solution.feasible) {
    result.tension_N =
        polished(equilibrium, solution, targets.min_N, targets.max_N, targets.preferred_N);
  } else {
    result.tension_N =
        least_violating(equilibrium, targets, scale, tolerance, result.iterations).tension_N;
  }
  result.equilibrium_residual_N = (structure * result.tension_N + wrench_N).norm();
  result.largest_violation_N = largest_violation(result.tension_N, targets);
  result.violations = violations_of(result.tension_N, targets, 1e-9 * scale);
  if (equilibrium.residual_N > 1e-9 * scale) {
    result.outcome = TensionOutcome::unbalanced;
  } else if (!result.violations.empty()) {
    result.outcome = TensionOutcome::out_of_limits;
  }
  return result;
}

std::string describe_refusal(const TensionDistribution& distribution,
                             std::span<const std::string> names) {
  std::string text;
  if (distribution.outcome == TensionOutcome::unbalanced) {
    text = format(
        "no cable tensions balance the load: %.3f N of it is outside what the cables "
        "can pull",
        distribution.equilibrium_residual_N);
  }
  for (const CableViolation& violation : distribution.violations) {
    if (!text.empty()) text += "; ";
    const std::size_t cable = static_cast<std::size_t>(violation.cable);
    text += cable < names.size() ? names[cable] : "cable " + std::to_string(cable + 1);
    text += format(violation.below_min ? " would need %.3f N (its min %.3f N)"
                                       : " would need %.3f N (its max %.3f N)",
                   violation.tension_N, violation.limit_N);
  }
  return text;
}

}  // namespace pkm::kinematics
