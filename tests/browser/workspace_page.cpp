// Writes the workspace page of a workspace JSON file (the schema of docs/html-views.md), the
// machine drawn from its machine file when one is given: for the browser tests, before
// `pkm workspace --html` exists. usage: pkm_workspace_page WORKSPACE.json OUT.html [MACHINE.toml]
#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>

#include "pkm/view/html_page.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: pkm_workspace_page WORKSPACE.json OUT.html [MACHINE.toml]\n");
    return 2;
  }
  try {
    std::ifstream in(argv[1]);
    const nlohmann::json workspace = nlohmann::json::parse(in);
    std::optional<pkm::machine::Machine> machine;
    if (argc > 3) machine = pkm::machine::load_machine(argv[3]);
    pkm::view::write_workspace_html(argv[2], workspace, machine ? &*machine : nullptr);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pkm_workspace_page: %s\n", error.what());
    return 1;
  }
  return 0;
}
