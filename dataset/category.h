#pragma once
// The ten action categories of the authors' capture (paper §III.A), in the order of their
// training and test scripts (docs/conventions.md#training-data). A dataset stores a category as
// its index here (docs/dataset.md); the capture performs them, training and the evaluation
// select by them.

#include <array>
#include <cstdint>
#include <string_view>

namespace deixis::dataset {

enum class Category : std::uint8_t {
  kPointingSingle = 0,   // pointing and gazing at a single target
  kPointingTwoTargets,   // pointing and gazing at two targets in sequence
  kPointingGazeShift,    // pointing at a target, gaze briefly shifts to a second and back
  kPointingExplanation,  // explaining to a person, pointing at an object, explaining again
  kPointingTransition,   // alternating pointing at a target and free-form gestures
  kTouchingSingle,
  kTouchingGazeShift,
  kTouchingExplanation,
  kTouchingTwoTargets,
  kTouchingTransition,
};
inline constexpr int kCategoryCount = 10;

inline constexpr std::array<Category, kCategoryCount> kAllCategories = {
    Category::kPointingSingle,      Category::kPointingTwoTargets,  Category::kPointingGazeShift,
    Category::kPointingExplanation, Category::kPointingTransition,  Category::kTouchingSingle,
    Category::kTouchingGazeShift,   Category::kTouchingExplanation, Category::kTouchingTwoTargets,
    Category::kTouchingTransition};

// Command-line names, e.g. "pointing-single" (the metadata "categories" lists them).
std::string_view category_name(Category category);
// The authors' folder names, e.g. "Pointing at single target".
std::string_view category_title(Category category);
// Parses a command-line name; an unknown name is a deixis::Error listing the known ones.
Category parse_category(std::string_view name);

bool is_touching(Category category);
// Categories with free-form movement: UGNet's free-form hold (docs/conventions.md#training-data;
// the authors' data_parser.py: transitions and explanations).
bool has_free_form(Category category);
// Categories the paper augments by speed (×0.5, ×2; paper §III.C).
bool is_speed_augmented(Category category);
// The deictic-gesture (DG) categories: single and two targets, pointing and touching — the kind
// of data AMNet was trained on (paper §V.B, docs/decisions.md).
bool is_deictic_gesture(Category category);

}  // namespace deixis::dataset
