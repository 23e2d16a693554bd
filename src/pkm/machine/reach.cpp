// What a machine can reach, and how to say so when it cannot: the explanations of refused poses
// and moves, the reachable extent as lines and as a box, the --origin hint, the conditioning of
// the machine at home.
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

namespace {

// Values in the machine file's units: three decimals of a mm or a degree, four of an inch.
std::string value_text(double value, const char* unit) {
  std::string text =
      kinematics::formatted_number(std::string(unit) == "in" ? "%.4f" : "%.3f", value);
  // A crossing found by bisection lies a hair past zero: "-0.000" says nothing more than 0.
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

}  // namespace

std::string Machine::format_pose(const geometry::Pose& pose) const {
  const geometry::Vector6d values = pose.as_vector();
  const geometry::Dof dof = kinematics_->dof();
  std::string lengths;
  std::string angles;
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!dof.controls(axis)) continue;
    std::string& part = axis < 3 ? lengths : angles;
    part += (part.empty() ? "" : " ") + std::string(geometry::kAxisNames[axis]) + " " +
            value_text(axis_to_file(axis, values[axis]), axis_file_unit(axis));
  }
  std::string text;
  if (!lengths.empty()) text += lengths + " " + length_unit();
  if (!angles.empty()) text += (text.empty() ? "" : " ") + angles + " deg";
  return text;
}

std::string Machine::joint_value_text(int joint, double value) const {
  const char* unit = joint_file_unit(joint);
  return value_text(joint_to_file(joint, value), unit) + " " + unit;
}

std::string Machine::explain_joint(int joint, double value) const {
  const JointSpec& spec = joints_[static_cast<std::size_t>(joint)];
  const std::string name = "joint '" + spec.name + "'";
  if (!std::isfinite(value)) return "the inverse kinematics gives no number for " + name;
  const auto shown = [&](double v) { return joint_value_text(joint, v); };
  std::string text = name + " = " + shown(value);
  if (value < spec.min) return text + " passes its min " + shown(spec.min);
  if (value > spec.max) return text + " passes its max " + shown(spec.max);
  return text + ", within its limits " + shown(spec.min) + " .. " + shown(spec.max);
}

std::string Machine::explain(const geometry::Pose& pose, const kinematics::Status& status) const {
  std::string text = "pose " + format_pose(pose) + ": ";
  const std::string joint_name =
      status.joint >= 0 && status.joint < static_cast<int>(joints_.size())
          ? "joint '" + joints_[static_cast<std::size_t>(status.joint)].name + "'"
          : "";
  kinematics::JointVector joints;
  switch (status.code) {
    case kinematics::StatusCode::joint_limit:
    case kinematics::StatusCode::unreachable:
    case kinematics::StatusCode::singular:
    case kinematics::StatusCode::tension:
      if (!joint_name.empty() && kinematics_->inverse(pose, joints).ok()) {
        return text + explain_joint(status.joint, joints[status.joint]);
      }
      if (const std::string why = kinematics_->why_refused(pose, status); !why.empty()) {
        return text + std::string(kinematics::status_name(status.code)) + ": " + why;
      }
      if (status.code == kinematics::StatusCode::singular)
        return text + kinematics::describe(status);
      return text + (joint_name.empty() ? "unreachable" : joint_name + " cannot reach it");
    case kinematics::StatusCode::outside_envelope: {
      const int axis = status.axis;
      const double value = pose.as_vector()[axis];
      const bool below = value < cartesian_.envelope_min[axis];
      const double limit = below ? cartesian_.envelope_min[axis] : cartesian_.envelope_max[axis];
      const char* unit = axis_file_unit(axis);
      return text + std::string(geometry::kAxisNames[axis]) + " = " +
             value_text(axis_to_file(axis, value), unit) + " " + unit +
             " passes the work envelope's " + (below ? "min " : "max ") +
             value_text(axis_to_file(axis, limit), unit) + " " + unit + " ([cartesian] " +
             (below ? "min" : "max") + ")";
    }
    case kinematics::StatusCode::other_assembly:
      return text + explain_other_assembly(pose);
    case kinematics::StatusCode::invalid_input:
      return text + "not a finite pose";
    case kinematics::StatusCode::joint_angle:
    case kinematics::StatusCode::interference:
      return text + explain_mechanism_limit(pose, status);
    default:
      // A tension limit, a balance not found: the model's own words where it has some.
      if (const std::string why = kinematics_->why_refused(pose, status); !why.empty()) {
        return text + pkm::kinematics::describe(status, joint_names()) + ": " + why;
      }
      return text + pkm::kinematics::describe(status, joint_names());
  }
}

