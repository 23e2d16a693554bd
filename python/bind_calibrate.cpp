// pkmkit.calibrate.fit: a machine's geometry fitted to measured poses given as arrays (the fit of
// `pkm calibrate fit DATA.csv`, calibration/geometry_fit.hpp), returning the fitted machine and
// the report `pkm calibrate fit --json` prints.
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bind_common.hpp"
#include "pkm/calibration/fit_report.hpp"
#include "pkm/calibration/geometry_fit.hpp"
#include "pkm/calibration/measurements.hpp"
#include "pkm/machine/machine_parameters.hpp"

namespace pkm::python {

namespace {

// Row i of the arrays as a measurement: joints (mm, deg) and the pose coordinates measured (NaN
// where not), its line the row's index.
std::vector<calibration::Measurement> measurements_from_arrays(const machine::Machine& machine,
                                                               const Array& joints,
                                                               const Array& poses) {
  const std::vector<int> axes = controlled_axes(machine);
  const std::size_t n = machine.joints().size();
  if (joints.ndim() != 2 || static_cast<std::size_t>(joints.shape(1)) != n) {
    throw py::value_error("joints must be an (N, " + std::to_string(n) + ") array");
  }
  if (poses.ndim() != 2 || static_cast<std::size_t>(poses.shape(1)) != axes.size() ||
      poses.shape(0) != joints.shape(0)) {
    throw py::value_error("poses must be an (N, " + std::to_string(axes.size()) +
                          ") array, a row per row of joints (NaN where not measured)");
  }
  std::vector<calibration::Measurement> measurements(static_cast<std::size_t>(joints.shape(0)));
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    calibration::Measurement& m = measurements[row];
    m.line = static_cast<int>(row);
    m.joints = kinematics::JointVector(static_cast<int>(n));
    for (std::size_t j = 0; j < n; ++j) {
      const double value = joints.data()[row * n + j];
      if (!std::isfinite(value)) {
        throw py::value_error("joints row " + std::to_string(row) + " is not finite");
      }
      m.joints[static_cast<int>(j)] = machine.joints()[j].from_interface(value);
    }
    bool any = false;
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const double value = poses.data()[row * axes.size() + i];
      if (std::isnan(value)) continue;
      m.pose[axes[i]] = axes[i] < 3 ? value : geometry::degrees_to_radians(value);
      m.measured[static_cast<std::size_t>(axes[i])] = any = true;
    }
    if (!any) throw py::value_error("poses row " + std::to_string(row) + " measures nothing");
  }
  return measurements;
}

py::tuple fit(const machine::Machine& machine, const Array& joints, const Array& poses,
              const std::vector<std::string>& parameters, double angle_weight_mm_per_rad) {
  const std::vector<calibration::Measurement> measurements =
      measurements_from_arrays(machine, joints, poses);
  calibration::FitOptions options;
  options.parameters = parameters;
  options.angle_weight_mm_per_rad = angle_weight_mm_per_rad;
  machine::Machine fitted = machine;
  calibration::FitReport report;
  {
    const py::gil_scoped_release released;
    report = calibration::fit_geometry(fitted.kinematics(), fitted.home(), measurements, options);
  }
  // Made again from its parts with the fitted values, as Machine.with_parameters makes one.
  std::vector<double> values;
  for (const kinematics::Parameter& parameter : fitted.kinematics().parameters()) {
    values.push_back(parameter.value);
  }
  return py::make_tuple(machine::with_kinematics_parameters(machine, values),
                        json_to_python(calibration::fit_report_json(report, "")));
}

}  // namespace

void bind_calibrate(py::module_& module) {
  py::module_ calibrate =
      module.def_submodule("calibrate", "Fitting a machine's geometry to measurements");
  py::register_exception<calibration::FitError>(calibrate, "FitError", PyExc_ValueError);
  calibrate.def(
      "fit", &fit, py::arg("machine"), py::arg("joints"), py::arg("poses"), py::kw_only(),
      py::arg("parameters") = std::vector<std::string>{}, py::arg("angle_weight") = 100.0,
      "Fits the machine's geometric parameters to measured poses, as pkm calibrate fit does with "
      "a CSV: joints (N, n) in mm or deg, poses (N, k) of the machine's coordinates in mm and "
      "deg, NaN where a coordinate was not measured. parameters: the names to fit ('*' matches "
      "any run of characters; default all); angle_weight: mm an angle residual of 1 rad counts "
      "as. Returns (the fitted machine, the report of pkm calibrate fit --json, its lines the "
      "rows' indices and its output ''). FitError when the data cannot fit.");
}

}  // namespace pkm::python
