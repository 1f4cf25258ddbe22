#pragma once
// A submitted view's pixels for the record (script "capture_frames"): the swapchain image read
// back from the application's GL context, its alpha counted over the layer's rectangle, and the
// rectangle written as a PAM (RGBA) file, so a test can check what the headset would show and
// where it would let the real world through (ALPHA_BLEND).

#include <openxr/openxr.h>

#include <string>

#include "xr_test_runtime/record.h"
#include "xr_test_runtime/runtime.h"

namespace deixis::xrt {

// Reads `image` of `swapchain` within `rect` and writes it to `file`; an empty file name in the
// result when it could not (no GL context, a format it cannot read).
RecordedImage capture_view(const GlFunctions& gl, const SwapchainObject& swapchain,
                           std::uint32_t image, const XrRect2Di& rect, const std::string& file);

}  // namespace deixis::xrt
