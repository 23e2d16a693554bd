// pkmkit.canon: the canonical commands of a G-code program (gcode::Interpreter, as `pkm gcode
// --canon` prints them) as an iterator of named tuples, pkmkit.Canon. The interpreter is stepped a
// line at a time as the iterator is pulled, so a program of any length runs in constant memory.
#include <pybind11/stl.h>

#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "bind_common.hpp"
#include "pkm/gcode/canon.hpp"
#include "pkm/gcode/interpreter.hpp"
#include "pkm/gcode/tool_table.hpp"

namespace pkm::python {

namespace {

// The fields of pkmkit.Canon: those of gcode::Canon, which of them a kind uses as canon.hpp says.
constexpr const char* kCanonFields[] = {"kind",    "line",      "n",     "units",      "end",
                                        "plane",   "center",    "turns", "value",      "value2",
                                        "integer", "feed_mode", "text",  "spindle_rpm"};

const char* kind_name(gcode::CanonKind kind) {
  using K = gcode::CanonKind;
  switch (kind) {
    case K::traverse:
      return "traverse";
    case K::feed:
      return "feed";
    case K::probe:
      return "probe";
    case K::arc:
      return "arc";
    case K::dwell:
      return "dwell";
    case K::set_feed_rate:
      return "set_feed_rate";
    case K::set_feed_mode:
      return "set_feed_mode";
    case K::select_plane:
      return "select_plane";
    case K::use_length_units:
      return "use_length_units";
    case K::comment:
      return "comment";
    case K::message:
      return "message";
    case K::spindle_speed:
      return "spindle_speed";
    case K::spindle_clockwise:
      return "spindle_clockwise";
    case K::spindle_counterclockwise:
      return "spindle_counterclockwise";
    case K::spindle_stop:
      return "spindle_stop";
    case K::orient_spindle:
      return "orient_spindle";
    case K::wait_orient_spindle:
      return "wait_orient_spindle";
    case K::mist_on:
      return "mist_on";
    case K::mist_off:
      return "mist_off";
    case K::flood_on:
      return "flood_on";
    case K::flood_off:
      return "flood_off";
    case K::select_tool:
      return "select_tool";
    case K::change_tool:
      return "change_tool";
    case K::tool_length_offset:
      return "tool_length_offset";
    case K::g5x_offset:
      return "g5x_offset";
    case K::g92_offset:
      return "g92_offset";
    case K::path_control:
      return "path_control";
    case K::program_stop:
      return "program_stop";
    case K::optional_stop:
      return "optional_stop";
    case K::program_end:
      return "program_end";
    case K::event:
      return "event";
    case K::xy_rotation:
      return "xy_rotation";
    case K::speed_feed_sync:
      return "speed_feed_sync";
    case K::speed_feed_sync_stop:
      return "speed_feed_sync_stop";
    case K::rigid_tap:
      return "rigid_tap";
    case K::feed_override:
      return "feed_override";
    case K::speed_override:
      return "speed_override";
  }
  return "";  // unreachable: -Wswitch names a kind added without its name
}

const char* feed_mode_name(gcode::FeedMode mode) {
  switch (mode) {
    case gcode::FeedMode::units_per_minute:
      return "units_per_minute";
    case gcode::FeedMode::inverse_time:
      return "inverse_time";
    case gcode::FeedMode::units_per_revolution:
      return "units_per_revolution";
  }
  return "";
}

const char* plane_name(gcode::Plane plane) {
  switch (plane) {
    case gcode::Plane::xy:
      return "xy";
    case gcode::Plane::xz:
      return "xz";
    case gcode::Plane::yz:
      return "yz";
  }
  return "";
}

// One command as a pkmkit.Canon, in the program's units (`units`), as the interpreter made it.
py::object canon_tuple(const py::object& type, const gcode::Canon& c) {
  return type(kind_name(c.kind), c.line, c.n_label,
              c.units == gcode::LengthUnits::inch ? "inch" : "mm", py::tuple(py::cast(c.end)),
              plane_name(c.plane), py::make_tuple(c.center[0], c.center[1]), c.turns, c.value,
              c.value2, c.integer, feed_mode_name(c.feed_mode), c.text, c.spindle_rpm);
}

// The interpreter, stepped as the commands are pulled; the commands of the last line stepped
// wait in `pending_`.
class CanonCommands {
 public:
  CanonCommands(const std::string& program, gcode::InterpreterOptions options)
      : interpreter_(program, std::move(options)),
        type_(py::module_::import("pkmkit").attr("Canon")),
        sink_([this](const gcode::Canon& canon) { pending_.push_back(canon); }) {
    interpreter_.start(sink_);  // which keeps a reference to the sink
  }

  py::object next() {
    while (pending_.empty()) {
      if (ended_ || !interpreter_.step()) {
        ended_ = true;
        throw py::stop_iteration();
      }
    }
    const gcode::Canon canon = std::move(pending_.front());
    pending_.pop_front();
    return canon_tuple(type_, canon);
  }

  // The interpreter's warnings so far, (line, message) each.
  py::list warnings() const {
    py::list out;
    for (const gcode::Warning& warning : interpreter_.warnings()) {
      out.append(py::make_tuple(warning.line, warning.message));
    }
    return out;
  }

 private:
  gcode::Interpreter interpreter_;
  py::object type_;
  gcode::CanonSink sink_;
  std::deque<gcode::Canon> pending_;
  bool ended_ = false;
};

std::unique_ptr<CanonCommands> canon(const std::string& program,
                                     const std::optional<std::string>& tool_table,
                                     const std::string& tool_table_units, bool block_delete) {
  if (tool_table_units != "mm" && tool_table_units != "inch") {
    throw py::value_error("tool_table_units must be 'mm' or 'inch'");
  }
  gcode::InterpreterOptions options;
  options.block_delete = block_delete;
  if (tool_table) {
    options.tool_table =
        gcode::read_tool_table(*tool_table, tool_table_units == "inch" ? gcode::LengthUnits::inch
                                                                       : gcode::LengthUnits::mm);
  }
  return std::make_unique<CanonCommands>(program, std::move(options));
}

}  // namespace

void bind_canon(py::module_& module) {
  py::list fields;
  for (const char* field : kCanonFields) fields.append(field);
  module.attr("Canon") = py::module_::import("collections")
                             .attr("namedtuple")("Canon", fields, py::arg("module") = "pkmkit");
  py::class_<CanonCommands>(module, "CanonCommands",
                            "The canonical commands of a G-code program, interpreted as they "
                            "are pulled; .warnings the interpreter's so far.")
      .def("__iter__", [](CanonCommands& commands) -> CanonCommands& { return commands; })
      .def("__next__", &CanonCommands::next)
      .def_property_readonly("warnings", &CanonCommands::warnings);
  module.def("canon", &canon, py::arg("program"), py::kw_only(), py::arg("tool_table") = py::none(),
             py::arg("tool_table_units") = "mm", py::arg("block_delete") = false,
             "The canonical commands of a G-code program, as pkm gcode --canon prints them: an "
             "iterator of pkmkit.Canon(kind, line, n, units, end, plane, center, turns, value, "
             "value2, integer, feed_mode, text), lengths in the program's units (units: 'mm' or "
             "'inch'), end the nine axes x y z a b c u v w. A program's error raises GcodeError "
             "(file, line, column) when the iterator reaches it.");
}

}  // namespace pkm::python
