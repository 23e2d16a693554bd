// The words of a move proof's findings (proof_wording.hpp).
#include "pkm/certify/proof_wording.hpp"

#include <cmath>

#include "pkm/kinematics/derivative_bounds.hpp"
#include "pkm/kinematics/leg_limits.hpp"

namespace pkm::certify {

namespace {
std::string as_built_pull_name(int index) {
  switch (index) {
    case 0:
      return "the left cable's pull (its tension's sign)";
    case 1:
      return "the right cable's pull (its tension's sign)";
    case 2:
      return "the angle between the cables";
    default:
      return "the effector's balance (a cable's end near its pulley, or its tilt not enclosed)";
  }
}

}  // namespace

kinematics::ReachMargin ProofWording::reach_margin(int index) const {
  const kinematics::DerivativeBounds* own = machine_.kinematics().derivative_bounds();
  if (own == nullptr) return {"the mechanism's reach", false, {}};
  return own->reach_margin(index);
}

std::string ProofWording::quantity_name(Quantity quantity, int index, int other) const {
  const auto joint = [&](int i) {
    return i >= 0 && i < static_cast<int>(machine_.joints().size())
               ? "'" + machine_.joints()[static_cast<std::size_t>(i)].name + "'"
               : std::to_string(i + 1);
  };
  switch (quantity) {
    case Quantity::joint:
      return "joint " + joint(index);
    case Quantity::envelope:
      return std::string(geometry::kAxisNames[index]) + " (the work envelope)";
    case Quantity::joint_angle:
      return std::string("the ") + (other == kinematics::kInnerEnd ? "inner" : "platform") +
             " joint angle of " + joint(index);
    case Quantity::clearance:
      return "the clearance between " + joint(index) + " and " + joint(other);
    case Quantity::assembly_mode:
      if (index >= 0) {
        return "the assembly mode (the side of the base plane the platform joint of " +
               joint(index) + " is on)";
      }
      return "the assembly mode (the sign of cos a cos b, or of the struts' determinant)";
    case Quantity::pull:
      if (cables_ != nullptr) return as_built_pull_name(index);
      return index < 2 ? "the pen's side of anchor " + std::to_string(index + 1) + "'s vertical"
                       : std::string("the angle between the cables");
    case Quantity::tension:
      return "the " + std::string(index == 0 ? "left" : "right") + " cable's tension";
    case Quantity::reach:
      return reach_margin(index).name;
    case Quantity::none:
      break;
  }
  return "the pose";
}

std::string ProofWording::value_text(Quantity quantity, int index, double value) const {
  const bool units_are_inches = machine_.units() == machine::LengthUnit::inch;
  switch (quantity) {
    case Quantity::joint:
      return kinematics::formatted_number(units_are_inches ? "%.4f " : "%.3f ",
                                          machine_.joint_to_file(index, value)) +
             machine_.joint_file_unit(index);
    case Quantity::envelope:
      return kinematics::formatted_number(units_are_inches && index < 3 ? "%.4f " : "%.3f ",
                                          machine_.axis_to_file(index, value)) +
             machine_.axis_file_unit(index);
    case Quantity::joint_angle:
      return kinematics::formatted_number("%.3f deg", geometry::radians_to_degrees(value));
    case Quantity::clearance:
      return kinematics::formatted_number(units_are_inches ? "%.4f " : "%.3f ",
                                          value / machine_.mm_per_unit()) +
             machine_.length_unit();
    case Quantity::tension:
      return kinematics::formatted_number("%.3f N", value);
    case Quantity::reach:
      if (reach_margin(index).newtons) return kinematics::formatted_number("%.3f N", value);
      return kinematics::formatted_number(units_are_inches ? "%.4f " : "%.3f ",
                                          value / machine_.mm_per_unit()) +
             machine_.length_unit();
    case Quantity::assembly_mode:
    case Quantity::pull:
    case Quantity::none:
      break;
  }
  return kinematics::formatted_number("%.7g", value);
}

std::string ProofWording::undecided_text(const Finding& finding) const {
  const std::string where = kinematics::formatted_number("%.6f", 100.0 * finding.u0) + " % and " +
                            kinematics::formatted_number("%.6f", 100.0 * finding.u1) +
                            " % of the move (pose " +
                            machine_.format_pose(geometry::Pose::from_vector(finding.pose)) + ")";
  if (finding.quantity == Quantity::assembly_mode || finding.quantity == Quantity::pull) {
    return "cannot prove " + quantity_name(finding.quantity, finding.index, -1) +
           " keeps its sign between " + where;
  }
  return "cannot prove " + quantity_name(finding.quantity, finding.index, finding.other) +
         " within its limit between " + where + ": its bound reaches " +
         value_text(finding.quantity, finding.index, finding.value) + " against the limit " +
         value_text(finding.quantity, finding.index, finding.limit);
}

std::string ProofWording::excess_text(const Finding& finding, double value, double excess) const {
  double file_units = excess;  // past the limit: file units below
  std::string unit = "deg";
  switch (finding.quantity) {
    case Quantity::joint:
      file_units = std::abs(machine_.joint_to_file(finding.index, value) -
                            machine_.joint_to_file(finding.index, finding.limit));
      unit = machine_.joint_file_unit(finding.index);
      break;
    case Quantity::envelope:
      file_units = std::abs(machine_.axis_to_file(finding.index, value) -
                            machine_.axis_to_file(finding.index, finding.limit));
      unit = machine_.axis_file_unit(finding.index);
      break;
    case Quantity::joint_angle:
      file_units = geometry::radians_to_degrees(file_units);
      break;
    case Quantity::clearance:
    case Quantity::assembly_mode:
      file_units /= machine_.mm_per_unit();
      unit = machine_.length_unit();
      break;
    case Quantity::tension:
      unit = "N";
      break;
    case Quantity::reach:
      if (reach_margin(finding.index).newtons) {
        unit = "N";
      } else {
        file_units /= machine_.mm_per_unit();
        unit = machine_.length_unit();
      }
      break;
    default:
      unit.clear();
  }
  return kinematics::formatted_number("%.3g ", file_units) + unit;
}

}  // namespace pkm::certify
