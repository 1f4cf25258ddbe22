#pragma once
// Bounds-checked reads of glTF accessors (internal to the avatar loader). tinygltf parses the JSON
// but trusts indices, offsets and counts; every read here checks them against the buffers first and
// throws deixis::Error naming the file and what was being read.

#include <tiny_gltf.h>

#include <cstdint>
#include <string>
#include <vector>

namespace deixis::avatar::gltf {

// What is being read, for error messages: "avatars/a.glb: meshes[0].primitives[1] POSITION".
struct ReadContext {
  const tinygltf::Model& model;
  std::string what;
};

// Accessor `index` as floats, `components` per element, of glTF type `type` (TINYGLTF_TYPE_*).
// Float data as stored; integer data converted (normalised when the accessor says so). Every
// value must be finite.
std::vector<float> read_floats(const ReadContext& context, int index, int type, int components);

// Accessor `index` as unsigned integers (unsigned byte, short or int components).
std::vector<std::uint32_t> read_uints(const ReadContext& context, int index, int type,
                                      int components);

}  // namespace deixis::avatar::gltf
