#include "pkm/calibration/parameter_plausibility.hpp"

#include <algorithm>
#include <cmath>

namespace pkm {

namespace {

bool starts_with(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

bool contains(std::string_view text, std::string_view part) {
  return text.find(part) != std::string_view::npos;
}

// Frame points, link lengths and joint zeros are built and measured to about the same share of
// the machine's size: a tape over the frame, a leg cut to length, a cable marked at its zero.
Plausibility size_relative(std::string kind, double size_mm) {
  return {std::move(kind), 2.0 + 0.02 * size_mm,
          "2 mm + 2 % of the machine's size of " + std::to_string(std::lround(size_mm)) + " mm"};
}

// A catalogue part (a pulley) or a weighed or looked-up property is known as a share of itself.
Plausibility value_relative(std::string kind, const Parameter& parameter, double share) {
  return {std::move(kind), share * std::abs(parameter.value),
          std::to_string(static_cast<int>(std::lround(100.0 * share))) + " % of its nominal value"};
}

Plausibility cable_plotter(const Parameter& p, double size_mm) {
  const std::string_view name = p.name;
  // The belt's or cable's effective radius on a catalogue pulley moves with its thickness and
  // how it sits in the teeth: a 20-tooth GT2's pitch radius is 6.37 mm, over the belt 7 mm.
  if (name == "pulley_radius") return value_relative("a pulley's radius", p, 0.2);
  if (starts_with(name, "cable_offset")) return size_relative("a cable's zero", size_mm);
  if (starts_with(name, "anchor")) return size_relative("an anchor's position", size_mm);
  if (starts_with(name, "attach") || starts_with(name, "center_of_mass"))
    return size_relative("a point on the effector", size_mm);
  return value_relative("a physical property", p, 0.5);  // mass, density, stretch, build-up
}

Plausibility glide(const Parameter& p, double size_mm) {
  if (contains(p.name, ".direction.")) return {"a rail direction's component", 0.02, "0.02"};
  if (contains(p.name, ".strut")) return size_relative("a strut's length", size_mm);
  if (contains(p.name, ".attach.")) return size_relative("a point on the platform", size_mm);
  return size_relative("a rail's origin", size_mm);
}

Plausibility hexapod(const Parameter& p, double size_mm) {
  if (contains(p.name, ".offset")) return size_relative("a leg's zero", size_mm);
  if (contains(p.name, ".platform.")) return size_relative("a platform joint", size_mm);
  if (p.name == "tool_length") return size_relative("the tool's length", size_mm);
  return size_relative("a base joint", size_mm);
}

}  // namespace

double machine_size_mm(const std::vector<Parameter>& parameters, double extent_mm) {
  double size = extent_mm;
  for (const Parameter& p : parameters) {
    if (p.unit == "mm") size = std::max(size, std::abs(p.value));
  }
  return size;
}

Plausibility parameter_plausibility(std::string_view model_type, const Parameter& parameter,
                                    double size_mm) {
  Plausibility result;
  if (model_type == "cable_plotter") {
    result = cable_plotter(parameter, size_mm);
  } else if (model_type == "glide") {
    result = glide(parameter, size_mm);
  } else if (model_type == "hexapod") {
    result = hexapod(parameter, size_mm);
  } else if (model_type == "rotary_delta") {
    result = size_relative("a link's length", size_mm);
  } else if (model_type == "matrix") {
    // matrixkins corrections are of the order of 1e-3 (a squareness of a millimetre per metre).
    result = {"a matrix coefficient", 0.01, "0.01"};
  }
  // A share of a nominal 0 (a cable without mass) judges nothing: such a parameter is held as
  // having no effect anyway.
  if (!(result.deviation > 0.0)) return {};
  return result;
}

}  // namespace pkm
