// pkm workspace: the reachable workspace of a machine over an orientation range, with its
// volume as proven bounds (docs/workspace.md).
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "app.hpp"
#include "pkm/view/html_page.hpp"
#include "pkm/workspace/workspace.hpp"
#include "pkm/workspace/workspace_json.hpp"

namespace pkm::app {

namespace {

struct WorkspaceCommandOptions {
  std::string machine;
  std::string orientation;
  double resolution = 0.0;  // the machine file's units; 0: the default
  bool json = false;
  std::string html;  // the workspace's page (--html), empty for none
  int threads = 2;
  double max_cells = 2e8;  // workspace::WorkspaceOptions::max_cells
};

double parse_degrees(const std::string& text, const std::string& whole) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value) || std::abs(value) > 360.0) {
    throw CommandError("--orientation '" + whole + "': '" + text +
                       "' is not an angle in degrees within +-360");
  }
  return value;
}

// "10" (+-10 deg about home on every angle the machine controls) or "a=-10:10,b=5,c=-2:2"
// (absolute deg; an angle not named stays at home's).
void read_orientation(const machine::Machine& machine, const std::string& text,
                      workspace::WorkspaceOptions& options) {
  if (text.empty()) return;
  if (text.find('=') == std::string::npos) {
    const double spread = std::abs(parse_degrees(text, text));
    for (int k = 0; k < 3; ++k) {
      if (!machine.kinematics().dof().controls(3 + k)) continue;
      options.orientation_min_rad[k] -= geometry::degrees_to_radians(spread);
      options.orientation_max_rad[k] += geometry::degrees_to_radians(spread);
    }
    return;
  }
  std::stringstream parts(text);
  std::string part;
  while (std::getline(parts, part, ',')) {
    const std::size_t equals = part.find('=');
    const int axis =
        equals == std::string::npos ? -1 : geometry::axis_index(part.substr(0, equals));
    if (axis < 3) {
      throw CommandError("--orientation '" + text + "': '" + part +
                         "' is not a=MIN:MAX, b=... or c=... (deg)");
    }
    if (!machine.kinematics().dof().controls(axis)) {
      throw CommandError("--orientation '" + text + "': the machine does not control " +
                         std::string(geometry::kAxisNames[axis]));
    }
    const std::string range = part.substr(equals + 1);
    const std::size_t colon = range.find(':', 1);
    const double lo = parse_degrees(range.substr(0, colon), text);
    const double hi =
        colon == std::string::npos ? lo : parse_degrees(range.substr(colon + 1), text);
    if (lo > hi) throw CommandError("--orientation '" + text + "': " + part + " has min > max");
    options.orientation_min_rad[axis - 3] = geometry::degrees_to_radians(lo);
    options.orientation_max_rad[axis - 3] = geometry::degrees_to_radians(hi);
  }
}

// "x -200.0..200.0 y ... mm", in the machine file's units (one more decimal for inches).
std::string box_text(const machine::Machine& machine, const Eigen::AlignedBox3d& box,
                     const std::array<bool, 3>& axes) {
  std::string text;
  char part[96];
  const int decimals = machine.units() == machine::LengthUnit::inch ? 2 : 1;
  for (int axis = 0; axis < 3; ++axis) {
    if (!axes[static_cast<std::size_t>(axis)]) continue;
    std::snprintf(part, sizeof part, "%s%s %.*f..%.*f", text.empty() ? "" : " ",
                  std::string(geometry::kAxisNames[axis]).c_str(), decimals,
                  machine.axis_to_file(axis, box.min()[axis]) + 0.0, decimals,
                  machine.axis_to_file(axis, box.max()[axis]) + 0.0);
    text += part;
  }
  return text + " " + machine.length_unit();
}

