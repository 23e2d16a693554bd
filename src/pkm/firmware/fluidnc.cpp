#include "pkm/firmware/fluidnc.hpp"

namespace pkm::firmware {

// Placeholder until the target's writer and reader land (issue 30).
Target fluidnc_target() {
  return Target{"fluidnc",
                "config.yaml",
                {FormKind::wall_plotter, FormKind::rotary_delta},
                [](const FirmwareMachine&, const ExportContext&) -> ExportedFile {
                  throw std::logic_error("fluidnc export: not built yet");
                },
                [](std::string_view, const std::string&) -> machine::ImportedMachine {
                  throw std::logic_error("fluidnc import: not built yet");
                }};
}

}  // namespace pkm::firmware
