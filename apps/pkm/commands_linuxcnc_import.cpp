// pkm import linuxcnc: a machine file from a LinuxCNC configuration.
#include <cstdio>
#include <memory>
#include <string>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/linuxcnc/config_import.hpp"

namespace pkm::app {

namespace {

struct ImportOptionsCli {
  std::string config;
  std::string output;
  std::string hallib = linuxcnc::kDefaultHallib.string();
};

void run_import_linuxcnc(const ImportOptionsCli& options) {
  refuse_overwriting_input(options.output, {{"the LinuxCNC configuration", options.config}});
  linuxcnc::ImportOptions import_options;
  import_options.hallib = options.hallib;
  const linuxcnc::ImportedConfig config =
      linuxcnc::read_linuxcnc_config(options.config, import_options);
  for (const std::string& warning : config.warnings)
    std::fprintf(stderr, "%s: warning: %s\n", options.config.c_str(), warning.c_str());
  const std::string text = linuxcnc::machine_file_text(
      config, options.output.empty() ? std::string("(standard output)") : options.output);
  if (options.output.empty()) {
    std::fputs(text.c_str(), stdout);
  } else {
    files::write_file_atomically(options.output, text);
  }
}

}  // namespace

void register_linuxcnc_import_commands(CLI::App& app) {
  CLI::App* import = app.add_subcommand("import", "Make a machine file from another tool's");
  import->require_subcommand(1);
  auto options = std::make_shared<ImportOptionsCli>();
  CLI::App* linuxcnc = import->add_subcommand(
      "linuxcnc",
      "A machine file from a LinuxCNC configuration (genhexkins, lineardeltakins, "
      "rotarydeltakins, matrixkins, trivkins)");
  linuxcnc->add_option("config", options->config, "The configuration's INI file")
      ->required()
      ->check(CLI::ExistingFile);
  linuxcnc->add_option("-o,--output", options->output,
                       "Machine file to write (default: standard output)");
  linuxcnc
      ->add_option("--hallib", options->hallib,
                   "LinuxCNC's HAL library, where HALFILE = LIB:name is found")
      ->capture_default_str();
  linuxcnc->callback([options] { run_import_linuxcnc(*options); });
}

}  // namespace pkm::app
