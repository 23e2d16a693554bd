// The pkmkit Python module: a machine file's machine (pkm::Machine) with its inverse and forward
// kinematics over NumPy arrays, in mm and degrees as every pkm interface (docs/python.md). A thin
// layer: the kinematics, limits and units are the pkm libraries'; this file only converts arrays
// and units, and runs the batch loops without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace py = pybind11;

namespace pkm::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Every identifier, indexed by the code's value (the last code is interference; a code added
// after it needs this bound moved as well as its case above).
std::vector<std::string> status_identifiers() {
  std::vector<std::string> names;
  for (int code = 0; code <= static_cast<int>(StatusCode::interference); ++code) {
    names.emplace_back(status_identifier(static_cast<StatusCode>(code)));
  }
  return names;
}

// The pose coordinates (0..5 = x y z a b c) the machine controls, in that order: the columns of
// every pose array.
std::vector<int> controlled_axes(const Machine& machine) {
  std::vector<int> axes;
  for (int axis = 0; axis < kPoseSize; ++axis) {
    if (machine.kinematics().dof().controls(axis)) axes.push_back(axis);
  }
  return axes;
}

// One row of a pose array (mm, deg; the controlled coordinates) over home's other coordinates.
Pose pose_from_row(const Machine& machine, const std::vector<int>& axes, const double* row) {
  Vector6d values = machine.home().as_vector();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    values[axes[i]] = axes[i] < 3 ? row[i] : degrees_to_radians(row[i]);
  }
  return Pose::from_vector(values);
}

void pose_to_row(const Pose& pose, const std::vector<int>& axes, double* row) {
  const Vector6d values = pose.as_vector();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    row[i] = axes[i] < 3 ? values[axes[i]] : radians_to_degrees(values[axes[i]]);
  }
}

std::string axes_text(const std::vector<int>& axes) {
  std::string text;
  for (int axis : axes) text += (text.empty() ? "" : " ") + std::string(kAxisNames[axis]);
  return text;
}

// The rows of an (N, columns) array, or a ValueError naming what it should have been.
std::size_t checked_rows(const Array& array, std::size_t columns, const std::string& what) {
  if (array.ndim() != 2 || static_cast<std::size_t>(array.shape(1)) != columns) {
    throw py::value_error(what + " must be an (N, " + std::to_string(columns) + ") array");
  }
  return static_cast<std::size_t>(array.shape(0));
}

// The status identifiers of `codes` as a NumPy array of strings: one lookup per row in NumPy, in
// the array of identifiers made once at import (the module's _STATUS_NAMES).
py::array status_array(const std::vector<std::int8_t>& codes) {
  const py::object names = py::module_::import("pkmkit").attr("_STATUS_NAMES");
  const py::array indices =
      py::array_t<std::int8_t>(static_cast<py::ssize_t>(codes.size()), codes.data());
  return names.attr("__getitem__")(indices);
}

// IK over the rows: joints (mm, deg) where the pose is taken, zeros where it is not.
void inverse_rows(const Machine& machine, const std::vector<int>& axes, const double* poses,
                  std::size_t rows, double* joints_out, std::int8_t* codes) {
  const std::size_t n = machine.joints().size();
  JointVector joints;
  for (std::size_t row = 0; row < rows; ++row) {
    const Status status =
        machine.inverse(pose_from_row(machine, axes, poses + row * axes.size()), joints);
    codes[row] = static_cast<std::int8_t>(status.code);
    double* out = joints_out + row * n;
    for (std::size_t j = 0; j < n; ++j) {
      out[j] = status.ok() ? machine.joints()[j].to_interface(joints[static_cast<int>(j)]) : 0.0;
    }
  }
}

// FK over the rows, each seeded with the previous row's pose (the seed's for the first, and
// after a row that failed): poses (mm, deg) where the joints give one, zeros where not.
void forward_rows(const Machine& machine, const std::vector<int>& axes, const double* joints_in,
                  std::size_t rows, Pose seed, double* poses_out, std::int8_t* codes) {
  const std::size_t n = machine.joints().size();
  JointVector joints(static_cast<int>(n));
  for (std::size_t row = 0; row < rows; ++row) {
    for (std::size_t j = 0; j < n; ++j) {
      joints[static_cast<int>(j)] = machine.joints()[j].from_interface(joints_in[row * n + j]);
    }
    Pose pose = seed;
    const Status status = machine.forward(joints, pose);
    codes[row] = static_cast<std::int8_t>(status.code);
    double* out = poses_out + row * axes.size();
    if (status.ok()) {
      pose_to_row(pose, axes, out);
      seed = pose;
    } else {
      std::fill(out, out + axes.size(), 0.0);
    }
  }
}

