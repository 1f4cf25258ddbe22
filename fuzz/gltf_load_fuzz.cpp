// libFuzzer target for the avatar loader (avatar/avatar_loader.h), which reads whole .glb and
// .gltf files from anywhere: every input must either load into an avatar whose mesh and rig hold
// together or be refused with a deixis::Error naming the file; anything else (another exception,
// a sanitizer report, a broken invariant, running out of memory or time) is a crash.
//
// The bytes are loaded from memory without a folder, so only data: URIs can supply buffers: the
// fuzzer never reads the disk. Seeds (fuzz/corpus/gltf_load/): a trimmed default avatar as .glb
// and as .gltf; ok-tiny-skinned.glb, the default avatar's whole rig with its mesh cut to its first
// 12 triangles (7.6 kB: long runs start from the small seeds, docs/security.md); and hostile files
// (deep nesting, lying chunk lengths, ../ and absolute URIs, an instanced-mesh blow-up).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

#include "avatar/avatar_loader.h"
#include "core/error.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "gltf_load_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string source = "fuzz-input.glb";
  try {
    const deixis::avatar::Avatar avatar =
        deixis::avatar::load_avatar(std::span<const std::uint8_t>(data, size), source);
    const auto& mesh = avatar.mesh;
    check(!mesh.indices.empty(), "a loaded avatar has triangles");
    for (const std::uint32_t i : mesh.indices) {
      check(i < mesh.positions.size(), "indices address vertices");
    }
    check(mesh.inverse_bind.size() == avatar.rig.skeleton.parents.size(),
          "one inverse bind per joint");
  } catch (const deixis::Error& e) {
    check(std::string(e.what()).rfind(source + ": ", 0) == 0, "errors name the file");
  }
  return 0;
}
