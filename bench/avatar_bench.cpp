// What a receiving site does with a person's chosen avatar file, off its 30 Hz tick
// (docs/avatars.md, "A person's own avatar"; site/avatar_cache.h, load_person_avatar): hash the
// bytes, load them as an untrusted glTF (limits, skeleton, skinned mesh) and build the IK solver
// for the rig. From bytes in memory, one thread: the default avatar (141 KB, 33 joints) and the
// BCN test rig (assimp's BCN_Epileptic.X converted to GLB here, 393 KB, 54 joints). A load that
// takes longer than a tick (33 ms) would stall a site that loaded on its tick's thread.

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "site/avatar_cache.h"

namespace {

namespace fs = std::filesystem;
using namespace deixis;

std::vector<std::byte> read_bytes(const fs::path& file) {
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  std::vector<std::byte> bytes(ec ? 0 : static_cast<std::size_t>(size));
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

// The BCN test rig as GLB (as tests/avatar/bcn_rig.h makes it); empty when assimp is missing.
std::vector<std::byte> bcn_glb() {
  const fs::path out = fs::temp_directory_path() / "deixis-avatar-bench-bcn.glb";
  const std::string command = "assimp export /usr/share/assimp/models/X/BCN_Epileptic.X " +
                              out.string() + " -fglb2 > /dev/null 2>&1";
  if (std::system(command.c_str()) != 0) {
    return {};
  }
  std::vector<std::byte> bytes = read_bytes(out);
  fs::remove(out);
  return bytes;
}

void load(benchmark::State& state, const std::vector<std::byte>& file) {
  if (file.empty()) {
    state.SkipWithError("no file (assimp-utils and assimp-testmodels: tools/install-deps)");
    return;
  }
  int joints = 0;
  for (auto _ : state) {
    const auto avatar = site::load_person_avatar(file, "bench", site::AvatarSource::kChosen);
    joints = avatar->solver.joint_count();
    benchmark::DoNotOptimize(joints);
  }
  state.counters["joints"] = joints;
  state.counters["bytes"] = static_cast<double>(file.size());
}

void BM_LoadPersonAvatar_Default(benchmark::State& state) {
  static const std::vector<std::byte> file =
      read_bytes(fs::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb");
  load(state, file);
}
BENCHMARK(BM_LoadPersonAvatar_Default)->Unit(benchmark::kMillisecond);

void BM_LoadPersonAvatar_Bcn(benchmark::State& state) {
  static const std::vector<std::byte> file = bcn_glb();
  load(state, file);
}
BENCHMARK(BM_LoadPersonAvatar_Bcn)->Unit(benchmark::kMillisecond);

}  // namespace
