#include "sim/sim_controls.h"

#include "sim/sim_pick.h"

namespace deixis::sim {

namespace {

constexpr float kLookPerPixel = 0.005f;  // rad per pixel of a look drag (0.29°)
constexpr double kExplainSeconds = 3.0;

const TargetObject* find_object(const TargetMap& map, TargetId id) {
  return map.find(id);
}

}  // namespace

SimControls::SimControls(RoomView& local, RoomView& remote, const TargetMap& local_map,
                         TargetMap& remote_map, SimUser* user)
    : local_(local),
      remote_(remote),
      local_map_(local_map),
      remote_map_(remote_map),
      original_remote_(remote_map),
      user_(user),
      status_(user != nullptr ? "Ready: click an object on the left to point at it"
                              : "The user follows the site's script") {}

bool SimControls::apply(const FrameInput& in, bool pointer_free, bool keys_free, double t) {
  if (keys_free) {
    for (std::size_t k = 0; k < in.key_count; ++k) {
      switch (in.keys[k]) {
        case 'e':
          run(UserCommand::kExplain, kNoTarget, t);
          break;
        case 'r':
          run(UserCommand::kRest, kNoTarget, t);
          break;
        case 'p':
          run(UserCommand::kLookAtPartner, kNoTarget, t);
          break;
        case 'q':
          return false;
        default:
          break;
      }
    }
  }
  // A drag or look in progress continues even over the panel; new ones start only in a view.
  if (pointer_free) {
    press(in, t);
  }
  drag(in);
  if (in.was_released(Button::kLeft)) {
    dragged_ = kNoTarget;
  }
  if (in.was_released(Button::kRight)) {
    looking_ = false;
  }
  return true;
}

void SimControls::press(const FrameInput& in, double t) {
  const bool left = in.was_pressed(Button::kLeft);
  const bool middle = in.was_pressed(Button::kMiddle);
  if (local_.rect().contains(in.pointer)) {
    if (in.was_pressed(Button::kRight) && user_ != nullptr) {
      looking_ = true;
      look_anchor_ = in.pointer;
      look_start_ = user_->look_angles();
    }
    if (left || middle) {
      const TargetId id = pick_object(local_.ray(in.pointer), local_map_);
      if (id != kNoTarget) {
        run(middle || in.shift ? UserCommand::kTouch : UserCommand::kPoint, id, t);
      }
    }
  } else if (remote_.rect().contains(in.pointer) && left) {
    const render::Ray ray = remote_.ray(in.pointer);
    const TargetId id = pick_object(ray, remote_map_);
    const TargetObject* object = find_object(remote_map_, id);
    if (object != nullptr) {
      if (const auto grabbed = ray_at_height(ray, object->position.y())) {
        dragged_ = id;
        grab_offset_ = object->position - *grabbed;
        status_ = "Moving " + object->name + " in room " + remote_map_.site;
      }
    }
  }
}

void SimControls::drag(const FrameInput& in) {
  if (looking_ && in.is_down(Button::kRight) && user_ != nullptr) {
    const render::Vec2 d = in.pointer - look_anchor_;
    // Dragging right turns to the right (negative yaw), dragging up looks up.
    user_->look(
        {look_start_.yaw - kLookPerPixel * d.x(), look_start_.pitch - kLookPerPixel * d.y()});
  }
  if (dragged_ == kNoTarget || !in.is_down(Button::kLeft)) {
    return;
  }
  for (TargetObject& object : remote_map_.objects) {
    if (object.id != dragged_) {
      continue;
    }
    if (const auto p = ray_at_height(remote_.ray(in.pointer), object.position.y())) {
      move_object(object,
                  Vec3(p->x() + grab_offset_.x(), object.position.y(), p->z() + grab_offset_.z()));
    }
  }
}

void SimControls::move_object(TargetObject& object, const Vec3& position) {
  object.position = position;
  remote_.renderer().move_target(object.id, position);
}

void SimControls::reset_objects() {
  for (std::size_t i = 0; i < remote_map_.objects.size(); ++i) {
    move_object(remote_map_.objects[i], original_remote_.objects[i].position);
  }
  status_ = "Room " + remote_map_.site + "'s objects are back in place";
}

void SimControls::run(UserCommand command, TargetId target, double t) {
  if (user_ == nullptr) {
    status_ = "The user follows the site's script (--script): commands are off";
    return;
  }
  const TargetObject* object = find_object(local_map_, target);
  const std::string name = object != nullptr ? object->name : std::to_string(target);
  std::string refused;
  switch (command) {
    case UserCommand::kLookAtPartner:
      user_->look_at_partner(t);
      status_ = "Looking at the other person";
      return;
    case UserCommand::kPoint:
      refused = user_->point(t, target);
      status_ = refused.empty() ? "Pointing at " + name : refused;
      return;
    case UserCommand::kTouch:
      refused = user_->touch(t, target);
      status_ = refused.empty() ? "Touching " + name : refused;
      return;
    case UserCommand::kExplain:
      user_->explain(t, kExplainSeconds);
      status_ = "Explaining (free-form gestures)";
      return;
    case UserCommand::kRest:
      user_->rest(t);
      status_ = "Resting (idle)";
      return;
  }
}

}  // namespace deixis::sim
