// Action sets, pose actions, suggested bindings for the two interaction profiles the scripted
// user has (khr/simple_controller: grip and aim poses; ext/eye_gaze_interaction: the gaze pose),
// attaching, xrSyncActions (counted per frame for the record) and pose action states.

#include <cstring>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

bool valid_instance(const Runtime& rt, XrInstance instance) {
  return rt.instance_live && from_handle(instance) == rt.instance;
}
bool valid_session(const Runtime& rt, XrSession session) {
  return rt.instance_live && rt.session != 0 && from_handle(session) == rt.session;
}

const std::string& path_string(const Runtime& rt, XrPath path) {
  static const std::string kNone;
  return path == XR_NULL_PATH || path > rt.paths.size() ? kNone : rt.paths[path - 1];
}

// The source behind a binding path of a profile; false when the profile has no such input.
bool binding_source(const Runtime& rt, const std::string& profile, const std::string& path,
                    Source& source, std::string& user) {
  if (profile == "/interaction_profiles/khr/simple_controller") {
    const struct {
      const char* path;
      Source source;
      const char* user;
    } table[] = {
        {"/user/hand/left/input/grip/pose", Source::kLeftGrip, "/user/hand/left"},
        {"/user/hand/left/input/aim/pose", Source::kLeftAim, "/user/hand/left"},
        {"/user/hand/right/input/grip/pose", Source::kRightGrip, "/user/hand/right"},
        {"/user/hand/right/input/aim/pose", Source::kRightAim, "/user/hand/right"},
    };
    for (const auto& row : table) {
      if (path == row.path) {
        source = row.source;
        user = row.user;
        return true;
      }
    }
    return false;
  }
  if (profile == "/interaction_profiles/ext/eye_gaze_interaction" &&
      rt.extension_enabled("XR_EXT_eye_gaze_interaction") &&
      path == "/user/eyes_ext/input/gaze_ext/pose") {
    source = Source::kGaze;
    user = "/user/eyes_ext";
    return true;
  }
  return false;
}

XrPath find_path(const Runtime& rt, const std::string& s) {
  for (std::size_t i = 0; i < rt.paths.size(); ++i) {
    if (rt.paths[i] == s) {
      return i + 1;
    }
  }
  return XR_NULL_PATH;
}

}  // namespace

XrResult XRAPI_CALL CreateActionSet(XrInstance instance, const XrActionSetCreateInfo* info,
                                    XrActionSet* set) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(rt, instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || set == nullptr || info->type != XR_TYPE_ACTION_SET_CREATE_INFO ||
      info->actionSetName[0] == '\0') {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const std::uint64_t id = rt.new_handle();
  rt.action_sets[id] = {info->actionSetName, false};
  *set = to_handle<XrActionSet>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroyActionSet(XrActionSet set) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const std::uint64_t id = from_handle(set);
  if (rt.action_sets.erase(id) != 1) {
    return XR_ERROR_HANDLE_INVALID;
  }
  std::erase_if(rt.actions, [id](const auto& a) { return a.second.set == id; });
  return XR_SUCCESS;
}

