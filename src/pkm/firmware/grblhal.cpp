#include "pkm/firmware/grblhal.hpp"

namespace pkm::firmware {

// Placeholder until the target's writer and reader land (issue 30).
Target grblhal_target() {
  return Target{"grblhal",
                "$ settings",
                {FormKind::wall_plotter, FormKind::rotary_delta},
                [](const FirmwareMachine&, const ExportContext&) -> ExportedFile {
                  throw std::logic_error("grblhal export: not built yet");
                },
                [](std::string_view, const std::string&) -> machine::ImportedMachine {
                  throw std::logic_error("grblhal import: not built yet");
                }};
}

}  // namespace pkm::firmware
