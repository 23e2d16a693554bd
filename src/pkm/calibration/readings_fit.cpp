#include "pkm/calibration/readings_fit.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "pkm/calibration/measurements.hpp"
#include "pkm/kinematics/cable_tensions.hpp"
#include "pkm/kinematics/line_spools.hpp"

namespace pkm::calibration {

namespace {

// Largest reading a file may hold, mm or deg (as a measurement file's).
constexpr double kLargestValue = 1e6;
// A sample's pose is solved until its step is below this share of its size (mm, rad): the fit
// differences the residuals over parameter steps of 1e-6 of their size and finds what they cannot
// see as singular values below 1e-6 of the largest, which needs poses to rounding level.
constexpr double kPoseConverged = 1e-15;
constexpr int kPoseIterations = 60;

// The joint each header column names (-1: t or line, ignored), every joint once.
std::vector<int> read_header(const std::vector<CsvField>& header, int line_number,
                             const std::string& source_name, const machine::Machine& machine) {
  const int joint_count = static_cast<int>(machine.joints().size());
  std::vector<int> joint_of_column(header.size(), -1);
  std::vector<bool> seen(static_cast<std::size_t>(joint_count), false);
  for (std::size_t c = 0; c < header.size(); ++c) {
    const std::string& name = header[c].text;
    if (name == "t" || name == "line") continue;
    int joint = -1;
    for (int j = 0; j < joint_count; ++j) {
      if (name == "j_" + machine.joints()[j].name) joint = j;
    }
    if (joint < 0) {
      fail_at(source_name, line_number, header[c].column,
              "unknown column '" + name + "' (expected j_<joint name>, t or line)");
    }
    if (seen[joint]) {
      fail_at(source_name, line_number, header[c].column, "column '" + name + "' appears twice");
    }
    seen[joint] = true;
    joint_of_column[c] = joint;
  }
  for (int j = 0; j < joint_count; ++j) {
    if (!seen[j])
      fail_at(source_name, line_number, 1, "no column 'j_" + machine.joints()[j].name + "'");
  }
  return joint_of_column;
}

// The line length from the origin (mm) that cable `cable`'s motor at `degrees` from the origin
// gives (RRF's motor position with 360 steps a turn, as Hangprinter's script reads its encoders);
// none where that pays out more line than the spool holds.
std::optional<double> line_from_motor_degrees(const kinematics::LineSpools& spools, int cable,
                                              double degrees) {
  const int steps_per_rev = spools.full_steps_per_rev(cable);
  const std::optional<double> joint =
      spools.joint_from_motor_full_steps(cable, degrees * steps_per_rev / 360.0);
  const std::optional<double> at_origin = spools.joint_from_motor_full_steps(cable, 0.0);
  if (!joint || !at_origin) return std::nullopt;
  return *joint - *at_origin;
}

JointReadings read_row(const std::vector<CsvField>& fields, const std::vector<int>& joint_of_column,
                       int line_number, const std::string& source_name,
                       const machine::Machine& machine, ReadingUnit unit) {
  JointReadings sample;
  sample.values.resize(static_cast<int>(machine.joints().size()));
  sample.line = line_number;
  for (std::size_t c = 0; c < fields.size(); ++c) {
    const int joint = joint_of_column[c];
    if (joint < 0) continue;
    const std::string& field = fields[c].text;
    double value = 0.0;
    if (!csv_number(field, value)) {
      fail_at(source_name, line_number, fields[c].column, "'" + field + "' is not a number");
    }
    if (!std::isfinite(value))
      fail_at(source_name, line_number, fields[c].column, "must be finite");
    if (std::abs(value) > kLargestValue) {
      fail_at(source_name, line_number, fields[c].column,
              "'" + field + "' is beyond any machine (at most 1e6 mm or deg in size)");
    }
    if (unit == ReadingUnit::joint) {
      sample.values[joint] = machine.joints()[joint].from_interface(value);
      continue;
    }
    // require_spools() has seen a spool on every joint.
    const std::optional<double> line_mm =
        line_from_motor_degrees(*machine.kinematics().line_spools(), joint, value);
    if (!line_mm) {
      fail_at(source_name, line_number, fields[c].column,
              "motor position " + field + " deg pays out more line than spool " +
                  std::to_string(joint + 1) +
                  " holds with the machine file's spool_radius and spool_buildup (its wound "
                  "radius would shrink to 0)");
    }
    sample.values[joint] = *line_mm;
  }
  return sample;
}

// The pose (its controlled coordinates `axes`, from `pose` as the seed) whose weighted joints
// fit `wanted` best in least squares (Levenberg-Marquardt), and what it leaves unexplained.
// False where the model fails on the way or the solve does not settle.
bool fit_pose(const kinematics::Kinematics& model, const kinematics::JointVector& wanted,
              const Eigen::VectorXd& weight, const std::vector<int>& axes, geometry::Pose& pose,
              Eigen::VectorXd& misfit) {
  const auto evaluate = [&](const geometry::Pose& at, Eigen::VectorXd& residual,
                            Eigen::MatrixXd& d_residual) {
    kinematics::JointVector joints;
    kinematics::JointJacobian d_joints;
    if (!model.inverse_and_jacobian(at, joints, d_joints).ok()) return false;
    residual = weight.cwiseProduct((joints - wanted).cast<double>());
    d_residual.resize(residual.size(), static_cast<Eigen::Index>(axes.size()));
    for (std::size_t c = 0; c < axes.size(); ++c) {
      d_residual.col(static_cast<Eigen::Index>(c)) = weight.cwiseProduct(d_joints.col(axes[c]));
    }
    return residual.allFinite() && d_residual.allFinite();
  };
  Eigen::VectorXd residual;
  Eigen::MatrixXd d_residual;
  if (!evaluate(pose, residual, d_residual)) return false;
  double damping = 0.0;
  double last_step = std::numeric_limits<double>::infinity();
  bool refused = false;  // the last step was rejected because the model failed there
  for (int iteration = 0; iteration < kPoseIterations; ++iteration) {
    Eigen::MatrixXd normal = d_residual.transpose() * d_residual;
    normal.diagonal() *= 1.0 + damping;
    const Eigen::VectorXd step = -normal.ldlt().solve(d_residual.transpose() * residual);
    if (!step.allFinite()) return false;
    geometry::Vector6d values = pose.as_vector();
    for (std::size_t c = 0; c < axes.size(); ++c)
      values[axes[c]] += step[static_cast<Eigen::Index>(c)];
    const geometry::Pose trial = geometry::Pose::from_vector(values);
    Eigen::VectorXd trial_residual;
    Eigen::MatrixXd trial_d_residual;
    // Near the solution the cost changes by less than its rounding (a step of 1e-7 mm changes
    // it by 1e-14 mm^2): Gauss-Newton's own steps are taken there, not judged by the cost.
    const double size = 1.0 + values.head<3>().norm();
    const bool near = damping == 0.0 && step.norm() <= 1e-6 * size;
    const bool solved = evaluate(trial, trial_residual, trial_d_residual);
    if (solved && (near || trial_residual.squaredNorm() <= residual.squaredNorm())) {
      pose = trial;
      residual = trial_residual;
      d_residual = trial_d_residual;
      damping = damping < 1e-6 ? 0.0 : damping / 10.0;
      refused = false;
    } else {
      damping = damping == 0.0 ? 1e-3 : damping * 10.0;
      refused = !solved;
    }
    last_step = step.norm() / size;
    if (last_step <= kPoseConverged) break;
  }
  // Rounding may keep the last steps above kPoseConverged; far above, the solve did not settle.
  // Steps shrunk by the model refusing every step further (a cable too short, a leg's reach)
  // end at the edge of what it holds, not at the least-squares pose.
  if (!(last_step <= 1e-12) || (refused && damping > 1.0)) return false;
  misfit = residual;
  return true;
}

// The residuals of a geometry: each sample's pose fitted to its readings, and what it leaves.
class ReadingsResiduals final : public ParameterResiduals {
 public:
  ReadingsResiduals(const kinematics::Kinematics& kinematics, const geometry::Pose& home,
                    const std::vector<JointReadings>& samples, const ReadingsFitOptions& options)
      : model_(kinematics.cable_tensions() != nullptr ? kinematics.cable_tensions()->geometry_only()
                                                      : kinematics.clone()),
        home_(home),
        samples_(samples),
        axes_(kinematics.dof().axes()),
        relative_(options.relative_to_home) {
    const int n = kinematics.joint_count();
    weight_ = Eigen::VectorXd::Ones(n);
    for (int j = 0; j < n; ++j) {
      if (kinematics.joint_kind(j) == kinematics::JointKind::rotary) {
        weight_[j] = options.fit.angle_weight_mm_per_rad;
      }
    }
    seeds_.assign(samples_.size(), home_);
    std::vector<double> nominal;
    for (const kinematics::Parameter& p : kinematics.parameters()) nominal.push_back(p.value);
    std::vector<geometry::Pose> found;
    std::vector<double> residuals(static_cast<std::size_t>(count()));
    const int failed = solve(nominal, residuals.data(), &found);
    if (failed >= 0) {
      throw SampleFitError(
          failed,
          "no pose fits these readings with the machine file's geometry (solved from home" +
              std::string(relative_ ? ", where the readings count from" : "") +
              "): check the joints' order and units, and that the machine file's geometry is near "
              "enough the machine's to start from (a cable robot's tension limits are not asked: "
              "the readings were taken where the machine held its effector)");
    }
    seeds_ = found;
  }

