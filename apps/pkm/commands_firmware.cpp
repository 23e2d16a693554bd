// pkm export fluidnc|klipper|rrf|marlin (and grblhal --kinematics), pkm import of the same: a
// machine to and from the configuration of a firmware with its own kinematics
// (docs/firmware.md). Each target is a pkm::firmware::Target; this file only turns options into
// calls and results into text.
#include <cstdio>
#include <memory>
#include <string>

#include "app.hpp"
#include "pkm/files/atomic_file.hpp"
#include "pkm/firmware/target.hpp"
#include "pkm/text/text_file.hpp"
#include "version.hpp"

namespace pkm::app {
namespace {

struct ImportOptions {
  std::string file;
  std::string output;
};

std::string cost_summary(const std::optional<firmware::ApproximationCost>& cost) {
  if (!cost) return "exact";
  char text[200];
  const Eigen::Vector3d& at = cost->worst_at.position_mm;
  std::snprintf(text, sizeof text,
                "approximated: worst tool error %.4f mm at x %.1f y %.1f z %.1f mm, rms %.4f mm",
                cost->worst_tool_error_mm, at.x(), at.y(), at.z(), cost->rms_tool_error_mm);
  return text;
}

void run_import(const firmware::Target& target, const ImportOptions& options) {
  refuse_overwriting_input(options.output, {{"the " + target.file_kind, options.file}});
  std::string text;
  try {
    text = text::read_text_file(options.file, text::kMaxConfigFileBytes);
  } catch (const text::FileReadError& error) {
    throw CommandError(options.file + ": " + error.what());
  }
  machine::ImportedMachine imported;
  std::string machine_text;
  try {
    imported = target.read(text, options.file);
    machine_text = machine::machine_file_text(
        imported, options.output.empty() ? std::string("(standard output)") : options.output);
  } catch (const firmware::FirmwareFileError& error) {
    throw CommandError(error.what());
  } catch (const machine::ImportedMachineError& error) {
    throw CommandError(options.file + ": " + error.what());
  }
  for (const std::string& warning : imported.warnings)
    std::fprintf(stderr, "%s: warning: %s\n", options.file.c_str(), warning.c_str());
  if (options.output.empty()) {
    std::fputs(machine_text.c_str(), stdout);
    return;
  }
  files::write_file_atomically(options.output, machine_text);
  std::printf("%s: machine file of %s (from %s's %s)\n", options.output.c_str(),
              imported.name.c_str(), target.name.c_str(), target.file_kind.c_str());
}

void register_import(CLI::App& import_command, const firmware::Target& target) {
  auto options = std::make_shared<ImportOptions>();
  CLI::App* command = import_command.add_subcommand(
      target.name, "A machine file from " + target.name + "'s " + target.file_kind);
  command->add_option("file", options->file, "The firmware's " + target.file_kind)
      ->required()
      ->check(CLI::ExistingFile);
  command
      ->add_option("-o,--output", options->output,
                   "Machine file to write (default: standard output)")
      ->check(file_name());
  command->callback([options, &target] { run_import(target, *options); });
}

}  // namespace

void run_firmware_export(const std::string& target_name, const FirmwareExportOptions& options) {
  const firmware::Target& target = firmware::target(target_name);
  refuse_overwriting_input(options.output, {{"the machine file", options.machine}});
  const machine::Machine machine = load_machine_or_default(options.machine);
  firmware::ExportedFile file;
  std::optional<firmware::FirmwareMachine> held;
  try {
    held = firmware::firmware_machine(machine, target.forms, target.name, options.approximate);
    const firmware::ExportContext context{
        kVersion, options.machine.empty() ? std::string("the embedded machine") : options.machine,
        options.approximate};
    file = target.write(*held, context);
  } catch (const firmware::ExportRefused& error) {
    throw CommandError(error.what());
  }
  for (const std::string& warning : file.warnings)
    std::fprintf(stderr, "%s: warning: %s\n", machine.source().c_str(), warning.c_str());
  const std::optional<firmware::ApproximationCost>& cost = file.cost ? file.cost : held->cost;
  if (cost) std::fprintf(stderr, "%s: %s\n", machine.source().c_str(), cost_summary(cost).c_str());
  if (options.output.empty()) {
    std::fputs(file.text.c_str(), stdout);
    return;
  }
  files::write_file_atomically(options.output, file.text);
  std::printf("%s: %s %s for %s (%s, %s)\n", options.output.c_str(), target.name.c_str(),
              target.file_kind.c_str(), machine.name().c_str(),
              kinematics::form_name(held->form.geometry), cost_summary(cost).c_str());
}

void add_firmware_export_options(CLI::App& command, FirmwareExportOptions& options) {
  command.add_option("-o,--output", options.output, "The file to write (default: standard output)")
      ->check(file_name());
  command.add_flag("--approximate", options.approximate,
                   "Where the firmware's kinematics cannot hold the machine exactly, write the "
                   "nearest machine they can hold (fitted over the workspace) and state the worst "
                   "tool error that costs");
}

void register_firmware_commands(CLI::App& app) {
  CLI::App* export_command = app.get_subcommand("export");
  CLI::App* import_command = app.get_subcommand("import");
  for (const firmware::Target& target : firmware::targets()) {
    register_import(*import_command, target);
    if (target.name == "grblhal") continue;  // `pkm export grblhal --kinematics` (commands_post)
    auto options = std::make_shared<FirmwareExportOptions>();
    CLI::App* command = export_command->add_subcommand(
        target.name, "The " + target.name + " " + target.file_kind +
                         " of a machine its own kinematics can drive (docs/firmware-" +
                         target.name + ".md)");
    command->add_option("-m,--machine", options->machine, "Machine file")->required();
    add_firmware_export_options(*command, *options);
    command->callback([options, &target] { run_firmware_export(target.name, *options); });
  }
}

}  // namespace pkm::app
