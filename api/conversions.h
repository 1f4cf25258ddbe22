#pragma once
// C structs of include/deixis/deixis.h to and from the C++ types they mirror. Plain copies; none
// allocates.
#include "core/tracking.h"
#include "deixis/deixis.h"

namespace deixis::api {

Vec3 from_c(const deixis_vec3& v);
deixis_vec3 to_c(const Vec3& v);
// The quaternion is normalised on the way in; a zero or non-finite one gives a non-finite
// rotation, which the translator rejects as it rejects any non-finite tracking.
Pose from_c(const deixis_pose& pose);
deixis_pose to_c(const Pose& pose);

TrackingFrame from_c(const deixis_tracking_frame& frame);
deixis_tracking_frame to_c(const TrackingFrame& frame);

// Throws deixis::Error for a deictic hand other than 0 or 1.
BodyCalibration from_c(const deixis_body_calibration& body);
deixis_body_calibration to_c(const BodyCalibration& body);

}  // namespace deixis::api
