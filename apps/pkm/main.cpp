// pkm: the command-line layer. Parses arguments, wires modules, prints, and exits.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "app.hpp"

int main(int argc, char** argv) {
  CLI::App app{"pkmkit: drive parallel-kinematic machines from Cartesian G-code", "pkm"};
  app.set_version_flag("--version", "pkm (pkmkit) " PKM_VERSION);
  app.require_subcommand(1);
  pkm::app::register_kinematics_commands(app);
  pkm::app::register_gcode_commands(app);
  pkm::app::register_plan_commands(app);
  pkm::app::register_post_commands(app);
  pkm::app::register_verify_commands(app);
  pkm::app::register_calibrate_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const pkm::MachineFileError& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  } catch (const pkm::app::CommandError& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pkm: error: %s\n", error.what());
    return 1;
  }
  return 0;
}