py::tuple inverse(const Machine& machine, const Array& poses) {
  const std::vector<int> axes = controlled_axes(machine);
  const std::size_t rows = checked_rows(poses, axes.size(), "poses (" + axes_text(axes) + ")");
  const std::size_t n = machine.joints().size();
  Array joints({rows, n});
  std::vector<std::int8_t> codes(rows);
  const double* in = poses.data();
  double* out = joints.mutable_data();
  {
    // A copy: a formula machine's evaluator keeps state per call, so two threads must not share
    // one; the copy is made with the GIL held, the loop runs without it.
    const Machine own = machine;
    const py::gil_scoped_release released;
    inverse_rows(own, axes, in, rows, out, codes.data());
  }
  return py::make_tuple(joints, status_array(codes));
}

py::tuple forward(const Machine& machine, const Array& joints, const std::optional<Array>& seed) {
  const std::vector<int> axes = controlled_axes(machine);
  const std::size_t rows = checked_rows(joints, machine.joints().size(), "joints");
  Pose start = machine.home();
  if (seed) {
    if (seed->ndim() != 1 || static_cast<std::size_t>(seed->shape(0)) != axes.size()) {
      throw py::value_error("seed must be a pose of " + std::to_string(axes.size()) + " values (" +
                            axes_text(axes) + ")");
    }
    start = pose_from_row(machine, axes, seed->data());
  }
  Array poses({rows, axes.size()});
  std::vector<std::int8_t> codes(rows);
  const double* in = joints.data();
  double* out = poses.mutable_data();
  {
    const Machine own = machine;  // as in inverse()
    const py::gil_scoped_release released;
    forward_rows(own, axes, in, rows, start, out, codes.data());
  }
  return py::make_tuple(poses, status_array(codes));
}

// d joints / d pose at one pose, (n, k): joints in mm or deg per pose coordinate in mm or deg.
Array jacobian(const Machine& machine, const Array& pose) {
  const std::vector<int> axes = controlled_axes(machine);
  if (pose.ndim() != 1 || static_cast<std::size_t>(pose.shape(0)) != axes.size()) {
    throw py::value_error("pose must have " + std::to_string(axes.size()) + " values (" +
                          axes_text(axes) + ")");
  }
  const Pose at = pose_from_row(machine, axes, pose.data());
  JointJacobian d_joints_d_pose;
  const Status status = machine.kinematics().jacobian(at, d_joints_d_pose);
  if (!status.ok()) throw py::value_error("no jacobian at this pose: " + machine.describe(status));
  const std::size_t n = machine.joints().size();
  Array out({n, axes.size()});
  auto values = out.mutable_unchecked<2>();
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i = 0; i < axes.size(); ++i) {
      // to_interface scales a rotary joint's rad to deg; a column per deg is one per rad / 57.3.
      const double per_axis_unit = axes[i] < 3 ? 1.0 : degrees_to_radians(1.0);
      values(j, i) =
          machine.joints()[j].to_interface(d_joints_d_pose(static_cast<int>(j), axes[i])) *
          per_axis_unit;
    }
  }
  return out;
}

Array pose_array(const Machine& machine, const Vector6d& values) {
  const std::vector<int> axes = controlled_axes(machine);
  Array out(static_cast<py::ssize_t>(axes.size()));
  pose_to_row(Pose::from_vector(values), axes, out.mutable_data());
  return out;
}

// name -> value in mm or deg (the file's rad shown as deg), and name -> that unit.
py::dict parameters(const Machine& machine, bool units) {
  py::dict out;
  for (const Parameter& parameter : machine.kinematics().parameters()) {
    const bool angle = parameter.unit == "rad";
    if (units) {
      out[py::str(parameter.name)] = angle ? std::string("deg") : parameter.unit;
    } else {
      out[py::str(parameter.name)] = angle ? radians_to_degrees(parameter.value) : parameter.value;
    }
  }
  return out;
}

