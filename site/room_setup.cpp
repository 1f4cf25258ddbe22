#include "site/room_setup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace deixis::site {

namespace {

constexpr float kDegToRad = 3.14159265358979f / 180.0f;

std::string format_cm(float metres) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f cm", static_cast<double>(metres * 100.0f));
  return text;
}

// The point inside the object, or within `margin` of its surface.
bool within_reach(const TargetObject& object, const Vec3& p, float margin) {
  const Vec3 offset = (p - object.position).cwiseAbs();
  const bool inside = object.kind == TargetKind::kSphere
                          ? offset.norm() <= object.size.x() / 2.0f
                          : (offset.array() <= object.size.array() / 2.0f).all();
  return inside || (closest_surface_point(object, p) - p).norm() <= margin;
}

}  // namespace

std::string_view setup_tool_name(SetupTool tool) {
  switch (tool) {
    case SetupTool::kTouch:
      return "touch";
    case SetupTool::kPoint:
      return "point";
    case SetupTool::kResize:
      return "resize";
  }
  return "?";
}

Vec3 centre_behind_touch(TargetKind kind, const Vec3& size, const Vec3& eye, const Vec3& touched) {
  const Vec3 along = touched - eye;
  const float n = along.norm();
  if (n < 1e-4f) {
    return touched;
  }
  const Vec3 d = along / n;
  if (kind == TargetKind::kSphere) {
    return touched + d * (size.x() / 2.0f);
  }
  // The box's (axis-aligned, as the renderer and the contact logic take it) half-extent through
  // its side in direction d: the first of its three slabs the ray from the centre leaves.
  float t = std::numeric_limits<float>::max();
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) > 1e-6f) {
      t = std::min(t, size[axis] / 2.0f / std::abs(d[axis]));
    }
  }
  return touched + d * t;
}

std::optional<RayMeeting> triangulate(const SetupRay& a, const SetupRay& b, float min_angle_deg) {
  // Closest points a.o + s a.d and b.o + t b.d (unit directions): solve the 2 × 2 normal system.
  const Vec3 w = a.origin - b.origin;
  const float c = a.direction.dot(b.direction);
  const float denominator = 1.0f - c * c;  // sin² of the angle between the rays
  if (denominator < std::pow(std::sin(min_angle_deg * kDegToRad), 2.0f)) {
    return std::nullopt;
  }
  const float d = a.direction.dot(w);
  const float e = b.direction.dot(w);
  const float s = (c * e - d) / denominator;
  const float t = (e - c * d) / denominator;
  if (s <= 0.0f || t <= 0.0f) {
    return std::nullopt;  // the rays diverge: they meet behind where the user stood
  }
  const Vec3 pa = a.origin + a.direction * s;
  const Vec3 pb = b.origin + b.direction * t;
  return RayMeeting{(pa + pb) / 2.0f, (pa - pb).norm()};
}

RoomSetup::RoomSetup(TargetMap map, Hand hand, std::string_view source)
    : map_(std::move(map)), hand_(hand) {
  if (map_.objects.empty()) {
    throw Error(std::string(source) +
                ": objects: none to set up (the room's objects are listed in the target map, "
                "docs/target-map.md)");
  }
  prompt();
}

bool RoomSetup::hand_ready(const TrackingFrame& user) const {
  return (user.valid & tracked::kHead) != 0 && (user.valid & tracked::hand(hand_)) != 0;
}

bool RoomSetup::update(const TrackingFrame& user, const SetupControls& controls) {
  if (controls.next_tool || controls.next_object) {
    const bool landed = release();  // whatever was held lands first
    if (controls.next_tool) {
      tool_ = static_cast<SetupTool>((static_cast<int>(tool_) + 1) % 3);
    }
    if (controls.next_object) {
      current_ = (current_ + 1) % map_.objects.size();
    }
    first_ray_.reset();
    prompt();
    return landed;
  }
  if (hold_ != Hold::kNone) {
    if (!controls.act) {
      return release();
    }
    if (hand_ready(user)) {
      follow(user);
    }
    return false;
  }
  if (controls.act_pressed) {
    if (!hand_ready(user)) {
      tell("your " + std::string(hand_ == Hand::kLeft ? "left" : "right") +
           " hand or your head is not tracked: try again");
      return false;
    }
    if (tool_ == SetupTool::kPoint) {
      return mark_ray(user);
    }
    press(user);
  }
  return false;
}

