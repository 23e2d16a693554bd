#include "pkm/kinematics/formula.hpp"

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <regex>
#include <stdexcept>

#include "pkm/kinematics/closed_form_text.hpp"

namespace pkm::kinematics {

FormulaKinematics::FormulaKinematics(FormulaDefinition definition)
    : definition_(std::move(definition)) {
  if (definition_.formulas.empty() || definition_.formulas.size() > kMaxJoints) {
    throw std::invalid_argument("a formula machine needs 1 to " + std::to_string(kMaxJoints) +
                                " formulas");
  }
  for (const int axis : definition_.axes) dof_ = dof_.with(axis);
  static std::atomic<std::uint64_t> next_serial{1};
  serial_ = next_serial.fetch_add(1, std::memory_order_relaxed);
  constant_values_ = std::make_unique<double[]>(definition_.constants.size());
  for (std::size_t i = 0; i < definition_.constants.size(); ++i) {
    constant_values_[i] = definition_.constants[i].second;
  }
  own_ = make_evaluator();
}

namespace {

// muparser's assignment operator '=' (enabled in every parser) would let a formula change a
// constant or an axis for every later evaluation: `d = d + 1e-3, sqrt(...)` moves an anchor by a
// micrometre per call. '=' is an operator character only in '=', '==', '<=', '>=' and '!=', so
// the first '=' not part of a comparison is an assignment; its 1-based column, or 0.
std::size_t assignment_column(const std::string& expression) {
  for (std::size_t i = 0; i < expression.size(); ++i) {
    if (expression[i] != '=') continue;
    if (i + 1 < expression.size() && expression[i + 1] == '=') {
      ++i;  // '==': a comparison
      continue;
    }
    if (i > 0 &&
        (expression[i - 1] == '<' || expression[i - 1] == '>' || expression[i - 1] == '!')) {
      continue;
    }
    return i + 1;
  }
  return 0;
}

void refuse_assignment(const std::string& joint, const std::string& expression) {
  if (const std::size_t column = assignment_column(expression); column != 0) {
    throw FormulaError(joint, "assigns with '=' at column " + std::to_string(column) +
                                  ": a formula only computes its joint from the pose; its "
                                  "constants and axes cannot be changed (compare with '==')");
  }
}

}  // namespace

std::unique_ptr<FormulaKinematics::Evaluator> FormulaKinematics::make_evaluator() const {
  auto evaluator = std::make_unique<Evaluator>();
  evaluator->parsers.reserve(definition_.formulas.size());
  for (const auto& [joint, expression] : definition_.formulas) {
    refuse_assignment(joint, expression);
    mu::Parser& parser = evaluator->parsers.emplace_back();
    try {
      for (const int axis : definition_.axes) {
        parser.DefineVar(std::string(geometry::kAxisNames[axis]), &evaluator->pose_variables[axis]);
      }
      for (std::size_t i = 0; i < definition_.constants.size(); ++i) {
        parser.DefineVar(definition_.constants[i].first, &constant_values_[i]);
      }
      parser.DefineConst("PI", std::numbers::pi);
      parser.SetExpr(expression);
      evaluator->pose_variables.fill(0.0);
      parser.Eval();  // parses now, so a bad formula fails at load, not mid-job
      if (parser.GetNumResults() != 1) {
        throw FormulaError(joint, "gives " + std::to_string(parser.GetNumResults()) +
                                      " values separated by commas: a formula gives its joint "
                                      "one value");
      }
    } catch (const mu::Parser::exception_type& error) {
      throw FormulaError(joint, error.GetMsg());
    }
  }
  return evaluator;
}

FormulaKinematics::Evaluator& FormulaKinematics::thread_evaluator() const {
  struct Cached {
    std::uint64_t serial = 0;
    std::unique_ptr<Evaluator> evaluator;
  };
  // A few models a thread used last: the workspace's threads share one; calibration's fits
  // make a model per step (a thread's oldest goes first).
  constexpr std::size_t kCachedModels = 8;
  thread_local std::vector<Cached> cache;
  for (Cached& cached : cache) {
    if (cached.serial == serial_) return *cached.evaluator;
  }
  if (cache.size() == kCachedModels) cache.erase(cache.begin());
  cache.push_back({serial_, make_evaluator()});
  return *cache.back().evaluator;
}

Status FormulaKinematics::evaluate(Evaluator& evaluator, const geometry::Pose& pose,
                                   JointVector& joints) const {
  for (const int axis : definition_.axes) {
    evaluator.pose_variables[axis] =
        axis < 3 ? pose.position_mm[axis] / definition_.mm_per_unit
                 : geometry::radians_to_degrees(pose.orientation_rad[axis - 3]);
  }
  joints.resize(joint_count());
  for (int i = 0; i < joint_count(); ++i) {
    double value = 0.0;
    try {
      value = evaluator.parsers[static_cast<std::size_t>(i)].Eval();
    } catch (const mu::Parser::exception_type&) {
      return Status::failure(StatusCode::unreachable, i);
    }
    // A formula that has no real value here (sqrt of a negative) means the pose is out of reach.
    if (!std::isfinite(value)) return Status::failure(StatusCode::unreachable, i);
    joints[i] = value * definition_.mm_per_unit;
  }
  return Status::success();
}

Status FormulaKinematics::inverse(const geometry::Pose& pose, JointVector& joints) const {
  if (!all_finite(pose)) return Status::failure(StatusCode::invalid_input);
  if (!own_busy_.test_and_set(std::memory_order_acquire)) {
    const Status status = evaluate(*own_, pose, joints);
    own_busy_.clear(std::memory_order_release);
    return status;
  }
  return evaluate(thread_evaluator(), pose, joints);
}

Status FormulaKinematics::forward(const JointVector& joints, geometry::Pose& pose_inout) const {
  if (joints.size() != joint_count()) return Status::failure(StatusCode::invalid_input);
  return solve_forward_newton(*this, joints, pose_inout, forward_options_);
}

Status FormulaKinematics::jacobian(const geometry::Pose& pose,
                                   JointJacobian& d_joints_d_pose) const {
  return numerical_jacobian(*this, pose, d_joints_d_pose);
}

int FormulaKinematics::assembly_mode(const geometry::Pose& pose) const {
  if (static_cast<int>(definition_.axes.size()) != joint_count()) return 0;
  JointJacobian jacobian;
  if (!numerical_jacobian(*this, pose, jacobian).ok()) return 0;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxJoints, geometry::kPoseSize> square(
      joint_count(), joint_count());
  for (int k = 0; k < joint_count(); ++k) square.col(k) = jacobian.col(definition_.axes[k]);
  return square.determinant() >= 0.0 ? 1 : -1;
}

std::vector<Parameter> FormulaKinematics::parameters() const {
  std::vector<Parameter> result;
  // A constant means what the formulas make of it: BuiltTolerance::none, judged by rank only.
  for (const auto& [name, value] : definition_.constants) result.push_back({name, value, ""});
  return result;
}

void FormulaKinematics::set_parameters(std::span<const double> values) {
  if (values.size() != definition_.constants.size()) {
    throw std::invalid_argument("formula machine takes " +
                                std::to_string(definition_.constants.size()) + " parameters");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) throw std::invalid_argument("constants must be finite");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    definition_.constants[i].second = values[i];
    constant_values_[i] = values[i];  // every evaluator reads them where they are
  }
}

