// The workspace's JSON document (workspace_json.hpp).
#include "pkm/workspace/workspace_json.hpp"

#include <cmath>

namespace pkm::workspace {

namespace {

nlohmann::json vector3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json box_json(const std::optional<AxisBox>& box) {
  if (!box) return nullptr;
  return {{"min", vector3(box->min_mm)}, {"max", vector3(box->max_mm)}};
}

// [[i, j, k, level], ...]: the cell covers [i, i + 2^level) finest steps on each axis spanned.
nlohmann::json cells_json(const std::vector<CellIndex>& cells) {
  nlohmann::json list = nlohmann::json::array();
  for (const CellIndex& cell : cells)
    list.push_back({cell.at[0], cell.at[1], cell.at[2], cell.level});
  return list;
}

nlohmann::json map_json(const PlaneMap& map) {
  nlohmann::json values = nlohmann::json::array();
  for (const double v : map.values) {
    if (std::isfinite(v)) {
      values.push_back(v);
    } else {
      values.push_back(nullptr);
    }
  }
  return {{"name", map.name},       {"plane", "z"},
          {"at_mm", map.at_mm},     {"origin_mm", {map.origin_mm.x(), map.origin_mm.y()}},
          {"step_mm", map.step_mm}, {"dims", {map.dims[0], map.dims[1]}},
          {"values", values}};
}

}  // namespace

nlohmann::json to_json(const Workspace& ws) {
  nlohmann::json doc;
  doc["machine"] = ws.machine;
  doc["planar"] = ws.planar;
  doc["guaranteed"] = ws.guaranteed;
  doc["notes"] = ws.notes;
  doc["resolution_mm"] = ws.resolution_mm;
  nlohmann::json orientation;
  for (int k = 0; k < 3; ++k) {
    orientation[std::string(kAxisNames[3 + k])] = {radians_to_degrees(ws.orientation_min_rad[k]),
                                                   radians_to_degrees(ws.orientation_max_rad[k])};
  }
  doc["orientation_deg"] = orientation;
  doc[ws.planar ? "area_mm2" : "volume_mm3"] = {
      {"inside", ws.inside_measure}, {"boundary", ws.boundary_measure}, {"estimate", ws.estimate}};
  doc["extent_mm"] = box_json(ws.extent);
  doc["largest_box_mm"] = box_json(ws.largest_box);
  if (ws.largest_cylinder) {
    const Cylinder& c = *ws.largest_cylinder;
    doc["largest_cylinder_mm"] = {{"center", {c.centre_mm.x(), c.centre_mm.y()}},
                                  {"radius", c.radius_mm},
                                  {"z", {c.z0_mm, c.z1_mm}}};
  } else {
    doc["largest_cylinder_mm"] = nullptr;
  }
  doc["limited_by"] = ws.limited_by;
  doc["cells_judged"] = ws.cells_judged;
  doc["boxes_judged"] = ws.boxes_judged;
  doc["cells"] = {{"origin_mm", vector3(ws.origin_mm)},
                  {"step_mm", ws.resolution_mm},
                  {"dims", {ws.dims[0], ws.dims[1], ws.dims[2]}},
                  {"inside", cells_json(ws.inside)},
                  {"boundary", cells_json(ws.boundary)}};
  nlohmann::json maps = nlohmann::json::array();
  for (const PlaneMap& map : ws.maps) maps.push_back(map_json(map));
  doc["maps"] = maps;
  return doc;
}

}  // namespace pkm::workspace
