// The pkmkit Python module: a machine file's machine (pkm::machine::Machine) with its inverse and
// forward kinematics over NumPy arrays, in mm and degrees as every pkm interface (docs/python.md).
// A thin layer: the kinematics, limits and units are the pkm libraries'; this file only converts
// arrays and units, and runs the batch loops without the GIL.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bind_common.hpp"
#include "pkm/gcode/gcode_error.hpp"
#include "pkm/machine/machine_parameters.hpp"
#include "pkm/machine/pose_tensions.hpp"
#include "pkm/motion/job_reach.hpp"
#include "pkm/motion/planner.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/verify/joint_path.hpp"

namespace pkm::python {

namespace {

// "x y z": the coordinates of a pose array, for messages.
std::string axes_text(const std::vector<int>& axes) {
  std::string text;
  for (int axis : axes) text += (text.empty() ? "" : " ") + std::string(geometry::kAxisNames[axis]);
  return text;
}

}  // namespace

std::vector<int> controlled_axes(const machine::Machine& machine) {
  return machine.kinematics().dof().axes();
}

geometry::Pose pose_from_row(const machine::Machine& machine, const std::vector<int>& axes,
                             const double* row) {
  geometry::Vector6d values = machine.home().as_vector();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    values[axes[i]] = axes[i] < 3 ? row[i] : geometry::degrees_to_radians(row[i]);
  }
  return geometry::Pose::from_vector(values);
}

geometry::Pose pose_argument(const machine::Machine& machine, const Array& pose,
                             const std::string& what) {
  const std::vector<int> axes = controlled_axes(machine);
  if (pose.ndim() != 1 || static_cast<std::size_t>(pose.shape(0)) != axes.size()) {
    throw py::value_error(what + " must have " + std::to_string(axes.size()) + " values (" +
                          axes_text(axes) + ")");
  }
  return pose_from_row(machine, axes, pose.data());
}

geometry::Vector6d origin_argument(const std::vector<double>& values, const std::string& what) {
  if (values.size() > geometry::kPoseSize) {
    throw py::value_error(what + " takes at most six values (x y z a b c, mm and deg)");
  }
  geometry::Vector6d origin = geometry::Vector6d::Zero();
  for (std::size_t i = 0; i < values.size(); ++i) {
    origin[static_cast<int>(i)] = i < 3 ? values[i] : geometry::degrees_to_radians(values[i]);
  }
  return origin;
}

py::object json_to_python(const nlohmann::json& document) {
  return py::module_::import("json").attr("loads")(document.dump());
}

void raise_with_reach_hint(const char* type_name, const std::string& message, int line,
                           const machine::Machine& machine, const std::string& program,
                           const gcode::InterpreterOptions& interpreter,
                           const geometry::Vector6d& origin) {
  std::string hint;
  {
    const py::gil_scoped_release released;  // the job is read again
    hint = motion::job_reach_hint(machine, program, interpreter, origin);
  }
  const py::object type = py::module_::import("pkmkit").attr(type_name);
  py::object instance = type(message + hint);
  if (line >= 0) instance.attr("line") = line;
  PyErr_SetObject(type.ptr(), instance.ptr());
  throw py::error_already_set();
}

