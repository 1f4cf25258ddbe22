#pragma once
// A picture of one sequence (`deixis capture preview`): the progression labels over time (and,
// when given, MPNet's predictions as thin lines), and the motion seen from above and from the
// side in the person's own frame — stick figures, fingertip and head paths, gaze rays, targets.

#include <filesystem>
#include <string>
#include <vector>

#include "capture/sequence.h"

namespace deixis::capture {

// The sequence must hold the generator's skeleton (a freshly performed sequence). Throws
// deixis::Error when it does not, or when the PNG cannot be written.
void write_preview(const Sequence& sequence, const std::vector<Labels>* predictions,
                   const std::string& title, const std::filesystem::path& path);

}  // namespace deixis::capture