std::string Machine::explain_other_assembly(const geometry::Pose& pose) const {
  const std::string across =
      "another assembly mode than home's, across a singularity (a platform below its "
      "carriages, a hexapod platform tilted past 90 deg)";
  const kinematics::BasePlaneMargin side = kinematics_->base_plane_margin(pose);
  if (!(side.margin_mm <= 0.0)) return across;
  return "another assembly mode than home's: the platform joint of '" +
         joints_[static_cast<std::size_t>(side.leg)].name + "' is " +
         value_text(-side.margin_mm / mm_per_unit(), length_unit()) + " " + length_unit() +
         " past the base joints' plane, on the other side of it than at home: toward the machine's "
         "mirror image, beyond the singularity where its legs lie flat in that plane";
}

std::string Machine::explain_mechanism_limit(const geometry::Pose& pose,
                                             const kinematics::Status& status) const {
  std::vector<kinematics::MechanismLimit> limits;
  kinematics_->mechanism_limits(pose, limits);
  const kinematics::MechanismLimit* worst = nullptr;
  for (const kinematics::MechanismLimit& limit : limits) {
    if (limit.code != status.code || limit.leg != status.joint) continue;
    if (worst == nullptr || limit.margin() < worst->margin()) worst = &limit;
  }
  if (worst == nullptr) return kinematics::describe(status);
  return mechanism_limit_text(*worst);
}

std::string Machine::mechanism_limit_text(const kinematics::MechanismLimit& limit) const {
  const auto joint = [&](int leg) {
    return leg < static_cast<int>(joints_.size())
               ? "'" + joints_[static_cast<std::size_t>(leg)].name + "'"
               : std::to_string(leg + 1);
  };
  if (limit.code == kinematics::StatusCode::joint_angle) {
    return std::string("joint_angle: the ") +
           (limit.other == 0 ? "inner (base or carriage)" : "platform") + " joint of " +
           joint(limit.leg) + " is at " +
           value_text(geometry::radians_to_degrees(limit.value), "deg") +
           " deg from its axis; max_joint_angle is " +
           value_text(geometry::radians_to_degrees(limit.limit), "deg") + " deg";
  }
  return "interference: " + joint(limit.leg) + " and " + joint(limit.other) + " are " +
         value_text(limit.value / mm_per_unit(), length_unit()) + " " + length_unit() +
         " apart (axis to axis); leg_diameter is " +
         value_text(limit.limit / mm_per_unit(), length_unit()) + " " + length_unit();
}

std::string Machine::explain_envelope_crossing(
    const geometry::Pose& pose, int axis,
    const std::function<geometry::Vector6d(double)>& pose_at) const {
  constexpr int kSamples = 1000;
  const double value = pose.as_vector()[axis];
  const bool over = value > cartesian_.envelope_max[axis];
  double worst = value;
  for (int k = 0; k <= kSamples; ++k) {
    const double sample = pose_at(static_cast<double>(k) / kSamples)[axis];
    worst = over ? std::max(worst, sample) : std::min(worst, sample);
  }
  const char* unit = axis_file_unit(axis);
  const auto shown = [&](double v) { return value_text(axis_to_file(axis, v), unit) + " " + unit; };
  return "pose " + format_pose(pose) + ": " + std::string(geometry::kAxisNames[axis]) +
         " passes the work envelope's " +
         (over ? "max " + shown(cartesian_.envelope_max[axis])
               : "min " + shown(cartesian_.envelope_min[axis])) +
         " there, " + (over ? "up to " : "down to ") + shown(worst) + " along the move";
}

std::string Machine::explain_path(const std::function<geometry::Vector6d(double)>& pose_at) const {
  constexpr int kSamples = 1000;
  kinematics::JointVector joints;
  const auto fails = [&](double u) {
    return !inverse(geometry::Pose::from_vector(pose_at(u)), joints).ok();
  };
  int first_bad = -1;
  for (int k = 0; k <= kSamples && first_bad < 0; ++k) {
    if (fails(static_cast<double>(k) / kSamples)) first_bad = k;
  }
  if (first_bad < 0) return "the move is within reach at every sampled pose";
  // The crossing, to a millionth of the move: every caller of the same move names the same
  // pose and joint.
  double good = first_bad == 0 ? 0.0 : (first_bad - 1.0) / kSamples;
  double bad = static_cast<double>(first_bad) / kSamples;
  if (first_bad > 0) {
    while (bad - good > 1e-6) (fails(0.5 * (good + bad)) ? bad : good) = 0.5 * (good + bad);
  }
  const geometry::Pose pose = geometry::Pose::from_vector(pose_at(bad));
  const kinematics::Status status = inverse(pose, joints);
  std::string text = first_bad == 0
                         ? "at its start: "
                         : "at " + kinematics::formatted_number("%.1f", 100.0 * bad) + " % of it: ";
  if (status.code == kinematics::StatusCode::outside_envelope) {
    return text + explain_envelope_crossing(pose, status.axis, pose_at);
  }
  if (status.code != kinematics::StatusCode::joint_limit) return text + explain(pose, status);
  // The joint is at its limit at the crossing: say which limit, and how far beyond it the joint
  // goes along the rest of the move (what must change).
  const int joint = status.joint;
  const JointSpec& spec = joints_[static_cast<std::size_t>(joint)];
  const bool over = joints[joint] > spec.max;
  double worst = joints[joint];
  for (int k = first_bad; k <= kSamples; ++k) {
    const geometry::Pose sample =
        geometry::Pose::from_vector(pose_at(static_cast<double>(k) / kSamples));
    if (!kinematics_->inverse(sample, joints).ok() || !std::isfinite(joints[joint])) continue;
    worst = over ? std::max(worst, joints[joint]) : std::min(worst, joints[joint]);
  }
  const char* unit = joint_file_unit(joint);
  const auto shown = [&](double v) {
    return value_text(joint_to_file(joint, v), unit) + " " + unit;
  };
  return text + "pose " + format_pose(pose) + ": joint '" + spec.name + "' passes its " +
         (over ? "max " + shown(spec.max) : "min " + shown(spec.min)) + " there, " +
         (over ? "up to " : "down to ") + shown(worst) + " along the move";
}

