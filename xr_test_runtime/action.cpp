// Action sets and actions, suggested bindings for every interaction profile of the spec
// (profiles.h: an unknown profile or path is XR_ERROR_PATH_UNSUPPORTED, §11.4), and attaching:
// each top-level user path takes an interaction profile the application suggested (the script's
// preference order) and each action is bound to the inputs of that profile whose type fits.

#include <algorithm>
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

// The profile a path names, when the spec defines it and its extension (if any) is enabled.
const Profile* usable_profile(const Runtime& rt, const std::string& path) {
  const Profile* p = find_profile(path);
  return p != nullptr && (p->extension == nullptr || rt.extension_enabled(p->extension)) ? p
                                                                                         : nullptr;
}

// The pose a pose binding locates.
Source pose_source(const BindingPath& b) {
  const bool aim = b.identifier->identifier == "aim";
  switch (b.top) {
    case TopLevel::kLeft:
      return aim ? Source::kLeftAim : Source::kLeftGrip;
    case TopLevel::kRight:
      return aim ? Source::kRightAim : Source::kRightGrip;
    case TopLevel::kEyes:
      return Source::kGaze;
    default:
      return Source::kHead;
  }
}

// Whether the application suggested a binding on `top` for `profile`.
bool suggested_for(const Runtime& rt, const Profile& profile, TopLevel top) {
  const auto it = rt.suggested.find(std::string(profile.path));
  if (it == rt.suggested.end()) {
    return false;
  }
  for (const auto& [id, path] : it->second) {
    const std::optional<BindingPath> b = parse_binding(profile, path);
    if (b && b->top == top) {
      return true;
    }
  }
  return false;
}

// The profile `top` takes: the first in the script's preference order (default: profiles()
// order) that the application suggested bindings on `top` for.
const Profile* choose_profile(const Runtime& rt, TopLevel top) {
  const auto try_profile = [&](const Profile* p) {
    return p != nullptr && (p->top_levels & (1u << static_cast<unsigned>(top))) != 0 &&
           usable_profile(rt, std::string(p->path)) != nullptr && suggested_for(rt, *p, top);
  };
  if (!rt.script.profiles.empty()) {
    for (const std::string& path : rt.script.profiles) {
      if (const Profile* p = find_profile(path); try_profile(p)) {
        return p;
      }
    }
    return nullptr;
  }
  for (const Profile& p : profiles()) {
    if (try_profile(&p)) {
      return &p;
    }
  }
  return nullptr;
}

// Binds every attached action to the inputs of `profile` on `top` that fit its type.
void bind_profile(Runtime& rt, const Profile& profile, TopLevel top) {
  const XrPath user = rt.intern(top_level_path(top));
  for (const auto& [id, path] : rt.suggested.at(std::string(profile.path))) {
    const auto it = rt.actions.find(id);
    const std::optional<BindingPath> b = parse_binding(profile, path);
    if (it == rt.actions.end() || !b || b->top != top ||
        !rt.action_sets.at(it->second.set).attached) {
      continue;
    }
    ActionObject& action = it->second;
    const std::uint16_t component = bound_component(action.type, *b);
    const bool in_subactions =
        action.subactions.empty() || std::find(action.subactions.begin(), action.subactions.end(),
                                               user) != action.subactions.end();
    if (component == 0 || !in_subactions) {
      rt.record.ignored_bindings.push_back({action.name, path});
      continue;
    }
    action.bindings.push_back({user, top, b->identifier, component, pose_source(*b), path});
    if (top == TopLevel::kEyes) {
      rt.record.gaze_bound = true;
    } else if (top == TopLevel::kLeft || top == TopLevel::kRight) {
      rt.record.interaction = "controllers";
    }
  }
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
  if (info->actionType != XR_ACTION_TYPE_BOOLEAN_INPUT &&
      info->actionType != XR_ACTION_TYPE_FLOAT_INPUT &&
      info->actionType != XR_ACTION_TYPE_VECTOR2F_INPUT &&
      info->actionType != XR_ACTION_TYPE_POSE_INPUT &&
      info->actionType != XR_ACTION_TYPE_VIBRATION_OUTPUT) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->actionName[0] == '\0' || info->localizedActionName[0] == '\0' ||
      (info->countSubactionPaths > 0 && info->subactionPaths == nullptr)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  for (const auto& [id, other] : rt.actions) {
    if (other.set == from_handle(set) && other.name == info->actionName) {
      return rt.refuse("xrCreateAction", XR_ERROR_NAME_DUPLICATED);
    }
  }
  ActionObject a;
  a.set = from_handle(set);
  a.type = info->actionType;
  a.name = info->actionName;
  a.localized_name = info->localizedActionName;
  for (uint32_t i = 0; i < info->countSubactionPaths; ++i) {
    // Subaction paths are top-level user paths (§11.3), each once.
    const XrPath sub = info->subactionPaths[i];
    bool top_level = false;
    for (std::size_t t = 0; t < kTopLevelCount; ++t) {
      top_level = top_level || rt.path_string(sub) == top_level_path(static_cast<TopLevel>(t));
    }
    if (!top_level ||
        std::find(a.subactions.begin(), a.subactions.end(), sub) != a.subactions.end()) {
      return rt.refuse("xrCreateAction", XR_ERROR_PATH_UNSUPPORTED);
    }
    a.subactions.push_back(sub);
  }
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
  const Profile* profile = usable_profile(rt, rt.path_string(suggested->interactionProfile));
  if (profile == nullptr) {
    return rt.refuse("xrSuggestInteractionProfileBindings", XR_ERROR_PATH_UNSUPPORTED);
  }
  std::vector<std::pair<std::uint64_t, std::string>> bindings;
  for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
    const XrActionSuggestedBinding& b = suggested->suggestedBindings[i];
    const auto action = rt.actions.find(from_handle(b.action));
    if (action == rt.actions.end()) {
      return XR_ERROR_HANDLE_INVALID;
    }
    if (rt.action_sets.at(action->second.set).attached) {
      return rt.refuse("xrSuggestInteractionProfileBindings", XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    }
    const std::string& path = rt.path_string(b.binding);
    if (!parse_binding(*profile, path)) {
      return rt.refuse("xrSuggestInteractionProfileBindings", XR_ERROR_PATH_UNSUPPORTED);
    }
    bindings.emplace_back(from_handle(b.action), path);
  }
  // The latest suggestion for a profile replaces the previous one (spec 11.4).
  auto& stored = rt.suggested[std::string(profile->path)];
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
  for (std::size_t t = 0; t < kTopLevelCount; ++t) {
    const auto top = static_cast<TopLevel>(t);
    s.profiles[t] = choose_profile(rt, top);
    if (s.profiles[t] != nullptr) {
      bind_profile(rt, *s.profiles[t], top);
      rt.record.profiles.emplace_back(top_level_path(top), s.profiles[t]->path);
    }
  }
  for (auto& [id, action] : rt.actions) {
    if (!rt.action_sets.at(action.set).attached) {
      continue;
    }
    action.states.assign(1, ActionState{});
    for (const XrPath sub : action.subactions) {
      action.states.push_back({sub});
    }
  }
  s.actions_attached = true;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
