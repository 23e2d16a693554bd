// From a machine file's `type` to a kinematic model.
#pragma once

#include <memory>
#include <string_view>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"
#include "pkm/kinematics/model_config.hpp"

namespace pkm {

// The model types a machine file may name.
std::vector<std::string_view> kinematics_types();

// Reads `type`, the model's own keys, and the keys every iterative FK shares
// (`forward_tolerance`, `forward_max_iterations`). Errors go through config.fail.
std::unique_ptr<Kinematics> make_kinematics(const ModelConfig& config);

}  // namespace pkm
