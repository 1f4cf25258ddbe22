#pragma once
// The people the synthetic capture records (docs/conventions.md#synthetic-capture): body size,
// handedness, eye dominance, speed and movement style. One training subject as in the paper
// (170 cm, 74 cm arm, right-handed, right-eye dominant), the paper's five test subjects (161, 172,
// 173, 174, 180 cm; 173 and 174 left-handed; mixed eye dominance) and extra validation subjects
// for the FMD autoencoder. Test and validation subjects differ from the training subject in body
// *and* seed.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/tracking.h"

namespace deixis::capture {

enum class Eye : std::uint8_t { kLeft = 0, kRight = 1 };

// How a person moves, beyond their size. The defaults are the training subject's neutral style
// (paper §III.A: "a neutral style to ensure data neutrality").
struct Style {
  // Scales the size of free-form strokes and beats.
  float gesture_amplitude = 1.0f;
  // Eye–head coordination (Freedman & Sparks 1997; Stahl 1999): gaze shifts smaller than
  // `eye_only_range` (rad) move the eyes only; beyond it the head takes `head_share` of the rest.
  float head_share = 0.8f;
  float eye_only_range = 0.20f;
  // Shoulder-to-fingertip distance at a pointing completion state, as a fraction of full reach.
  float arm_extension = 0.93f;
  // Scales postural sway while standing.
  float sway = 1.0f;
};

struct Subject {
  std::string name;
  float height = 1.70f;          // m, standing
  float arm_length = 0.74f;      // m, shoulder joint to index fingertip, arm straight
  float shoulder_width = 0.39f;  // m, between the shoulder joints' outer edges (biacromial)
  Hand handedness = Hand::kRight;
  Eye dominant_eye = Eye::kRight;
  float speed = 1.0f;  // movement speed relative to the training subject (durations ÷ speed)
  Style style;
};

// Throws deixis::Error naming the subject and the bad field, e.g.
// "subject '161': height -1.000 m is not in [1.00, 2.30]".
void validate(const Subject& subject);

const Subject& training_subject();
std::span<const Subject> test_subjects();
std::span<const Subject> validation_subjects();

// Any built-in subject by name ("170", "161", …, "v158", …); an unknown name is an error that
// lists the known ones.
const Subject& find_subject(std::string_view name);

}  // namespace deixis::capture
