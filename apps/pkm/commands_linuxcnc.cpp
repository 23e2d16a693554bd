// pkm export linuxcnc: a LinuxCNC configuration running the pkmkins kinematics module; pkm
// linuxcnc migrate: a configuration of LinuxCNC's own kinematics switched to pkmkins.
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "app.hpp"
#include "pkm/linuxcnc/config_export.hpp"
#include "pkm/linuxcnc/config_migrate.hpp"
#include "pkm/text/text_file.hpp"

namespace pkm::app {

namespace {

struct ExportLinuxcncOptions {
  std::string machine;
  std::string directory;
  bool sim = false;
  bool force = false;
};

std::string read_text(const std::string& path) {
  try {
    return text::read_text_file(path, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw CommandError(path + ": " + error.what());
  }
}

// What --force kept of the configuration it replaced, said so that nothing kept surprises.
void print_kept(const linuxcnc::KeptFiles& kept) {
  const auto joined = [](const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  };
  if (!kept.state.empty()) {
    std::printf(
        "kept from the configuration replaced (LinuxCNC's tool table and parameters, your "
        "wiring; delete them to have the export's): %s\n",
        joined(kept.state).c_str());
  }
  if (!kept.others.empty()) {
    std::printf("carried over from the configuration replaced (not written by pkm): %s\n",
                joined(kept.others).c_str());
  }
}

void export_linuxcnc(const ExportLinuxcncOptions& options) {
  const machine::Machine machine = machine::load_machine(options.machine);
  linuxcnc::ExportOptions export_options;
  export_options.sim = options.sim;
  export_options.machine_file_name = std::filesystem::path(options.machine).filename().string();
  export_options.machine_text = read_text(options.machine);
  linuxcnc::LinuxcncConfig config;
  try {
    config = linuxcnc::make_linuxcnc_config(machine, export_options);
  } catch (const std::runtime_error& error) {
    throw CommandError(options.machine + ": " + error.what());
  }
  linuxcnc::KeptFiles kept;
  try {
    kept = linuxcnc::write_config_directory(options.directory, config, options.force);
  } catch (const std::runtime_error& error) {
    throw CommandError(error.what());
  }
  std::printf("%s: %s (%s), %zu files\n", options.directory.c_str(), config.ini_name.c_str(),
              options.sim ? "simulated joints" : "wire hardware.hal", config.files.size());
  std::printf(
      "joint-rate bound over the work envelope: %s, %ld cells, %.3f s%s\n",
      config.bound.proven ? "proven" : "SAMPLED, not proven (no Hessian bound for this model)",
      config.bound.cells, config.bound_seconds,
      config.bound.uncovered > 0.0 ? " (part of the box at the edge of reach unbounded)" : "");
  if (config.shrink < 1.0) {
    std::printf(
        "axis limits: the work envelope shrunk about home to %.1f %% (beyond, a joint "
        "moves more than %.0f times as fast per unit of tool motion as at home)\n",
        100.0 * config.shrink, bounds::kMaxSlopeGrowth);
  }
  for (const std::string& line : config.cost) std::printf("  %s\n", line.c_str());
  print_kept(kept);
}

struct MigrateOptionsCli {
  std::string config;
  std::string machine;
  std::string directory;
  std::string hallib = linuxcnc::kDefaultHallib.string();
  bool force = false;
};

void migrate_linuxcnc(const MigrateOptionsCli& options) {
  std::error_code same_error;
  const std::filesystem::path source = std::filesystem::absolute(options.config).parent_path();
  if (std::filesystem::equivalent(options.directory, source, same_error)) {
    throw CommandError(options.directory +
                       " is the configuration's own directory: give a new one (the "
                       "configuration is copied, never edited in place)");
  }
  const machine::Machine machine = machine::load_machine(options.machine);
  linuxcnc::MigrateOptions migrate_options;
  migrate_options.hallib = options.hallib;
  migrate_options.machine_file_name = std::filesystem::path(options.machine).filename().string();
  migrate_options.machine_text = read_text(options.machine);
  migrate_options.machine_joints = static_cast<int>(machine.joints().size());
  migrate_options.machine_units = machine.units() == machine::LengthUnit::inch ? "inch" : "mm";
  linuxcnc::Migration migration;
  linuxcnc::KeptFiles kept;
  try {
    migration = linuxcnc::migrate_linuxcnc_config(options.config, migrate_options);
    kept = linuxcnc::write_config_directory(options.directory, migration.files, options.force);
  } catch (const std::runtime_error& error) {
    throw CommandError(error.what());
  }
  std::printf("%s: %s switched from %s to pkmkins (%s), %zu files; the edits:\n",
              options.directory.c_str(), migration.ini_name.c_str(), migration.module.c_str(),
              migrate_options.machine_file_name.c_str(), migration.files.size());
  for (const std::string& edit : migration.edits) std::printf("  %s\n", edit.c_str());
  print_kept(kept);
  for (const std::string& warning : migration.warnings)
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
}

void register_migrate_command(CLI::App& app) {
  CLI::App* group = app.add_subcommand("linuxcnc", "Work on LinuxCNC configurations");
  group->require_subcommand(1);
  auto options = std::make_shared<MigrateOptionsCli>();
  CLI::App* command = group->add_subcommand(
      "migrate",
      "Copy a genhexkins, lineardeltakins, rotarydeltakins or matrixkins configuration to a new "
      "directory running pkmkins with a machine file, keeping its HAL wiring, panels and remaps");
  command->add_option("config", options->config, "The configuration's INI file")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-m,--machine", options->machine, "Machine file (copied beside the INI)")
      ->required();
  command->add_option("-o,--output", options->directory, "The configuration directory to write")
      ->required();
  command
      ->add_option("--hallib", options->hallib,
                   "LinuxCNC's HAL library, where HALFILE = LIB:name is found")
      ->capture_default_str();
  command->add_flag(
      "--force", options->force,
      "Replace the configuration in a directory that is not empty (in one step; files it does "
      "not write are kept)");
  command->callback([options] { migrate_linuxcnc(*options); });
}

}  // namespace

void register_linuxcnc_commands(CLI::App& app) {
  register_migrate_command(app);
  CLI::App* export_command = app.get_subcommand("export");
  auto options = std::make_shared<ExportLinuxcncOptions>();
  CLI::App* command = export_command->add_subcommand(
      "linuxcnc", "A LinuxCNC configuration directory running the pkmkins kinematics module");
  command->add_option("-m,--machine", options->machine, "Machine file")->required();
  command->add_option("-o,--output", options->directory, "The configuration directory to write")
      ->required();
  command->add_flag("--sim", options->sim,
                    "Loop each joint's command to its feedback: runs with no hardware");
  command->add_flag(
      "--force", options->force,
      "Replace the configuration in a directory that is not empty (in one step; files it does "
      "not write are kept)");
  command->callback([options] { export_linuxcnc(*options); });
}

}  // namespace pkm::app