XrResult XRAPI_CALL CreateAction(XrActionSet set, const XrActionCreateInfo* info,
                                 XrAction* action) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.action_sets.find(from_handle(set));
  if (it == rt.action_sets.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || action == nullptr || info->type != XR_TYPE_ACTION_CREATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (it->second.attached) {
    return rt.refuse("xrCreateAction", XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  }
  ActionObject a;
  a.set = from_handle(set);
  a.type = info->actionType;
  a.name = info->actionName;
  a.subactions.assign(info->subactionPaths, info->subactionPaths + info->countSubactionPaths);
  const std::uint64_t id = rt.new_handle();
  rt.actions[id] = std::move(a);
  *action = to_handle<XrAction>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroyAction(XrAction action) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  return rt.actions.erase(from_handle(action)) == 1 ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}

XrResult XRAPI_CALL SuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* suggested) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(rt, instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (suggested == nullptr || suggested->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
      suggested->countSuggestedBindings == 0 || suggested->suggestedBindings == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (rt.session != 0 && rt.session_state.actions_attached) {
    return rt.refuse("xrSuggestInteractionProfileBindings", XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  }
  const std::string profile = path_string(rt, suggested->interactionProfile);
  if (profile != "/interaction_profiles/khr/simple_controller" &&
      profile != "/interaction_profiles/ext/eye_gaze_interaction") {
    return XR_ERROR_PATH_UNSUPPORTED;
  }
  std::vector<std::pair<std::uint64_t, std::string>> bindings;
  for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
    const XrActionSuggestedBinding& b = suggested->suggestedBindings[i];
    Source source;
    std::string user;
    const std::string path = path_string(rt, b.binding);
    if (rt.actions.count(from_handle(b.action)) == 0) {
      return XR_ERROR_HANDLE_INVALID;
    }
    if (!binding_source(rt, profile, path, source, user)) {
      return XR_ERROR_PATH_UNSUPPORTED;
    }
    bindings.emplace_back(from_handle(b.action), path);
  }
  // The latest suggestion for a profile replaces the previous one (spec 11.4).
  auto& stored = rt.suggested[profile];
  stored.clear();
  for (const auto& [id, path] : bindings) {
    stored.emplace_back(id, path);
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL AttachSessionActionSets(XrSession session,
                                            const XrSessionActionSetsAttachInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO ||
      info->countActionSets == 0 || info->actionSets == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SessionObject& s = rt.session_state;
  if (s.actions_attached) {
    return rt.refuse("xrAttachSessionActionSets", XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  }
  for (uint32_t i = 0; i < info->countActionSets; ++i) {
    const auto it = rt.action_sets.find(from_handle(info->actionSets[i]));
    if (it == rt.action_sets.end()) {
      return XR_ERROR_HANDLE_INVALID;
    }
    it->second.attached = true;
  }
  for (const auto& [profile, list] : rt.suggested) {
    for (const auto& [id, path] : list) {
      const auto it = rt.actions.find(id);
      Source source;
      std::string user;
      if (it == rt.actions.end() || !rt.action_sets.at(it->second.set).attached ||
          !binding_source(rt, profile, path, source, user)) {
        continue;
      }
      it->second.bindings.emplace_back(find_path(rt, user), source);
      if (source == Source::kGaze) {
        rt.record.gaze_bound = true;
      } else {
        rt.record.interaction = "controllers";
      }
    }
  }
  s.actions_attached = true;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL SyncActions(XrSession session, const XrActionsSyncInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_ACTIONS_SYNC_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (!rt.session_state.actions_attached) {
    return rt.refuse("xrSyncActions", XR_ERROR_ACTIONSET_NOT_ATTACHED);
  }
  ++rt.record.syncs_since_frame;
  return rt.session_state.state == XR_SESSION_STATE_FOCUSED ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

XrResult XRAPI_CALL GetActionStatePose(XrSession session, const XrActionStateGetInfo* info,
                                       XrActionStatePose* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || out == nullptr || info->type != XR_TYPE_ACTION_STATE_GET_INFO ||
      out->type != XR_TYPE_ACTION_STATE_POSE) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const auto it = rt.actions.find(from_handle(info->action));
  if (it == rt.actions.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (!rt.action_sets.at(it->second.set).attached) {
    return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  }
  if (it->second.type != XR_ACTION_TYPE_POSE_INPUT) {
    return XR_ERROR_ACTION_TYPE_MISMATCH;
  }
  out->isActive = XR_FALSE;
  if (rt.session_state.state != XR_SESSION_STATE_FOCUSED) {
    return XR_SUCCESS;
  }
  for (const auto& [user, source] : it->second.bindings) {
    if (info->subactionPath == XR_NULL_PATH || info->subactionPath == user) {
      out->isActive = XR_TRUE;
    }
  }
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
