// Tracking through the C API: the structs' defaults, the upright calibration and the target
// selection of a live user.
#include <cmath>

#include "api/boundary.h"
#include "api/conversions.h"
#include "api/handles.h"
#include "gesture/upright_calibration.h"

using namespace deixis;
using namespace deixis::api;

extern "C" {

void deixis_tracking_frame_init(deixis_tracking_frame* frame) {
  if (frame != nullptr) {
    *frame = to_c(TrackingFrame{});
  }
}

void deixis_body_calibration_init(deixis_body_calibration* body) {
  if (body != nullptr) {
    *body = to_c(BodyCalibration{});
  }
}

void deixis_upright_body_init(deixis_upright_body* body) {
  if (body != nullptr) {
    *body = {DEIXIS_HAND_RIGHT, 0.0f, 0.0f};
  }
}

deixis_status deixis_calibrate_upright(const deixis_tracking_frame* upright,
                                       const deixis_upright_body* body,
                                       deixis_body_calibration* out, deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_INVALID_ARGUMENT, [&] {
    require(upright != nullptr && body != nullptr && out != nullptr,
            "deixis_calibrate_upright: upright, body and out must not be null");
    require(body->deictic_hand == DEIXIS_HAND_LEFT || body->deictic_hand == DEIXIS_HAND_RIGHT,
            "deixis_calibrate_upright: deictic_hand is not DEIXIS_HAND_LEFT 0 or _RIGHT 1");
    require(std::isfinite(body->height) && std::isfinite(body->arm_length),
            "deixis_calibrate_upright: height and arm_length must be finite (0: estimate)");
    const TrackingFrame frame = from_c(*upright);
    require(frame.T_world_head.rotation.allFinite() && frame.T_world_head.translation.allFinite(),
            "deixis_calibrate_upright: the head pose is not finite (or a zero quaternion)");
    const UprightBody known{static_cast<Hand>(body->deictic_hand), body->height, body->arm_length};
    *out = to_c(calibrate_upright(frame, known));
  });
}

deixis_status deixis_target_selector_create(uint32_t abi_version,
                                            const deixis_body_calibration* user, uint8_t self,
                                            deixis_target_selector** out, deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_INVALID_ARGUMENT, [&] {
    check_abi(abi_version);
    require(out != nullptr && user != nullptr,
            "deixis_target_selector_create: user and out must not be null");
    *out = nullptr;
    require(self <= kMaxPersonId, "deixis_target_selector_create: self is 0 or a person 1..254");
    auto handle = std::make_unique<deixis_target_selector>();
    handle->selector.config = target_selection_for(from_c(*user));
    handle->self = self;
    *out = handle.release();
  });
}

void deixis_target_selector_destroy(deixis_target_selector* selector) {
  delete selector;
}

const char* deixis_target_selector_last_error(const deixis_target_selector* selector) {
  return selector == nullptr ? "null target selector" : selector->last_error.c_str();
}

deixis_status deixis_target_selector_select(deixis_target_selector* selector,
                                            deixis_tracking_frame* frame, const deixis_room* room,
                                            int32_t two_site) {
  if (selector == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&selector->last_error, [&] {
    require(frame != nullptr && room != nullptr,
            "deixis_target_selector_select: frame and room must not be null");
    TrackingFrame tracking = from_c(*frame);
    const SelectionCandidates candidates{
        &room->map, two_site != 0 ? &room->partner_head : nullptr,
        std::span<const PersonTarget>(room->people.data(), room->people_count), selector->self};
    selector->selector.select(tracking, candidates);
    frame->head_target = tracking.head_target;
    frame->hand_target = tracking.hand_target;
    frame->head_target_position = to_c(tracking.head_target_position);
    frame->hand_target_position = to_c(tracking.hand_target_position);
  });
}

}  // extern "C"