  int count() const override { return static_cast<int>(samples_.size()) * model_->joint_count(); }
  int eliminated_unknowns() const override {
    return static_cast<int>(samples_.size() * axes_.size());
  }

  bool evaluate(std::span<const double> parameters, double* residuals) const override {
    last_failure_ = solve(parameters, residuals, nullptr);
    return last_failure_ < 0;
  }
  // The line of the sample the last evaluate() could not solve (0: the geometry itself failed).
  int last_failure() const { return last_failure_; }

  // -1 on success, else the line of the sample that failed (0: the geometry or home failed).
  int solve(std::span<const double> parameters, double* residuals,
            std::vector<geometry::Pose>* poses) const {
    try {
      model_->set_parameters(parameters);
    } catch (const std::invalid_argument&) {
      return 0;
    }
    kinematics::JointVector zero = kinematics::JointVector::Zero(model_->joint_count());
    if (relative_ && !model_->inverse(home_, zero).ok()) return 0;
    const int n = model_->joint_count();
    if (poses != nullptr) poses->clear();
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      geometry::Pose pose = seeds_[i];
      Eigen::VectorXd misfit;
      const kinematics::JointVector wanted = zero + samples_[i].values;
      if (!fit_pose(*model_, wanted, weight_, axes_, pose, misfit)) return samples_[i].line;
      for (int j = 0; j < n; ++j) residuals[static_cast<int>(i) * n + j] = misfit[j];
      if (poses != nullptr) poses->push_back(pose);
    }
    return -1;
  }

