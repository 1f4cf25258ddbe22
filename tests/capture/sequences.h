#pragma once
// Clean sequences of every category for a training subject, a left-handed left-eyed subject and
// a right-handed left-eyed one, performed once and shared by the capture tests.

#include <vector>

#include "capture/generate.h"
#include "capture/script.h"

namespace deixis::capture::testing {

// Sanitized builds run every test in its own process ~10× slower; the checks are the same.
#ifdef DEIXIS_SANITIZED
inline constexpr int kPerCategory = 2;
#else
inline constexpr int kPerCategory = 6;
#endif

inline const std::vector<Sequence>& sample_sequences() {
  static const std::vector<Sequence> all = [] {
    std::vector<Sequence> out;
    for (const char* name : {"170", "173", "161"}) {
      const Subject& subject = find_subject(name);
      for (const Category c : kAllCategories) {
        for (int i = 0; i < kPerCategory; ++i) {
          out.push_back(clean_sequence(7, "test", subject, c, i));
        }
      }
    }
    return out;
  }();
  return all;
}

inline Vec3 surface_offset_of(const TargetObject& target, const Vec3& p) {
  return p - closest_surface_point(target, p);
}

inline const TargetObject& target_of(const Sequence& s, TargetId id) {
  for (const TargetObject& t : s.targets) {
    if (t.id == id) {
      return t;
    }
  }
  ADD_FAILURE() << "no target " << id;
  return s.targets.front();
}

}  // namespace deixis::capture::testing
