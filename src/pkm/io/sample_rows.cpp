#include "pkm/io/sample_rows.hpp"

#include <stdexcept>

namespace pkm::io {

namespace {

bool shows_orientation(const machine::Machine& machine) {
  return machine.kinematics().dof().any_rotation();
}

bool shows_pen(const machine::Machine& machine) {
  return machine.tool().z == machine::ToolZ::pen;
}

}  // namespace

std::vector<std::string> sample_columns(const machine::Machine& machine) {
  std::vector<std::string> columns = {"t", "line", "x", "y", "z"};
  if (shows_orientation(machine)) columns.insert(columns.end(), {"a", "b", "c"});
  for (const machine::JointSpec& joint : machine.joints()) columns.push_back("j_" + joint.name);
  if (shows_pen(machine)) columns.push_back("pen");
  return columns;
}

SampleRows::SampleRows(const machine::Machine& machine)
    : machine_(machine),
      orientation_(shows_orientation(machine)),
      pen_(shows_pen(machine)),
      columns_(sample_columns(machine).size()) {
  if (columns_ > kMaxColumns) {
    throw std::invalid_argument(machine.name() + ": " + std::to_string(columns_) +
                                " sample columns, more than the " + std::to_string(kMaxColumns) +
                                " a row holds");
  }
}

std::size_t SampleRows::fill(const motion::Sample& s, double* row) const {
  std::size_t n = 0;
  row[n++] = s.time_s;
  row[n++] = s.line;
  for (int axis = 0; axis < 3; ++axis) row[n++] = s.pose[axis];
  if (orientation_) {
    for (int axis = 3; axis < 6; ++axis) row[n++] = geometry::radians_to_degrees(s.pose[axis]);
  }
  for (int i = 0; i < s.joints.size(); ++i) {
    row[n++] = machine_.joints()[static_cast<std::size_t>(i)].to_interface(s.joints[i]);
  }
  if (pen_) row[n++] = s.pen_down ? 1.0 : 0.0;
  return n;
}

}  // namespace pkm::io
