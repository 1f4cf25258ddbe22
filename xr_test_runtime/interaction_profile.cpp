// What the application may ask about its bindings once attached (spec §11.6): the interaction
// profile current for a top-level user path, the input sources bound to an action, and an
// input source's localized name ("Right Hand Index Controller Trigger Value").

#include <algorithm>
#include <cstdio>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

XrResult check_attached(const Runtime& rt, XrSession session) {
  if (!rt.instance_live || rt.session == 0 || from_handle(session) != rt.session) {
    return XR_ERROR_HANDLE_INVALID;
  }
  return rt.session_state.actions_attached ? XR_SUCCESS : XR_ERROR_ACTIONSET_NOT_ATTACHED;
}

// The top-level user path `path` names, or nothing.
std::optional<TopLevel> top_level_of(std::string_view path) {
  for (std::size_t t = 0; t < kTopLevelCount; ++t) {
    if (top_level_path(static_cast<TopLevel>(t)) == path) {
      return static_cast<TopLevel>(t);
    }
  }
  return std::nullopt;
}

}  // namespace

XrResult XRAPI_CALL GetCurrentInteractionProfile(XrSession session, XrPath top_level,
                                                 XrInteractionProfileState* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check_attached(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrGetCurrentInteractionProfile", r);
  }
  if (out == nullptr || out->type != XR_TYPE_INTERACTION_PROFILE_STATE) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (top_level == XR_NULL_PATH || top_level > rt.paths.size()) {
    return XR_ERROR_PATH_INVALID;
  }
  const std::optional<TopLevel> top = top_level_of(rt.path_string(top_level));
  if (!top) {
    return rt.refuse("xrGetCurrentInteractionProfile", XR_ERROR_PATH_UNSUPPORTED);
  }
  const Profile* p = rt.session_state.profiles[static_cast<std::size_t>(*top)];
  out->interactionProfile = p != nullptr ? rt.intern(p->path) : XR_NULL_PATH;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL EnumerateBoundSourcesForAction(XrSession session,
                                                   const XrBoundSourcesForActionEnumerateInfo* info,
                                                   uint32_t capacity, uint32_t* count,
                                                   XrPath* sources) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check_attached(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrEnumerateBoundSourcesForAction", r);
  }
  if (info == nullptr || info->type != XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const auto it = rt.actions.find(from_handle(info->action));
  if (it == rt.actions.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  // At most one path per binding; bindings are few (one per suggested path).
  std::vector<XrPath> bound;
  for (const ActionBinding& b : it->second.bindings) {
    bound.push_back(rt.intern(b.path));
  }
  return two_call(capacity, count, sources, bound.data(), static_cast<uint32_t>(bound.size()));
}

XrResult XRAPI_CALL GetInputSourceLocalizedName(XrSession session,
                                                const XrInputSourceLocalizedNameGetInfo* info,
                                                uint32_t capacity, uint32_t* count, char* buffer) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check_attached(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrGetInputSourceLocalizedName", r);
  }
  if (info == nullptr || info->type != XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  constexpr XrInputSourceLocalizedNameFlags kAll =
      XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
      XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
      XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
  if (info->whichComponents == 0 || (info->whichComponents & ~kAll) != 0) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->sourcePath == XR_NULL_PATH || info->sourcePath > rt.paths.size()) {
    return XR_ERROR_PATH_INVALID;
  }
  // The source is an input of the profile current on its top-level path.
  const std::string& path = rt.path_string(info->sourcePath);
  std::optional<BindingPath> b;
  const Profile* profile = nullptr;
  for (const Profile* p : rt.session_state.profiles) {
    if (p != nullptr && (b = parse_binding(*p, path))) {
      profile = p;
      break;
    }
  }
  if (!b) {
    return rt.refuse("xrGetInputSourceLocalizedName", XR_ERROR_PATH_UNSUPPORTED);
  }
  std::string name;
  const auto add = [&name](std::string_view part) {
    name += name.empty() ? "" : " ";
    name += part;
  };
  if ((info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT) != 0) {
    add(top_level_name(b->top));
  }
  if ((info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT) != 0) {
    add(profile->name);
  }
  if ((info->whichComponents & XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT) != 0) {
    add(localized_component(*b));
  }
  return two_call(capacity, count, buffer, name.c_str(), static_cast<uint32_t>(name.size() + 1));
}

}  // namespace deixis::xrt
