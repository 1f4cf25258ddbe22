#include "avatar/default_avatar.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "avatar/glb_writer.h"
#include "avatar/shapes.h"
#include "core/error.h"

namespace deixis::avatar {

namespace {

// Fractions of the arm length from the upper-arm joint to the index fingertip (sum 1): upper arm
// 0.186 and forearm 0.146 of stature against a hand of 0.108 (Winter), the hand split into
// metacarpal and the three phalanges of the index.
constexpr float kUpperArm = 0.4225f;
constexpr float kForearm = 0.3320f;
constexpr float kMetacarpal = 0.1225f;
constexpr float kIndexProximal = 0.0565f;
constexpr float kIndexIntermediate = 0.0345f;
constexpr float kIndexDistal = 0.0320f;

// Heights as fractions of stature (Winter's segment diagram; the eye at 0.936, shoulder 0.818,
// hip joint 0.530, knee 0.285, ankle 0.039); the rest placed between them.
constexpr float kEyeHeight = 0.936f;

struct Layout {
  ik::Skeleton skeleton;
  std::vector<Vec3> position;  // T_model_joint translation (rotations are identity)

  int add(const std::string& name, int parent, const Vec3& p) {
    skeleton.joint_names.push_back(name);
    skeleton.parents.push_back(static_cast<std::int16_t>(parent));
    const Vec3 parent_position = parent == ik::kNoParent ? Vec3::Zero() : position[parent];
    skeleton.rest_local.push_back(Pose{Mat3::Identity(), p - parent_position});
    position.push_back(p);
    return static_cast<int>(position.size()) - 1;
  }
};

struct Arm {
  int shoulder, upper_arm, lower_arm, hand, index_proximal, index_intermediate, index_distal;
  int thumb_metacarpal, thumb_proximal, thumb_distal;
  Vec3 index_tip, thumb_tip;
};

struct Leg {
  int upper_leg, lower_leg, foot;
};

struct Body {
  Layout layout;
  int hips, spine, chest, neck, head, left_eye, right_eye;
  Vec3 head_centre, head_radii;
  float eye_radius;
  std::array<Arm, 2> arms;  // left, right
  std::array<Leg, 2> legs;
};

std::string side_name(float side, const char* bone) {
  return std::string(side > 0.0f ? "left" : "right") + bone;
}

// The character's left is +X in glTF's frame (it faces +Z), so side = +1 is the left.
Arm add_arm(Layout& l, int chest, float side, float h, float a) {
  Arm arm{};
  const Vec3 x = Vec3::UnitX() * side;
  const Vec3 shoulder(side * 0.020f * h, 0.815f * h, 0.0f);
  const Vec3 upper(side * 0.112f * h, 0.815f * h, 0.0f);
  arm.shoulder = l.add(side_name(side, "Shoulder"), chest, shoulder);
  arm.upper_arm = l.add(side_name(side, "UpperArm"), arm.shoulder, upper);
  Vec3 p = upper + kUpperArm * a * x;
  arm.lower_arm = l.add(side_name(side, "LowerArm"), arm.upper_arm, p);
  p += kForearm * a * x;
  arm.hand = l.add(side_name(side, "Hand"), arm.lower_arm, p);
  const Vec3 wrist = p;
  p += kMetacarpal * a * x;
  arm.index_proximal = l.add(side_name(side, "IndexProximal"), arm.hand, p);
  p += kIndexProximal * a * x;
  arm.index_intermediate = l.add(side_name(side, "IndexIntermediate"), arm.index_proximal, p);
  p += kIndexIntermediate * a * x;
  arm.index_distal = l.add(side_name(side, "IndexDistal"), arm.index_intermediate, p);
  arm.index_tip = p + kIndexDistal * a * x;
  // The thumb leaves the wrist on the radial side (+Z in the T-pose, palms down), slightly palmar.
  p = wrist + Vec3(side * 0.022f * a, -0.006f * h, 0.010f * h);
  arm.thumb_metacarpal = l.add(side_name(side, "ThumbMetacarpal"), arm.hand, p);
  p += Vec3(side * 0.040f * a, -0.003f * h, 0.017f * h);
  arm.thumb_proximal = l.add(side_name(side, "ThumbProximal"), arm.thumb_metacarpal, p);
  p += Vec3(side * 0.028f * a, -0.001f * h, 0.010f * h);
  arm.thumb_distal = l.add(side_name(side, "ThumbDistal"), arm.thumb_proximal, p);
  arm.thumb_tip = p + Vec3(side * 0.024f * a, 0.0f, 0.007f * h);
  return arm;
}

Leg add_leg(Layout& l, int hips, float side, float h) {
  Leg leg{};
  const float x = side * 0.052f * h;
  leg.upper_leg = l.add(side_name(side, "UpperLeg"), hips, Vec3(x, 0.520f * h, 0.0f));
  leg.lower_leg = l.add(side_name(side, "LowerLeg"), leg.upper_leg, Vec3(x, 0.285f * h, 0.0f));
  leg.foot = l.add(side_name(side, "Foot"), leg.lower_leg, Vec3(x, 0.045f * h, 0.0f));
  return leg;
}

// Depth-first: the spine up to the eyes, then each arm (off the chest), then each leg (off the
// hips).
Body make_body(float h, float a) {
  Body b{};
  Layout& l = b.layout;
  b.hips = l.add("hips", ik::kNoParent, Vec3(0.0f, 0.555f * h, 0.0f));
  b.spine = l.add("spine", b.hips, Vec3(0.0f, 0.620f * h, 0.0f));
  b.chest = l.add("chest", b.spine, Vec3(0.0f, 0.715f * h, 0.0f));
  b.neck = l.add("neck", b.chest, Vec3(0.0f, 0.835f * h, 0.0f));
  b.head = l.add("head", b.neck, Vec3(0.0f, 0.875f * h, 0.0f));
  // The head is an ellipsoid whose top is the top of the body; the eyes sit in its front surface,
  // half a radius proud of it.
  b.head_radii = Vec3(0.047f, 0.068f, 0.058f) * h;
  b.head_centre = Vec3(0.0f, h - b.head_radii.y(), 0.012f * h);
  b.eye_radius = 0.0072f * h;
  for (const float side : {1.0f, -1.0f}) {
    const Vec3 e(side * 0.0185f * h, kEyeHeight * h, 0.0f);
    const Vec3 u = (e - b.head_centre).cwiseQuotient(b.head_radii);
    const float surface_z =
        b.head_centre.z() + b.head_radii.z() * std::sqrt(1.0f - u.x() * u.x() - u.y() * u.y());
    const Vec3 eye(e.x(), e.y(), surface_z - 0.5f * b.eye_radius);
    (side > 0.0f ? b.left_eye : b.right_eye) = l.add(side_name(side, "Eye"), b.head, eye);
  }
  b.arms[0] = add_arm(l, b.chest, 1.0f, h, a);
  b.arms[1] = add_arm(l, b.chest, -1.0f, h, a);
  b.legs[0] = add_leg(l, b.hips, 1.0f, h);
  b.legs[1] = add_leg(l, b.hips, -1.0f, h);
  return b;
}

struct Materials {
  int skin, shirt, trousers, shoes, eye_white, iris;
};

Materials add_materials(MeshBuilder& m) {
  // Linear RGB (glTF's baseColorFactor).
  return {m.add_material("skin", {0.72f, 0.50f, 0.38f, 1.0f}),
          m.add_material("shirt", {0.10f, 0.25f, 0.55f, 1.0f}),
          m.add_material("trousers", {0.08f, 0.09f, 0.12f, 1.0f}),
          m.add_material("shoes", {0.03f, 0.03f, 0.03f, 1.0f}),
          m.add_material("eye white", {0.90f, 0.90f, 0.88f, 1.0f}),
          m.add_material("iris", {0.03f, 0.02f, 0.015f, 1.0f})};
}

SegmentWeights blended(int joint, int start_joint, int end_joint, const Vec3& from, const Vec3& to,
                       float blend = 0.25f) {
  return {joint, start_joint, end_joint, from, to, blend};
}

// A capsule from `from` to `to` (its caps reach r0 beyond `from` and r1 beyond `to`).
void add_limb(MeshBuilder& m, int material, const Vec3& from, const Vec3& to, float r0, float r1,
              const SegmentWeights& w, int segments = 12) {
  Capsule c;
  c.length = (to - from).norm();
  c.r0 = r0;
  c.r1 = r1;
  c.segments = segments;
  m.add_capsule(material, segment_frame(from, to, Vec3::UnitZ()), c, w);
}

// A torso section: a capsule along +Y with an elliptic cross-section and flattened caps.
void add_torso(MeshBuilder& m, int material, float y0, float y1, float width, float depth,
               const SegmentWeights& w) {
  Capsule c;
  c.length = y1 - y0;
  c.r0 = width;
  c.r1 = width;
  c.depth = depth;
  c.cap = 0.35f;
  c.segments = 16;
  m.add_capsule(material, segment_frame(Vec3(0.0f, y0, 0.0f), Vec3(0.0f, y1, 0.0f), Vec3::UnitX()),
                c, w);
}

ShapeFrame at(const Vec3& origin) {
  ShapeFrame f;
  f.origin = origin;
  return f;
}

void add_arm_mesh(MeshBuilder& m, const Materials& mat, const Body& b, const Arm& arm, float h) {
  const auto& P = b.layout.position;
  const float side = P[arm.hand].x() > 0.0f ? 1.0f : -1.0f;
  add_limb(m, mat.shirt, P[arm.shoulder], P[arm.upper_arm], 0.030f * h, 0.030f * h,
           blended(arm.shoulder, b.chest, arm.upper_arm, P[arm.shoulder], P[arm.upper_arm]));
  add_limb(m, mat.shirt, P[arm.upper_arm], P[arm.lower_arm], 0.031f * h, 0.025f * h,
           blended(arm.upper_arm, arm.shoulder, arm.lower_arm, P[arm.upper_arm], P[arm.lower_arm]));
  add_limb(m, mat.skin, P[arm.lower_arm], P[arm.hand], 0.024f * h, 0.018f * h,
           blended(arm.lower_arm, arm.upper_arm, arm.hand, P[arm.lower_arm], P[arm.hand]));

  // Palm from the wrist to the knuckles, the index on its radial (+Z) edge.
  const Vec3 wrist = P[arm.hand];
  const Vec3 knuckle = P[arm.index_proximal];
  const float palm_half = 0.5f * (knuckle - wrist).norm();
  m.add_box(mat.skin, at(Vec3(wrist.x() + side * palm_half, wrist.y() - 0.002f * h, -0.015f * h)),
            Vec3(palm_half, 0.008f * h, 0.025f * h),
            blended(arm.hand, arm.lower_arm, -1, wrist, knuckle, 0.3f));
  // The other three fingers as one block beside the index.
  const Vec3 tip = arm.index_tip;
  const float fingers_half = 0.5f * 0.85f * (tip - knuckle).norm();
  m.add_box(mat.skin,
            at(Vec3(knuckle.x() + side * fingers_half, knuckle.y() - 0.003f * h, -0.026f * h)),
            Vec3(fingers_half, 0.0065f * h, 0.0145f * h), rigid(arm.hand));

  // Index: the last capsule's cap ends exactly at the fingertip.
  const float r_tip = 0.0048f * h;
  const Vec3 along = (tip - P[arm.index_distal]).normalized();
  add_limb(m, mat.skin, knuckle, P[arm.index_intermediate], 0.0058f * h, 0.0055f * h,
           blended(arm.index_proximal, arm.hand, arm.index_intermediate, knuckle,
                   P[arm.index_intermediate]),
           8);
  add_limb(m, mat.skin, P[arm.index_intermediate], P[arm.index_distal], 0.0055f * h, 0.0052f * h,
           blended(arm.index_intermediate, arm.index_proximal, arm.index_distal,
                   P[arm.index_intermediate], P[arm.index_distal]),
           8);
  add_limb(m, mat.skin, P[arm.index_distal], tip - r_tip * along, 0.0052f * h, r_tip,
           blended(arm.index_distal, arm.index_intermediate, -1, P[arm.index_distal], tip), 8);

  add_limb(m, mat.skin, P[arm.thumb_metacarpal], P[arm.thumb_proximal], 0.0075f * h, 0.0068f * h,
           blended(arm.thumb_metacarpal, arm.hand, arm.thumb_proximal, P[arm.thumb_metacarpal],
                   P[arm.thumb_proximal]),
           8);
  add_limb(m, mat.skin, P[arm.thumb_proximal], P[arm.thumb_distal], 0.0068f * h, 0.0062f * h,
           blended(arm.thumb_proximal, arm.thumb_metacarpal, arm.thumb_distal,
                   P[arm.thumb_proximal], P[arm.thumb_distal]),
           8);
  add_limb(m, mat.skin, P[arm.thumb_distal], arm.thumb_tip, 0.0062f * h, 0.0056f * h,
           blended(arm.thumb_distal, arm.thumb_proximal, -1, P[arm.thumb_distal], arm.thumb_tip),
           8);
}

void add_leg_mesh(MeshBuilder& m, const Materials& mat, const Body& b, const Leg& leg, float h) {
  const auto& P = b.layout.position;
  add_limb(m, mat.trousers, P[leg.upper_leg], P[leg.lower_leg], 0.047f * h, 0.034f * h,
           blended(leg.upper_leg, b.hips, leg.lower_leg, P[leg.upper_leg], P[leg.lower_leg]));
  add_limb(m, mat.trousers, P[leg.lower_leg], P[leg.foot], 0.032f * h, 0.022f * h,
           blended(leg.lower_leg, leg.upper_leg, leg.foot, P[leg.lower_leg], P[leg.foot]));
  // The sole is the floor (y = 0).
  const Vec3 ankle = P[leg.foot];
  m.add_box(mat.shoes, at(Vec3(ankle.x(), 0.0275f * h, 0.040f * h)),
            Vec3(0.030f * h, 0.0275f * h, 0.075f * h), rigid(leg.foot));
}

void add_head_mesh(MeshBuilder& m, const Materials& mat, const Body& b, float h) {
  const auto& P = b.layout.position;
  add_limb(m, mat.skin, P[b.neck], P[b.head], 0.028f * h, 0.028f * h,
           blended(b.neck, b.chest, b.head, P[b.neck], P[b.head]));
  m.add_ellipsoid(mat.skin, at(b.head_centre), b.head_radii, 20, 14, rigid(b.head));
  for (const int eye : {b.left_eye, b.right_eye}) {
    const float r = b.eye_radius;
    m.add_ellipsoid(mat.eye_white, at(P[eye]), Vec3::Constant(r), 12, 8, rigid(eye));
    // The iris and pupil as one dark cap on the front (+Z) of the eye, so the gaze shows.
    m.add_ellipsoid(mat.iris, at(P[eye] + Vec3(0.0f, 0.0f, 0.70f * r)), Vec3::Constant(0.42f * r),
                    10, 6, rigid(eye));
  }
}

void add_torso_mesh(MeshBuilder& m, const Materials& mat, const Body& b, float h) {
  const auto& P = b.layout.position;
  add_torso(m, mat.trousers, 0.50f * h, 0.60f * h, 0.090f * h, 0.66f,
            blended(b.hips, -1, b.spine, P[b.hips], P[b.spine], 0.3f));
  add_torso(m, mat.shirt, 0.60f * h, 0.70f * h, 0.082f * h, 0.68f,
            blended(b.spine, b.hips, b.chest, P[b.spine], P[b.chest], 0.3f));
  add_torso(m, mat.shirt, 0.70f * h, 0.815f * h, 0.092f * h, 0.70f,
            blended(b.chest, b.spine, -1, P[b.chest], P[b.neck], 0.3f));
}

}  // namespace

void validate(const AvatarParameters& p) {
  const auto metres = [](float v) {
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%.3f m", static_cast<double>(v));
    return std::string(text.data());
  };
  if (!std::isfinite(p.height) || p.height < 0.5f || p.height > 2.5f) {
    throw Error("avatar height " + metres(p.height) +
                " is outside what the body model builds (0.5 to 2.5 m)");
  }
  const float lo = 0.30f * p.height;
  const float hi = 0.60f * p.height;
  if (!std::isfinite(p.arm_length) || p.arm_length < lo || p.arm_length > hi) {
    throw Error("avatar arm length " + metres(p.arm_length) +
                " is outside 0.30 to 0.60 times the height (" + metres(lo) + " to " + metres(hi) +
                " for a height of " + metres(p.height) + ")");
  }
}

AvatarAsset make_default_avatar(const AvatarParameters& p) {
  validate(p);
  const float h = p.height;
  const Body body = make_body(h, p.arm_length);

  MeshBuilder builder;
  const Materials materials = add_materials(builder);
  add_head_mesh(builder, materials, body, h);
  add_torso_mesh(builder, materials, body, h);
  for (const Arm& arm : body.arms) {
    add_arm_mesh(builder, materials, body, arm, h);
  }
  for (const Leg& leg : body.legs) {
    add_leg_mesh(builder, materials, body, leg, h);
  }

  AvatarAsset asset;
  asset.skeleton = body.layout.skeleton;
  asset.mesh = std::move(builder).finish();
  for (const Vec3& p_joint : body.layout.position) {
    asset.mesh.inverse_bind.push_back(Pose{Mat3::Identity(), -p_joint});
  }
  for (const Arm& arm : body.arms) {
    const int distal = arm.index_distal;
    const std::string name =
        body.layout.skeleton.joint_names[arm.hand] == "leftHand" ? "leftIndexTip" : "rightIndexTip";
    asset.end_sites.push_back({name, distal, arm.index_tip - body.layout.position[distal]});
  }
  asset.generator = "Deixis default avatar (deixis avatar generate)";
  // Parameters rounded to micrometres so the JSON shows 1.7, not float's 1.7000000476837158.
  const auto rounded = [](float v) { return std::round(static_cast<double>(v) * 1e6) / 1e6; };
  asset.metadata["height"] = rounded(p.height);
  asset.metadata["armLength"] = rounded(p.arm_length);
  return asset;
}

std::vector<std::uint8_t> generate_default_avatar(const AvatarParameters& parameters) {
  return write_glb(make_default_avatar(parameters));
}

}  // namespace deixis::avatar
