// Hostile glTF files: deep JSON nesting, GLB lengths that lie, URIs that leave the
// file's folder, and a mesh instanced into a blow-up are each a clear deixis::Error naming the file
// and what was wrong, checked before tinygltf parses or the bake allocates.

#include <gtest/gtest.h>

#include <sstream>

#include "avatar/avatar_loader.h"
#include "avatar/default_avatar.h"
#include "avatar_test_support.h"
#include "core/error.h"
#include "test_support.h"

namespace deixis::avatar {
namespace {

using testing::default_model;
using testing::load_error;
using testing::replace_in_json;
using testing::to_glb;

std::string nested(int depth) {
  return std::string(static_cast<std::size_t>(depth), '[') +
         std::string(static_cast<std::size_t>(depth), ']');
}

std::vector<std::uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

// The default avatar as .gltf text, its buffer in a data: URI.
std::string default_gltf_text() {
  tinygltf::Model model = default_model();
  std::ostringstream json;
  tinygltf::TinyGLTF writer;
  EXPECT_TRUE(writer.WriteGltfSceneToStream(&model, json, true, false));
  return json.str();
}

// The same text with its buffer's data: URI replaced by `uri`.
std::string with_buffer_uri(const std::string& uri) {
  std::string text = default_gltf_text();
  const std::size_t start = text.find("\"data:application/octet-stream;base64,");
  EXPECT_NE(start, std::string::npos);
  const std::size_t end = text.find('"', start + 1);
  return text.replace(start, end + 1 - start, "\"" + uri + "\"");
}

void expect_error(const std::string& message, const std::string& file,
                  const std::vector<std::string>& parts) {
  ASSERT_FALSE(message.empty()) << "loaded without error";
  EXPECT_EQ(message.rfind(file + ": ", 0), 0u) << message;
  for (const std::string& part : parts) {
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

std::string load_error_in(const std::string& text, const std::string& source,
                          const std::filesystem::path& folder) {
  try {
    load_avatar(bytes_of(text), source, folder);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(AvatarUntrusted, DeepJsonNestingIsRefusedBeforeParsing) {
  const std::vector<std::uint8_t> glb = generate_default_avatar({});
  // 100 levels inside the asset's extras: tinygltf would convert them recursively.
  const auto deep_glb = replace_in_json(glb, "{", "{\"extras\":" + nested(100) + ",");
  expect_error(load_error(deep_glb, "deep.glb"), "deep.glb",
               {"nested deeper than 64 levels", "at byte"});
  // The same in a .gltf, in a node's extensions; brackets inside strings do not count.
  std::string text = default_gltf_text();
  text.replace(text.find('{'), 1, "{\"extensions\":{\"X\":" + nested(70) + "},");
  expect_error(load_error(bytes_of(text), "deep.gltf"), "deep.gltf", {"nested deeper than 64"});
  std::string strings = default_gltf_text();
  strings.replace(strings.find('{'), 1, "{\"extras\":\"" + nested(500) + "\",");
  EXPECT_EQ(load_error(bytes_of(strings), "brackets-in-a-string.gltf"), "");
}

TEST(AvatarUntrusted, GlbLengthsAreCheckedAgainstTheFile) {
  std::vector<std::uint8_t> glb = generate_default_avatar({});
  const auto put = [&](std::size_t at, std::uint32_t v) { std::memcpy(glb.data() + at, &v, 4); };
  const std::vector<std::uint8_t> good = glb;
  put(8, static_cast<std::uint32_t>(good.size() + 4096));  // total length past the file
  expect_error(load_error(glb, "long.glb"), "long.glb",
               {"not a readable glTF binary", "the header says"});
  glb = good;
  put(12, 0xFFFFFFF0u);  // JSON chunk past the end
  expect_error(load_error(glb, "json.glb"), "json.glb", {"JSON chunk of 4294967280 bytes"});
  glb = good;
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  put(20 + json_length, 0xFFFFFF00u);  // BIN chunk past the end
  expect_error(load_error(glb, "bin.glb"), "bin.glb", {"BIN chunk of", "runs past the end"});
}

TEST(AvatarUntrusted, BufferUrisMustStayInsideTheFilesFolder) {
  deixis::testing::ScratchDir dir;
  const std::filesystem::path folder = dir.path() / "avatars";
  std::filesystem::create_directories(folder / "parts");
  // The real buffer, both outside the folder (where an escaping URI would find it) and inside.
  const tinygltf::Model model = default_model();
  testing::write_bytes(dir.path() / "secret.bin", model.buffers[0].data);
  testing::write_bytes(folder / "parts" / "body.bin", model.buffers[0].data);
  const std::string source = (folder / "a.gltf").string();

  EXPECT_EQ(load_error_in(with_buffer_uri("parts/body.bin"), source, folder), "");
  EXPECT_EQ(load_error_in(with_buffer_uri("parts/../parts/body.bin"), source, folder), "");
  expect_error(load_error_in(with_buffer_uri("../secret.bin"), source, folder), source,
               {"buffers[0].uri '../secret.bin' leaves the file's folder"});
  expect_error(load_error_in(with_buffer_uri("parts/../../secret.bin"), source, folder), source,
               {"'parts/../../secret.bin' leaves the file's folder"});
  expect_error(load_error_in(with_buffer_uri("%2e%2e/secret.bin"), source, folder), source,
               {"'%2e%2e/secret.bin' leaves the file's folder"});
  const std::string absolute = (dir.path() / "secret.bin").string();
  expect_error(load_error_in(with_buffer_uri(absolute), source, folder), source,
               {"buffers[0].uri '" + absolute + "' is an absolute path"});
  expect_error(load_error_in(with_buffer_uri("file://" + absolute), source, folder), source,
               {"has a scheme or drive other than data:"});
  // Bytes in memory have no folder: only data: URIs.
  expect_error(load_error_in(with_buffer_uri("parts/body.bin"), "memory.gltf", {}), "memory.gltf",
               {"'parts/body.bin' is an external file"});
}

TEST(AvatarUntrusted, ImageUrisFollowTheSameRule) {
  deixis::testing::ScratchDir dir;
  std::string text = default_gltf_text();
  text.replace(text.find('{'), 1, "{\"images\":[{\"uri\":\"../../etc/passwd\"}],");
  expect_error(load_error_in(text, "img.gltf", dir.path()), "img.gltf",
               {"images[0].uri '../../etc/passwd' leaves the file's folder"});
}

TEST(AvatarUntrusted, InstancedMeshCountsOncePerNode) {
  // One mesh placed by enough nodes to pass the vertex cap: refused before baking, whereas the
  // old loader baked every copy.
  tinygltf::Model model = default_model();
  int mesh_node = -1;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    if (model.nodes[i].mesh >= 0) {
      mesh_node = static_cast<int>(i);
    }
  }
  ASSERT_GE(mesh_node, 0);
  const tinygltf::Node copy = model.nodes[static_cast<std::size_t>(mesh_node)];
  const auto& primitive = model.meshes[static_cast<std::size_t>(copy.mesh)].primitives[0];
  const std::size_t vertices = model.accessors[primitive.attributes.at("POSITION")].count;
  const std::size_t copies = 2'000'000 / vertices + 2;
  for (std::size_t k = 0; k < copies; ++k) {
    model.scenes[0].nodes.push_back(static_cast<int>(model.nodes.size()));
    model.nodes.push_back(copy);
  }
  expect_error(load_error(to_glb(model), "instanced.glb"), "instanced.glb",
               {"more than 2000000 vertices", "every node that uses a mesh"});
}

TEST(AvatarUntrusted, TooManyValuesAndLongSkinsAreRefused) {
  std::string text = default_gltf_text();
  std::string many = "[";
  for (int i = 0; i < 1'000'001; ++i) {
    many += "0,";
  }
  many.back() = ']';
  text.replace(text.find('{'), 1, "{\"extras\":" + many + ",");
  expect_error(load_error(bytes_of(text), "values.gltf"), "values.gltf",
               {"more than 1000000 values"});

  tinygltf::Model model = default_model();
  const std::vector<int> joints = model.skins[0].joints;
  while (model.skins[0].joints.size() <= 1024) {
    model.skins[0].joints.insert(model.skins[0].joints.end(), joints.begin(), joints.end());
  }
  expect_error(load_error(to_glb(model), "skin.glb"), "skin.glb", {"skins[0] has", "(1 to 1024)"});
}

}  // namespace
}  // namespace deixis::avatar
