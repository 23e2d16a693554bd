// Output files appear whole or not at all: written to a temporary name beside the target, then
// renamed over it.
#pragma once

#include <filesystem>
#include <string_view>

namespace pkm {

// Throws std::runtime_error naming the path and the system's reason; leaves no temporary behind.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace pkm