// The summary in the machine file's units (the JSON document keeps mm: its keys say so).
void print_summary(const machine::Machine& machine, const workspace::Workspace& ws) {
  const double per_unit = machine.mm_per_unit();
  const std::string unit = machine.length_unit();
  std::printf("%s: workspace at %g %s resolution", ws.machine.c_str(), ws.resolution_mm / per_unit,
              unit.c_str());
  std::string angles;
  for (int k = 0; k < 3; ++k) {
    if (ws.orientation_max_rad[k] == ws.orientation_min_rad[k]) continue;
    char part[80];
    std::snprintf(part, sizeof part, " %s %g..%g", std::string(geometry::kAxisNames[3 + k]).c_str(),
                  geometry::radians_to_degrees(ws.orientation_min_rad[k]),
                  geometry::radians_to_degrees(ws.orientation_max_rad[k]));
    angles += part;
  }
  std::printf("%s\n", angles.empty() ? "" : (", every orientation of" + angles + " deg").c_str());
  const std::string measure_unit = unit + (ws.planar ? "^2" : "^3");
  const double per_measure = ws.planar ? per_unit * per_unit : per_unit * per_unit * per_unit;
  std::printf("%s: %.6g .. %.6g %s (proven inside .. inside + boundary cells)\n",
              ws.planar ? "area" : "volume", ws.inside_measure / per_measure,
              (ws.inside_measure + ws.boundary_measure) / per_measure, measure_unit.c_str());
  std::printf("estimate: %.6g %s (inside + the share of boundary cells' sample points reached)\n",
              ws.estimate / per_measure, measure_unit.c_str());
  if (ws.extent) {
    std::printf("extent: %s\n", box_text(machine, *ws.extent, ws.position_axes).c_str());
  }
  if (ws.largest_box) {
    std::printf("largest box inside: %s\n",
                box_text(machine, *ws.largest_box, ws.position_axes).c_str());
  }
  if (ws.largest_cylinder) {
    const workspace::Cylinder& c = *ws.largest_cylinder;
    std::printf("largest %s about z inside: centre x %.1f y %.1f, radius %.1f %s",
                ws.planar ? "disk" : "cylinder", c.centre_mm.x() / per_unit + 0.0,
                c.centre_mm.y() / per_unit + 0.0, c.radius_mm / per_unit, unit.c_str());
    if (!ws.planar) {
      std::printf(", z %.1f..%.1f %s", c.z0_mm / per_unit + 0.0, c.z1_mm / per_unit + 0.0,
                  unit.c_str());
    }
    std::printf("\n");
  }
  std::string limits;
  for (const auto& [name, count] : ws.limited_by) {
    limits += (limits.empty() ? "" : ", ") + name + " " + std::to_string(count);
  }
  std::printf("limited by (outside and boundary cells): %s\n",
              limits.empty() ? "nothing" : limits.c_str());
  std::printf("cells: %zu inside, %zu boundary, %lld judged (%lld cells of poses)\n",
              ws.inside.size(), ws.boundary.size(), static_cast<long long>(ws.cells_judged),
              static_cast<long long>(ws.boxes_judged));
  for (const std::string& note : ws.notes) std::printf("note: %s\n", note.c_str());
}

// The refusal of a resolution too fine, in the machine file's units, naming the options.
std::string cell_bound_text(const machine::Machine& machine,
                            const workspace::WorkspaceOptions& settings,
                            const workspace::CellBoundError& error) {
  const workspace::CellEstimate& estimate = error.estimate;
  const double per_unit = machine.mm_per_unit();
  const std::string unit = machine.length_unit();
  char text[600];
  std::snprintf(text, sizeof text,
                "--resolution %g %s: the workspace would judge about %.3g cells and list %.3g "
                "(about %s of memory), more than --max-cells %lld (estimated from a run at "
                "%g %s, the count growing %d times with each halving of the resolution)",
                settings.resolution_mm / per_unit, unit.c_str(), estimate.judged, estimate.listed,
                size_text(estimate.bytes).c_str(), static_cast<long long>(settings.max_cells),
                estimate.from_resolution_mm / per_unit, unit.c_str(), estimate.growth);
  std::string message = text;
  if (error.fitting_resolution_mm > 0.0) {
    std::snprintf(text, sizeof text, ": --resolution %.2g %s or coarser fits",
                  error.fitting_resolution_mm / per_unit, unit.c_str());
    message += text;
  }
  return message + ", or raise --max-cells";
}

