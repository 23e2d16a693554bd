// The workspace as the JSON document `pkm workspace --json` writes and the HTML view reads
// (the schema is in docs/workspace.md, "JSON").
#pragma once

#include <nlohmann/json.hpp>

#include "pkm/workspace/workspace.hpp"

namespace pkm::workspace {

nlohmann::json to_json(const Workspace& ws);

}  // namespace pkm::workspace
