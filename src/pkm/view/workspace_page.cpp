// The page of pkm workspace: the reachable cells (inside and boundary), the largest box and
// cylinder, the maps of dexterity and joint speed, and the numbers, from the workspace JSON
// (docs/html-views.md, "Workspace").
#include <cmath>
#include <numbers>

#include "pkm/view/html_page.hpp"
#include "pkm/view/machine_drawing.hpp"
#include "pkm/view/page_data.hpp"

namespace pkm::view {

namespace {

using nlohmann::json;

Eigen::Vector3d vector3(const json& values) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < 3 && k < values.size(); ++k) v[static_cast<int>(k)] = values[k];
  return v;
}

// Cells as flat centre x y z and edge (mm). A cell [i, j, k, level] spans 2^level steps of the
// finest grid from origin + (i, j, k) * step (an entry without a level is one step).
json cells_json(const json& cells, const char* kind) {
  json flat = json::array();
  if (!cells.contains(kind) || !cells[kind].is_array()) return flat;
  const json& list = cells[kind];
  const Eigen::Vector3d origin = vector3(cells.value("origin_mm", json::array({0, 0, 0})));
  const double step = cells.value("step_mm", 1.0);
  const std::size_t every =
      std::max<std::size_t>(1, (list.size() + kWorkspaceCellsDrawn - 1) / kWorkspaceCellsDrawn);
  for (std::size_t n = 0; n < list.size(); n += every) {
    const json& cell = list[n];
    if (!cell.is_array() || cell.size() < 3) continue;
    const double edge = step * std::ldexp(1.0, cell.size() > 3 ? cell[3].get<int>() : 0);
    const Eigen::Vector3d corner =
        origin +
        step * Eigen::Vector3d(cell[0].get<double>(), cell[1].get<double>(), cell[2].get<double>());
    for (int k = 0; k < 3; ++k) flat.push_back(rounded(corner[k] + 0.5 * edge));
    flat.push_back(rounded(edge));
  }
  return flat;
}

void add_box(std::vector<Segment>& out, const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  const auto corner = [&](int bits) {
    return Eigen::Vector3d(bits & 1 ? high.x() : low.x(), bits & 2 ? high.y() : low.y(),
                           bits & 4 ? high.z() : low.z());
  };
  for (int a = 0; a < 8; ++a) {
    for (int bit : {1, 2, 4}) {
      if ((a & bit) == 0) out.push_back({Part::platform, corner(a), corner(a | bit)});
    }
  }
}

// The largest box and cylinder as outlines, beside the machine at home when it is given.
std::vector<Segment> outlines(const json& workspace) {
  std::vector<Segment> out;
  if (workspace.contains("largest_box_mm")) {
    add_box(out, vector3(workspace["largest_box_mm"]["min"]),
            vector3(workspace["largest_box_mm"]["max"]));
  }
  if (workspace.contains("largest_cylinder_mm")) {
    const json& cylinder = workspace["largest_cylinder_mm"];
    const double radius = cylinder.value("radius", 0.0);
    const json& centre = cylinder["center"];
    const json& z = cylinder["z"];
    for (int end = 0; end < 2 && radius > 0.0; ++end) {
      for (int k = 0; k < 48; ++k) {
        const auto point = [&](int i) {
          const double angle = 2.0 * std::numbers::pi * i / 48.0;
          return Eigen::Vector3d(centre[0].get<double>() + radius * std::cos(angle),
                                 centre[1].get<double>() + radius * std::sin(angle),
                                 z[static_cast<std::size_t>(end)].get<double>());
        };
        out.push_back({Part::tool, point(k), point(k + 1)});
      }
    }
  }
  return out;
}

json workspace_summary(const json& w) {
  const bool planar = w.value("planar", false);
  const json& size = planar ? w["area_mm2"] : w["volume_mm3"];
  const std::string unit = planar ? "mm^2" : "mm^3";
  json rows =
      json::array({row("inside", planar ? "area inside" : "volume inside", size["inside"], unit),
                   row("boundary", "boundary (undecided)", size["boundary"], unit),
                   row("resolution_mm", "resolution", w["resolution_mm"], "mm")});
  if (w.contains("largest_cylinder_mm")) {
    rows.push_back(row("cylinder_radius", "largest cylinder's radius",
                       w["largest_cylinder_mm"]["radius"], "mm"));
  }
  if (w.contains("limited_by")) {
    for (const auto& [status, cells] : w["limited_by"].items()) {
      rows.push_back(row("limited_by." + status, "cells limited by " + status, cells, ""));
    }
  }
  return rows;
}

}  // namespace

std::string workspace_page(const json& workspace, const machine::Machine* machine,
                           const std::string& title) {
  json data = {{"kind", "workspace"},
               {"title", title},
               {"machine", workspace.value("machine", std::string())},
               {"planar", workspace.value("planar", false)},
               {"report", workspace}};
  data["summary"] = workspace_summary(workspace);
  std::vector<Segment> fixed = outlines(workspace);
  json moments = json::array(), times = json::array();
  if (machine != nullptr) {
    const std::vector<Segment> parts = fixed_parts(*machine);
    fixed.insert(fixed.end(), parts.begin(), parts.end());
    data["joints"] = joints_json(*machine);
  }
  json drawing = {{"fixed", json::array()}, {"t", json::array()}, {"frames", json::array()}};
  if (machine != nullptr) {
    kinematics::JointVector joints;
    if (machine->inverse(machine->home(), joints).ok()) {
      drawing = drawing_json(*machine, {Moment{0.0, machine->home(), joints}});
    }
  }
  json flat = json::array();
  for (const Segment& segment : fixed) {
    flat.push_back(static_cast<int>(segment.part));
    for (const Eigen::Vector3d* point : {&segment.from, &segment.to}) {
      for (int k = 0; k < 3; ++k) flat.push_back(rounded((*point)[k]));
    }
  }
  drawing["fixed"] = flat;
  data["drawing"] = drawing;
  if (workspace.contains("cells")) {
    data["cells"] = {{"inside", cells_json(workspace["cells"], "inside")},
                     {"boundary", cells_json(workspace["cells"], "boundary")}};
  }
  data["maps"] = workspace.value("maps", json::array());
  return page_with(data, title);
}

void write_workspace_html(const std::filesystem::path& path, const json& workspace,
                          const machine::Machine* machine) {
  write_page(path, workspace_page(workspace, machine,
                                  "pkm workspace: " + workspace.value("machine", std::string())));
}

}  // namespace pkm::view
