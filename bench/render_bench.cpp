// Render time per frame at 1280 × 720 on the headless context (EGL surfaceless; llvmpipe on a
// machine without GPU): a skinned avatar, four target objects with labels, the floor and two
// debug lines, posed differently every frame. Each iteration ends with glFinish, so the time is
// the frame's, not just its command submission; the second benchmark adds the read-back the
// demo's video needs.
//
//   build/release/bench/render_bench
//
// llvmpipe renders with one thread per core (LP_NUM_THREADS overrides); the figure is for the
// whole machine, unlike the single-threaded network benchmarks.

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "avatar/avatar_loader.h"
#include "avatar/default_avatar.h"
#include "render/headless_context.h"
#include "render/image.h"
#include "render/primitives.h"
#include "render/renderer.h"

namespace {

using namespace deixis;
using namespace deixis::render;

constexpr int kWidth = 1280;
constexpr int kHeight = 720;

struct Figure {
  ik::Skeleton skeleton;
  SkinnedMesh mesh;
  std::vector<int> swinging;  // joints that move from frame to frame
};

int add_joint(ik::Skeleton& s, const char* name, int parent, const Vec3& offset) {
  s.joint_names.emplace_back(name);
  s.parents.push_back(static_cast<std::int16_t>(parent));
  s.rest_local.push_back(Pose{Mat3::Identity(), offset});
  return s.joint_count() - 1;
}

// A mannequin of skinned tubes (torso, head, arms, legs): 4,608 triangles over 19 joints.
Figure mannequin() {
  Figure f;
  ik::Skeleton& s = f.skeleton;
  const int hips = add_joint(s, "hips", ik::kNoParent, Vec3(0, 1.0f, 0));
  const int spine = add_joint(s, "spine", hips, Vec3(0, 0.2f, 0));
  const int chest = add_joint(s, "chest", spine, Vec3(0, 0.2f, 0));
  const int neck = add_joint(s, "neck", chest, Vec3(0, 0.12f, 0));
  const int head = add_joint(s, "head", neck, Vec3(0, 0.1f, 0));
  const int top = add_joint(s, "headTop", head, Vec3(0, 0.2f, 0));
  std::vector<std::vector<int>> arms;
  std::vector<std::vector<int>> legs;
  for (const float side : {-1.0f, 1.0f}) {
    const int shoulder = add_joint(s, "shoulder", chest, Vec3(side * 0.18f, 0.08f, 0));
    const int elbow = add_joint(s, "elbow", shoulder, Vec3(side * 0.28f, 0, 0));
    const int wrist = add_joint(s, "wrist", elbow, Vec3(side * 0.25f, 0, 0));
    const int tip = add_joint(s, "fingertip", wrist, Vec3(side * 0.18f, 0, 0));
    arms.push_back({shoulder, elbow, wrist, tip});
    const int hip = add_joint(s, "hip", hips, Vec3(side * 0.1f, -0.02f, 0));
    const int knee = add_joint(s, "knee", hip, Vec3(0, -0.45f, 0));
    const int ankle = add_joint(s, "ankle", knee, Vec3(0, -0.45f, 0));
    legs.push_back({hip, knee, ankle});
    f.swinging.insert(f.swinging.end(), {shoulder, elbow, hip});
  }
  f.swinging.push_back(neck);
  TubeOptions o;
  o.rings_per_bone = 6;
  o.segments = 24;
  const auto tube = [&](std::span<const int> chain, float radius, const Colour& colour) {
    o.radius = radius;
    o.colour = colour;
    return skinned_tube(s, chain, o);
  };
  const int torso[] = {hips, spine, chest, neck};
  const int skull[] = {neck, head, top};
  f.mesh = tube(torso, 0.14f, Colour(0.3f, 0.45f, 0.7f, 1));
  append(f.mesh, tube(skull, 0.1f, Colour(0.9f, 0.75f, 0.6f, 1)));
  for (const auto& arm : arms) {
    append(f.mesh, tube(arm, 0.045f, Colour(0.9f, 0.75f, 0.6f, 1)));
  }
  for (const auto& leg : legs) {
    append(f.mesh, tube(leg, 0.07f, Colour(0.25f, 0.25f, 0.3f, 1)));
  }
  return f;
}

// Deixis' default avatar (avatar/default_avatar.h), generated and loaded as a .glb would be.
Figure default_avatar() {
  avatar::Avatar a = avatar::load_avatar(avatar::generate_default_avatar({}), "default avatar");
  Figure f{a.rig.skeleton, a.mesh, {}};
  for (const ik::Bone b : {ik::Bone::kLeftUpperArm, ik::Bone::kLeftLowerArm,
                           ik::Bone::kRightUpperArm, ik::Bone::kRightLowerArm, ik::Bone::kNeck}) {
    if (a.rig[b] >= 0) {
      f.swinging.push_back(a.rig[b]);
    }
  }
  return f;
}

TargetMap room() {
  TargetMap map;
  map.objects = {
      {1, "Jupiter", TargetKind::kSphere, Vec3(1.2f, 1.4f, -2.0f), Vec3::Constant(0.4f)},
      {2, "TV", TargetKind::kScreen, Vec3(-1.5f, 1.2f, -2.5f), Vec3(1.2f, 0.7f, 0.05f)},
      {3, "Box", TargetKind::kBox, Vec3(0.4f, 0.9f, -0.6f), Vec3::Constant(0.3f)},
      {4, "Saturn", TargetKind::kSphere, Vec3(-0.6f, 1.8f, -3.0f), Vec3::Constant(0.5f)}};
  return map;
}

// Frame i's pose: the moving joints swing by up to ±0.6 rad, out of phase.
void pose_at(const Figure& f, int i, std::vector<Pose>& local, std::vector<Pose>& model) {
  local = f.skeleton.rest_local;
  for (std::size_t k = 0; k < f.swinging.size(); ++k) {
    const float angle = 0.6f * std::sin(0.1f * static_cast<float>(i) + static_cast<float>(k));
    local[f.swinging[k]].rotation =
        Eigen::AngleAxisf(angle, Vec3(0.3f, 0.4f, 1.0f).normalized()).toRotationMatrix();
  }
  ik::local_to_model(f.skeleton, local, model);
}

void run(benchmark::State& state, const Figure& figure, bool read_back) {
  HeadlessContext context(kWidth, kHeight);
  Renderer renderer;
  const SkinnedMeshId mesh = renderer.add_skinned_mesh(figure.mesh);
  renderer.set_targets(room());
  std::vector<Pose> local;
  std::vector<Pose> model(figure.skeleton.rest_local.size());
  const DebugLine lines[] = {{Vec3(0, 1.6f, -1), Vec3(1.2f, 1.4f, -2.0f), Colour(1, 0.9f, 0.1f, 1)},
                             {Vec3(0.3f, 1.3f, -1), Vec3(0.4f, 0.9f, -0.6f), Colour(1, 0, 1, 1)}};
  SceneView view;
  view.camera = look_at(Vec3(0.3f, 1.6f, 2.2f), Vec3(0, 1.2f, -1.0f),
                        symmetric_fov(1.0471976f, static_cast<float>(kWidth) / kHeight));
  view.lines = lines;
  Image frame;
  int i = 0;
  for (auto _ : state) {
    pose_at(figure, i++, local, model);
    const AvatarDraw avatar{mesh, Pose{yaw_rotation(0.3f), Vec3(0, 0, -1.0f)}, model};
    view.avatars = {&avatar, 1};
    renderer.render(view, context.target());
    if (read_back) {
      read_pixels(context.target(), frame);  // waits for the frame
      benchmark::DoNotOptimize(frame.rgb.data());
    } else {
      context.present();  // glFinish
    }
  }
  state.counters["triangles"] = static_cast<double>(figure.mesh.indices.size() / 3);
  state.SetLabel(context.description());
}

void BM_RenderFrame_Mannequin(benchmark::State& state) {
  run(state, mannequin(), false);
}
void BM_RenderFrameAndReadBack_Mannequin(benchmark::State& state) {
  run(state, mannequin(), true);
}
void BM_RenderFrame_DefaultAvatar(benchmark::State& state) {
  run(state, default_avatar(), false);
}

BENCHMARK(BM_RenderFrame_Mannequin)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderFrameAndReadBack_Mannequin)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RenderFrame_DefaultAvatar)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
