#pragma once
// Helpers for the avatar tests: editing .glb files through tinygltf (to hand-make broken and
// renamed avatars), rest and posed model transforms, and linear blend skinning as a renderer would
// do it.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "avatar/avatar_loader.h"
#include "avatar/default_avatar.h"
#include "core/error.h"

namespace deixis::avatar::testing {

inline std::vector<std::uint8_t> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::filesystem::path& file, const std::vector<std::uint8_t>& b) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

inline tinygltf::Model parse_glb(const std::vector<std::uint8_t>& bytes) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err;
  std::string warn;
  EXPECT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                          static_cast<unsigned int>(bytes.size())))
      << err;
  return model;
}

inline std::vector<std::uint8_t> to_glb(const tinygltf::Model& model) {
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  EXPECT_TRUE(writer.WriteGltfSceneToStream(&model, stream, false, true));
  const std::string s = std::move(stream).str();
  return {s.begin(), s.end()};
}

// The default avatar (1.70 m, 0.74 m) as an editable model.
inline tinygltf::Model default_model() {
  return parse_glb(generate_default_avatar({}));
}

inline int find_node(const tinygltf::Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    if (model.nodes[i].name == name) {
      return static_cast<int>(i);
    }
  }
  ADD_FAILURE() << "no node named " << name;
  return 0;
}

// A float stored in the binary buffer, addressed through a tightly packed accessor (as the
// generator writes them).
inline float* accessor_float(tinygltf::Model& model, int accessor, std::size_t element,
                             int component) {
  const tinygltf::Accessor& a = model.accessors[accessor];
  const tinygltf::BufferView& v = model.bufferViews[a.bufferView];
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  std::uint8_t* base = model.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset;
  return reinterpret_cast<float*>(base) + element * static_cast<std::size_t>(components) +
         static_cast<std::size_t>(component);
}

inline std::uint8_t* accessor_byte(tinygltf::Model& model, int accessor, std::size_t element,
                                   int component) {
  const tinygltf::Accessor& a = model.accessors[accessor];
  const tinygltf::BufferView& v = model.bufferViews[a.bufferView];
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  std::uint8_t* base = model.buffers[v.buffer].data.data() + v.byteOffset + a.byteOffset;
  return base + element * static_cast<std::size_t>(components) +
         static_cast<std::size_t>(component);
}

// The .glb with `from` replaced by `to` in its JSON chunk (lengths and padding fixed up), for
// corruptions tinygltf's writer cannot produce, such as numbers that overflow a double.
inline std::vector<std::uint8_t> replace_in_json(const std::vector<std::uint8_t>& glb,
                                                 const std::string& from, const std::string& to) {
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  const std::uint32_t json_length = u32(12);
  std::string json(glb.begin() + 20, glb.begin() + 20 + json_length);
  const std::size_t at = json.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  json.replace(at, from.size(), to);
  while (json.size() % 4 != 0) {
    json.push_back(' ');
  }
  std::vector<std::uint8_t> out(glb.begin(), glb.begin() + 12);
  const auto put = [&](std::uint32_t v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    out.insert(out.end(), p, p + 4);
  };
  put(static_cast<std::uint32_t>(json.size()));
  put(u32(16));
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), glb.begin() + 20 + json_length, glb.end());
  const auto total = static_cast<std::uint32_t>(out.size());
  std::memcpy(out.data() + 8, &total, 4);
  return out;
}

// The message of the deixis::Error that loading `bytes` throws, or "" when it loads.
inline std::string load_error(const std::vector<std::uint8_t>& bytes, const std::string& source) {
  try {
    load_avatar(bytes, source);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

inline std::vector<Pose> model_poses(const ik::Skeleton& skeleton, const std::vector<Pose>& local) {
  std::vector<Pose> model(local.size());
  ik::local_to_model(skeleton, local, model);
  return model;
}

inline std::vector<Pose> rest_model(const ik::HumanoidRig& rig) {
  return model_poses(rig.skeleton, rig.skeleton.rest_local);
}

// Linear blend skinning, as the renderer does it.
inline std::vector<Vec3> skin(const SkinnedMesh& mesh, const std::vector<Pose>& model) {
  std::vector<Vec3> out(mesh.vertex_count(), Vec3::Zero());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    for (int k = 0; k < kMaxInfluences; ++k) {
      const float w = mesh.weights[v][k];
      if (w > 0.0f) {
        const int j = mesh.joints[v][k];
        out[v] += w * transform_point(compose(model[j], mesh.inverse_bind[j]), mesh.positions[v]);
      }
    }
  }
  return out;
}

}  // namespace deixis::avatar::testing
