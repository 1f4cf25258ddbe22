#include "avatar/influences.h"

#include <algorithm>

namespace deixis::avatar {

bool pack_influences(std::span<Influence> influences, PackedInfluences& packed) {
  packed = {};
  // Merge duplicates: sort by joint, then fold equal neighbours into the first.
  std::sort(influences.begin(), influences.end(),
            [](const Influence& a, const Influence& b) { return a.joint < b.joint; });
  std::size_t unique = 0;
  for (std::size_t i = 0; i < influences.size(); ++i) {
    if (influences[i].weight <= 0.0f) {
      continue;
    }
    if (unique > 0 && influences[unique - 1].joint == influences[i].joint) {
      influences[unique - 1].weight += influences[i].weight;
    } else {
      influences[unique++] = influences[i];
    }
  }
  if (unique == 0) {
    return false;
  }
  const auto kept = influences.first(unique);
  std::stable_sort(kept.begin(), kept.end(),
                   [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
  const std::size_t n = std::min<std::size_t>(unique, kMaxInfluences);
  double sum = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    sum += static_cast<double>(kept[k].weight);
  }
  // Normalise the smaller weights, then give the largest what is left, so that the sum of the
  // stored floats is 1 to within rounding of a single value.
  double rest = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    packed.weights[k] = static_cast<float>(static_cast<double>(kept[k].weight) / sum);
    rest += static_cast<double>(packed.weights[k]);
  }
  packed.weights[0] = static_cast<float>(1.0 - rest);
  for (std::size_t k = 0; k < n; ++k) {
    packed.joints[k] = static_cast<std::uint16_t>(kept[k].joint);
  }
  return true;
}

}  // namespace deixis::avatar
