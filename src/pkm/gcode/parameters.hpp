// Numbered and named parameters as LinuxCNC keeps them: numbered 1..5602 (1..30 local to a
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
  static constexpr int kCount = 5603;
  static constexpr int kLocalNumbered = 30;

  Parameters();

  bool valid_number(int number) const { return number >= 1 && number < kCount; }
  double numbered(int number) const;
  void set_numbered(int number, double value);
  // nullopt when the name is not defined (reading it is an error in LinuxCNC).
  std::optional<double> named(const std::string& lower_name) const;
  void set_named(const std::string& lower_name, double value);
  bool exists(const std::string& lower_name) const { return named(lower_name).has_value(); }

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