  void summarise(const std::vector<double>& residuals, double& rms, double& max,
                 int& max_line) const override {
    double sum = 0.0;
    max = 0.0;
    const int n = model_->joint_count();
    for (std::size_t k = 0; k < residuals.size(); ++k) {
      sum += residuals[k] * residuals[k];
      if (std::abs(residuals[k]) > max) {
        max = std::abs(residuals[k]);
        max_line = samples_[k / static_cast<std::size_t>(n)].line;
      }
    }
    rms = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(residuals.size(), 1)));
  }

  std::string nominal_failure_hint() const override {
    return "no pose fits a sample's readings; check that the readings are the machine's joints";
  }

  double extent_mm() const override {
    Eigen::AlignedBox3d box;
    for (const geometry::Pose& pose : seeds_) box.extend(pose.position_mm);
    return box.isEmpty() ? 0.0 : box.diagonal().norm();
  }

 private:
  std::unique_ptr<kinematics::Kinematics> model_;
  geometry::Pose home_;
  const std::vector<JointReadings>& samples_;
  std::vector<int> axes_;
  bool relative_;
  Eigen::VectorXd weight_;
  std::vector<geometry::Pose> seeds_;  // the poses fitted with the machine file's geometry
  mutable int last_failure_ = -1;
};

// The first of `kept` whose column acts as column `c` does (parallel to 1e-6 of its length, either
// sign: an anchor and its cable's attach point on an effector tied at one point), or -1.
int twin_column(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& norms,
                const std::vector<int>& kept, int c) {
  for (const int k : kept) {
    const double cosine = jacobian.col(k).dot(jacobian.col(c)) / (norms[k] * norms[c]);
    if (std::abs(cosine) > 1.0 - 1e-6) return k;
  }
  return -1;
}

