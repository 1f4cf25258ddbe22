// Loading glTF avatars: the skeleton comes out depth-first whatever the file's node order, bone
// names are mapped (Deixis/VRM, Mixamo, VRM extensions), −Z-facing files are turned, and every
// hand-made broken file is an error naming the file and the problem, never a crash.

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>
#include <sstream>

#include "avatar/avatar_loader.h"
#include "avatar/bone_names.h"
#include "avatar/default_avatar.h"
#include "avatar_test_support.h"
#include "core/error.h"
#include "test_support.h"

namespace deixis::avatar {
namespace {

using ik::Bone;
using testing::default_model;
using testing::find_node;
using testing::load_error;
using testing::to_glb;

constexpr const char* kFile = "avatars/broken.glb";

void expect_same_rig(const Avatar& a, const Avatar& b, float tolerance) {
  ASSERT_EQ(a.rig.skeleton.joint_names, b.rig.skeleton.joint_names);
  ASSERT_EQ(a.rig.skeleton.parents, b.rig.skeleton.parents);
  EXPECT_EQ(a.rig.joint, b.rig.joint);
  const auto ma = testing::rest_model(a.rig);
  const auto mb = testing::rest_model(b.rig);
  for (std::size_t j = 0; j < ma.size(); ++j) {
    EXPECT_LT((ma[j].translation - mb[j].translation).norm(), tolerance)
        << a.rig.skeleton.joint_names[j];
    EXPECT_LT((ma[j].rotation - mb[j].rotation).norm(), tolerance) << a.rig.skeleton.joint_names[j];
  }
  EXPECT_NEAR(a.rig.height, b.rig.height, tolerance);
  EXPECT_NEAR(a.rig.arm_length, b.rig.arm_length, tolerance);
  ASSERT_EQ(a.mesh.vertex_count(), b.mesh.vertex_count());
  for (std::size_t v = 0; v < a.mesh.vertex_count(); ++v) {
    ASSERT_LT((a.mesh.positions[v] - b.mesh.positions[v]).norm(), tolerance);
  }
}

// Moves node i to position perm[i], fixing every reference to nodes.
void permute_nodes(tinygltf::Model& model, const std::vector<int>& perm) {
  std::vector<tinygltf::Node> nodes(model.nodes.size());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    tinygltf::Node n = model.nodes[i];
    for (int& c : n.children) {
      c = perm[c];
    }
    nodes[perm[i]] = std::move(n);
  }
  model.nodes = std::move(nodes);
  for (tinygltf::Scene& s : model.scenes) {
    for (int& n : s.nodes) {
      n = perm[n];
    }
  }
  for (tinygltf::Skin& s : model.skins) {
    for (int& j : s.joints) {
      j = perm[j];
    }
    if (s.skeleton >= 0) {
      s.skeleton = perm[s.skeleton];
    }
  }
}

TEST(AvatarLoader, SkeletonIsDepthFirstWhateverTheNodeOrder) {
  const Avatar original = load_avatar(generate_default_avatar({}), "default.glb");
  tinygltf::Model model = default_model();
  // Reverse the nodes (children now come before parents) and shuffle the skin's joint list.
  std::vector<int> perm(model.nodes.size());
  for (std::size_t i = 0; i < perm.size(); ++i) {
    perm[i] = static_cast<int>(perm.size() - 1 - i);
  }
  permute_nodes(model, perm);
  const std::vector<int> joints_before = model.skins[0].joints;
  std::mt19937 rng(7);
  std::vector<int> order(joints_before.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = static_cast<int>(i);
  }
  std::shuffle(order.begin(), order.end(), rng);
  // Skin joint k moves to slot order[k]; remap JOINTS_0 and the inverse binds accordingly.
  tinygltf::Skin& skin = model.skins[0];
  std::vector<float> ibm_before;
  for (std::size_t k = 0; k < joints_before.size(); ++k) {
    for (int e = 0; e < 16; ++e) {
      ibm_before.push_back(*testing::accessor_float(model, skin.inverseBindMatrices, k, e));
    }
  }
  for (std::size_t k = 0; k < joints_before.size(); ++k) {
    skin.joints[order[k]] = joints_before[k];
    for (int e = 0; e < 16; ++e) {
      *testing::accessor_float(model, skin.inverseBindMatrices, order[k], e) =
          ibm_before[k * 16 + e];
    }
  }
  const int joints_accessor = model.meshes[0].primitives[0].attributes.at("JOINTS_0");
  for (std::size_t v = 0; v < model.accessors[joints_accessor].count; ++v) {
    for (int c = 0; c < 4; ++c) {
      std::uint8_t* j = testing::accessor_byte(model, joints_accessor, v, c);
      *j = static_cast<std::uint8_t>(order[*j]);
    }
  }
  const Avatar reordered = load_avatar(to_glb(model), "reordered.glb");
  expect_same_rig(original, reordered, 1e-5f);
  for (int j = 0; j < reordered.rig.skeleton.joint_count(); ++j) {
    EXPECT_LT(reordered.rig.skeleton.parents[j], j);
  }
}

TEST(AvatarLoader, MixamoNamesWithAndWithoutNamespace) {
  const Avatar original = load_avatar(generate_default_avatar({}), "default.glb");
  for (const std::string prefix : {"mixamorig:", "mixamorig1_", ""}) {
    tinygltf::Model model = default_model();
    for (int b = 0; b < ik::kBoneCount; ++b) {
      const Bone bone = static_cast<Bone>(b);
      model.nodes[find_node(model, std::string(ik::bone_name(bone)))].name =
          prefix + std::string(expected_name(NamingScheme::kMixamo, bone));
    }
    const Avatar a = load_avatar(to_glb(model), "mixamo.glb");
    EXPECT_EQ(a.bone_source, "joint names (Mixamo)") << prefix;
    EXPECT_EQ(a.rig.joint, original.rig.joint) << prefix;
    EXPECT_EQ(a.rig.skeleton.joint_names[a.rig[Bone::kLeftLowerArm]], prefix + "LeftForeArm");
    EXPECT_NEAR(a.rig.arm_length, original.rig.arm_length, 1e-5f);
  }
}

TEST(AvatarLoader, VrmHumanoidExtensionsNameTheBones) {
  const Avatar original = load_avatar(generate_default_avatar({}), "default.glb");
  for (const bool vrm1 : {true, false}) {
    tinygltf::Model model = default_model();
    tinygltf::Value::Object bones1;
    tinygltf::Value::Array bones0;
    for (int b = 0; b < ik::kBoneCount; ++b) {
      const std::string name(ik::bone_name(static_cast<Bone>(b)));
      const int node = find_node(model, name);
      model.nodes[node].name = "J_Bip_" + std::to_string(b);  // names now say nothing
      tinygltf::Value::Object entry;
      entry["node"] = tinygltf::Value(node);
      if (vrm1) {
        bones1[name] = tinygltf::Value(entry);
      } else {
        entry["bone"] = tinygltf::Value(name);
        bones0.push_back(tinygltf::Value(entry));
      }
    }
    tinygltf::Value::Object humanoid;
    humanoid["humanBones"] = vrm1 ? tinygltf::Value(bones1) : tinygltf::Value(bones0);
    tinygltf::Value::Object extension;
    extension["humanoid"] = tinygltf::Value(humanoid);
    model.extensions[vrm1 ? "VRMC_vrm" : "VRM"] = tinygltf::Value(extension);
    const Avatar a = load_avatar(to_glb(model), "vrm.glb");
    EXPECT_EQ(a.bone_source, vrm1 ? "VRM 1.0 (VRMC_vrm)" : "VRM 0.x (VRM)");
    EXPECT_EQ(a.rig.joint, original.rig.joint);
  }
}

TEST(AvatarLoader, MinusZFacingFileIsTurnedToFaceMinusZ) {
  // VRM 0.x and some exporters face −Z in glTF: turn the whole file 180° about +Y (the skeleton
  // root; the skinned mesh follows its joints) and it must load exactly as before.
  const Avatar original = load_avatar(generate_default_avatar({}), "default.glb");
  tinygltf::Model model = default_model();
  tinygltf::Node& hips = model.nodes[find_node(model, "hips")];
  hips.rotation = {0.0, 1.0, 0.0, 0.0};
  hips.translation = {-hips.translation[0], hips.translation[1], -hips.translation[2]};
  const Avatar turned = load_avatar(to_glb(model), "turned.glb");
  EXPECT_NEAR(turned.facing_turn, 0.0f, 1e-6f);
  const auto ma = testing::rest_model(original.rig);
  const auto mt = testing::rest_model(turned.rig);
  for (std::size_t j = 0; j < ma.size(); ++j) {
    EXPECT_LT((ma[j].translation - mt[j].translation).norm(), 1e-5f);
  }
  for (std::size_t v = 0; v < original.mesh.vertex_count(); ++v) {
    ASSERT_LT((original.mesh.positions[v] - turned.mesh.positions[v]).norm(), 1e-5f);
  }
}

TEST(AvatarLoader, NodeScaleIsBakedIntoRigidJoints) {
  // An exporter's centimetre rig under a 0.01 root scale loads in metres with rigid joints.
  const Avatar original = load_avatar(generate_default_avatar({}), "default.glb");
  tinygltf::Model model = default_model();
  for (tinygltf::Node& n : model.nodes) {
    for (double& t : n.translation) {
      t *= 100.0;
    }
  }
  const int ibm = model.skins[0].inverseBindMatrices;
  const int positions = model.meshes[0].primitives[0].attributes.at("POSITION");
  for (std::size_t k = 0; k < model.accessors[ibm].count; ++k) {
    for (int e = 12; e < 15; ++e) {
      *testing::accessor_float(model, ibm, k, e) *= 100.0f;
    }
  }
  for (std::size_t v = 0; v < model.accessors[positions].count; ++v) {
    for (int c = 0; c < 3; ++c) {
      *testing::accessor_float(model, positions, v, c) *= 100.0f;
    }
  }
  model.accessors[positions].minValues.clear();
  model.accessors[positions].maxValues.clear();
  // An "Armature" parent with the scale, as Blender and FBX converters write it.
  tinygltf::Node armature;
  armature.name = "Armature";
  armature.scale = {0.01, 0.01, 0.01};
  const int hips = find_node(model, "hips");
  armature.children = {hips};
  model.nodes.push_back(armature);
  auto& roots = model.scenes[0].nodes;
  std::replace(roots.begin(), roots.end(), hips, static_cast<int>(model.nodes.size()) - 1);
  const Avatar scaled = load_avatar(to_glb(model), "centimetres.glb");
  EXPECT_NEAR(scaled.rig.height, original.rig.height, 1e-4f);
  EXPECT_NEAR(scaled.rig.arm_length, original.rig.arm_length, 1e-4f);
  for (const Pose& T : scaled.rig.skeleton.rest_local) {
    EXPECT_LT((T.rotation * T.rotation.transpose() - Mat3::Identity()).norm(), 1e-5f);
  }
}

// ---- broken files: each is an error naming the file and what is wrong ----

struct Broken {
  std::string name;
  std::function<std::vector<std::uint8_t>()> make;
  std::vector<std::string> expected;  // substrings of the message
};

std::vector<std::uint8_t> edited(const std::function<void(tinygltf::Model&)>& edit) {
  tinygltf::Model model = default_model();
  edit(model);
  return to_glb(model);
}

int accessor_of(const tinygltf::Model& m, const std::string& attribute) {
  return m.meshes[0].primitives[0].attributes.at(attribute);
}

std::vector<Broken> broken_files() {
  const std::vector<std::uint8_t> good = generate_default_avatar({});
  std::vector<Broken> cases;
  cases.push_back({"empty", [] { return std::vector<std::uint8_t>{}; }, {"empty"}});
  cases.push_back({"truncated",
                   [good] { return std::vector<std::uint8_t>(good.begin(), good.begin() + 5000); },
                   {"not a readable glTF binary"}});
  cases.push_back({"header only",
                   [good] { return std::vector<std::uint8_t>(good.begin(), good.begin() + 12); },
                   {"not a readable glTF"}});
  cases.push_back({"not glTF at all",
                   [] {
                     const std::string text = "solid cube\nfacet normal 0 0 1\n";
                     return std::vector<std::uint8_t>(text.begin(), text.end());
                   },
                   {"not a readable glTF"}});
  cases.push_back({"corrupt JSON chunk",
                   [good] {
                     auto b = good;
                     std::fill(b.begin() + 20, b.begin() + 60, std::uint8_t{'#'});
                     return b;
                   },
                   {"not a readable glTF binary"}});
  cases.push_back({"no skin",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.skins.clear();
                       m.nodes[0].skin = -1;
                     });
                   },
                   {"has no skin"}});
  cases.push_back({"skin but no skinned mesh",
                   [] { return edited([](tinygltf::Model& m) { m.nodes[0].skin = -1; }); },
                   {"no skinned mesh"}});
  cases.push_back({"missing left hand",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "leftHand")].name = "leftPaw";
                     });
                   },
                   {"missing required bone 'leftHand'", "(a joint named 'leftHand')"}});
  cases.push_back({"missing two bones",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "spine")].name = "torso";
                       m.nodes[find_node(m, "rightLowerArm")].name = "rightForearm";
                     });
                   },
                   {"missing required bones 'spine'", "'rightLowerArm'"}});
  cases.push_back({"lower arm on the wrong side",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "leftLowerArm")].name = "tmp";
                       m.nodes[find_node(m, "rightLowerArm")].name = "leftLowerArm";
                       m.nodes[find_node(m, "tmp")].name = "rightLowerArm";
                     });
                   },
                   {"bone 'leftLowerArm'", "is not below bone 'leftUpperArm'"}});
  cases.push_back({"two heads",
                   [] {
                     return edited(
                         [](tinygltf::Model& m) { m.nodes[find_node(m, "neck")].name = "head"; });
                   },
                   {"joints 3 'head' and 4 'head' both name bone 'head'"}});
  cases.push_back({"translation overflows float",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "leftLowerArm")].translation = {1e39, 0.0, 0.0};
                     });
                   },
                   {"'leftLowerArm'", "non-finite transform"}});
  cases.push_back({"translation beyond double in the JSON",
                   [good] {
                     return testing::replace_in_json(good, R"("name":"spine","translation":[0.0,)",
                                                     R"("name":"spine","translation":[1e999,)");
                   },
                   {"not a readable glTF binary", "number overflow"}});
  cases.push_back({"transform overflows when composed",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "hips")].scale = {1e30, 1e30, 1e30};
                       m.nodes[find_node(m, "spine")].scale = {1e30, 1e30, 1e30};
                     });
                   },
                   {"non-finite transform"}});
  cases.push_back({"zero rotation quaternion",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "chest")].rotation = {0.0, 0.0, 0.0, 0.0};
                     });
                   },
                   {"'chest'", "zero length"}});
  cases.push_back({"mirrored root",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "hips")].scale = {-1.0, 1.0, 1.0};
                     });
                   },
                   {"'hips'", "mirrored or degenerate"}});
  cases.push_back({"NaN inverse bind matrix",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       *testing::accessor_float(m, m.skins[0].inverseBindMatrices, 4, 13) =
                           std::nanf("");
                     });
                   },
                   {"inverseBindMatrices", "element 4 is not a finite number"}});
  cases.push_back({"infinite vertex",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       *testing::accessor_float(m, accessor_of(m, "POSITION"), 10, 1) =
                           std::numeric_limits<float>::infinity();
                     });
                   },
                   {"POSITION", "element 10 is not a finite number"}});
  cases.push_back({"weights summing to zero",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       for (int c = 0; c < 4; ++c) {
                         *testing::accessor_float(m, accessor_of(m, "WEIGHTS_0"), 17, c) = 0.0f;
                       }
                     });
                   },
                   {"meshes[0].primitives[0]", "vertex 17: skin weights sum to zero"}});
  cases.push_back({"negative weight",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       *testing::accessor_float(m, accessor_of(m, "WEIGHTS_0"), 3, 1) = -0.5f;
                     });
                   },
                   {"vertex 3: negative skin weight"}});
  cases.push_back({"joint outside the skin",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       *testing::accessor_byte(m, accessor_of(m, "JOINTS_0"), 5, 0) = 200;
                     });
                   },
                   {"vertex 5: joint 200 is not in its skin"}});
  cases.push_back({"index past the vertices",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       const int a = m.meshes[0].primitives[0].indices;
                       auto* index = reinterpret_cast<std::uint16_t*>(
                           m.buffers[0].data.data() +
                           m.bufferViews[m.accessors[a].bufferView].byteOffset);
                       index[7] = 60000;
                     });
                   },
                   {"index 7 is 60000, past the"}});
  cases.push_back({"accessor longer than its view",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.accessors[accessor_of(m, "NORMAL")].count += 10;
                     });
                   },
                   {"NORMAL", "buffer view has"}});
  cases.push_back(
      {"buffer view past the buffer",
       [] {
         return edited([](tinygltf::Model& m) {
           m.bufferViews[m.accessors[accessor_of(m, "POSITION")].bufferView].byteOffset += 1u << 30;
         });
       },
       {"runs past the end of its buffer"}});
  cases.push_back({"positions stored as integers",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.accessors[accessor_of(m, "POSITION")].componentType =
                           TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
                     });
                   },
                   {"POSITION", "cannot hold these values"}});
  cases.push_back({"node with two parents",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "neck")].children.push_back(find_node(m, "leftHand"));
                     });
                   },
                   {"'leftHand' has more than one parent"}});
  cases.push_back({"cycle",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       const int hips = find_node(m, "hips");
                       m.nodes[find_node(m, "head")].children.push_back(hips);
                       auto& roots = m.scenes[0].nodes;
                       roots.erase(std::find(roots.begin(), roots.end(), hips));
                     });
                   },
                   {"lies on a cycle"}});
  cases.push_back({"child that does not exist",
                   [] {
                     return edited([](tinygltf::Model& m) {
                       m.nodes[find_node(m, "head")].children.push_back(999);
                     });
                   },
                   {"'head': child 999 does not exist"}});
  cases.push_back({"skin joint that does not exist",
                   [] { return edited([](tinygltf::Model& m) { m.skins[0].joints[3] = -4; }); },
                   {"skins[0]: joint node -4 does not exist"}});
  cases.push_back(
      {"VRM bone on a node that does not exist",
       [] {
         return edited([](tinygltf::Model& m) {
           tinygltf::Value::Object node;
           node["node"] = tinygltf::Value(4000);
           tinygltf::Value::Object bones;
           bones["hips"] = tinygltf::Value(node);
           tinygltf::Value::Object humanoid;
           humanoid["humanBones"] = tinygltf::Value(bones);
           tinygltf::Value::Object vrm;
           vrm["humanoid"] = tinygltf::Value(humanoid);
           m.extensions["VRMC_vrm"] = tinygltf::Value(vrm);
         });
       },
       {"extensions.VRMC_vrm.humanoid.humanBones.hips.node: 4000 is not a node index"}});
  return cases;
}

