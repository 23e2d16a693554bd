#include "pkm/machine/machine_writer.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/rotary_delta.hpp"
#include "pkm/machine/machine_file_error.hpp"
#include "pkm/machine/toml_config.hpp"

namespace pkm {

std::string toml_number(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  std::string written(text, result.ptr);
  // Keep floats recognisable as floats in TOML.
  if (written.find_first_of(".en") == std::string::npos) written += ".0";
  return written;
}

std::string toml_string(const std::string& text) {
  std::string result = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      result += '\\';
      result += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof escape, "\\u%04x", c);
      result += escape;
    } else {
      result += c;
    }
  }
  return result + "\"";
}

namespace {

class Writer {
 public:
  explicit Writer(LengthUnit units) : per_mm_(units == LengthUnit::inch ? 1.0 / 25.4 : 1.0) {}

  void line(const std::string& text) { out_ << text << "\n"; }
  void length(const std::string& key, double mm) { line(key + " = " + toml_number(mm * per_mm_)); }
  void value(const std::string& key, double value) { line(key + " = " + toml_number(value)); }
  void lengths(const std::string& key, const double* mm, int count) {
    std::string text = key + " = [";
    for (int i = 0; i < count; ++i) text += (i ? ", " : "") + toml_number(mm[i] * per_mm_);
    line(text + "]");
  }
  void vector3(const std::string& key, const Eigen::Vector3d& v, bool is_length) {
    const double scale = is_length ? per_mm_ : 1.0;
    line(key + " = [" + toml_number(v.x() * scale) + ", " + toml_number(v.y() * scale) + ", " +
         toml_number(v.z() * scale) + "]");
  }
  void points(const std::string& key, const std::array<Eigen::Vector3d, 6>& points) {
    line(key + " = [");
    for (const Eigen::Vector3d& p : points) {
      line("  [" + toml_number(p.x() * per_mm_) + ", " + toml_number(p.y() * per_mm_) + ", " +
           toml_number(p.z() * per_mm_) + "],");
    }
    line("]");
  }
  double per_mm() const { return per_mm_; }
  std::string text() const { return out_.str(); }

 private:
  double per_mm_;
  std::ostringstream out_;
};

void write_cable_plotter(Writer& w, const CablePlotterGeometry& g) {
  const auto pair = [&](const std::string& key, const std::array<Eigen::Vector2d, 2>& points) {
    const double per_mm = w.per_mm();
    w.line(key + " = [[" + toml_number(points[0].x() * per_mm) + ", " +
           toml_number(points[0].y() * per_mm) + "], [" + toml_number(points[1].x() * per_mm) +
           ", " + toml_number(points[1].y() * per_mm) + "]]");
  };
  if (g.anchors_mm[0].isZero() && g.anchors_mm[1].y() == 0.0) {
    w.length("anchor_distance", g.anchors_mm[1].x());
  } else {
    pair("anchors", g.anchors_mm);
  }
  if (g.pulley_radius_mm != 0.0) w.length("pulley_radius", g.pulley_radius_mm);
  w.lengths("cable_offsets", g.cable_offsets_mm.data(), 2);
  if (!g.attach_mm[0].isZero() || !g.attach_mm[1].isZero()) pair("effector_attach", g.attach_mm);
  if (g.effector_mass_kg != 0.0) w.value("effector_mass", g.effector_mass_kg);
  if (!g.center_of_mass_mm.isZero()) {
    const double com[2] = {g.center_of_mass_mm.x(), g.center_of_mass_mm.y()};
    w.lengths("center_of_mass", com, 2);
  }
  if (g.tension_limited) {
    w.line("tension_limits = [" + toml_number(g.tension_min_N) + ", " +
           toml_number(g.tension_max_N) + "]");
  }
  if (g.cable_density_kg_per_m != 0.0) w.value("cable_density", g.cable_density_kg_per_m);
  if (g.spool_buildup_mm_per_m != 0.0) w.value("spool_buildup", g.spool_buildup_mm_per_m);
  if (g.cable_stretch_mm_per_m_per_N != 0.0) {
    w.value("cable_stiffness", 1000.0 / g.cable_stretch_mm_per_m_per_N);
  }
}

// The optional joint-angle and interference keys (leg_limits.hpp), as the file gave them: angles
// in deg, the diameter in the file's unit; the axes only where the file named them.
void write_leg_limits(Writer& w, const LegLimitSettings& limits, const char* inner_axis_key) {
  const auto& angle = limits.max_joint_angle_rad;
  if (limits.checks_angles()) {
    if (angle[0] == angle[1]) {
      w.value("max_joint_angle", radians_to_degrees(angle[0]));
    } else {
      w.line("max_joint_angle = [" + toml_number(radians_to_degrees(angle[0])) + ", " +
             toml_number(radians_to_degrees(angle[1])) + "]");
    }
  }
  if (limits.leg_diameter_mm > 0.0) w.length("leg_diameter", limits.leg_diameter_mm);
  if (limits.inner_axis) w.vector3(inner_axis_key, *limits.inner_axis, false);
  if (limits.platform_axis) w.vector3("platform_joint_axis", *limits.platform_axis, false);
}

std::string axis_list(Dof dof) {
  std::string text = "[";
  for (int axis = 0, n = 0; axis < kPoseSize; ++axis) {
    if (dof.controls(axis))
      text += std::string(n++ ? ", " : "") + "\"" + std::string(kAxisNames[axis]) + "\"";
  }
  return text + "]";
}

}  // namespace

