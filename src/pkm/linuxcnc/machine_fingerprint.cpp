#include "pkm/linuxcnc/machine_fingerprint.hpp"

#include <openssl/evp.h>

#include <stdexcept>

namespace pkm::linuxcnc {

std::string sha256_hex(std::string_view bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("cannot compute a SHA-256 digest (OpenSSL's EVP_Digest failed)");
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex += kHex[digest[i] >> 4];
    hex += kHex[digest[i] & 0xf];
  }
  return hex;
}

std::string machine_file_changed(const std::string& machine_file, const std::string& machine_sha256,
                                 const IniFile& ini) {
  const IniEntry* recorded = ini.find("KINS", kMachineFingerprintKey);
  if (recorded == nullptr || recorded->value == machine_sha256) return {};
  const std::string& now = machine_sha256;
  const std::string directory = ini.directory().empty() ? "." : ini.directory().string();
  // The command that wrote it, as far as the INI tells: --sim loads sim.hal.
  std::string sim;
  for (const IniEntry* hal_file : ini.find_all("HAL", "HALFILE")) {
    if (hal_file->value == "sim.hal") sim = " --sim";
  }
  return recorded->where.file + ":" + std::to_string(recorded->where.line) + ": machine file " +
         machine_file +
         " changed since `pkm export linuxcnc` wrote this configuration (its SHA-256 is now " +
         now + "; [KINS] " + std::string(kMachineFingerprintKey) + " = " + recorded->value +
         " is the file the INI's joint and axis limits were made from): export again, `pkm "
         "export linuxcnc -m " +
         machine_file + " -o " + directory + sim + " --force`, or put the exported file back";
}

}  // namespace pkm::linuxcnc
