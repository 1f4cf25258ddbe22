#pragma once
// The ten categories as scripts of behaviours (actor.h) with randomised targets, dwell times and
// transitions; performing a script gives a Sequence with exact labels.

#include <cstdint>

#include "capture/sequence.h"
#include "capture/subject.h"
#include "capture/targets.h"

namespace deixis::capture {

// Performs one sequence of `category` by `subject`, its targets placed by `rules`; the same
// arguments give the same sequence. Throws deixis::Error for an invalid subject.
Sequence perform(const Subject& subject, Category category, std::uint64_t seed,
                 const TargetRules& rules = {});

}  // namespace deixis::capture