std::vector<AxisExtent> reachable_extent(const Machine& machine) {
  std::vector<AxisExtent> extents;
  const geometry::Vector6d home = machine.home().as_vector();
  kinematics::JointVector joints;
  const auto reachable = [&](int axis, double offset) {
    geometry::Vector6d pose = home;
    pose[axis] += offset;
    return machine.inverse(geometry::Pose::from_vector(pose), joints).ok();
  };
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!machine.kinematics().dof().controls(axis)) continue;
    AxisExtent extent{axis, home[axis], home[axis]};
    // Angles are bounded by a half turn; lengths by a kilometre.
    const double limit = axis < 3 ? 1e6 : 3.14159265358979323846;
    const double first_step = axis < 3 ? 1.0 : 1e-3;
    const double resolution = axis < 3 ? 1e-6 : 1e-9;
    for (const double sign : {-1.0, 1.0}) {
      double inside = 0.0;
      double outside = first_step;
      while (outside < limit && reachable(axis, sign * outside)) {
        inside = outside;
        outside *= 2.0;
      }
      if (outside >= limit) {
        outside = limit;
        if (reachable(axis, sign * limit)) inside = limit;
      }
      while (outside - inside > resolution && inside < limit) {
        const double middle = 0.5 * (inside + outside);
        (reachable(axis, sign * middle) ? inside : outside) = middle;
      }
      (sign < 0 ? extent.min : extent.max) = home[axis] + sign * inside;
    }
    extents.push_back(extent);
  }
  return extents;
}

bool PoseBox::contains(const PoseBox& inner) const {
  for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
    if (!axes.controls(axis) || !inner.axes.controls(axis)) continue;
    if (inner.min[axis] < min[axis] || inner.max[axis] > max[axis]) return false;
  }
  return true;
}

PoseBox reach_box(const Machine& machine) {
  PoseBox box;
  for (const AxisExtent& extent : reachable_extent(machine)) {
    box.axes = box.axes.with(extent.axis);
    box.min[extent.axis] = extent.min;
    box.max[extent.axis] = extent.max;
  }
  return box;
}

namespace {

// "x 0.000..500.000 y -20.000..40.000 mm" over the translational axes both boxes share, in the
// machine file's units.
std::string box_text(const Machine& machine, const PoseBox& box, geometry::Dof axes) {
  std::string text;
  for (int axis = 0; axis < 3; ++axis) {
    if (!axes.controls(axis)) continue;
    text += (text.empty() ? "" : " ") + std::string(geometry::kAxisNames[axis]) + " " +
            kinematics::formatted_number("%.3f", machine.axis_to_file(axis, box.min[axis]) + 0.0) +
            ".." +
            kinematics::formatted_number("%.3f", machine.axis_to_file(axis, box.max[axis]) + 0.0);
  }
  return text + " " + machine.length_unit();
}

}  // namespace

