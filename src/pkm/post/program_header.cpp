#include "pkm/post/program_header.hpp"

#include <cstdio>

namespace pkm::post {

std::string joint_program_header(const machine::Machine& machine, const std::string& program,
                                 Dialect dialect, double tolerance_mm, const PostReport* report) {
  char numbers[128];
  std::snprintf(numbers, sizeof numbers, "(tolerance %11.6f mm; %s %11.6f mm, %10ld blocks)\n",
                tolerance_mm,
                report && !report->bounded ? "sampled deviation" : "bounded deviation",
                report ? report->max_deviation_mm : 0.0, report ? report->blocks : 0L);
  return comment_line(dialect, "joint-space program by pkmkit for ", machine.name(), "") +
         comment_line(dialect, "from ", program,
                      ", dialect " + std::string(dialect_name(dialect))) +
         numbers;
}

}  // namespace pkm::post
