#pragma once
// The left–right mirror image of a sequence through the person's own sagittal plane (the root's
// y–z plane): a right-handed recording becomes a left-handed one (paper §III.C: "we generated
// training data for left-handed subjects by mirroring"). Positions and directions reflect; a
// rotation R becomes M·R·M, which carries the right wrist frame of docs/decisions.md §7 onto the
// left one; left and right hands, eyes and eye dominance swap.

#include "capture/sequence.h"

namespace deixis::capture {

Sequence mirror(const Sequence& sequence);

}  // namespace deixis::capture