std::string kinematics_toml(const Kinematics& kinematics, LengthUnit units) {
  Writer w(units);
  w.line("[kinematics]");
  w.line("type = \"" + std::string(kinematics.type()) + "\"");
  const ForwardOptions defaults;
  if (kinematics.forward_options().tolerance_mm != defaults.tolerance_mm) {
    w.length("forward_tolerance", kinematics.forward_options().tolerance_mm);
  }
  if (kinematics.forward_options().max_iterations != defaults.max_iterations) {
    w.line("forward_max_iterations = " +
           std::to_string(kinematics.forward_options().max_iterations));
  }
  if (const auto* matrix = dynamic_cast<const MatrixKinematics*>(&kinematics)) {
    const Eigen::Matrix3d& c = matrix->coefficients();
    w.line("matrix = [");
    for (int row = 0; row < 3; ++row) {
      w.line("  [" + toml_number(c(row, 0)) + ", " + toml_number(c(row, 1)) + ", " +
             toml_number(c(row, 2)) + "],");
    }
    w.line("]");
    const PassThroughAxes passthrough(matrix->passthrough_axes(), Dof::translation());
    if (passthrough.count() > 0) w.line(passthrough.toml_line());
  } else if (const auto* plotter = dynamic_cast<const CablePlotterKinematics*>(&kinematics)) {
    write_cable_plotter(w, plotter->geometry());
    if (plotter->passthrough().count() > 0) w.line(plotter->passthrough().toml_line());
  } else if (const auto* glide = dynamic_cast<const GlideKinematics*>(&kinematics)) {
    const bool orientation = glide->rail_dof().any_rotation();
    w.line(std::string("orientation = ") + (orientation ? "true" : "false"));
    if (!orientation) w.line("axes = " + axis_list(glide->rail_dof()));
    if (glide->passthrough().count() > 0) w.line(glide->passthrough().toml_line());
    write_leg_limits(w, glide->leg_limits().settings(), "carriage_joint_axis");
    for (const GlideRail& rail : glide->rails()) {
      w.line("");
      w.line("[[kinematics.rails]]");
      w.vector3("origin", rail.origin_mm, true);
      w.vector3("direction", rail.direction, false);
      w.length("strut", rail.strut_mm);
      w.vector3("attach", rail.attach_mm, true);
      w.line("branch = " + std::to_string(rail.branch));
    }
  } else if (const auto* hexapod = dynamic_cast<const HexapodKinematics*>(&kinematics)) {
    const HexapodGeometry& g = hexapod->geometry();
    w.points("base", g.base_mm);
    w.points("platform", g.platform_mm);
    w.length("tool_length", g.tool_length_mm);
    w.lengths("leg_offsets", g.leg_offset_mm.data(), 6);
    write_leg_limits(w, hexapod->leg_limits().settings(), "base_joint_axis");
  } else if (const auto* delta = dynamic_cast<const RotaryDeltaKinematics*>(&kinematics)) {
    const RotaryDeltaGeometry& g = delta->geometry();
    w.length("base_radius", g.base_radius_mm);
    w.length("arm_length", g.arm_length_mm);
    w.length("forearm_length", g.forearm_length_mm);
    w.length("platform_radius", g.platform_radius_mm);
    if (delta->passthrough().count() > 0) w.line(delta->passthrough().toml_line());
  } else if (const auto* formula = dynamic_cast<const FormulaKinematics*>(&kinematics)) {
    const FormulaDefinition& d = formula->definition();
    w.line("axes = " + axis_list(formula->dof()));
    w.line("");
    w.line("[kinematics.constants]");
    for (const auto& [name, value] : d.constants) w.value(name, value);
    w.line("");
    w.line("[kinematics.formulas]");
    for (const auto& [joint, expression] : d.formulas) {
      w.line(joint + " = " + toml_string(expression));
    }
  }
  return w.text();
}