void bind_joint(py::module_& module) {
  py::class_<JointSpec>(module, "Joint", "A joint of the machine file: limits in mm or deg.")
      .def_readonly("name", &JointSpec::name)
      .def_property_readonly("min", [](const JointSpec& j) { return j.to_interface(j.min); })
      .def_property_readonly("max", [](const JointSpec& j) { return j.to_interface(j.max); })
      .def_property_readonly("unit", &JointSpec::interface_unit)
      .def_property_readonly(
          "kind",
          [](const JointSpec& j) { return j.kind == JointKind::rotary ? "rotary" : "linear"; })
      .def_property_readonly("max_velocity",
                             [](const JointSpec& j) { return j.to_interface(j.max_velocity); })
      .def("__repr__", [](const JointSpec& j) {
        return "<Joint " + j.name + " " + std::to_string(j.to_interface(j.min)) + ".." +
               std::to_string(j.to_interface(j.max)) + " " + j.interface_unit() + ">";
      });
}

void bind_machine_properties(py::class_<Machine>& machine) {
  machine.def_property_readonly("name", &Machine::name)
      .def_property_readonly("source", &Machine::source)
      .def_property_readonly("kinematics",
                             [](const Machine& m) { return std::string(m.kinematics().type()); })
      .def_property_readonly("dof", [](const Machine& m) { return m.kinematics().dof().count(); })
      .def_property_readonly("coordinates",
                             [](const Machine& m) {
                               std::vector<std::string> names;
                               for (int axis : controlled_axes(m)) {
                                 names.emplace_back(kAxisNames[axis]);
                               }
                               return names;
                             })
      .def_property_readonly("joints", &Machine::joints)
      .def_property_readonly("joint_names", &Machine::joint_names)
      .def_property_readonly("home",
                             [](const Machine& m) { return pose_array(m, m.home().as_vector()); })
      .def_property_readonly("envelope",
                             [](const Machine& m) {
                               return py::make_tuple(pose_array(m, m.cartesian().envelope_min),
                                                     pose_array(m, m.cartesian().envelope_max));
                             })
      .def_property_readonly("parameters", [](const Machine& m) { return parameters(m, false); })
      .def_property_readonly("parameter_units",
                             [](const Machine& m) { return parameters(m, true); })
      .def("__repr__", [](const Machine& m) {
        return "<pkmkit.Machine '" + m.name() + "' " + std::string(m.kinematics().type()) + ", " +
               std::to_string(m.joints().size()) + " joints>";
      });
}

void bind_machine(py::module_& module) {
  py::class_<Machine> machine(module, "Machine", "A machine file's machine (mm and deg outside).");
  machine.def_static(
      "load", [](const std::string& path) { return load_machine(path); }, py::arg("path"),
      "Reads a machine file (TOML); a MachineFileError says file:line:key of a problem.");
  bind_machine_properties(machine);
  machine.def("inverse", &inverse, py::arg("poses"),
              "IK of an (N, k) pose array (mm, deg): (joints (N, n), status (N,) of str).");
  machine.def("forward", &forward, py::arg("joints"), py::arg("seed") = py::none(),
              "FK of an (N, n) joint array, each row seeded with the previous row's pose (home, "
              "or seed, first): (poses (N, k), status (N,) of str).");
  machine.def("jacobian", &jacobian, py::arg("pose"),
              "d joints / d pose at one pose (k,): an (n, k) array in mm or deg per mm or deg.");
}

// MachineFileError(ValueError) with .file, .line and .key besides the located message.
void bind_machine_file_error(py::module_& module) {
  static py::exception<MachineFileError> type(module, "MachineFileError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const MachineFileError& error) {
      py::object instance = py::reinterpret_borrow<py::object>(type.ptr())(error.what());
      instance.attr("file") = error.file();
      instance.attr("line") = error.line();
      instance.attr("key") = error.key();
      PyErr_SetObject(type.ptr(), instance.ptr());
    }
  });
}

}  // namespace

}  // namespace pkm::python

PYBIND11_MODULE(pkmkit, module) {
  module.doc() = "pkmkit: machine files and their kinematics over NumPy arrays (mm, deg)";
  const std::vector<std::string> statuses = pkm::python::status_identifiers();
  module.attr("STATUSES") = py::tuple(py::cast(statuses));
  module.attr("_STATUS_NAMES") = py::module_::import("numpy").attr("array")(statuses);
  pkm::python::bind_machine_file_error(module);
  pkm::python::bind_joint(module);
  pkm::python::bind_machine(module);
}
