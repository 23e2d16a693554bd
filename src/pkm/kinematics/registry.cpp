#include "pkm/kinematics/registry.hpp"

#include <cmath>
#include <string>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm {

namespace {
struct Entry {
  std::string_view type;
  std::unique_ptr<Kinematics> (*make)(const ModelConfig&);
};
constexpr Entry kModels[] = {
    {"matrix", make_matrix_kinematics},   {"cable_plotter", make_cable_plotter_kinematics},
    {"glide", make_glide_kinematics},     {"hexapod", make_hexapod_kinematics},
    {"formula", make_formula_kinematics}, {"rotary_delta", make_rotary_delta_kinematics},
};

ForwardOptions read_forward_options(const ModelConfig& config) {
  ForwardOptions options;
  if (config.has("forward_tolerance")) {
    options.tolerance_mm = config.length("forward_tolerance");
    if (!(options.tolerance_mm > 0.0) || !(options.tolerance_mm < 1.0)) {
      config.fail("forward_tolerance", "must be a length between 0 and 1 mm");
    }
  }
  if (config.has("forward_max_iterations")) {
    const double iterations = config.number("forward_max_iterations");
    if (!(iterations >= 1.0) || iterations != std::floor(iterations) || iterations > 10000.0) {
      config.fail("forward_max_iterations", "must be a whole number from 1 to 10000");
    }
    options.max_iterations = static_cast<int>(iterations);
  }
  return options;
}
}  // namespace

std::vector<std::string_view> kinematics_types() {
  std::vector<std::string_view> types;
  for (const Entry& entry : kModels) types.push_back(entry.type);
  return types;
}

std::unique_ptr<Kinematics> make_kinematics(const ModelConfig& config) {
  const std::string type = config.string("type");
  for (const Entry& entry : kModels) {
    if (entry.type == type) {
      auto model = entry.make(config);
      model->set_forward_options(read_forward_options(config));
      return model;
    }
  }
  std::string known;
  for (const Entry& entry : kModels) known += (known.empty() ? "" : ", ") + std::string(entry.type);
  config.fail("type", "unknown kinematics type '" + type + "' (known: " + known + ")");
}

void write_kinematics_config(const Kinematics& model, ModelConfigWriter& out) {
  out.string("type", model.type());
  const ForwardOptions defaults;
  const ForwardOptions& options = model.forward_options();
  if (options.tolerance_mm != defaults.tolerance_mm) {
    out.length("forward_tolerance", options.tolerance_mm);
  }
  if (options.max_iterations != defaults.max_iterations) {
    out.whole_number("forward_max_iterations", options.max_iterations);
  }
  model.write_config(out);
}

}  // namespace pkm