// The residuals' Jacobian over `requested` at the machine file's geometry. A parameter at the
// edge of its range gets a zero column (held: no effect); a sample lost when a parameter moves by
// a millionth sits where the machine file's geometry only just holds its effector, and would
// silently take that parameter out of the fit: refused at its line.
Eigen::MatrixXd nominal_jacobian(const std::vector<double>& nominal,
                                 const ReadingsResiduals& residuals,
                                 const std::vector<int>& requested) {
  Eigen::MatrixXd jacobian;
  int failed_line = 0;
  const auto function = [&](std::span<const double> p, double* out) {
    if (residuals.evaluate(p, out)) return true;
    failed_line = std::max(failed_line, residuals.last_failure());
    return false;
  };
  if (!parameter_jacobian(function, residuals.count(), nominal, requested, jacobian)) {
    throw FitError("the model fails with the machine file's geometry: " +
                   residuals.nominal_failure_hint());
  }
  if (failed_line > 0) {
    throw SampleFitError(failed_line,
                         "the machine file's geometry only just holds the effector where these "
                         "readings put it (the pose is lost when a parameter moves by a "
                         "millionth): leave the sample out, or check its readings");
  }
  return jacobian;
}

// One parameter per direction of the null space of `jacobian`'s `columns` (normalised; singular
// values below rank_tolerance of the largest): each time the column with the largest share in
// what is left unseen (the parameter that carries it most firmly; on ties the later), that share
// then taken out. Returns indices into `columns`.
std::vector<int> null_space_holds(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& norms,
                                  const std::vector<int>& columns, double rank_tolerance) {
  std::vector<int> held;
  Eigen::MatrixXd normalised(jacobian.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) {
    normalised.col(static_cast<Eigen::Index>(k)) = jacobian.col(columns[k]) / norms[columns[k]];
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(normalised, Eigen::ComputeFullV);
  const Eigen::VectorXd& singular = svd.singularValues();
  Eigen::Index rank = 0;
  while (rank < singular.size() && singular[rank] > rank_tolerance * singular[0]) ++rank;
  const Eigen::Index unseen = static_cast<Eigen::Index>(columns.size()) - rank;
  if (unseen <= 0) return held;
  // Back to the parameters' own units (mm), orthonormal again.
  Eigen::MatrixXd basis = svd.matrixV().rightCols(unseen);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    basis.row(static_cast<Eigen::Index>(k)) /= norms[columns[k]];
  }
  basis = Eigen::HouseholderQR<Eigen::MatrixXd>(basis).householderQ() *
          Eigen::MatrixXd::Identity(basis.rows(), unseen);
  for (Eigen::Index direction = 0; direction < unseen; ++direction) {
    const Eigen::VectorXd share = basis.rowwise().norm();
    Eigen::Index best = 0;
    for (Eigen::Index k = 1; k < share.size(); ++k) {
      if (share[k] >= share[best] * (1.0 - 1e-6)) best = k;
    }
    if (share[best] < 1e-9) break;
    held.push_back(static_cast<int>(best));
    const Eigen::RowVectorXd along = basis.row(best) / share[best];
    basis -= (basis * along.transpose()) * along;
  }
  return held;
}

