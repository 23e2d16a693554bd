// The least-squares machinery every calibration fit shares: which named parameters of a model
// the residuals can identify (column-pivoted QR of the Jacobian, SVD for the groups it cannot
// tell apart), the Ceres solve over those, the parameters held because the data pin them less
// well than their kind's plausible deviation, the refusal of a fitted value no such hardware can
// have, and the report with standard deviations. A fit supplies only its residuals (measured
// poses, measured distances between drawn marks).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "pkm/calibration/identifiability.hpp"
#include "pkm/kinematics/kinematics.hpp"

namespace pkm::calibration {

struct FitOptions {
  // Parameter names to fit; '*' matches any run of characters ("leg*.offset"). Empty: all.
  std::vector<std::string> parameters;
  // Angle residuals count as this many mm per radian (a 100 mm lever).
  double angle_weight_mm_per_rad = 100.0;
  // A direction of parameter space whose (column-normalised) singular value is below this
  // fraction of the largest cannot be told apart by the data.
  double rank_tolerance = 1e-6;
  // The measurement noise an identification before any measurement assumes (`pkm calibrate
  // pattern`: a tape read to the half millimetre), mm. A fit takes its noise from its residuals.
  double design_noise_mm = 0.5;
};

struct ParameterEstimate {
  std::string name;
  std::string unit;
  double nominal = 0.0;
  double fitted = 0.0;
  double standard_deviation = 0.0;   // 0 for parameters held at nominal
  bool free = false;                 // fitted (true) or held at its nominal value
  std::string kind;                  // parameter_plausibility.hpp; "" when not judged
  double plausible_deviation = 0.0;  // from nominal, in `unit`; 0 when not judged
};

struct FitReport {
  int measurements = 0;
  // Per-measurement distance between modelled and measured value (a pose over its measured
  // coordinates, angles weighted by angle_weight_mm_per_rad; a distance between two marks), mm.
  double rms_before_mm = 0.0;
  double max_before_mm = 0.0;
  double rms_after_mm = 0.0;
  double max_after_mm = 0.0;
  int max_after_line = 0;
  std::vector<ParameterEstimate> parameters;
  // Groups of parameters the data cannot tell apart, each a direction of parameter space the
  // residuals do not see; the fit holds enough of them at their nominal values.
  std::vector<std::vector<std::string>> indistinguishable;
  // Parameters that do not act on the data at the nominal geometry at all (a matrix mill's z
  // column measured at z = 0), or cannot move both ways from their nominal value (a pulley
  // radius or an effector mass of 0): held.
  std::vector<std::string> no_effect;
  // Parameters held because together they only move the whole drawing (a rigid motion), which
  // distances between marks cannot see. Empty for pose fits.
  std::vector<std::string> held_rigid_motion;
  // Parameters the data determine less well than their kind's plausible deviation from the
  // machine file (a pulley radius to +-18 mm): held at nominal, each with its numbers and the
  // parameters it trades with, in the order held.
  std::vector<PoorlyDetermined> poorly_determined;
  std::vector<std::string> held;  // requested parameters held at nominal (all reasons)
  bool converged = false;
  int iterations = 0;
};

class FitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A fit's residuals as a function of the model's full parameter vector (parameters() order).
class ParameterResiduals {
 public:
  virtual ~ParameterResiduals() = default;
  virtual int count() const = 0;
  // false where the geometry is impossible (set_parameters refuses it) or the model fails.
  virtual bool evaluate(std::span<const double> parameters, double* residuals) const = 0;
  // Per-measurement RMS and largest size (mm) of a residual vector, and the source line of the
  // largest.
  virtual void summarise(const std::vector<double>& residuals, double& rms_mm, double& max_mm,
                         int& max_line) const = 0;
  // What to check when the nominal geometry already fails ("every row's joints inside reach").
  virtual std::string nominal_failure_hint() const = 0;
  // The size of what was measured (the diagonal of the bounding box of the measured positions
  // or of the marks), mm: the scale of a frame position's plausible deviation.
  virtual double extent_mm() const = 0;
  // Unknowns solved for inside evaluate() beside the parameters (each sample's pose where the
  // fit eliminates them, readings_fit.hpp): they take degrees of freedom from the residuals'
  // noise estimate and from what the measured values can fit.
  virtual int eliminated_unknowns() const { return 0; }
};

// Indices (parameters() order) of the parameters `patterns` name ('*' wildcards; empty: all).
// Throws FitError naming the model's parameters when a pattern names none.
std::vector<int> requested_parameters(const kinematics::Kinematics& kinematics,
                                      const std::vector<std::string>& patterns);

// Central-difference Jacobian of `function` (`rows` values) at `at` over the parameters
// `columns`. A parameter that cannot move both ways (an impossible geometry on one side: a
// length at 0) gets a zero column (identification: it is held), or is differenced on its valid
// side (the solver, at a parameter it drove to the edge of its range). False when `function`
// fails at `at` itself, or on both sides of a parameter with one_sided_at_edges.
using VectorFunction = std::function<bool(std::span<const double>, double*)>;
enum class Differencing { zero_at_edges, one_sided_at_edges };
bool parameter_jacobian(const VectorFunction& function, int rows, const std::vector<double>& at,
                        const std::vector<int>& columns, Eigen::MatrixXd& result,
                        Differencing differencing = Differencing::zero_at_edges);

struct Identification {
  std::vector<int> candidates;  // parameter indices the identification looked at
  std::vector<int> free;        // those it identifies, sorted
  std::vector<std::vector<std::string>> indistinguishable;
  std::vector<std::string> no_effect;  // zero columns (FitReport::no_effect)
};
// Which of `candidates` (parameter indices; `jacobian` has one column per candidate) the data
// identifies: column-pivoted QR of the column-normalised Jacobian keeps the best-conditioned
// set; the SVD's null directions name the groups it cannot tell apart. A parameter whose column
// is zero (at rounding level) is named in `no_effect`, not in a group.
Identification identify_parameters(const Eigen::MatrixXd& jacobian,
                                   const std::vector<int>& candidates,
                                   const std::vector<kinematics::Parameter>& parameters,
                                   double rank_tolerance);

// identify_parameters from the residuals' Jacobian at the model's current (nominal) geometry,
// over `requested` minus the parameters named in `held`. Throws FitError where the model fails.
Identification identify_at_nominal(const kinematics::Kinematics& kinematics,
                                   const ParameterResiduals& residuals,
                                   const std::vector<int>& requested,
                                   const std::vector<std::string>& held, double rank_tolerance);

// The parameters of `free` (indices) with their kinds' plausible deviations, at `values`.
std::vector<ScreenedParameter> screened_parameters(const kinematics::Kinematics& kinematics,
                                                   const std::vector<int>& free,
                                                   const std::vector<double>& values,
                                                   double extent_mm);

// Levenberg-Marquardt (Ceres) alone over the parameters `free` (indices), the others held at
// `nominal`: no identification, no plausibility (what fit_parameters adds). For fits that are not
// identifications of a built machine (the nearest machine of a firmware's form).
struct LeastSquaresSolution {
  std::vector<double> fitted;
  bool converged = true;
  int iterations = 0;
};
LeastSquaresSolution least_squares(const ParameterResiduals& residuals,
                                   const std::vector<double>& nominal,
                                   const std::vector<int>& free);

// The whole fit: identification at the model's current (nominal) geometry over `requested`
// minus `held_rigid_motion`, Levenberg-Marquardt over the identified parameters, standard
// deviations from sigma^2 (J^T J)^-1 at the solution (sigma^2 from the residuals); parameters
// poorly determined (poorly_determined()) are held and the rest fitted again. Throws FitError,
// naming its numbers, when a fitted value is more than kImplausibleDeviations plausible
// deviations from nominal. Updates `kinematics` to the fit.
FitReport fit_parameters(kinematics::Kinematics& kinematics, const ParameterResiduals& residuals,
                         const std::vector<int>& requested,
                         const std::vector<std::string>& held_rigid_motion,
                         const FitOptions& options);

}  // namespace pkm::calibration
