// What the pkmkit module's source files share: the array type, poses as rows of the machine's
// controlled coordinates (mm, deg), JSON documents as Python objects, and the binders each file
// adds to the module (pkmkit.cpp calls them).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pkm/gcode/interpreter.hpp"
#include "pkm/machine/machine.hpp"

namespace pkm::python {

namespace py = pybind11;

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The pose coordinates (0..5 = x y z a b c) the machine controls, in that order: the columns of
// every pose array.
std::vector<int> controlled_axes(const machine::Machine& machine);

// One row of a pose array (mm, deg; the controlled coordinates) over home's other coordinates.
geometry::Pose pose_from_row(const machine::Machine& machine, const std::vector<int>& axes,
                             const double* row);

// A pose (k,) of the machine's coordinates from Python, or a ValueError naming `what`.
geometry::Pose pose_argument(const machine::Machine& machine, const Array& pose,
                             const std::string& what);

// x y [z [a b c]] (mm, deg; up to six values, the rest 0) from Python as mm and rad, as the
// command line's --origin; a ValueError naming `what` for more than six.
geometry::Vector6d origin_argument(const std::vector<double>& values, const std::string& what);

// A JSON document (a report) as Python's json module reads it: dicts, lists, numbers, None.
py::object json_to_python(const nlohmann::json& document);

// Raises the module's exception `type_name` (PlanError, PostError) with `message` and the hint of
// a job out of the machine's reach appended, as pkm prints it (motion/job_reach.hpp); `line`, when
// not negative, as its .line.
[[noreturn]] void raise_with_reach_hint(const char* type_name, const std::string& message, int line,
                                        const machine::Machine& machine, const std::string& program,
                                        const gcode::InterpreterOptions& interpreter,
                                        const geometry::Vector6d& origin);

void bind_plan(py::module_& module);
void bind_canon(py::module_& module);
void bind_post_verify(py::module_& module);
void bind_calibrate(py::module_& module);

}  // namespace pkm::python
