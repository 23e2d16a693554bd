// The comment lines `pkm post` writes at the top of a joint program: what made it, from which job
// in which dialect, and the numbers known only at the end (tolerance, deviation, blocks). It is
// written first with zeros and rewritten in place once the body is written: the numbers line
// keeps its width (79 characters, within grbl's 80), whatever the numbers.
#pragma once

#include <string>

#include "pkm/machine/machine.hpp"
#include "pkm/post/joint_program.hpp"

namespace pkm::post {

// `report` null: the placeholder written before the body.
std::string joint_program_header(const machine::Machine& machine, const std::string& program,
                                 Dialect dialect, double tolerance_mm, const PostReport* report);

}  // namespace pkm::post
