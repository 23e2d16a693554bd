#include "pkm/firmware/klipper.hpp"

namespace pkm::firmware {

// Placeholder until the target's writer and reader land (issue 30).
Target klipper_target() {
  return Target{"klipper",
                "printer.cfg",
                {FormKind::linear_delta, FormKind::rotary_delta},
                [](const FirmwareMachine&, const ExportContext&) -> ExportedFile {
                  throw std::logic_error("klipper export: not built yet");
                },
                [](std::string_view, const std::string&) -> machine::ImportedMachine {
                  throw std::logic_error("klipper import: not built yet");
                }};
}

}  // namespace pkm::firmware
