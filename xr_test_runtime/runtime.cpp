#include "xr_test_runtime/runtime.h"

#include <openxr/openxr_reflection.h>
#include <algorithm>

#include <cstring>

namespace deixis::xrt {

Runtime& state() {
  static Runtime runtime;  // the ABI-forced global (runtime.h)
  return runtime;
}

bool Runtime::extension_enabled(const char* name) const {
  return std::find(enabled_extensions.begin(), enabled_extensions.end(), name) !=
         enabled_extensions.end();
}

XrTime Runtime::period() const {
  return static_cast<XrTime>(1e9 / script.display_hz + 0.5);
}

XrTime Runtime::input_time() const {
  return epoch + static_cast<XrTime>(std::max<std::uint64_t>(session_state.waited, 1)) * period();
}

XrPath Runtime::find_path(std::string_view s) const {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (paths[i] == s) {
      return i + 1;
    }
  }
  return XR_NULL_PATH;
}

XrPath Runtime::intern(std::string_view s) {
  if (const XrPath found = find_path(s); found != XR_NULL_PATH) {
    return found;
  }
  paths.emplace_back(s);
  return paths.size();
}

const std::string& Runtime::path_string(XrPath path) const {
  static const std::string kNone;
  return path == XR_NULL_PATH || path > paths.size() ? kNone : paths[path - 1];
}

ScriptSample Runtime::sample(XrTime time) const {
  return script.at(static_cast<double>(time - epoch - period()) * 1e-9);
}

void Runtime::change_state(XrSessionState s, XrTime time) {
  session_state.state = s;
  XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER, nullptr, {}};
  XrEventDataSessionStateChanged changed{XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED, nullptr,
                                         to_handle<XrSession>(session), s, time};
  static_assert(sizeof(changed) <= sizeof(buffer));
  std::memcpy(&buffer, &changed, sizeof(changed));
  events.push_back(buffer);
  const char* names[] = {"UNKNOWN", "IDLE",     "READY",        "SYNCHRONIZED", "VISIBLE",
                         "FOCUSED", "STOPPING", "LOSS_PENDING", "EXITING"};
  const auto i = static_cast<std::size_t>(s);
  record.states.push_back(i < std::size(names) ? names[i] : "?");
}

XrResult Runtime::refuse(const char* call, XrResult result) {
  record.refusals.push_back({call, result_name(result)});
  return result;
}

const char* result_name(XrResult result) {
  switch (result) {
#define DEIXIS_XRT_RESULT_CASE(name, value) \
  case name:                                \
    return #name;
    XR_LIST_ENUM_XrResult(DEIXIS_XRT_RESULT_CASE)
#undef DEIXIS_XRT_RESULT_CASE
        default : return "XR_UNKNOWN_RESULT";
  }
}

XrPosef to_xr(const ScriptPose& p) {
  const Eigen::Quaternionf q = p.orientation.normalized();
  return {{q.x(), q.y(), q.z(), q.w()}, {p.position.x(), p.position.y(), p.position.z()}};
}

ScriptPose from_xr(const XrPosef& p) {
  ScriptPose out;
  out.position = Eigen::Vector3f(p.position.x, p.position.y, p.position.z);
  out.orientation =
      Eigen::Quaternionf(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  if (out.orientation.norm() < 1e-6f) {
    out.orientation = Eigen::Quaternionf::Identity();
  }
  out.orientation.normalize();
  return out;
}

ScriptPose compose(const ScriptPose& a, const ScriptPose& b) {
  return {a.position + a.orientation * b.position, a.orientation * b.orientation};
}

ScriptPose inverse(const ScriptPose& p) {
  const Eigen::Quaternionf q = p.orientation.conjugate();
  return {-(q * p.position), q};
}

}  // namespace deixis::xrt
