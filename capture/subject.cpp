#include "capture/subject.h"

#include <array>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace deixis::capture {

namespace {

Subject make(std::string name, float height, float arm, float shoulders, Hand hand, Eye eye,
             float speed, Style style) {
  return Subject{std::move(name), height, arm, shoulders, hand, eye, speed, style};
}

// Test subjects follow the paper's five (§V; 173 and 174 are left-handed and use the left-hand
// weights: docs/conventions.md#synthetic-capture).
// Arm lengths are plausible for their heights (≈ 0.44 × height, ± individual variation); eye
// dominance is mixed and crossed with handedness; speed and style differ from the training
// subject, who was asked for a neutral style while the others were given no guidance.
const std::array<Subject, 5>& test_list() {
  static const std::array<Subject, 5> list = {
      make("161", 1.61f, 0.70f, 0.36f, Hand::kRight, Eye::kLeft, 0.90f,
           Style{0.80f, 0.70f, 0.26f, 0.90f, 1.2f}),
      make("172", 1.72f, 0.77f, 0.41f, Hand::kRight, Eye::kRight, 1.15f,
           Style{1.25f, 0.85f, 0.15f, 0.95f, 0.8f}),
      make("173", 1.73f, 0.75f, 0.40f, Hand::kLeft, Eye::kLeft, 0.95f,
           Style{1.10f, 0.75f, 0.22f, 0.92f, 1.0f}),
      make("174", 1.74f, 0.78f, 0.42f, Hand::kLeft, Eye::kRight, 1.10f,
           Style{0.90f, 0.90f, 0.12f, 0.96f, 1.3f}),
      make("180", 1.80f, 0.80f, 0.43f, Hand::kRight, Eye::kLeft, 0.85f,
           Style{1.00f, 0.80f, 0.18f, 0.91f, 0.9f}),
  };
  return list;
}

const std::array<Subject, 5>& validation_list() {
  static const std::array<Subject, 5> list = {
      make("v158", 1.58f, 0.68f, 0.35f, Hand::kRight, Eye::kRight, 1.05f,
           Style{0.90f, 0.75f, 0.20f, 0.93f, 1.1f}),
      make("v166", 1.66f, 0.72f, 0.38f, Hand::kLeft, Eye::kLeft, 0.90f,
           Style{1.15f, 0.85f, 0.17f, 0.94f, 0.9f}),
      make("v168", 1.68f, 0.73f, 0.39f, Hand::kLeft, Eye::kRight, 1.20f,
           Style{0.85f, 0.70f, 0.24f, 0.90f, 1.0f}),
      make("v177", 1.77f, 0.78f, 0.42f, Hand::kRight, Eye::kLeft, 0.95f,
           Style{1.20f, 0.90f, 0.14f, 0.95f, 1.2f}),
      make("v185", 1.85f, 0.82f, 0.45f, Hand::kRight, Eye::kRight, 1.00f,
           Style{1.00f, 0.80f, 0.20f, 0.92f, 0.8f}),
  };
  return list;
}

void check_range(const Subject& s, const char* field, float value, float lo, float hi,
                 const char* unit) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "subject '%s': %s %.3f%s is not in [%.2f, %.2f]",
                  s.name.c_str(), field, static_cast<double>(value), unit, static_cast<double>(lo),
                  static_cast<double>(hi));
    throw Error(buffer);
  }
}

}  // namespace

void validate(const Subject& s) {
  if (s.name.empty()) {
    throw Error("subject: empty name");
  }
  check_range(s, "height", s.height, 1.0f, 2.3f, " m");
  check_range(s, "arm_length", s.arm_length, 0.45f, 1.05f, " m");
  // Arm length (shoulder to fingertip) is 0.40–0.48 of height in adults; allow a wide margin, but
  // not bodies the kinematics cannot reach their own gesture space with.
  check_range(s, "arm_length/height", s.arm_length / s.height, 0.34f, 0.54f, "");
  check_range(s, "shoulder_width", s.shoulder_width, 0.25f, 0.55f, " m");
  check_range(s, "speed", s.speed, 0.4f, 2.5f, "");
  check_range(s, "style.gesture_amplitude", s.style.gesture_amplitude, 0.2f, 2.0f, "");
  check_range(s, "style.head_share", s.style.head_share, 0.2f, 1.0f, "");
  check_range(s, "style.eye_only_range", s.style.eye_only_range, 0.0f, 0.5f, " rad");
  check_range(s, "style.arm_extension", s.style.arm_extension, 0.75f, 0.99f, "");
  check_range(s, "style.sway", s.style.sway, 0.0f, 3.0f, "");
  if (s.handedness != Hand::kLeft && s.handedness != Hand::kRight) {
    throw Error("subject '" + s.name + "': handedness is neither left nor right");
  }
  if (s.dominant_eye != Eye::kLeft && s.dominant_eye != Eye::kRight) {
    throw Error("subject '" + s.name + "': dominant eye is neither left nor right");
  }
}

const Subject& training_subject() {
  static const Subject subject =
      make("170", 1.70f, 0.74f, 0.39f, Hand::kRight, Eye::kRight, 1.0f, Style{});
  return subject;
}

std::span<const Subject> test_subjects() {
  return test_list();
}

std::span<const Subject> validation_subjects() {
  return validation_list();
}

const Subject& find_subject(std::string_view name) {
  if (name == training_subject().name) {
    return training_subject();
  }
  std::string known = training_subject().name;
  for (const auto list : {test_subjects(), validation_subjects()}) {
    for (const Subject& s : list) {
      if (s.name == name) {
        return s;
      }
      known += ", " + s.name;
    }
  }
  throw Error("unknown subject '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace deixis::capture
