#pragma once
// A tracked person's body calibration from one frame in the upright posture (paper §IV.A: the
// user stands upright once; root O sits at the head with the head's yaw only). For a headset
// user, whose body the site does not know: the root from the head pose; the stature from the eye
// height (eyes at 0.936 of stature, the anthropometric ratio the synthetic capture's bodies use)
// unless given; the arm length as 0.435 of stature (the capture's training subject, 74 cm at
// 170 cm) unless given; the rest wrists where the tracked hands hang, or the default posture
// scaled to the stature when a hand is not tracked or not hanging.

#include "core/tracking.h"

namespace deixis {

struct UprightBody {
  Hand deictic_hand = Hand::kRight;
  float height = 0.0f;      // m; 0: from the eye height
  float arm_length = 0.0f;  // m; 0: from the height
};

// Throws deixis::Error when the head is not tracked or the body is out of human range.
BodyCalibration calibrate_upright(const TrackingFrame& upright, const UprightBody& body);

}  // namespace deixis
