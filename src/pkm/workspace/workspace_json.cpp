// The workspace's JSON document (workspace_json.hpp).
#include "pkm/workspace/workspace_json.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pkm::workspace {

namespace {

nlohmann::json vector3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::json box_json(const std::optional<Eigen::AlignedBox3d>& box) {
  if (!box) return nullptr;
  return {{"min", vector3(box->min())}, {"max", vector3(box->max())}};
}

// [[i, j, k, level], ...]: the cell covers [i, i + 2^level) finest steps on each axis spanned.
nlohmann::json cells_json(const std::vector<CellIndex>& cells, std::size_t max_listed) {
  nlohmann::json list = nlohmann::json::array();
  if (max_listed == 0) return list;
  // Every k-th, k the smallest that lists at most max_listed.
  const std::size_t every = std::max<std::size_t>(1, (cells.size() + max_listed - 1) / max_listed);
  for (std::size_t n = 0; n < cells.size(); n += every) {
    const CellIndex& cell = cells[n];
    list.push_back({cell.at[0], cell.at[1], cell.at[2], cell.level});
  }
  return list;
}

// The same list as cells_json(cells, all).dump() gives, written a cell at a time.
void stream_cells(std::ostream& out, const std::vector<CellIndex>& cells) {
  char text[80];
  out << '[';
  for (std::size_t n = 0; n < cells.size(); ++n) {
    char* end = text;
    if (n > 0) *end++ = ',';
    *end++ = '[';
    const std::array<std::int32_t, 4> values{cells[n].at[0], cells[n].at[1], cells[n].at[2],
                                             cells[n].level};
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (k > 0) *end++ = ',';
      end = std::to_chars(end, text + sizeof text, values[k]).ptr;
    }
    *end++ = ']';
    out.write(text, end - text);
  }
  out << ']';
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

nlohmann::json to_json(const Workspace& ws, std::size_t max_cells_listed) {
  nlohmann::json doc;
  doc["machine"] = ws.machine;
  doc["planar"] = ws.planar;
  doc["guaranteed"] = ws.guaranteed;
  doc["notes"] = ws.notes;
  doc["resolution_mm"] = ws.resolution_mm;
  nlohmann::json orientation;
  for (int k = 0; k < 3; ++k) {
    orientation[std::string(geometry::kAxisNames[3 + k])] = {
        geometry::radians_to_degrees(ws.orientation_min_rad[k]),
        geometry::radians_to_degrees(ws.orientation_max_rad[k])};
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
                  {"inside", cells_json(ws.inside, max_cells_listed)},
                  {"boundary", cells_json(ws.boundary, max_cells_listed)}};
  nlohmann::json maps = nlohmann::json::array();
  for (const PlaneMap& map : ws.maps) maps.push_back(map_json(map));
  doc["maps"] = maps;
  return doc;
}

// The document without cells, dumped, with the cell lists written in place of two empty ones
// (keys sort as nlohmann's objects do: "boundary" comes before "inside").
void write_json(std::ostream& out, const Workspace& ws) {
  const std::string text = to_json(ws, 0).dump();
  const std::string boundary_key = "\"boundary\":[]", inside_key = "\"inside\":[]";
  const std::size_t cells_at = text.find("\"cells\":{");
  const std::size_t boundary_at = text.find(boundary_key, cells_at);
  const std::size_t inside_at = text.find(inside_key, boundary_at);
  if (cells_at == std::string::npos || boundary_at == std::string::npos ||
      inside_at == std::string::npos) {
    throw std::logic_error("workspace JSON: the cell lists were not where they are written");
  }
  const std::size_t boundary_list = boundary_at + boundary_key.size() - 2;
  const std::size_t inside_list = inside_at + inside_key.size() - 2;
  out.write(text.data(), static_cast<std::streamsize>(boundary_list));
  stream_cells(out, ws.boundary);
  out.write(text.data() + boundary_list + 2,
            static_cast<std::streamsize>(inside_list - boundary_list - 2));
  stream_cells(out, ws.inside);
  out.write(text.data() + inside_list + 2,
            static_cast<std::streamsize>(text.size() - inside_list - 2));
}

}  // namespace pkm::workspace
