// The workspace as the JSON document `pkm workspace --json` writes and the HTML view reads
// (the schema is in docs/workspace.md, "JSON").
#pragma once

#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <ostream>

#include "pkm/workspace/workspace.hpp"

namespace pkm::workspace {

// The document, each cell list thinned to at most `max_cells_listed` cells (every k-th: a
// page draws a sample of them); by default every cell.
nlohmann::json to_json(const Workspace& ws,
                       std::size_t max_cells_listed = std::numeric_limits<std::size_t>::max());

// The whole document as to_json(ws).dump() writes it, its cell lists streamed rather than built:
// a 1 mm hexapod lists 7e7 cells, 1.5 GB of text but ~10 GB as a JSON tree.
void write_json(std::ostream& out, const Workspace& ws);

}  // namespace pkm::workspace
