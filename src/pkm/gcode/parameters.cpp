#include "pkm/gcode/parameters.hpp"

namespace pkm::gcode {

Parameters::Parameters() : numbered_(kCount, 0.0), scopes_(1) {
  set_returned(std::nullopt);
}

void Parameters::forget_returned() {
  globals_.erase("_value");
  globals_.erase("_value_returned");
}

void Parameters::set_returned(std::optional<double> value) {
  globals_["_value"] = value.value_or(0.0);
  globals_["_value_returned"] = value ? 1.0 : 0.0;
}

double Parameters::numbered(int number) const {
  if (number <= kLocalNumbered && local_owner_ != 0) {
    return scopes_[local_owner_].numbered[number];
  }
  return numbered_[number];
}

void Parameters::set_numbered(int number, double value) {
  if (number <= kLocalNumbered && local_owner_ != 0) {
    scopes_[local_owner_].numbered[number] = value;
  } else {
    numbered_[number] = value;
  }
}

std::optional<double> Parameters::named(const std::string& lower_name) const {
  if (!lower_name.empty() && lower_name[0] == '_') {
    const auto found = globals_.find(lower_name);
    if (found == globals_.end()) return std::nullopt;
    return found->second;
  }
  const auto& locals = scopes_.back().named;
  const auto found = locals.find(lower_name);
  if (found == locals.end()) return std::nullopt;
  return found->second;
}

void Parameters::set_named(const std::string& lower_name, double value) {
  if (!lower_name.empty() && lower_name[0] == '_') {
    globals_[lower_name] = value;
  } else {
    scopes_.back().named[lower_name] = value;
  }
}

void Parameters::push_scope(const std::vector<double>& arguments) {
  Scope scope;
  for (std::size_t i = 0; i < arguments.size() && i < kLocalNumbered; ++i) {
    scope.numbered[i + 1] = arguments[i];
  }
  scope.numbered_owner = scopes_.size();
  scopes_.push_back(std::move(scope));
  local_owner_ = scopes_.back().numbered_owner;
}

void Parameters::push_scope_sharing_numbered() {
  Scope scope;
  scope.numbered_owner = scopes_.back().numbered_owner;
  scopes_.push_back(std::move(scope));
}

void Parameters::pop_scope() {
  if (scopes_.size() > 1) scopes_.pop_back();
  local_owner_ = scopes_.back().numbered_owner;
}

}  // namespace pkm::gcode
