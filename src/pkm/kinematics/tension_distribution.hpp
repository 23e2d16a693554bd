// The tension distribution of an effector hung on n cables (issue 31): of all tensions within
// their limits that hold the effector, the one closest (least squares) to the tensions a
// controller prefers; or, where none exist, the tensions that break the limits least and by how
// much. Model-independent: the caller gives the structure matrix and the wrench. The method and
// its guarantees are in docs/cable-machines.md ("N cables: the tension distribution").
// Allocation-free where the tensions are held (inverse kinematics runs it in LinuxCNC's servo
// thread): every vector and matrix has a fixed capacity, at most kMaxCables cables and
// kMaxWrenchRows wrench rows; only a refusal's list of violations allocates.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

namespace pkm::kinematics {

// At most 26 cables (Klipper's winch kinematics' maximum) and 6 wrench rows (force and moment).
inline constexpr int kMaxCables = 26;
inline constexpr int kMaxWrenchRows = 6;
// Per-cable tensions (N), on the stack.
using TensionVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCables, 1>;
// The structure matrix A (d x n) and the wrench w (d), on the stack.
using StructureMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxWrenchRows, kMaxCables>;
using WrenchVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxWrenchRows, 1>;

// Per-cable limits and preferred tensions (N). The preferred tension is what a controller aims
// for: the middle of the limits, or a pretension.
struct TensionTargets {
  TensionVector min_N;
  TensionVector max_N;
  TensionVector preferred_N;

  // The same limits and preference for all n cables (at most kMaxCables; std::invalid_argument
  // otherwise).
  static TensionTargets uniform(int cables, double min_N, double max_N, double preferred_N);
  // The same limits for all n cables, preferring their middle (both must be finite).
  static TensionTargets middle(int cables, double min_N, double max_N);
};

enum class TensionOutcome {
  held,           // tensions within the limits hold the effector
  out_of_limits,  // the cables can balance the wrench, but not within their limits
  unbalanced,     // no tensions at all balance it (the wrench is outside the span of A)
};

// A cable outside its limits at the least-violating tensions.
struct CableViolation {
  int cable = -1;  // index into the columns of A (0-based; messages number cables from 1)
  double tension_N = 0.0;
  double limit_N = 0.0;   // the limit it passes
  bool below_min = true;  // false: above its max
  double excess_N = 0.0;  // how far past the limit: > 0
};

struct TensionDistribution {
  TensionOutcome outcome = TensionOutcome::held;
  // held: the tensions closest to the preferred ones. out_of_limits: the least-violating
  // tensions (the largest violation minimised; of those, the closest to the preferred ones).
  // unbalanced: the tensions within the limits closest to the preferred ones that come nearest
  // to equilibrium in least squares (the residual says how far).
  TensionVector tension_N;
  double equilibrium_residual_N = 0.0;     // |A t + w|
  double largest_violation_N = 0.0;        // max over cables of how far t passes a limit; 0: held
  std::vector<CableViolation> violations;  // out_of_limits: worst first
  int iterations = 0;                      // active-set steps taken (all solves together)

  bool held() const { return outcome == TensionOutcome::held; }
};

// The distribution for structure matrix A (d x n, d from 1 to 6: column i is cable i's unit
// direction from the effector towards its anchor, with its moment rows below for d > 3) and the
// external wrench w (d; the effector's m (g - a), and its moment): A t + w = 0,
// min <= t <= max, |t - preferred| least. Throws std::invalid_argument on sizes that do not
// agree, more than kMaxCables cables or kMaxWrenchRows rows, non-finite entries, min > max or a
// non-finite min. Allocates nothing unless it refuses (then only the violations list).
TensionDistribution distribute_tensions(const Eigen::Ref<const Eigen::MatrixXd>& structure,
                                        const Eigen::Ref<const Eigen::VectorXd>& wrench_N,
                                        const TensionTargets& targets);

// A sentence per violation for a user: "cable 4 would need -12.400 N (its min 5.000 N)", cables
// numbered from 1, or named by `names` where given (one per cable: "D would need ..."); for
// `unbalanced`, the residual. Empty when held.
std::string describe_refusal(const TensionDistribution& distribution,
                             std::span<const std::string> names = {});

}  // namespace pkm::kinematics