void RoomSetup::press(const TrackingFrame& user) {
  TargetObject& object = map_.objects[current_];
  const Vec3 tip = user.index_tip[static_cast<std::size_t>(index(hand_))];
  if (tool_ == SetupTool::kResize) {
    hold_ = Hold::kResize;
    size_at_press_ = object.size;
    reach_at_press_ = std::max((tip - object.position).norm(), 0.02f);
    tell("resizing " + object.name + ": move your hand away to grow it, nearer to shrink it");
    return;
  }
  // Touch: grab it where it is, or put its near surface at the fingertip.
  if (!within_reach(object, tip, kGrabMarginM)) {
    object.position =
        centre_behind_touch(object.kind, object.size, user.T_world_head.translation, tip);
  }
  grab_offset_ = object.position - tip;
  hold_ = Hold::kMove;
  tell("moving " + object.name + ": let go to put it down");
}

void RoomSetup::follow(const TrackingFrame& user) {
  TargetObject& object = map_.objects[current_];
  const Vec3 tip = user.index_tip[static_cast<std::size_t>(index(hand_))];
  if (hold_ == Hold::kMove) {
    object.position = tip + grab_offset_;
    return;
  }
  const float scale = (tip - object.position).norm() / reach_at_press_;
  object.size = (size_at_press_ * scale)
                    .cwiseMax(Vec3::Constant(kMinSizeM))
                    .cwiseMin(Vec3::Constant(kMaxSizeM));
  if (object.kind == TargetKind::kSphere) {
    object.size = Vec3::Constant(object.size.x());  // a sphere's diameter in all three
  }
}

bool RoomSetup::release() {
  if (hold_ == Hold::kNone) {
    return false;
  }
  const TargetObject& object = map_.objects[current_];
  tell(std::string(hold_ == Hold::kMove ? "placed " : "resized ") + object.name + " (" +
       format_cm(object.size.maxCoeff()) + ")");
  hold_ = Hold::kNone;
  ++edits_;
  return true;
}

bool RoomSetup::mark_ray(const TrackingFrame& user) {
  const Vec3 eye = user.T_world_head.translation;
  const Vec3 tip = user.index_tip[static_cast<std::size_t>(index(hand_))];
  if ((tip - eye).norm() < 0.1f) {
    tell("hold your fingertip out in front of your eyes, on the object");
    return false;
  }
  const SetupRay ray{eye, (tip - eye).normalized()};
  TargetObject& object = map_.objects[current_];
  if (!first_ray_) {
    first_ray_ = ray;
    tell("point at " + object.name + " again from another place (" + format_cm(kMinBaselineM) +
         " or more away)");
    return false;
  }
  if ((ray.origin - first_ray_->origin).norm() < kMinBaselineM) {
    tell("step " + format_cm(kMinBaselineM) + " or more away from where you first pointed");
    return false;
  }
  const std::optional<RayMeeting> meeting = triangulate(*first_ray_, ray, kMinRayAngleDeg);
  if (!meeting || meeting->miss_m > kMaxMissM) {
    first_ray_ = ray;  // this one becomes the first: the user points again from elsewhere
    tell(std::string("the two rays do not meet") +
         (meeting ? " (" + format_cm(meeting->miss_m) + " apart)" : "") + ": point at " +
         object.name + " again from another place");
    return false;
  }
  object.position = meeting->point;
  first_ray_.reset();
  ++edits_;
  tell("placed " + object.name + " (rays " + format_cm(meeting->miss_m) + " apart)");
  return true;
}

void RoomSetup::tell(std::string message) {
  message_ = std::move(message);
}

void RoomSetup::prompt() {
  const TargetObject& object = map_.objects[current_];
  switch (tool_) {
    case SetupTool::kTouch:
      tell("touch " + object.name + " and press select (hold to move it)");
      return;
    case SetupTool::kPoint:
      tell("point at " + object.name + " and press select, then again from another place");
      return;
    case SetupTool::kResize:
      tell("hold select and move your hand to resize " + object.name);
      return;
  }
}

}  // namespace deixis::site