std::unique_ptr<Kinematics> make_formula_kinematics(const ModelConfig& config) {
  FormulaDefinition definition;
  definition.mm_per_unit = config.mm_per_file_unit();
  for (const std::string& name : config.string_list("axes")) {
    const int axis = geometry::axis_index(name);
    if (axis < 0) config.fail("axes", "'" + name + "' is not one of x, y, z, a, b, c");
    for (const int seen : definition.axes) {
      if (seen == axis) config.fail("axes", "'" + name + "' is listed twice");
    }
    definition.axes.push_back(axis);
  }
  if (definition.axes.empty()) config.fail("axes", "needs at least one axis");
  if (config.has("constants")) {
    for (const auto& [name, value] : config.number_table("constants")) {
      if (geometry::axis_index(name) >= 0) {
        config.fail("constants", "'" + name + "' would hide the axis of the same name");
      }
      definition.constants.emplace_back(name, value);
    }
  }
  // Formulas are keyed by joint name; order them as the [[joints]] tables are.
  const auto formulas = config.string_table("formulas");
  for (const std::string& joint : config.joint_names()) {
    bool found = false;
    for (const auto& [name, expression] : formulas) {
      if (name == joint) {
        definition.formulas.emplace_back(name, expression);
        found = true;
      }
    }
    if (!found) config.fail("formulas", "joint '" + joint + "' has no formula");
  }
  for (const auto& [name, expression] : formulas) {
    bool known = false;
    for (const std::string& joint : config.joint_names()) known = known || joint == name;
    if (!known) config.fail("formulas." + name, "names no joint of this machine");
  }
  if (static_cast<int>(definition.formulas.size()) != static_cast<int>(definition.axes.size())) {
    config.fail("axes", "needs one axis per joint: " + std::to_string(definition.axes.size()) +
                            " axes for " + std::to_string(definition.formulas.size()) + " joints");
  }
  try {
    return std::make_unique<FormulaKinematics>(std::move(definition));
  } catch (const FormulaError& error) {
    config.fail("formulas." + error.joint(), error.what());
  } catch (const std::invalid_argument& error) {
    config.fail("formulas", error.what());
  }
}

void FormulaKinematics::write_config(ModelConfigWriter& out) const {
  out.axis_list("axes", dof_);
  out.number_table("constants", definition_.constants);
  out.string_table("formulas", definition_.formulas);
}

std::optional<std::vector<std::string>> FormulaKinematics::joint_formulas() const {
  std::vector<std::string> formulas;
  for (const auto& [joint, expression] : definition_.formulas) {
    std::string e = expression;
    for (const auto& [name, value] : definition_.constants) {
      e = std::regex_replace(e, std::regex("\\b" + name + "\\b"), "(" + plain_decimal(value) + ")");
    }
    formulas.push_back(e);
  }
  return formulas;
}

}  // namespace pkm::kinematics
