// From a machine file's `type` to a kinematic model, and back.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"
#include "pkm/kinematics/model_config_writer.hpp"

namespace pkm {

// The model types a machine file may name.
std::vector<std::string_view> kinematics_types();

// Reads `type`, the model's own keys, and the keys every iterative FK shares
// (`forward_tolerance`, `forward_max_iterations`). Errors go through config.fail.
std::unique_ptr<Kinematics> make_kinematics(const ModelConfig& config);

// What make_kinematics reads, for `model` as it is now: `type`, the forward options that differ
// from the defaults, then the model's own keys (Kinematics::write_config).
void write_kinematics_config(const Kinematics& model, ModelConfigWriter& out);

}  // namespace pkm
