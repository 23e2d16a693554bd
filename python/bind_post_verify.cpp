// pkmkit.post and pkmkit.verify: a joint-space program written from a Cartesian job within a
// tolerance (post::post_program, with the header `pkm post` writes), and such a program checked
// against its job by forward kinematics (verify::verify_joint_program); each returns the report
// `--report` writes, as a dict. The file is the same byte for byte as pkm post's.
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "bind_common.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/gcode/tool_table.hpp"
#include "pkm/io/input_files.hpp"
#include "pkm/io/json_reports.hpp"
#include "pkm/post/joint_program.hpp"
#include "pkm/post/program_header.hpp"
#include "pkm/verify/joint_path.hpp"
#include "pkm/view/html_page.hpp"

namespace pkm::python {

namespace {

// The bounds of pkm's --tolerance (kMinTolerance, kMaxTolerance in apps/pkm/app.hpp), mm.
void check_tolerance(double tolerance_mm) {
  if (!(tolerance_mm >= 1e-4 && tolerance_mm <= 1000.0)) {
    throw py::value_error("tolerance must lie within [0.0001, 1000] mm");
  }
}

std::optional<gcode::ToolTable> tool_table_argument(const std::optional<std::string>& path,
                                                    const std::string& units) {
  if (units != "mm" && units != "inch") {
    throw py::value_error("tool_table_units must be 'mm' or 'inch'");
  }
  if (!path) return std::nullopt;
  return gcode::read_tool_table(
      *path, units == "inch" ? gcode::LengthUnits::inch : gcode::LengthUnits::mm);
}

py::object post(const machine::Machine& machine, const std::string& program,
                const std::string& output, double tolerance_mm, const std::string& dialect,
                const std::vector<double>& origin, const std::optional<std::string>& tool_table,
                const std::string& tool_table_units, bool span_moves, long max_blocks) {
  check_tolerance(tolerance_mm);
  if (max_blocks < 0) throw py::value_error("max_blocks must be >= 0 (0: no bound)");
  post::PostOptions options;
  options.tolerance_mm = tolerance_mm;
  options.span_moves = span_moves;
  options.max_blocks = max_blocks;
  try {
    options.dialect = post::dialect_named(dialect);
    post::check_axis_letters(machine, options.dialect);
  } catch (const std::invalid_argument& error) {
    throw py::value_error(machine.source() + ": " + error.what());
  }
  options.origin = origin_argument(origin, "origin");
  gcode::InterpreterOptions interpreter;
  interpreter.tool_table = tool_table_argument(tool_table, tool_table_units);
  std::vector<io::NamedInput> inputs{{"the job", program},
                                     {"the machine file", machine.source()},
                                     {"the tool table", tool_table.value_or("")}};
  if (const std::string reason = io::overwrites_input(output, inputs); !reason.empty()) {
    throw py::value_error(reason);
  }
  const machine::Machine own = machine;  // the loop runs without the GIL (pkmkit.cpp)
  post::PostReport report;
  try {
    const py::gil_scoped_release released;
    files::AtomicFileWriter file(output);
    file.write(post::joint_program_header(own, program, options.dialect, tolerance_mm, nullptr));
    report = post::post_program(own, program, interpreter, options,
                                [&](const std::string& line) { file.write(line + "\n"); });
    file.write_at(0,
                  post::joint_program_header(own, program, options.dialect, tolerance_mm, &report));
    for (std::size_t i = 1; i < report.files_read.size(); ++i) {
      inputs.push_back({"a subroutine file the job calls", report.files_read[i]});
    }
    if (const std::string reason = io::overwrites_input(output, inputs); !reason.empty()) {
      throw std::invalid_argument(reason);
    }
    file.commit();
  } catch (const post::BlockBoundError& error) {
    const py::object type = py::module_::import("pkmkit").attr("PostError");
    PyErr_SetObject(type.ptr(), type(std::string(error.what()) +
                                     ". Check the job's arcs (their P, the turns) and the "
                                     "tolerance, or raise max_blocks")
                                    .ptr());
    throw py::error_already_set();
  } catch (const post::PostError& error) {
    raise_with_reach_hint("PostError", error.what(), -1, own, program, interpreter, options.origin);
  }
  return json_to_python(io::post_report_json(own, program, output, report, tolerance_mm));
}

py::object verify(const machine::Machine& machine, const std::string& joint_program,
                  const std::string& against, const std::optional<double>& tolerance_mm,
                  const std::vector<double>& origin, const std::optional<std::string>& tool_table,
                  const std::string& tool_table_units) {
  verify::VerifyOptions options;
  if (tolerance_mm) {
    check_tolerance(*tolerance_mm);
    options.tolerance_mm = *tolerance_mm;
  } else {
    const std::optional<double> header = verify::tolerance_in_header(joint_program);
    if (!header) {
      throw py::value_error(joint_program +
                            ": no tolerance to verify against: give tolerance= (mm; the joint "
                            "program's header, where pkm post writes one, has none)");
    }
    options.tolerance_mm = *header;
  }
  options.origin = origin_argument(origin, "origin");
  options.job_options.tool_table = tool_table_argument(tool_table, tool_table_units);
  const machine::Machine own = machine;
  verify::VerifyReport report;
  {
    const py::gil_scoped_release released;
    report = verify::verify_joint_program(own, joint_program, against, options);
  }
  return json_to_python(io::verify_report_json(own, joint_program, against, report));
}

}  // namespace

void bind_post_verify(py::module_& module) {
  module.def(
      "post", &post, py::arg("machine"), py::arg("program"), py::arg("output"), py::kw_only(),
      py::arg("tolerance") = 0.01, py::arg("dialect") = "linuxcnc",
      py::arg("origin") = std::vector<double>{}, py::arg("tool_table") = py::none(),
      py::arg("tool_table_units") = "mm", py::arg("span_moves") = true,
      py::arg("max_blocks") = post::kDefaultMaxBlocks,
      "Writes the joint-space program of a G-code job to `output` as pkm post does (the "
      "tool tip within `tolerance` mm of the programmed path; dialect linuxcnc, mach3, "
      "grbl or grblhal; origin x y [z [a b c]] in mm and deg; span_moves=False covers "
      "every move on its own, as --no-span-moves; max_blocks as pkm post's --max-blocks, 0 for no "
      "bound) and returns the report of "
      "pkm post --report as a dict. A move the machine cannot make raises PostError.");
  module.def("verify", &verify, py::arg("machine"), py::arg("joint_program"), py::kw_only(),
             py::arg("against"), py::arg("tolerance") = py::none(),
             py::arg("origin") = std::vector<double>{}, py::arg("tool_table") = py::none(),
             py::arg("tool_table_units") = "mm",
             "Checks a joint-space program against the Cartesian job it should follow, by "
             "forward kinematics, as pkm verify does; returns the report of pkm verify --report "
             "as a dict ('passed' says whether pkm verify would exit 0). tolerance in mm "
             "(default: the one in the program's header, as pkm post writes it).");
}

}  // namespace pkm::python
