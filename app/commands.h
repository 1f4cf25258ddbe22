#pragma once
// The `deixis` subcommands. main.cpp parses flags (CLI11, one translation unit); each command's
// work lives in its own file and returns the process exit code.

#include <filesystem>
#include <vector>

namespace deixis::app {

struct ParityOptions {
  std::vector<std::filesystem::path> fixtures;
  std::filesystem::path reference_dir;
};
int run_parity(const ParityOptions& options);

}  // namespace deixis::app
