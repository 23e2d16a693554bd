#include "pkm/stream/grbl_zero.hpp"

#include "pkm/post/joint_program.hpp"

namespace pkm::stream {

std::string grbl_zero_line(const Machine& machine, const JointVector& joints) {
  std::string line = "G10 L20 P1";
  const post::DialectRules rules = post::rules_of(post::Dialect::grbl);
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    line += post::joint_word(machine.joints()[i], joints[static_cast<Eigen::Index>(i)], rules);
  }
  return line;
}

}  // namespace pkm::stream
