#pragma once
// A third-party rig for tests: BCN_Epileptic.X from Debian's assimp-testmodels
// (docs/avatars.md#bone-names), converted once per test program with `assimp export … -fglb2` into
// a scratch directory that lives until exit.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_support.h"

namespace deixis::testing {

inline constexpr const char* kBcnSource = "/usr/share/assimp/models/X/BCN_Epileptic.X";

inline const std::filesystem::path& bcn_glb() {
  static ScratchDir dir;
  static const std::filesystem::path glb = [] {
    const std::filesystem::path out = dir.path() / "bcn.glb";
    if (!std::filesystem::exists(kBcnSource)) {
      ADD_FAILURE() << kBcnSource << " is missing: install assimp-testmodels (tools/install-deps)";
      return out;
    }
    const std::string command = std::string("assimp export ") + kBcnSource + " " + out.string() +
                                " -fglb2 > " + (dir.path() / "assimp.log").string() + " 2>&1";
    if (std::system(command.c_str()) != 0) {
      ADD_FAILURE() << "`" << command
                    << "` failed: is assimp-utils installed (tools/install-deps)?";
    }
    return out;
  }();
  return glb;
}

}  // namespace deixis::testing
