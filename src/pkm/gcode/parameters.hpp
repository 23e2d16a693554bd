// Numbered and named parameters as LinuxCNC keeps them: numbered 1..5601 (1..30 local to a
// subroutine call), named ones local to their subroutine unless they start with '_'.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace pkm::gcode {

class Parameters {
 public:
  static constexpr int kCount = 5602;  // LinuxCNC's RS274NGC_MAX_PARAMETERS: #5602 is refused
  static constexpr int kLocalNumbered = 30;

  Parameters();

  bool valid_number(int number) const { return number >= 1 && number < kCount; }
  double numbered(int number) const;
  void set_numbered(int number, double value);
  // nullopt when the name is not defined (reading it is an error in LinuxCNC).
  std::optional<double> named(const std::string& lower_name) const;
  void set_named(const std::string& lower_name, double value);
  bool exists(const std::string& lower_name) const {
    return read_only(lower_name) || named(lower_name).has_value();
  }
  // #<_value> and #<_value_returned>, read-only: what the last endsub, return or M99 returned
  // (0 and 0 when it returned nothing, and before any has).
  void set_returned(std::optional<double> value);
  void forget_returned();  // not known (reading them is an error) until set_returned
  static bool read_only(const std::string& lower_name) {
    return lower_name == "_value" || lower_name == "_value_returned";
  }

  // A subroutine call: #1..#30 and local names get a fresh scope, with arguments in #1..
  void push_scope(const std::vector<double>& arguments);
  // A Fanuc-style M98 call: local names get a fresh scope, #1..#30 stay the caller's.
  void push_scope_sharing_numbered();
  void pop_scope();
  int depth() const { return static_cast<int>(scopes_.size()); }

 private:
  struct Scope {
    std::array<double, kLocalNumbered + 1> numbered{};
    std::unordered_map<std::string, double> named;
    std::size_t numbered_owner = 0;  // the scope whose #1..#30 these are (0: numbered_)
  };
  std::vector<double> numbered_;
  std::unordered_map<std::string, double> globals_;
  std::vector<Scope> scopes_;  // scopes_[0] is the main program's
  // The scope whose #1..#30 are in use now (0: numbered_, the main program's).
  std::size_t local_owner_ = 0;
};

}  // namespace pkm::gcode
