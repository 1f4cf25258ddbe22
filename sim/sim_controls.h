#pragma once
// What the person's mouse and keys mean in the simulator (docs/sim.md):
//
//   local view (A)   right-drag: look around (head and eyes); click an object: point at it;
//                    shift-click or middle-click: touch it
//   remote view (B)  drag an object: it slides across the room at its height, and the avatar
//                    adapts on the next tick (the translator reads B's target map every tick)
//   keys             E explain (free-form gestures), R rest (idle), P look at the other person,
//                    Q or Esc quit
//
// The panel's buttons run the same commands. A scripted user (--script) ignores the user's
// commands; dragging still works.

#include <string>

#include "sim/sim_input.h"
#include "sim/sim_user.h"
#include "sim/sim_views.h"

namespace deixis::sim {

enum class UserCommand { kLookAtPartner, kPoint, kTouch, kExplain, kRest };

class SimControls {
 public:
  // `user` is null for a scripted user. `remote_map` is the map the remote avatar's translator
  // reads; dragging moves its objects in place. All must outlive the controls.
  SimControls(RoomView& local, RoomView& remote, const TargetMap& local_map, TargetMap& remote_map,
              SimUser* user);

  // This frame's input at simulator time `t`. `pointer_free` / `keys_free`: the panel does not
  // want the mouse / keyboard. Returns false when the person asked to quit.
  bool apply(const FrameInput& in, bool pointer_free, bool keys_free, double t);
  // A user command (from a key, a click or the panel); the outcome goes to status().
  void run(UserCommand command, TargetId target, double t);
  // Puts B's objects back where its target map first had them.
  void reset_objects();

  const std::string& status() const { return status_; }
  TargetId dragging() const { return dragged_; }

 private:
  void press(const FrameInput& in, double t);
  void drag(const FrameInput& in);
  void move_object(TargetObject& object, const Vec3& position);

  RoomView& local_;
  RoomView& remote_;
  const TargetMap& local_map_;
  TargetMap& remote_map_;
  const TargetMap original_remote_;
  SimUser* user_;
  std::string status_;
  // A drag in the remote view: the object, and its centre's offset from the point grabbed on the
  // horizontal plane through that centre.
  TargetId dragged_ = kNoTarget;
  Vec3 grab_offset_ = Vec3::Zero();
  // A look in the local view: where the right button went down and the look angles then.
  bool looking_ = false;
  render::Vec2 look_anchor_ = render::Vec2::Zero();
  LookAngles look_start_;
};

}  // namespace deixis::sim
