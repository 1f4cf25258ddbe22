#pragma once
// Shared by the tests: where the authors' reference data lives, and scratch directories.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

namespace deixis::testing {

// ../shared/reference (the authors' converted checkpoints and parity fixtures). CI always has it;
// DEIXIS_REFERENCE_DIR in the environment overrides the configured path.
inline std::filesystem::path reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return DEIXIS_REFERENCE_DIR;
}

inline std::filesystem::path source_dir() {
  return DEIXIS_SOURCE_DIR;
}

// A fresh directory under the system temp dir, removed when the object goes out of scope.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("deixis-test-" + std::to_string(rd()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace deixis::testing