// What joint readings cannot see at all: the directions of parameter space that change no
// residual (the frame turned about home, an anchor moved with its attach point), found from the
// residuals' Jacobian at the machine file's geometry. A parameter that acts exactly as an earlier
// one (an attach point as its cable's anchor) is held first: the later in the model's order, so
// the frame's anchors are fitted and the effector's points kept. Then the null space of the rest,
// one parameter per direction (null_space_holds). Parameters without effect are left to the
// identification (no_effect).
struct UnseenParameters {
  std::vector<std::string> held;
  int without_effect = 0;
};
UnseenParameters unseen_by_readings(const kinematics::Kinematics& kinematics,
                                    const ReadingsResiduals& residuals,
                                    const std::vector<int>& requested, double rank_tolerance) {
  UnseenParameters result;
  if (requested.empty()) return result;
  const std::vector<kinematics::Parameter> parameters = kinematics.parameters();
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : parameters) nominal.push_back(p.value);
  const Eigen::MatrixXd jacobian = nominal_jacobian(nominal, residuals, requested);
  const Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  std::vector<int> columns;
  for (Eigen::Index c = 0; c < norms.size(); ++c) {
    if (!(norms[c] > 1e-9 * norms.maxCoeff())) {
      ++result.without_effect;
    } else if (twin_column(jacobian, norms, columns, static_cast<int>(c)) >= 0) {
      result.held.push_back(parameters[requested[c]].name);
    } else {
      columns.push_back(static_cast<int>(c));
    }
  }
  if (columns.empty()) return result;
  for (const int k : null_space_holds(jacobian, norms, columns, rank_tolerance)) {
    result.held.push_back(parameters[requested[columns[k]]].name);
  }
  return result;
}

}  // namespace

void require_spools(const machine::Machine& machine) {
  const kinematics::LineSpools* spools = machine.kinematics().line_spools();
  if (spools == nullptr && machine.kinematics().cable_tensions() == nullptr) {
    throw FitError("motor degrees are a cable robot's spool positions; a " +
                   std::string(machine.kinematics().type()) +
                   " has none: give its joints' own values");
  }
  for (int cable = 0; cable < machine.kinematics().joint_count(); ++cable) {
    if (spools != nullptr && spools->has_spool(cable)) continue;
    throw FitError(
        "motor degrees need the spools that turn them into line lengths, and cable " +
        std::to_string(cable + 1) + " (joint " + machine.joints()[cable].name +
        ") has none: add spool_radius (mm, M666 R) to its [[kinematics.cables]] or to "
        "[kinematics], with mechanical_advantage, lines_per_spool, motor_gear_teeth, "
        "spool_gear_teeth (M666 U O L H) and spool_buildup (mm, M666 Q) as the machine has them");
  }
}

std::vector<JointReadings> parse_readings_csv(const std::string& text,
                                              const std::string& source_name,
                                              const machine::Machine& machine, ReadingUnit unit) {
  if (unit == ReadingUnit::motor_degrees) require_spools(machine);
  std::istringstream in(text);
  int line_number = 0;
  const std::string line =
      csv_header_line(in, source_name, line_number, "naming every joint, such as j_A,j_B,j_C,j_D");
  const std::vector<CsvField> header = split_csv_line(line);
  const std::vector<int> joint_of_column = read_header(header, line_number, source_name, machine);
  std::vector<JointReadings> samples;
  for_each_csv_row(
      in, source_name, line_number, header.size(),
      [&](const std::vector<CsvField>& fields, int at) {
        samples.push_back(read_row(fields, joint_of_column, at, source_name, machine, unit));
      });
  if (samples.empty()) fail_at(source_name, line_number, 1, "no samples after the header");
  return samples;
}

std::vector<JointReadings> read_readings_csv(const std::filesystem::path& path,
                                             const machine::Machine& machine, ReadingUnit unit) {
  return parse_readings_csv(read_text_file(path), path.string(), machine, unit);
}

