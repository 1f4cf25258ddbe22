#pragma once
// Writing a whole file so that a crash (or a full disk) never leaves a half-written file under
// its final name: the bytes go to a temporary file beside it, which is then renamed over it
// (rename(2) replaces atomically within one file system). Used for weights (core/io/safetensors.h)
// and target maps saved from the headset (docs/xr.md "Setting up the room").

#include <cstddef>
#include <filesystem>
#include <span>

namespace deixis {

// Throws deixis::Error naming the file when it cannot be written or moved into place.
void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes);

}  // namespace deixis
