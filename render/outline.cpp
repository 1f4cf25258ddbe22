#include "render/outline.h"

#include <array>
#include <cmath>

namespace deixis::render {

namespace {

std::size_t box_edges(const TargetObject& object, const Colour& colour, std::span<DebugLine> out) {
  const Vec3 h = object.size / 2.0f;
  auto corner = [&](int i) -> Vec3 {  // bit 0: +x, bit 1: +y, bit 2: +z
    return object.position + Vec3((i & 1) != 0 ? h.x() : -h.x(), (i & 2) != 0 ? h.y() : -h.y(),
                                  (i & 4) != 0 ? h.z() : -h.z());
  };
  std::size_t n = 0;
  for (int i = 0; i < 8; ++i) {
    for (const int bit : {1, 2, 4}) {
      if ((i & bit) == 0) {  // each edge once, from its lower corner
        out[n++] = {corner(i), corner(i | bit), colour};
      }
    }
  }
  return n;  // 12
}

std::size_t sphere_circles(const TargetObject& object, const Colour& colour,
                           std::span<DebugLine> out) {
  const float r = object.size.x() / 2.0f;
  constexpr float kStep = 2.0f * 3.14159265358979f / kSphereOutlineSegments;
  std::size_t n = 0;
  for (int plane = 0; plane < 3; ++plane) {  // circles about x, y and z
    auto at = [&](int k) -> Vec3 {
      const float a = kStep * static_cast<float>(k);
      const float c = r * std::cos(a);
      const float s = r * std::sin(a);
      const Vec3 offset = plane == 0 ? Vec3(0, c, s) : plane == 1 ? Vec3(c, 0, s) : Vec3(c, s, 0);
      return object.position + offset;
    };
    for (int k = 0; k < kSphereOutlineSegments; ++k) {
      out[n++] = {at(k), at(k + 1), colour};
    }
  }
  return n;
}

}  // namespace

std::size_t outline(const TargetObject& object, const Colour& colour, std::span<DebugLine> out) {
  if (out.size() < kMaxOutlineLines) {
    return 0;
  }
  return object.kind == TargetKind::kSphere ? sphere_circles(object, colour, out)
                                            : box_edges(object, colour, out);
}

}  // namespace deixis::render
