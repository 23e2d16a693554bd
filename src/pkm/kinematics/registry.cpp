#include "pkm/kinematics/registry.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "pkm/kinematics/cable_plotter.hpp"
#include "pkm/kinematics/cable_robot.hpp"
#include "pkm/kinematics/formula.hpp"
#include "pkm/kinematics/glide.hpp"
#include "pkm/kinematics/hexapod.hpp"
#include "pkm/kinematics/matrix.hpp"
#include "pkm/kinematics/rotary_delta.hpp"

namespace pkm::kinematics {

namespace {
struct Entry {
  std::string_view type;
  KinematicsReader make;
};
constexpr Entry kModels[] = {
    {"matrix", make_matrix_kinematics},
    {"cable_plotter", make_cable_plotter_kinematics},
    {"glide", make_glide_kinematics},
    {"hexapod", make_hexapod_kinematics},
    {"formula", make_formula_kinematics},
    {"rotary_delta", make_rotary_delta_kinematics},
    {"cable_robot", make_cable_robot_kinematics},
};

// The kinds registered at run time (KinematicsKind), behind a lock: machine files may load on
// several threads while a test registers its kind.
struct RegisteredKinds {
  std::mutex mutex;
  std::map<std::string, KinematicsReader, std::less<>> readers;
};
RegisteredKinds& registered_kinds() {
  static RegisteredKinds kinds;
  return kinds;
}

std::optional<KinematicsReader> reader_of(std::string_view type) {
  for (const Entry& entry : kModels) {
    if (entry.type == type) return entry.make;
  }
  RegisteredKinds& kinds = registered_kinds();
  const std::lock_guard lock(kinds.mutex);
  const auto found = kinds.readers.find(type);
  if (found == kinds.readers.end()) return std::nullopt;
  return found->second;
}

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

std::vector<std::string> kinematics_types() {
  std::vector<std::string> types;
  for (const Entry& entry : kModels) types.emplace_back(entry.type);
  RegisteredKinds& kinds = registered_kinds();
  const std::lock_guard lock(kinds.mutex);
  for (const auto& [type, reader] : kinds.readers) types.push_back(type);
  return types;
}

std::unique_ptr<Kinematics> make_kinematics(const ModelConfig& config) {
  const std::string type = config.string("type");
  const std::optional<KinematicsReader> reader = reader_of(type);
  if (!reader) {
    std::string known;
    for (const std::string& name : kinematics_types()) known += (known.empty() ? "" : ", ") + name;
    config.fail("type", "unknown kinematics type '" + type + "' (known: " + known + ")");
  }
  auto model = (*reader)(config);
  // What write_kinematics_config writes as `type` must read back as this kind.
  if (model == nullptr || model->type() != type) {
    throw std::logic_error("the reader of kinematics type '" + type +
                           "' made no model of that type");
  }
  model->set_forward_options(read_forward_options(config));
  return model;
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

KinematicsKind::KinematicsKind(std::string type, KinematicsReader reader) : type_(std::move(type)) {
  if (type_.empty()) throw std::invalid_argument("a kinematics type needs a name");
  if (reader == nullptr) {
    throw std::logic_error("kinematics type '" + type_ + "' registered without a reader");
  }
  for (const Entry& entry : kModels) {
    if (entry.type == type_) {
      throw std::invalid_argument("kinematics type '" + type_ + "' is built in");
    }
  }
  RegisteredKinds& kinds = registered_kinds();
  const std::lock_guard lock(kinds.mutex);
  if (!kinds.readers.emplace(type_, reader).second) {
    throw std::invalid_argument("kinematics type '" + type_ + "' is already registered");
  }
}

KinematicsKind::KinematicsKind(KinematicsKind&& other) noexcept
    : type_(std::exchange(other.type_, {})) {}

KinematicsKind::~KinematicsKind() {
  if (type_.empty()) return;
  RegisteredKinds& kinds = registered_kinds();
  const std::lock_guard lock(kinds.mutex);
  kinds.readers.erase(type_);
}

}  // namespace pkm::kinematics
