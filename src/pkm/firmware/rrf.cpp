#include "pkm/firmware/rrf.hpp"

namespace pkm::firmware {

// Placeholder until the target's writer and reader land (issue 30).
Target rrf_target() {
  return Target{"rrf",
                "config.g",
                {FormKind::linear_delta, FormKind::rotary_delta},
                [](const FirmwareMachine&, const ExportContext&) -> ExportedFile {
                  throw std::logic_error("rrf export: not built yet");
                },
                [](std::string_view, const std::string&) -> machine::ImportedMachine {
                  throw std::logic_error("rrf import: not built yet");
                }};
}

}  // namespace pkm::firmware