TEST(AvatarLoader, BrokenFilesAreErrorsNamingFileAndProblem) {
  for (const Broken& c : broken_files()) {
    SCOPED_TRACE(c.name);
    const std::string message = load_error(c.make(), kFile);
    ASSERT_FALSE(message.empty()) << "loaded without error";
    EXPECT_EQ(message.rfind(kFile, 0), 0u) << message;
    for (const std::string& part : c.expected) {
      EXPECT_NE(message.find(part), std::string::npos) << message;
    }
  }
}

TEST(AvatarLoader, MissingFileIsAnError) {
  deixis::testing::ScratchDir dir;
  try {
    load_avatar(dir.path() / "nobody.glb");
    FAIL() << "loaded a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nobody.glb: cannot open"), std::string::npos);
  }
}

TEST(AvatarLoader, LoadsFromAFileAndAsGltfText) {
  deixis::testing::ScratchDir dir;
  const std::vector<std::uint8_t> glb = generate_default_avatar({});
  testing::write_bytes(dir.path() / "a.glb", glb);
  const Avatar from_file = load_avatar(dir.path() / "a.glb");
  // The same model as .gltf JSON with its buffer in a data URI.
  tinygltf::Model model = default_model();
  std::ostringstream json;
  tinygltf::TinyGLTF writer;
  ASSERT_TRUE(writer.WriteGltfSceneToStream(&model, json, true, false));
  const std::string text = json.str();
  const Avatar from_text =
      load_avatar(std::vector<std::uint8_t>(text.begin(), text.end()), "a.gltf");
  expect_same_rig(from_file, from_text, 1e-7f);
}

