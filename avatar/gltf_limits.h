#pragma once
// What the avatar loader accepts from a glTF file before it trusts it (internal to the loader;
// the limits are listed in docs/avatars.md). A file is untrusted input: its JSON is checked for
// size, depth and size of the document before tinygltf parses it (tinygltf converts extras and
// extensions recursively), its buffers and images may only come from data: URIs or files inside
// its own folder, and the mesh it describes is counted, every node that uses a mesh once more,
// before anything is baked.

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace deixis::avatar::gltf {

// Generous for real avatars: a VRoid or Ready Player Me avatar has 20k–150k vertices, a
// photogrammetry scan about a million, and a JSON part of a few hundred kilobytes.
inline constexpr std::size_t kMaxFileBytes = std::size_t{512} << 20;          // .glb or .gltf
inline constexpr std::uint64_t kMaxExternalBytes = std::uint64_t{512} << 20;  // buffers + images
inline constexpr std::size_t kMaxJsonBytes = std::size_t{32} << 20;
inline constexpr std::size_t kMaxJsonDepth = 64;
inline constexpr std::uint64_t kMaxJsonValues = 1'000'000;  // numbers, strings, arrays, objects
inline constexpr std::uint64_t kMaxVertices = 2'000'000;    // baked, instances included
inline constexpr std::uint64_t kMaxIndices = 12'000'000;    // as triangle lists, instances incl.
inline constexpr std::uint64_t kMaxMeshNodes = 10'000;      // nodes that place a mesh
inline constexpr std::size_t kMaxSkinJoints = 1024;         // entries in one skin's joint list
inline constexpr int kMaxInfluenceSets = 4;                 // JOINTS_n/WEIGHTS_n pairs

// The JSON text of a .glb (its first chunk, once the header's and the chunks' lengths are checked
// against the file) or of a .gltf (the whole file). Throws deixis::Error naming `source`.
std::string_view gltf_json(std::span<const std::uint8_t> bytes, bool binary,
                           const std::string& source);

// Checks the JSON before tinygltf sees it: its size, nesting depth and number of values, and
// every buffers[i].uri and images[i].uri: a data: URI, or a relative path that stays inside the
// file's folder (`has_folder`; without one, data: URIs only). Throws deixis::Error naming `source`
// and the offending URI.
// `kind` says what the file is in messages, e.g. "glTF binary (.glb)".
void check_gltf_json(std::string_view json, const std::string& source, bool has_folder,
                     const std::string& kind);

// Whether `uri` may be read, and why not: "" when it may.
std::string uri_problem(std::string_view uri, bool has_folder);

// File access for tinygltf confined to one folder (defence in depth behind check_gltf_json): only
// regular files whose path, normalised, lies inside the folder, at most kMaxExternalBytes in all.
class ConfinedFiles {
 public:
  explicit ConfinedFiles(std::filesystem::path folder) : folder_(std::move(folder)) {}
  tinygltf::FsCallbacks callbacks();

 private:
  static bool exists(const std::string& path, void* self);
  static std::string expand(const std::string& path, void* self);
  static bool read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* self);
  static bool write(std::string* err, const std::string& path,
                    const std::vector<unsigned char>& bytes, void* self);
  bool inside(const std::string& path) const;

  std::filesystem::path folder_;
  std::uint64_t read_bytes_ = 0;
};

// Counts what baking the mesh would produce, each node that places a mesh counting that mesh once
// more, and throws deixis::Error naming `source` and the cap before anything is allocated.
void check_mesh_budget(const tinygltf::Model& model, const std::vector<int>& nodes,
                       const std::string& source);

}  // namespace deixis::avatar::gltf