namespace {

// Every identifier, indexed by the code's value (the last code is interference; a code added
// after it needs this bound moved as well as its case above).
std::vector<std::string> status_identifiers() {
  std::vector<std::string> names;
  for (int code = 0; code <= static_cast<int>(kinematics::StatusCode::interference); ++code) {
    names.emplace_back(kinematics::status_identifier(static_cast<kinematics::StatusCode>(code)));
  }
  return names;
}

void pose_to_row(const geometry::Pose& pose, const std::vector<int>& axes, double* row) {
  const geometry::Vector6d values = pose.as_vector();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    row[i] = axes[i] < 3 ? values[axes[i]] : geometry::radians_to_degrees(values[axes[i]]);
  }
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
void inverse_rows(const machine::Machine& machine, const std::vector<int>& axes,
                  const double* poses, std::size_t rows, double* joints_out, std::int8_t* codes) {
  const std::size_t n = machine.joints().size();
  kinematics::JointVector joints;
  for (std::size_t row = 0; row < rows; ++row) {
    const kinematics::Status status =
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
void forward_rows(const machine::Machine& machine, const std::vector<int>& axes,
                  const double* joints_in, std::size_t rows, geometry::Pose seed, double* poses_out,
                  std::int8_t* codes) {
  const std::size_t n = machine.joints().size();
  kinematics::JointVector joints(static_cast<int>(n));
  for (std::size_t row = 0; row < rows; ++row) {
    for (std::size_t j = 0; j < n; ++j) {
      joints[static_cast<int>(j)] = machine.joints()[j].from_interface(joints_in[row * n + j]);
    }
    geometry::Pose pose = seed;
    const kinematics::Status status = machine.forward(joints, pose);
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

// A batch's input as the C-contiguous float64 array the loop reads: the array itself when it is
// one (no copy), else a converted copy, with a CopyWarning when it was a NumPy array (a list is
// expected to be converted; an array the caller may not know is strided, transposed or of
// another type).
Array batch_input(const py::object& input, const char* what) {
  Array array = Array::ensure(input);
  if (!array) throw py::type_error(std::string(what) + " must be an array of numbers");
  // A view (a memmap's, a subclass's) reads the same memory: only new data is a copy.
  if (py::isinstance<py::array>(input) &&
      py::reinterpret_borrow<py::array>(input).data() != array.data()) {
    const py::object warning = py::module_::import("pkmkit").attr("CopyWarning");
    const std::string message = std::string(what) +
                                " is not a C-contiguous float64 array: a copy was made "
                                "(np.ascontiguousarray(" +
                                what + ", dtype=float) once avoids it)";
    if (PyErr_WarnEx(warning.ptr(), message.c_str(), 2) != 0) throw py::error_already_set();
  }
  return array;
}

py::tuple inverse(const machine::Machine& machine, const py::object& pose_input) {
  const Array poses = batch_input(pose_input, "poses");
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
    const machine::Machine own = machine;
    const py::gil_scoped_release released;
    inverse_rows(own, axes, in, rows, out, codes.data());
  }
  return py::make_tuple(joints, status_array(codes));
}

py::tuple forward(const machine::Machine& machine, const py::object& joint_input,
                  const std::optional<Array>& seed) {
  const Array joints = batch_input(joint_input, "joints");
  const std::vector<int> axes = controlled_axes(machine);
  const std::size_t rows = checked_rows(joints, machine.joints().size(), "joints");
  const geometry::Pose start = seed ? pose_argument(machine, *seed, "seed") : machine.home();
  Array poses({rows, axes.size()});
  std::vector<std::int8_t> codes(rows);
  const double* in = joints.data();
  double* out = poses.mutable_data();
  {
    const machine::Machine own = machine;  // as in inverse()
    const py::gil_scoped_release released;
    forward_rows(own, axes, in, rows, start, out, codes.data());
  }
  return py::make_tuple(poses, status_array(codes));
}

// The cables' tensions at rest (N) at each pose of an (N, k) array, by the model's interface (the
// distribution of an effector on more cables than coordinates, a plotter's balance):
// (tensions (N, c), held (N,) of bool); a row with no balance is NaN and not held.
py::tuple tensions(const machine::Machine& machine, const py::object& pose_input) {
  if (!machine::lists_tensions(machine)) {
    throw py::value_error(machine.name() +
                          " has no cable tensions to list: no cables, or cables without an "
                          "effector_mass or tension_limits");
  }
  const Array poses = batch_input(pose_input, "poses");
  const std::vector<int> axes = controlled_axes(machine);
  const std::size_t rows = checked_rows(poses, axes.size(), "poses (" + axes_text(axes) + ")");
  const std::optional<machine::PoseTensions> at_home =
      machine::pose_tensions(machine, machine.home());
  const std::size_t cables = at_home ? at_home->names.size() : 0;
  Array out({rows, cables});
  py::array_t<bool> held(static_cast<py::ssize_t>(rows));
  auto values = out.mutable_unchecked<2>();
  auto held_out = held.mutable_unchecked<1>();
  for (std::size_t row = 0; row < rows; ++row) {
    const std::optional<machine::PoseTensions> t = machine::pose_tensions(
        machine, pose_from_row(machine, axes, poses.data() + row * axes.size()));
    held_out(row) = t && t->held;
    for (std::size_t c = 0; c < cables; ++c) values(row, c) = t ? t->tension_N[c] : NAN;
  }
  return py::make_tuple(out, held);
}

// d joints / d pose at one pose, (n, k): joints in mm or deg per pose coordinate in mm or deg.
Array jacobian(const machine::Machine& machine, const Array& pose) {
  const std::vector<int> axes = controlled_axes(machine);
  const geometry::Pose at = pose_argument(machine, pose, "pose");
  kinematics::JointJacobian d_joints_d_pose;
  const kinematics::Status status = machine.kinematics().jacobian(at, d_joints_d_pose);
  if (!status.ok()) throw py::value_error("no jacobian at this pose: " + machine.describe(status));
  const std::size_t n = machine.joints().size();
  Array out({n, axes.size()});
  auto values = out.mutable_unchecked<2>();
  for (std::size_t j = 0; j < n; ++j) {
    for (std::size_t i = 0; i < axes.size(); ++i) {
      // to_interface scales a rotary joint's rad to deg; a column per deg is one per rad / 57.3.
      const double per_axis_unit = axes[i] < 3 ? 1.0 : geometry::degrees_to_radians(1.0);
      values(j, i) =
          machine.joints()[j].to_interface(d_joints_d_pose(static_cast<int>(j), axes[i])) *
          per_axis_unit;
    }
  }
  return out;
}

Array pose_array(const machine::Machine& machine, const geometry::Vector6d& values) {
  const std::vector<int> axes = controlled_axes(machine);
  Array out(static_cast<py::ssize_t>(axes.size()));
  pose_to_row(geometry::Pose::from_vector(values), axes, out.mutable_data());
  return out;
}

// name -> value in mm or deg (the file's rad shown as deg), and name -> that unit.
py::dict parameters(const machine::Machine& machine, bool units) {
  py::dict out;
  for (const kinematics::Parameter& parameter : machine.kinematics().parameters()) {
    const bool angle = parameter.unit == "rad";
    if (units) {
      out[py::str(parameter.name)] = angle ? std::string("deg") : parameter.unit;
    } else {
      out[py::str(parameter.name)] =
          angle ? geometry::radians_to_degrees(parameter.value) : parameter.value;
    }
  }
  return out;
}

// The machine with the named parameters changed (mm, or deg for angles, as parameters() shows
// them), the others kept: a new machine, as calibration makes one.
machine::Machine with_parameters(const machine::Machine& machine,
                                 const std::map<std::string, double>& changes) {
  const std::vector<kinematics::Parameter> parameters = machine.kinematics().parameters();
  std::vector<double> values;
  for (const kinematics::Parameter& parameter : parameters) values.push_back(parameter.value);
  for (const auto& [name, value] : changes) {
    const auto found = std::find_if(parameters.begin(), parameters.end(),
                                    [&](const kinematics::Parameter& p) { return p.name == name; });
    if (found == parameters.end()) {
      std::string names;
      for (const kinematics::Parameter& p : parameters)
        names += (names.empty() ? "" : ", ") + p.name;
      throw py::key_error("no parameter '" + name + "' in the " +
                          std::string(machine.kinematics().type()) +
                          " model; its parameters: " + names);
    }
    values[static_cast<std::size_t>(found - parameters.begin())] =
        found->unit == "rad" ? geometry::degrees_to_radians(value) : value;
  }
  try {
    return machine::with_kinematics_parameters(machine, values);
  } catch (const std::invalid_argument& error) {
    throw py::value_error(std::string("impossible geometry: ") + error.what());
  }
}

void bind_joint(py::module_& module) {
  py::class_<machine::JointSpec>(module, "Joint",
                                 "A joint of the machine file: limits in mm or deg.")
      .def_readonly("name", &machine::JointSpec::name)
      .def_property_readonly("min",
                             [](const machine::JointSpec& j) { return j.to_interface(j.min); })
      .def_property_readonly("max",
                             [](const machine::JointSpec& j) { return j.to_interface(j.max); })
      .def_property_readonly("unit", &machine::JointSpec::interface_unit)
      .def_property_readonly("kind",
                             [](const machine::JointSpec& j) {
                               return j.kind == kinematics::JointKind::rotary ? "rotary" : "linear";
                             })
      .def_property_readonly(
          "max_velocity",
          [](const machine::JointSpec& j) { return j.to_interface(j.max_velocity); })
      .def("__repr__", [](const machine::JointSpec& j) {
        return "<Joint " + j.name + " " + std::to_string(j.to_interface(j.min)) + ".." +
               std::to_string(j.to_interface(j.max)) + " " + j.interface_unit() + ">";
      });
}

void bind_machine_properties(py::class_<machine::Machine>& machine) {
  machine.def_property_readonly("name", &machine::Machine::name)
      .def_property_readonly("source", &machine::Machine::source)
      .def_property_readonly(
          "kinematics",
          [](const machine::Machine& m) { return std::string(m.kinematics().type()); })
      .def_property_readonly("dof",
                             [](const machine::Machine& m) { return m.kinematics().dof().count(); })
      .def_property_readonly("coordinates",
                             [](const machine::Machine& m) {
                               std::vector<std::string> names;
                               for (int axis : controlled_axes(m)) {
                                 names.emplace_back(geometry::kAxisNames[axis]);
                               }
                               return names;
                             })
      .def_property_readonly("joints", &machine::Machine::joints)
      .def_property_readonly("joint_names", &machine::Machine::joint_names)
      .def_property_readonly(
          "home", [](const machine::Machine& m) { return pose_array(m, m.home().as_vector()); })
      .def_property_readonly("envelope",
                             [](const machine::Machine& m) {
                               return py::make_tuple(pose_array(m, m.cartesian().envelope_min),
                                                     pose_array(m, m.cartesian().envelope_max));
                             })
      .def_property_readonly("parameters",
                             [](const machine::Machine& m) { return parameters(m, false); })
      .def_property_readonly("parameter_units",
                             [](const machine::Machine& m) { return parameters(m, true); })
      .def("__repr__", [](const machine::Machine& m) {
        return "<pkmkit.Machine '" + m.name() + "' " + std::string(m.kinematics().type()) + ", " +
               std::to_string(m.joints().size()) + " joints>";
      });
}

void bind_machine(py::module_& module) {
  py::class_<machine::Machine> machine(module, "Machine",
                                       "A machine file's machine (mm and deg outside).");
  machine.def_static(
      "load", [](const std::string& path) { return machine::load_machine(path); }, py::arg("path"),
      "Reads a machine file (TOML); a MachineFileError says file:line:key of a problem.");
  bind_machine_properties(machine);
  machine.def("with_parameters", &with_parameters, py::arg("changes"),
              "A new machine with the named parameters of the kinematic model changed (a dict, "
              "mm or deg as .parameters shows them); this one is left as it is.");
  machine.def("inverse", &inverse, py::arg("poses"),
              "IK of an (N, k) pose array (mm, deg): (joints (N, n), status (N,) of str).");
  machine.def("forward", &forward, py::arg("joints"), py::arg("seed") = py::none(),
              "FK of an (N, n) joint array, each row seeded with the previous row's pose (home, "
              "or seed, first): (poses (N, k), status (N,) of str).");
  machine.def("tensions", &tensions, py::arg("poses"),
              "Cable tensions at rest (N) at an (N, k) pose array (mm, deg), cables in the "
              "joints' order: (tensions (N, c), held (N,) of bool: tensions within the limits "
              "hold the effector); ValueError for a machine without cable tensions.");
  machine.def("jacobian", &jacobian, py::arg("pose"),
              "d joints / d pose at one pose (k,): an (n, k) array in mm or deg per mm or deg.");
}

// MachineFileError(ValueError) with .file, .line and .key besides the located message.
void bind_machine_file_error(py::module_& module) {
  static py::exception<machine::MachineFileError> type(module, "MachineFileError",
                                                       PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const machine::MachineFileError& error) {
      py::object instance = py::reinterpret_borrow<py::object>(type.ptr())(error.what());
      instance.attr("file") = error.file();
      instance.attr("line") = error.line();
      instance.attr("key") = error.key();
      PyErr_SetObject(type.ptr(), instance.ptr());
    }
  });
}

// GcodeError(ValueError) with .file, .line and .column (a G-code program's error, as pkm prints
// it), PlanError(ValueError) with .line (a move the machine cannot make), PostError and
// VerifyError (ValueError) with pkm's message (file:line: what).
void bind_job_errors(py::module_& module) {
  static py::exception<gcode::GcodeError> gcode_type(module, "GcodeError", PyExc_ValueError);
  static py::exception<motion::PlanError> plan_type(module, "PlanError", PyExc_ValueError);
  py::register_exception<post::PostError>(module, "PostError", PyExc_ValueError);
  py::register_exception<verify::VerifyError>(module, "VerifyError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const gcode::GcodeError& error) {
      py::object instance = py::reinterpret_borrow<py::object>(gcode_type.ptr())(error.what());
      instance.attr("file") = error.file();
      instance.attr("line") = error.line();
      instance.attr("column") = error.column();
      PyErr_SetObject(gcode_type.ptr(), instance.ptr());
    } catch (const motion::PlanError& error) {
      py::object instance = py::reinterpret_borrow<py::object>(plan_type.ptr())(error.what());
      instance.attr("line") = error.line();
      PyErr_SetObject(plan_type.ptr(), instance.ptr());
    }
  });
}

}  // namespace

}  // namespace pkm::python

namespace py = pybind11;

PYBIND11_MODULE(pkmkit, module) {
  module.doc() = "pkmkit: machine files and their kinematics over NumPy arrays (mm, deg)";
  const std::vector<std::string> statuses = pkm::python::status_identifiers();
  module.attr("STATUSES") = py::tuple(py::cast(statuses));
  module.attr("_STATUS_NAMES") = py::module_::import("numpy").attr("array")(statuses);
  module.attr("CopyWarning") = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "pkmkit.CopyWarning",
      "A batch call's NumPy input was not C-contiguous float64 and was copied first.",
      PyExc_UserWarning, nullptr));
  pkm::python::bind_machine_file_error(module);
  pkm::python::bind_joint(module);
  pkm::python::bind_machine(module);
  pkm::python::bind_job_errors(module);
  pkm::python::bind_plan(module);
  pkm::python::bind_canon(module);
  pkm::python::bind_post_verify(module);
  pkm::python::bind_calibrate(module);
}
