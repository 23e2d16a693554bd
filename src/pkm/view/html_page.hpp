// Self-contained HTML views (docs/html-views.md): one file per plan, post, verify or workspace,
// with the page's script and style (web/, inlined at build time) and the view's data (JSON) inside
// it, so it opens offline in any browser and makes no network request. The summary numbers are
// the JSON report's own, embedded verbatim beside the data drawn from them.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "pkm/view/recorders.hpp"

namespace pkm::view {

// The page of `pkm plan` / `pkm demo`: `report` is the JSON report (pkm plan --report) of the
// run `recorder` saw; `title` names the job.
std::string plan_page(const nlohmann::json& report, const PlanRecorder& recorder,
                      const std::string& title);

// The page of `pkm post` (kind "post") or `pkm verify` (kind "verify"): the joint program's blocks
// as verify reconstructs them, coloured by their deviation against `tolerance_mm`, over the job's
// outline (job_outline; empty: none drawn).
std::string blocks_page(const std::string& kind, const nlohmann::json& report,
                        const BlockRecorder& recorder, double tolerance_mm,
                        const std::vector<PathPoint>& outline, const std::string& title);

// The page of `pkm view`: `report` is view_report_json of the trace `recorder` saw.
std::string view_page(const nlohmann::json& report, const TraceRecorder& recorder,
                      const std::string& title);

// Workspace cells the page draws at most, per kind: past it, every k-th (the page says how many
// it stands for). A document thinned to this many beforehand draws the same.
inline constexpr std::size_t kWorkspaceCellsDrawn = 40000;

// The page of `pkm workspace`: `workspace` follows the workspace JSON schema
// (docs/html-views.md, "Workspace"); its machine is drawn at home when `machine` is given.
std::string workspace_page(const nlohmann::json& workspace, const machine::Machine* machine,
                           const std::string& title);
// Writes it through the atomic file helper. Throws std::runtime_error (path and reason).
void write_workspace_html(const std::filesystem::path& path, const nlohmann::json& workspace,
                          const machine::Machine* machine = nullptr);

// Any page, written whole or not at all (files/atomic_file.hpp).
void write_page(const std::filesystem::path& path, const std::string& html);

}  // namespace pkm::view
