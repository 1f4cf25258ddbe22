#include "avatar/glb_writer.h"

#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace deixis::avatar {

namespace {

constexpr int kArrayBuffer = 34962;         // GL_ARRAY_BUFFER
constexpr int kElementArrayBuffer = 34963;  // GL_ELEMENT_ARRAY_BUFFER

// The one binary buffer of the .glb, cut into buffer views aligned to 4 bytes.
class BinaryChunk {
 public:
  explicit BinaryChunk(tinygltf::Model& model) : model_(model) {}

  template <typename T>
  int add_view(const std::vector<T>& values, int target) {
    while (bytes_.size() % 4 != 0) {
      bytes_.push_back(0);
    }
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes_.size();
    view.byteLength = values.size() * sizeof(T);
    view.target = target;
    const auto* begin = reinterpret_cast<const std::uint8_t*>(values.data());
    bytes_.insert(bytes_.end(), begin, begin + view.byteLength);
    model_.bufferViews.push_back(std::move(view));
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  void finish() {
    while (bytes_.size() % 4 != 0) {
      bytes_.push_back(0);
    }
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes_);
    model_.buffers.push_back(std::move(buffer));
  }

 private:
  tinygltf::Model& model_;
  std::vector<std::uint8_t> bytes_;
};

int add_accessor(tinygltf::Model& model, int view, std::size_t byte_offset, int component_type,
                 int type, std::size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.byteOffset = byte_offset;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(std::move(accessor));
  return static_cast<int>(model.accessors.size()) - 1;
}

std::vector<float> flatten(const std::vector<Vec3>& vectors) {
  std::vector<float> flat;
  flat.reserve(vectors.size() * 3);
  for (const Vec3& v : vectors) {
    flat.insert(flat.end(), {v.x(), v.y(), v.z()});
  }
  return flat;
}

// Column-major 4 × 4, as glTF stores matrices.
void append_matrix(const Pose& T, std::vector<float>& out) {
  for (int c = 0; c < 3; ++c) {
    out.insert(out.end(), {T.rotation(0, c), T.rotation(1, c), T.rotation(2, c), 0.0f});
  }
  out.insert(out.end(), {T.translation.x(), T.translation.y(), T.translation.z(), 1.0f});
}

void set_node_transform(const Pose& T, tinygltf::Node& node) {
  if (!T.translation.isZero(0.0f)) {
    node.translation = {T.translation.x(), T.translation.y(), T.translation.z()};
  }
  if (!T.rotation.isIdentity(0.0f)) {
    const Quat q = Quat(T.rotation).normalized();
    node.rotation = {q.x(), q.y(), q.z(), q.w()};
  }
}

int add_vertex_attributes(const SkinnedMesh& mesh, int joint_count, BinaryChunk& chunk,
                          tinygltf::Model& model, std::map<std::string, int>& attributes) {
  const std::size_t n = mesh.vertex_count();
  const int positions = add_accessor(model, chunk.add_view(flatten(mesh.positions), kArrayBuffer),
                                     0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  // glTF requires the bounds of POSITION.
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max());
  Vec3 hi = -lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  model.accessors[positions].minValues = {lo.x(), lo.y(), lo.z()};
  model.accessors[positions].maxValues = {hi.x(), hi.y(), hi.z()};
  attributes["POSITION"] = positions;
  attributes["NORMAL"] = add_accessor(model, chunk.add_view(flatten(mesh.normals), kArrayBuffer), 0,
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  if (joint_count <= 256) {
    std::vector<std::uint8_t> joints;
    for (const auto& j : mesh.joints) {
      for (const std::uint16_t k : j) {
        joints.push_back(static_cast<std::uint8_t>(k));
      }
    }
    attributes["JOINTS_0"] =
        add_accessor(model, chunk.add_view(joints, kArrayBuffer), 0,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, n);
  } else {
    attributes["JOINTS_0"] =
        add_accessor(model, chunk.add_view(mesh.joints, kArrayBuffer), 0,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, n);
  }
  attributes["WEIGHTS_0"] = add_accessor(model, chunk.add_view(mesh.weights, kArrayBuffer), 0,
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, n);
  return positions;
}

void add_mesh(const AvatarAsset& asset, BinaryChunk& chunk, tinygltf::Model& model) {
  const SkinnedMesh& mesh = asset.mesh;
  std::map<std::string, int> attributes;
  add_vertex_attributes(mesh, asset.skeleton.joint_count(), chunk, model, attributes);

  // Index 65535 is the primitive-restart value for 16-bit indices, so it may not be used.
  const bool short_indices = mesh.vertex_count() < 65535;
  int index_view = 0;
  if (short_indices) {
    std::vector<std::uint16_t> indices(mesh.indices.begin(), mesh.indices.end());
    index_view = chunk.add_view(indices, kElementArrayBuffer);
  } else {
    index_view = chunk.add_view(mesh.indices, kElementArrayBuffer);
  }
  const std::size_t index_size = short_indices ? 2 : 4;

  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = "body";
  for (const SkinnedPrimitive& p : mesh.primitives) {
    tinygltf::Material material;
    material.name = p.name;
    material.pbrMetallicRoughness.baseColorFactor = {p.base_color[0], p.base_color[1],
                                                     p.base_color[2], p.base_color[3]};
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 0.8;
    model.materials.push_back(std::move(material));

    tinygltf::Primitive primitive;
    primitive.attributes = attributes;
    primitive.indices = add_accessor(model, index_view, p.first_index * index_size,
                                     short_indices ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                   : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                     TINYGLTF_TYPE_SCALAR, p.index_count);
    primitive.material = static_cast<int>(model.materials.size()) - 1;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    gltf_mesh.primitives.push_back(std::move(primitive));
  }
  model.meshes.push_back(std::move(gltf_mesh));
}

// Nodes: 0 is the skinned mesh (glTF wants skinned mesh nodes at the root, untransformed),
// 1..n the joints in skeleton order, then the end sites.
void add_nodes(const AvatarAsset& asset, BinaryChunk& chunk, tinygltf::Model& model) {
  const ik::Skeleton& skeleton = asset.skeleton;
  const int n = skeleton.joint_count();
  tinygltf::Node mesh_node;
  mesh_node.name = "avatar";
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  model.nodes.push_back(std::move(mesh_node));

  tinygltf::Scene scene;
  scene.name = "avatar";
  scene.nodes.push_back(0);
  for (int j = 0; j < n; ++j) {
    tinygltf::Node node;
    node.name = skeleton.joint_names[j];
    set_node_transform(skeleton.rest_local[j], node);
    model.nodes.push_back(std::move(node));
    const int parent = skeleton.parents[j];
    if (parent == ik::kNoParent) {
      scene.nodes.push_back(1 + j);
    } else {
      model.nodes[1 + parent].children.push_back(1 + j);
    }
  }
  for (const EndSite& site : asset.end_sites) {
    tinygltf::Node node;
    node.name = site.name;
    node.translation = {site.offset.x(), site.offset.y(), site.offset.z()};
    model.nodes.push_back(std::move(node));
    model.nodes[1 + site.joint].children.push_back(static_cast<int>(model.nodes.size()) - 1);
  }
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;

  std::vector<float> inverse_binds;
  for (const Pose& T : asset.mesh.inverse_bind) {
    append_matrix(T, inverse_binds);
  }
  tinygltf::Skin skin;
  skin.name = "skeleton";
  skin.skeleton = 1;
  for (int j = 0; j < n; ++j) {
    skin.joints.push_back(1 + j);
  }
  skin.inverseBindMatrices =
      add_accessor(model, chunk.add_view(inverse_binds, 0), 0, TINYGLTF_COMPONENT_TYPE_FLOAT,
                   TINYGLTF_TYPE_MAT4, static_cast<std::size_t>(n));
  model.skins.push_back(std::move(skin));
}

void add_asset_info(const AvatarAsset& asset, tinygltf::Model& model) {
  model.asset.version = "2.0";
  model.asset.generator = asset.generator;
  if (!asset.metadata.empty()) {
    tinygltf::Value::Object values;
    for (const auto& [key, value] : asset.metadata) {
      values[key] = tinygltf::Value(value);
    }
    tinygltf::Value::Object extras;
    extras["deixis"] = tinygltf::Value(std::move(values));
    model.asset.extras = tinygltf::Value(std::move(extras));
  }
}

}  // namespace

std::vector<std::uint8_t> write_glb(const AvatarAsset& asset) {
  ik::validate(asset.skeleton, "avatar asset");
  if (asset.mesh.inverse_bind.size() != asset.skeleton.parents.size()) {
    throw Error("avatar asset: " + std::to_string(asset.mesh.inverse_bind.size()) +
                " inverse bind matrices for " + std::to_string(asset.skeleton.joint_count()) +
                " joints");
  }
  tinygltf::Model model;
  BinaryChunk chunk(model);
  add_asset_info(asset, model);
  add_mesh(asset, chunk, model);
  add_nodes(asset, chunk, model);
  chunk.finish();

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/false, /*writeBinary=*/true)) {
    throw Error("avatar asset: tinygltf could not serialise the model");
  }
  const std::string bytes = std::move(stream).str();
  return {bytes.begin(), bytes.end()};
}

void save_file(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) {
    throw Error(file.string() + ": cannot open for writing");
  }
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) {
    throw Error(file.string() + ": write failed");
  }
}

}  // namespace deixis::avatar
