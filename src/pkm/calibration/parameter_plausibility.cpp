#include "pkm/calibration/parameter_plausibility.hpp"

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
Plausibility size_relative(std::string kind, double extent_mm) {
  return {std::move(kind), 2.0 + 0.02 * extent_mm, "2 mm + 2 % of the measured extent"};
}

// A catalogue part (a pulley) or a weighed or looked-up property is known as a share of itself.
Plausibility value_relative(std::string kind, const Parameter& parameter, double share) {
  return {std::move(kind), share * std::abs(parameter.value),
          std::to_string(static_cast<int>(std::lround(100.0 * share))) + " % of its nominal value"};
}

Plausibility cable_plotter(const Parameter& p, double extent_mm) {
  const std::string_view name = p.name;
  // The belt's or cable's effective radius on a catalogue pulley moves with its thickness and
  // how it sits in the teeth: a 20-tooth GT2's pitch radius is 6.37 mm, over the belt 7 mm.
  if (name == "pulley_radius") return value_relative("a pulley's radius", p, 0.2);
  if (starts_with(name, "cable_offset")) return size_relative("a cable's zero", extent_mm);
  if (starts_with(name, "anchor")) return size_relative("an anchor's position", extent_mm);
  if (starts_with(name, "attach") || starts_with(name, "center_of_mass"))
    return size_relative("a point on the effector", extent_mm);
  return value_relative("a physical property", p, 0.5);  // mass, density, stretch, build-up
}

Plausibility glide(const Parameter& p, double extent_mm) {
  if (contains(p.name, ".direction.")) return {"a rail direction's component", 0.02, "0.02"};
  if (contains(p.name, ".strut")) return size_relative("a strut's length", extent_mm);
  if (contains(p.name, ".attach.")) return size_relative("a point on the platform", extent_mm);
  return size_relative("a rail's origin", extent_mm);
}

Plausibility hexapod(const Parameter& p, double extent_mm) {
  if (contains(p.name, ".offset")) return size_relative("a leg's zero", extent_mm);
  if (contains(p.name, ".platform.")) return size_relative("a platform joint", extent_mm);
  if (p.name == "tool_length") return size_relative("the tool's length", extent_mm);
  return size_relative("a base joint", extent_mm);
}

}  // namespace

Plausibility parameter_plausibility(std::string_view model_type, const Parameter& parameter,
                                    double extent_mm) {
  Plausibility result;
  if (model_type == "cable_plotter") {
    result = cable_plotter(parameter, extent_mm);
  } else if (model_type == "glide") {
    result = glide(parameter, extent_mm);
  } else if (model_type == "hexapod") {
    result = hexapod(parameter, extent_mm);
  } else if (model_type == "rotary_delta") {
    result = size_relative("a link's length", extent_mm);
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
