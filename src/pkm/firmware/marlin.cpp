#include "pkm/firmware/marlin.hpp"

namespace pkm::firmware {

// Placeholder until the target's writer and reader land (issue 30).
Target marlin_target() {
  return Target{"marlin",
                "Configuration.h",
                {FormKind::wall_plotter, FormKind::linear_delta},
                [](const FirmwareMachine&, const ExportContext&) -> ExportedFile {
                  throw std::logic_error("marlin export: not built yet");
                },
                [](std::string_view, const std::string&) -> machine::ImportedMachine {
                  throw std::logic_error("marlin import: not built yet");
                }};
}

}  // namespace pkm::firmware