std::string replace_kinematics_section(const std::string& original_text,
                                       const std::string& source_name, const Kinematics& kinematics,
                                       LengthUnit units) {
  // Where the section starts and ends comes from the parser, not from scanning text: a line
  // beginning with '[' may as well be a row of a multi-line array.
  refuse_unbounded_toml(original_text, source_name);
  toml::table document;
  try {
    document = toml::parse(original_text, source_name);
  } catch (const toml::parse_error& error) {
    throw MachineFileError(source_name, static_cast<int>(error.source().begin.line), "(syntax)",
                           std::string(error.description()));
  }
  const toml::table* section = document.get_as<toml::table>("kinematics");
  if (section == nullptr || section->is_inline()) {
    throw MachineFileError(source_name, 1, "kinematics",
                           "cannot rewrite this file: it has no [kinematics] table header");
  }
  const auto first_line = static_cast<std::size_t>(section->source().begin.line);
  std::size_t next_line = std::numeric_limits<std::size_t>::max();
  const auto consider = [&](const toml::node& node) {
    const auto line = static_cast<std::size_t>(node.source().begin.line);
    if (line > first_line && line < next_line) next_line = line;
  };
  for (const auto& [key, node] : document) {
    if (key.str() == "kinematics") continue;
    if (const toml::table* table = node.as_table(); table != nullptr && !table->is_inline()) {
      consider(*table);
    } else if (const toml::array* array = node.as_array();
               array != nullptr && array->is_array_of_tables()) {
      for (const toml::node& element : *array) consider(element);
    }
  }
  std::vector<std::string> lines;
  {
    std::istringstream in(original_text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  const std::size_t begin = first_line - 1;  // 0-based
  std::size_t end = std::min(lines.size(), next_line - 1);
  // Comments and blank lines just before the next table belong to that table.
  while (end > begin + 1) {
    const std::string& previous = lines[end - 1];
    const auto first = previous.find_first_not_of(" \t\r");
    if (first != std::string::npos && previous[first] != '#') break;
    --end;
  }
  std::string text;
  for (std::size_t i = 0; i < begin; ++i) text += lines[i] + "\n";
  text += kinematics_toml(kinematics, units);
  for (std::size_t i = end; i < lines.size(); ++i) text += lines[i] + "\n";
  return text;
}

}  // namespace pkm