TEST(AvatarLoader, CorruptedBytesNeverCrash) {
  // Truncations and byte flips all over the file: each either loads (a flip that hits, e.g., a
  // colour) or throws deixis::Error. The ASan build checks nothing is read out of bounds.
  const std::vector<std::uint8_t> good = generate_default_avatar({});
  std::mt19937 rng(2024);
  std::uniform_int_distribution<std::size_t> position(0, good.size() - 1);
  std::uniform_int_distribution<int> byte(0, 255);
  int errors = 0;
  for (int trial = 0; trial < 150; ++trial) {
    std::vector<std::uint8_t> bytes = good;
    if (trial % 3 == 0) {
      bytes.resize(position(rng));
    } else {
      // Flips concentrated in the JSON chunk (the first ~6 KB) half of the time.
      for (int k = 0; k < 4; ++k) {
        const std::size_t at = trial % 3 == 1 ? position(rng) % 6000 : position(rng);
        bytes[at] = static_cast<std::uint8_t>(byte(rng));
      }
    }
    try {
      load_avatar(bytes, "corrupt.glb");
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("corrupt.glb: ", 0), 0u) << e.what();
      ++errors;
    }
  }
  EXPECT_GT(errors, 50);
}

}  // namespace
}  // namespace deixis::avatar
