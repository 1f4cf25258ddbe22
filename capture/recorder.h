#pragma once
// What every planned performance shares once its tracks and labels are written (script.h's
// categories, virtual_user.h's site scripts): the body calibration a headset would measure, the
// idle course the labeller derives from the motion, and recording at 30 Hz what a perfect tracker
// reports, with the targets and labels of each frame.

#include <span>

#include "capture/labelling.h"
#include "capture/motion.h"
#include "capture/sequence.h"

namespace deixis::capture {

// Root O = H in the upright posture (no sway), yaw-only (paper §IV.A), and the rest wrists.
BodyCalibration calibrate(const Motion& motion);

// The idle label course of `labels` for this motion (adds the idle phase keys to `labels`).
Ramp idle_course(Labelling& labels, const Motion& motion, const BodyCalibration& calibration);

// Records frames 0 … floor(end · 30) into `s` (frames, labels, joints, phase keys). Every head
// and hand target the labels name must be in `targets`; throws deixis::Error otherwise.
void record(const Motion& motion, const Labelling& labels, const Ramp& idle,
            std::span<const TargetObject> targets, double end, Sequence& s);

}  // namespace deixis::capture
