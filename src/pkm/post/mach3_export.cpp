#include "pkm/post/mach3_export.hpp"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <regex>
#include <stdexcept>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/matrix.hpp"

namespace pkm::post {

namespace {

// The shortest plain decimal that reads back as the same double (no exponent: a formula
// parser may not take one).
std::string number(double value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return std::string(text, result.ptr);
}

// "(x + 12.5)" or "(x - 3)" or "x": a coordinate shifted by a constant.
std::string shifted(const char* axis, double offset) {
  if (offset == 0.0) return axis;
  return std::string("(") + axis + (offset > 0.0 ? " + " : " - ") + number(std::abs(offset)) + ")";
}

}  // namespace

std::vector<std::pair<char, std::string>> mach3_formulas(const Machine& machine) {
  const Kinematics& kinematics = machine.kinematics();
  std::vector<std::string> expressions;
  if (const auto* plotter = dynamic_cast<const CablePlotterKinematics*>(&kinematics)) {
    const CablePlotterGeometry& g = plotter->geometry();
    if (!g.ideal()) {
      throw std::invalid_argument(
          "a cable plotter with pulleys, a tilting effector, tension limits or sagging or "
          "stretching cables has no formula: its joints come from a balance of forces");
    }
    // sqrt(((x0 - x)^2) + ((y0 - y)^2)): the cable from each anchor.
    const auto from = [](double anchor, const char* axis) {
      return anchor == 0.0 ? std::string(axis) : "(" + number(anchor) + " - " + axis + ")";
    };
    const auto cable = [&](int side) {
      const Eigen::Vector2d& anchor = g.anchors_mm[side];
      std::string text =
          "sqrt((" + from(anchor.x(), "x") + "^2) + (" + from(anchor.y(), "y") + "^2))";
      if (g.cable_offsets_mm[side] != 0.0) text += " + " + number(g.cable_offsets_mm[side]);
      return text;
    };
    const std::string left = cable(0), right = cable(1);
    expressions = {left, right};
  } else if (const auto* matrix = dynamic_cast<const MatrixKinematics*>(&kinematics)) {
    static constexpr const char* kAxes[] = {"x", "y", "z"};
    const Eigen::Matrix3d& c = matrix->coefficients();
    for (int row = 0; row < 3; ++row) {
      std::string e;
      for (int col = 0; col < 3; ++col) {
        if (c(row, col) == 0.0) continue;
        e += (e.empty() ? "" : " + ") + std::string("(") + number(c(row, col)) + "*" + kAxes[col] +
             ")";
      }
      expressions.push_back(e.empty() ? "0" : e);
    }
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&kinematics)) {
    if (glide->rail_dof().any_rotation()) {
      throw std::invalid_argument("a glide that turns its platform has no formula in x y z alone");
    }
    static constexpr const char* kAxes[] = {"x", "y", "z"};
    for (const GlideRail& rail : glide->rails()) {
      // w = tip + attach - origin per axis (uncontrolled axes are 0); q = d.w + branch sqrt(...).
      std::string w[3];
      for (int k = 0; k < 3; ++k) {
        const double offset = rail.attach_mm[k] - rail.origin_mm[k];
        w[k] = glide->rail_dof().controls(k) ? shifted(kAxes[k], offset) : number(offset);
      }
      std::string along;
      for (int k = 0; k < 3; ++k) {
        if (rail.direction[k] == 0.0) continue;
        along += (along.empty() ? "" : " + ") + std::string("(") + number(rail.direction[k]) + "*" +
                 w[k] + ")";
      }
      if (along.empty()) along = "0";
      const std::string squares = "(" + w[0] + "^2) + (" + w[1] + "^2) + (" + w[2] + "^2)";
      expressions.push_back("(" + along + ") " + (rail.branch > 0 ? "+" : "-") + " sqrt(((" +
                            along + ")^2) - (" + squares + ") + " +
                            number(rail.strut_mm * rail.strut_mm) + ")");
    }
  } else if (const auto* formula = dynamic_cast<const FormulaKinematics*>(&kinematics)) {
    for (const auto& [joint, expression] : formula->definition().formulas) {
      std::string e = expression;
      for (const auto& [name, value] : formula->definition().constants) {
        e = std::regex_replace(e, std::regex("\\b" + name + "\\b"), "(" + number(value) + ")");
      }
      expressions.push_back(e);
    }
  } else {
    throw std::invalid_argument("a " + std::string(kinematics.type()) +
                                " machine has no closed formula for Mach3's formula axes");
  }
  // Pass-through joints (a matrix mill's A and C, a plotter's pen Z) follow the mechanism's.
  for (int joint = static_cast<int>(expressions.size()); joint < kinematics.joint_count();
       ++joint) {
    const int axis = kinematics.passthrough_axis(joint);
    if (axis < 0) throw std::logic_error("a joint of the mechanism has no formula");
    expressions.push_back(std::string(kAxisNames[axis]));
  }
  std::vector<std::pair<char, std::string>> formulas;
  for (std::size_t i = 0; i < expressions.size(); ++i) {
    formulas.emplace_back(static_cast<char>(std::tolower(machine.joints()[i].axis_letter)),
                          expressions[i]);
  }
  return formulas;
}

}  // namespace pkm::post
