// From a machine file's `type` to a kinematic model, and back: the built-in kinds (a table in
// registry.cpp) and the kinds registered while the program runs (a test's model, a plugin's).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm::kinematics {

// A model's reader: its make_<kind>_kinematics, from its keys of a machine file's [kinematics].
using KinematicsReader = std::unique_ptr<Kinematics> (*)(const ModelConfig&);

// The model types a machine file may name: the built-in ones, then the registered ones in
// alphabetical order.
std::vector<std::string> kinematics_types();

// Reads `type`, the model's own keys, and the keys every iterative FK shares
// (`forward_tolerance`, `forward_max_iterations`). Errors go through config.fail.
std::unique_ptr<Kinematics> make_kinematics(const ModelConfig& config);

// What make_kinematics reads, for `model` as it is now: `type`, the forward options that differ
// from the defaults, then the model's own keys (Kinematics::write_config).
void write_kinematics_config(const Kinematics& model, ModelConfigWriter& out);

// A kind made known to make_kinematics for as long as the object lives (docs/architecture.md,
// "Adding a machine kind"): machine files with `type = "<type>"` load through `reader`, whose
// models must answer type() with the same name, so that write_kinematics_config's `type` reads
// back. Built-in kinds are a line of registry.cpp's table instead.
class KinematicsKind {
 public:
  // Throws std::invalid_argument for an empty type or one already known (built in or
  // registered), std::logic_error for a null reader.
  [[nodiscard]] KinematicsKind(std::string type, KinematicsReader reader);
  ~KinematicsKind();
  KinematicsKind(KinematicsKind&& other) noexcept;
  KinematicsKind& operator=(KinematicsKind&&) = delete;
  KinematicsKind(const KinematicsKind&) = delete;
  KinematicsKind& operator=(const KinematicsKind&) = delete;

  const std::string& type() const { return type_; }

 private:
  std::string type_;  // empty once moved from
};

}  // namespace pkm::kinematics
