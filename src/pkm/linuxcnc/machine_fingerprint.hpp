// The fingerprint an exported LinuxCNC configuration keeps of its machine file: the SHA-256 of the
// file's bytes (what `sha256sum FILE` prints), written by `pkm export linuxcnc` to the INI as
// [KINS] PKM_MACHINE_SHA256 (LinuxCNC ignores a key it does not know). The INI's joint and axis
// limits are derived from the machine file, so pkmkins refuses to load a file that changed after
// the export instead of failing later, after homing, with a message about the work envelope.
#pragma once

#include <string>
#include <string_view>

#include "pkm/linuxcnc/ini_file.hpp"

namespace pkm::linuxcnc {

inline constexpr std::string_view kMachineFingerprintKey = "PKM_MACHINE_SHA256";

// 64 lowercase hexadecimal digits.
std::string sha256_hex(std::string_view bytes);

// "" when the INI records no fingerprint (a configuration written by hand, by `pkm linuxcnc
// migrate` or by an older pkm) or records `machine_sha256` (sha256_hex of the file's bytes as
// read now); else "INI:LINE: " and a sentence naming the machine file, both digests and the fix
// (export again).
std::string machine_file_changed(const std::string& machine_file, const std::string& machine_sha256,
                                 const IniFile& ini);

}  // namespace pkm::linuxcnc
