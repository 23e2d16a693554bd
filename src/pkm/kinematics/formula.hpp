// Mach3-style formula axes: one expression per joint in the pose coordinates, evaluated by
// muparser. FK by damped Newton with a central-difference Jacobian.
#pragma once

#include <muParser.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

struct FormulaDefinition {
  std::vector<int> axes;  // pose indices the formulas may use (and the machine controls)
  std::vector<std::pair<std::string, double>> constants;
  std::vector<std::pair<std::string, std::string>>
      formulas;  // joint name -> expression, in joint order
  // Formulas see lengths in the machine file's units (mm or inch) and angles in degrees, as a
  // Mach3 user typing them would; joint values come back in the same length unit.
  double mm_per_unit = 1.0;
};

// Raised for an expression muparser refuses; names the joint and the position in the expression.
class FormulaError : public std::runtime_error {
 public:
  FormulaError(std::string joint, std::string message)
      : std::runtime_error(message), joint_(std::move(joint)) {}
  const std::string& joint() const { return joint_; }

 private:
  std::string joint_;
};

// Constant calls from several threads at once are safe: a muparser parser reads the pose from
// variables bound into it and keeps its own stacks, so a call evaluates on the model's own
// parsers when no other call is using them, else on its thread's own (made on that thread's
// first such call, kept for the few models it used last). A single thread (pkmkins' servo
// thread) always finds the model's own free: nothing is made or allocated per call.
class FormulaKinematics final : public Kinematics {
 public:
  explicit FormulaKinematics(FormulaDefinition definition);
  FormulaKinematics(const FormulaKinematics& other) : FormulaKinematics(other.definition_) {
    forward_options_ = other.forward_options_;
  }
  FormulaKinematics& operator=(const FormulaKinematics&) = delete;

  std::string_view type() const override { return "formula"; }
  int joint_count() const override { return static_cast<int>(definition_.formulas.size()); }
  geometry::Dof dof() const override { return dof_; }
  Status inverse(const geometry::Pose& pose, JointVector& joints) const override;
  Status forward(const JointVector& joints, geometry::Pose& pose_inout) const override;
  Status jacobian(const geometry::Pose& pose, JointJacobian& d_joints_d_pose) const override;
  // Sign of det(d joints / d pose): formulas such as Hektor's are met by mirror-image poses
  // (above and below the anchors), and only the home pose's side is the machine's.
  int assembly_mode(const geometry::Pose& pose) const override;
  std::vector<Parameter> parameters() const override;
  void set_parameters(std::span<const double> values) override;
  std::unique_ptr<Kinematics> clone() const override {
    return std::make_unique<FormulaKinematics>(*this);
  }
  // axes, then the [kinematics.constants] and [kinematics.formulas] tables.
  void write_config(ModelConfigWriter& out) const override;
  // The file's formulas with each constant's value in its place.
  std::optional<std::vector<std::string>> joint_formulas() const override;

  const FormulaDefinition& definition() const { return definition_; }

 private:
  // One set of parsers, one per formula, and the pose they read: x y z (file units), a b c (deg).
  struct Evaluator {
    std::array<double, geometry::kPoseSize> pose_variables{};
    std::vector<mu::Parser> parsers;
  };
  // Parses every formula (throws FormulaError naming the joint), binding this model's constants.
  std::unique_ptr<Evaluator> make_evaluator() const;
  Status evaluate(Evaluator& evaluator, const geometry::Pose& pose, JointVector& joints) const;
  // This thread's evaluator for this model, made on first use.
  Evaluator& thread_evaluator() const;

  FormulaDefinition definition_;
  geometry::Dof dof_;
  // Names this model (not its address, which a later one may reuse) in the threads' evaluators.
  std::uint64_t serial_ = 0;
  // The constants' values, read by every evaluator; written only by set_parameters, which no
  // call runs beside. Held by pointer so their addresses, bound into the parsers, never move.
  std::unique_ptr<double[]> constant_values_;
  std::unique_ptr<Evaluator> own_;
  mutable std::atomic_flag own_busy_;  // set while a call evaluates on own_
};

std::unique_ptr<Kinematics> make_formula_kinematics(const ModelConfig& config);

}  // namespace pkm::kinematics
