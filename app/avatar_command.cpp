// `deixis avatar generate` writes the default avatar as .glb and checks it by loading it back;
// `deixis avatar info FILE...` loads avatars as Deixis does and prints what it found. Exit code 0
// on success, 2 when parameters are bad or a file cannot be written or loaded.

#include <cstdio>
#include <numbers>

#include "app/commands.h"
#include "avatar/avatar_loader.h"
#include "avatar/default_avatar.h"
#include "avatar/glb_writer.h"
#include "core/error.h"

namespace deixis::app {

namespace {

void print_vector(const char* label, const Vec3& v, const char* frame) {
  std::printf("  %-22s (%+.4f, %+.4f, %+.4f) m in %s\n", label, static_cast<double>(v.x()),
              static_cast<double>(v.y()), static_cast<double>(v.z()), frame);
}

void print_avatar(const std::filesystem::path& file, const avatar::Avatar& a) {
  const ik::HumanoidRig& rig = a.rig;
  std::printf("%s\n", file.string().c_str());
  std::printf("  bones found from       %s; turned %.0f deg about +Y to face -Z\n",
              a.bone_source.c_str(), static_cast<double>(a.facing_turn) * 180.0 / std::numbers::pi);
  std::printf("  skeleton               %d joints\n", rig.skeleton.joint_count());
  std::printf("  mesh                   %zu vertices, %zu triangles, %zu primitives\n",
              a.mesh.vertex_count(), a.mesh.triangle_count(), a.mesh.primitives.size());
  std::printf("  height                 %.3f m\n", static_cast<double>(rig.height));
  std::printf("  arm length             %.3f m\n", static_cast<double>(rig.arm_length));
  print_vector("eye midpoint H", rig.eye_midpoint_in_head, "the head joint's frame");
  print_vector("left index fingertip", rig.index_tip_in_distal[0], "leftIndexDistal's frame");
  print_vector("right index fingertip", rig.index_tip_in_distal[1], "rightIndexDistal's frame");
  std::printf("  %-22s %s\n", "bone", "joint");
  for (int b = 0; b < ik::kBoneCount; ++b) {
    const int j = rig.joint[b];
    std::printf("  %-22s %s\n", std::string(ik::bone_name(static_cast<ik::Bone>(b))).c_str(),
                j == -1 ? "-" : rig.skeleton.joint_names[j].c_str());
  }
}

}  // namespace

int run_avatar_generate(const AvatarGenerateOptions& options) {
  try {
    const avatar::AvatarParameters parameters{options.height, options.arm_length};
    const std::vector<std::uint8_t> bytes = avatar::generate_default_avatar(parameters);
    avatar::save_file(options.output, bytes);
    // Read it back the way every user of the file will, and show what was measured.
    const avatar::Avatar loaded = avatar::load_avatar(options.output);
    std::printf("wrote %s: %zu bytes, %d joints, %zu vertices, %zu triangles\n",
                options.output.string().c_str(), bytes.size(), loaded.rig.skeleton.joint_count(),
                loaded.mesh.vertex_count(), loaded.mesh.triangle_count());
    std::printf("measured on load: height %.4f m (asked %.4f), arm length %.4f m (asked %.4f)\n",
                static_cast<double>(loaded.rig.height), static_cast<double>(options.height),
                static_cast<double>(loaded.rig.arm_length),
                static_cast<double>(options.arm_length));
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis avatar generate: %s\n", e.what());
    return 2;
  }
}

int run_avatar_info(const AvatarInfoOptions& options) {
  int unreadable = 0;
  for (const auto& file : options.files) {
    try {
      print_avatar(file, avatar::load_avatar(file));
    } catch (const Error& e) {
      std::fprintf(stderr, "deixis avatar info: %s\n", e.what());
      ++unreadable;
    }
  }
  return unreadable > 0 ? 2 : 0;
}

}  // namespace deixis::app
