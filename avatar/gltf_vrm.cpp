#include "avatar/gltf_vrm.h"

#include <array>
#include <cstdio>

#include "avatar/bone_names.h"
#include "core/error.h"

namespace deixis::avatar::gltf {

namespace {

const tinygltf::Value* member(const tinygltf::Value& object, const std::string& key) {
  if (!object.IsObject() || !object.Has(key)) {
    return nullptr;
  }
  return &object.Get(key);
}

int node_index(const tinygltf::Value* value, const tinygltf::Model& model,
               const std::string& where) {
  if (value == nullptr || !value->IsNumber()) {
    throw Error(where + ".node: missing or not a number");
  }
  const double v = value->GetNumberAsDouble();
  if (!(v >= 0.0 && v < static_cast<double>(model.nodes.size())) || v != static_cast<int>(v)) {
    std::array<char, 32> number{};
    std::snprintf(number.data(), number.size(), "%g", v);
    throw Error(where + ".node: " + number.data() + " is not a node index (the file has " +
                std::to_string(model.nodes.size()) + " nodes)");
  }
  return static_cast<int>(v);
}

void add_bone(VrmHumanoid& humanoid, const std::string& name, int node) {
  if (const std::optional<ik::Bone> bone = bone_for_name(NamingScheme::kDeixis, name)) {
    humanoid.bones.emplace_back(*bone, node);
  }
}

}  // namespace

std::optional<VrmHumanoid> read_vrm_humanoid(const tinygltf::Model& model,
                                             const std::string& source) {
  if (const auto it = model.extensions.find("VRMC_vrm"); it != model.extensions.end()) {
    VrmHumanoid humanoid{"VRM 1.0 (VRMC_vrm)", {}};
    const std::string where = source + ": extensions.VRMC_vrm.humanoid.humanBones";
    const tinygltf::Value* humanoid_value = member(it->second, "humanoid");
    const tinygltf::Value* bones = humanoid_value ? member(*humanoid_value, "humanBones") : nullptr;
    if (bones == nullptr || !bones->IsObject()) {
      throw Error(where + ": missing or not an object");
    }
    for (const std::string& name : bones->Keys()) {
      add_bone(humanoid, name,
               node_index(member(bones->Get(name), "node"), model, where + "." + name));
    }
    return humanoid;
  }
  if (const auto it = model.extensions.find("VRM"); it != model.extensions.end()) {
    VrmHumanoid humanoid{"VRM 0.x (VRM)", {}};
    const std::string where = source + ": extensions.VRM.humanoid.humanBones";
    const tinygltf::Value* humanoid_value = member(it->second, "humanoid");
    const tinygltf::Value* bones = humanoid_value ? member(*humanoid_value, "humanBones") : nullptr;
    if (bones == nullptr || !bones->IsArray()) {
      throw Error(where + ": missing or not an array");
    }
    for (std::size_t i = 0; i < bones->ArrayLen(); ++i) {
      const tinygltf::Value& entry = bones->Get(static_cast<int>(i));
      const std::string at = where + "[" + std::to_string(i) + "]";
      const tinygltf::Value* name = member(entry, "bone");
      if (name == nullptr || !name->IsString()) {
        throw Error(at + ".bone: missing or not a string");
      }
      add_bone(humanoid, name->Get<std::string>(), node_index(member(entry, "node"), model, at));
    }
    return humanoid;
  }
  return std::nullopt;
}

}  // namespace deixis::avatar::gltf