int fewest_samples(int readings_per_sample, int pose_coordinates, int parameters) {
  const int spare = readings_per_sample - pose_coordinates;
  return spare <= 0 ? std::numeric_limits<int>::max() : parameters / spare + 1;
}

namespace {

// Throws FitError with the numbers when the samples leave no degree of freedom for the noise.
void refuse_too_few_samples(const ReadingsFitReport& report, int fitted) {
  const int spare = report.readings_per_sample - report.pose_coordinates;
  const int fewest = fewest_samples(report.readings_per_sample, report.pose_coordinates, fitted);
  if (report.samples >= fewest) return;
  throw FitError(
      std::to_string(report.samples) + " samples of " + std::to_string(report.readings_per_sample) +
      " readings pin " + std::to_string(spare) + " each beyond their own " +
      std::to_string(report.pose_coordinates) + " pose coordinates, " +
      std::to_string(report.samples * spare) + " in all: too few for " + std::to_string(fitted) +
      " parameters with the noise left to estimate; take at least " + std::to_string(fewest) +
      " samples (30 or more spread over the workspace pin them well), or fit fewer "
      "with --params");
}

// The residuals' spread (robust) and the noise of a reading they show, from the residuals at the
// solution.
void measure_noise(const ReadingsResiduals& residuals, std::vector<double> values,
                   ReadingsFitReport& report) {
  for (double& value : values) value = std::abs(value);
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  report.residual_spread_mm = 1.4826 * *middle;
  const auto fitted = std::count_if(report.fit.parameters.begin(), report.fit.parameters.end(),
                                    [](const ParameterEstimate& p) { return p.free; });
  const double left = static_cast<double>(residuals.count() - residuals.eliminated_unknowns() -
                                          static_cast<int>(fitted));
  report.noise_mm = report.fit.rms_after_mm * std::sqrt(residuals.count() / left);
}

}  // namespace

ReadingsFitReport fit_readings(kinematics::Kinematics& kinematics, const geometry::Pose& home,
                               const std::vector<JointReadings>& samples,
                               const ReadingsFitOptions& options) {
  ReadingsFitReport report;
  report.samples = static_cast<int>(samples.size());
  for (const JointReadings& sample : samples) report.lines.push_back(sample.line);
  report.readings_per_sample = kinematics.joint_count();
  report.pose_coordinates = kinematics.dof().count();
  if (report.readings_per_sample <= report.pose_coordinates) {
    throw FitError("a " + std::string(kinematics.type()) + " has " +
                   std::to_string(report.readings_per_sample) + " joints for " +
                   std::to_string(report.pose_coordinates) +
                   " coordinates: its readings fix each pose and leave nothing to pin its "
                   "geometry; measure the poses and use `pkm calibrate fit`");
  }
  if (samples.empty()) throw FitError("no samples to fit");
  const std::vector<int> requested = requested_parameters(kinematics, options.fit.parameters);
  const ReadingsResiduals residuals(kinematics, home, samples, options);
  const UnseenParameters unseen =
      unseen_by_readings(kinematics, residuals, requested, options.fit.rank_tolerance);
  const int fitted =
      static_cast<int>(requested.size() - unseen.held.size()) - unseen.without_effect;
  refuse_too_few_samples(report, fitted);
  std::vector<double> nominal;
  for (const kinematics::Parameter& p : kinematics.parameters()) nominal.push_back(p.value);
  std::vector<double> values(static_cast<std::size_t>(residuals.count()));
  residuals.solve(nominal, values.data(), &report.poses_before);
  report.fit = fit_parameters(kinematics, residuals, requested, unseen.held, options.fit);
  report.fit.measurements = report.samples;
  std::vector<double> after;
  for (const kinematics::Parameter& p : kinematics.parameters()) after.push_back(p.value);
  residuals.solve(after, values.data(), &report.poses);
  measure_noise(residuals, values, report);
  return report;
}

}  // namespace pkm::calibration