void run_workspace(const WorkspaceCommandOptions& options) {
  check_outputs({{"--html", options.html}});
  refuse_overwriting_input(options.html, {{"the machine file", options.machine}});
  const machine::Machine machine = load_machine_or_default(options.machine);
  workspace::WorkspaceOptions settings = workspace::default_options(machine);
  read_orientation(machine, options.orientation, settings);
  settings.resolution_mm =
      options.resolution > 0.0 ? mm_from_machine_units(machine, options.resolution) : 0.0;
  if (settings.resolution_mm == 0.0) {
    // A default that keeps about 200 steps across the reach through home: a power of two in
    // the machine file's units (1/8 in on an inch machine, not 3.175 mm's awkward 0.125).
    const machine::PoseBox reach = machine::reach_box(machine);
    const double per_unit = machine.mm_per_unit();
    double longest = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
      if (reach.axes.controls(axis)) {
        longest = std::max(longest, (reach.max[axis] - reach.min[axis]) / per_unit);
      }
    }
    settings.resolution_mm =
        per_unit * std::max(0.01, std::exp2(std::round(std::log2(longest / 200.0))));
  }
  settings.threads = options.threads;
  settings.max_cells = static_cast<std::int64_t>(options.max_cells);
  workspace::Workspace ws;
  try {
    ws = workspace::compute_workspace(machine, settings);
  } catch (const workspace::CellBoundError& error) {
    throw CommandError(cell_bound_text(machine, settings, error));
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
  // The page gets the cells it draws, the document all of them, streamed (a 1 mm hexapod's).
  if (!options.html.empty()) {
    view::write_workspace_html(options.html, workspace::to_json(ws, view::kWorkspaceCellsDrawn),
                               &machine);
  }
  if (options.json) {
    workspace::write_json(std::cout, ws);
    std::cout << "\n";
    return;
  }
  print_summary(machine, ws);
  if (!options.html.empty()) {
    std::printf("wrote the page %s: open it in a browser\n", options.html.c_str());
  }
}

}  // namespace

void register_workspace_commands(CLI::App& app) {
  auto options = std::make_shared<WorkspaceCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "workspace",
      "The reachable workspace over an orientation range: volume (area) as proven bounds, "
      "extent, largest box and cylinder, dexterity and joint-speed maps (docs/workspace.md)");
  command->add_option("-m,--machine", options->machine,
                      "Machine file (default: the embedded hexapod)");
  command->add_option("--orientation", options->orientation,
                      "Orientations every point must reach: DEG (+-DEG about home's on each "
                      "controlled angle) or a=MIN:MAX,b=MIN:MAX,c=MIN:MAX (deg); default home's");
  command
      ->add_option("--resolution", options->resolution,
                   "Side of the finest cells, in the machine file's units (the guaranteed "
                   "resolution; default about 1/200 of the reach through home)")
      ->check(number_in(1e-3, 1e5));
  command
      ->add_option("--max-cells", options->max_cells,
                   "Refuse a run estimated to judge more cells than this (default 2e8: about 3.5 "
                   "GB)")
      ->check(number_in(1, 1e12));
  command->add_option("--threads", options->threads, "Worker threads (default 2)")
      ->check(CLI::Range(1, 64));
  command->add_flag("--json", options->json, "Write the workspace as JSON to standard output");
  command
      ->add_option("--html", options->html,
                   "Write the workspace's page: one HTML file that opens offline")
      ->check(file_name());
  command->callback([options] { run_workspace(*options); });
}

}  // namespace pkm::app
