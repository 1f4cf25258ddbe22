#pragma once
// Meshes built from parameters: the unit sphere and cube the target objects are drawn with, and a
// skinned tube along a chain of joints (the stand-in limb the tests and the benchmark skin, and a
// fallback figure when no avatar file is at hand).

#include <span>

#include "ik/skeleton.h"
#include "render/skinned_mesh.h"

namespace deixis::render {

// A UV sphere of diameter 1 centred on the origin (`rings` ≥ 2 latitude bands, `segments` ≥ 3).
StaticMesh unit_sphere(int rings, int segments);

// A cube of edge 1 centred on the origin, with flat normals (24 vertices, 12 triangles).
StaticMesh unit_cube();

struct TubeOptions {
  float radius = 0.05f;          // m
  int rings_per_bone = 8;        // cross-sections along each bone
  int segments = 16;             // vertices around each cross-section
  float blend_fraction = 0.25f;  // weights blend over this fraction of a bone each side of a joint
  Colour colour = Colour(0.8f, 0.8f, 0.8f, 1.0f);
};

// A capped tube through the rest-pose positions of `chain` (≥ 2 joints of `skeleton`, each the
// next one's ancestor): the bone from chain[k] to chain[k + 1] follows joint chain[k], and the
// weights blend linearly between neighbouring bones around each inner joint. The last joint is the
// tip and drives nothing. inverse_bind covers every joint of the skeleton. Throws deixis::Error
// for a bad chain.
SkinnedMesh skinned_tube(const ik::Skeleton& skeleton, std::span<const int> chain,
                         const TubeOptions& options);

// Appends `part` to `mesh` (same skeleton): vertices, re-based indices and primitives.
void append(SkinnedMesh& mesh, const SkinnedMesh& part);

}  // namespace deixis::render