std::string outside_reach_hint(const Machine& machine, const PoseBox& job,
                               const geometry::Vector6d& origin) {
  const PoseBox reach = reach_box(machine);
  geometry::Dof shared;
  for (int axis = 0; axis < 3; ++axis) {
    if (reach.axes.controls(axis) && job.axes.controls(axis)) shared = shared.with(axis);
  }
  PoseBox placed = job;
  placed.min += origin;
  placed.max += origin;
  if (reach.contains(placed)) return "";
  std::string text = "the job spans " + box_text(machine, placed, shared) +
                     "; the machine reaches " + box_text(machine, reach, shared) +
                     " (along lines through home)";
  // --origin is typed in the machine file's units: whole mm, or hundredths of an inch.
  const char* origin_format = machine.units() == LengthUnit::inch ? "%.2f" : "%.0f";
  std::string suggestion;
  std::string too_big;
  int last = -1;
  for (int axis = 0; axis < 3; ++axis) {
    if (shared.controls(axis)) last = axis;
  }
  for (int axis = 0; axis <= last; ++axis) {
    const double centred = shared.controls(axis) ? 0.5 * (reach.min[axis] + reach.max[axis]) -
                                                       0.5 * (job.min[axis] + job.max[axis])
                                                 : origin[axis];
    suggestion += " " + kinematics::formatted_number(origin_format,
                                                     machine.axis_to_file(axis, centred) + 0.0);
    if (shared.controls(axis) &&
        job.max[axis] - job.min[axis] > reach.max[axis] - reach.min[axis]) {
      too_big += std::string(too_big.empty() ? "" : ", ") + std::string(geometry::kAxisNames[axis]);
    }
  }
  if (!too_big.empty()) {
    return text + "; the job is larger than the reach in " + too_big + ": no --origin fits it";
  }
  return text + "; --origin" + suggestion + " would centre it";
}

namespace {

// The machine's jacobian at home with each controlled coordinate's column scaled to unit length,
// and those lengths; false when it has none there.
bool scaled_jacobian_at_home(const Machine& machine, Eigen::MatrixXd& columns,
                             Eigen::VectorXd& norms) {
  kinematics::JointJacobian jacobian;
  if (!machine.kinematics().jacobian(machine.home(), jacobian).ok()) return false;
  const geometry::Dof dof = machine.kinematics().dof();
  columns.resize(jacobian.rows(), dof.count());
  norms.resize(dof.count());
  for (int axis = 0, k = 0; axis < geometry::kPoseSize; ++axis) {
    if (!dof.controls(axis)) continue;
    norms[k] = jacobian.col(axis).norm();
    columns.col(k) = jacobian.col(axis) / norms[k];
    ++k;
  }
  return true;
}

}  // namespace

double relative_conditioning_at_home(const Machine& machine) {
  Eigen::MatrixXd columns;
  Eigen::VectorXd norms;
  if (!scaled_jacobian_at_home(machine, columns, norms)) return 0.0;
  // An axis no joint moves, or one the jacobian cannot say.
  if (!(norms.minCoeff() > 0.0) || !norms.allFinite()) return 0.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(columns);
  const Eigen::VectorXd values = svd.singularValues();
  if (values.size() == 0 || !(values[0] > 0.0)) return 0.0;
  return values[values.size() - 1] / values[0];
}

std::string singular_at_home(const Machine& machine) {
  const double conditioning = relative_conditioning_at_home(machine);
  if (!(conditioning < kSingularAtHome)) return "";
  Eigen::MatrixXd columns;
  Eigen::VectorXd norms;
  if (!scaled_jacobian_at_home(machine, columns, norms)) {
    return "the machine has no jacobian at home: it cannot be moved from there under control";
  }
  const std::vector<int> axes = machine.kinematics().dof().axes();
  // The motion of the tool that moves the joints least: the right singular vector of the smallest
  // singular value, back in mm and rad.
  Eigen::VectorXd motion = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(axes.size()));
  if (!(norms.minCoeff() > 0.0) || !norms.allFinite()) {
    Eigen::Index still = 0;
    for (Eigen::Index k = 0; k < norms.size(); ++k) {
      if (!(norms[k] > 0.0)) still = k;
    }
    motion[still] = 1.0;
  } else {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(columns, Eigen::ComputeFullV);
    motion = svd.matrixV().col(svd.matrixV().cols() - 1).cwiseQuotient(norms);
  }
  // In the file's units (mm or inch, deg), of unit length, its largest part positive.
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const auto at = static_cast<Eigen::Index>(k);
    motion[at] = machine.axis_to_file(axes[k], motion[at]);
  }
  motion /= motion.norm();
  Eigen::Index largest = 0;
  motion.cwiseAbs().maxCoeff(&largest);
  if (motion[largest] < 0.0) motion = -motion;
  std::string direction;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const double value = motion[static_cast<Eigen::Index>(k)];
    if (std::abs(value) < 5e-4) continue;
    direction += (direction.empty() ? "" : " ") + std::string(geometry::kAxisNames[axes[k]]) + " " +
                 kinematics::formatted_number("%.3f", value);
  }
  return "the machine is singular at home: the relative smallest singular value of its jacobian "
         "is " +
         kinematics::formatted_number("%.3g", conditioning) + ", below " +
         kinematics::formatted_number("%.0e", kSingularAtHome) + "; the tool's motion " +
         direction + " (" + machine.length_unit() +
         ", deg) moves no joint, so no motor can drive or hold it there";
}

}  // namespace pkm::machine
