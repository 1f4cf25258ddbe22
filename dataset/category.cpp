#include "dataset/category.h"

#include <string>

#include "core/error.h"

namespace deixis::dataset {

namespace {

struct Names {
  std::string_view name;
  std::string_view title;
};

constexpr std::array<Names, kCategoryCount> kNames = {{
    {"pointing-single", "Pointing at single target"},
    {"pointing-two-targets", "Pointing at two targets"},
    {"pointing-gaze-shift", "Pointing at single target with gaze shift"},
    {"pointing-explanation", "Pointing at single target with explanation"},
    {"pointing-transition", "Transition (Pointing)"},
    {"touching-single", "Touching single target"},
    {"touching-gaze-shift", "Touching single target with gaze shift"},
    {"touching-explanation", "Touching single target with explanation"},
    {"touching-two-targets", "Touching two targets"},
    {"touching-transition", "Transition (Touching)"},
}};

}  // namespace

std::string_view category_name(Category category) {
  return kNames[static_cast<std::size_t>(category)].name;
}

std::string_view category_title(Category category) {
  return kNames[static_cast<std::size_t>(category)].title;
}

Category parse_category(std::string_view name) {
  std::string known;
  for (const Category c : kAllCategories) {
    if (category_name(c) == name) {
      return c;
    }
    if (!known.empty()) {
      known.append(", ");
    }
    known.append(category_name(c));
  }
  throw Error("unknown category '" + std::string(name) + "' (known: " + known + ")");
}

bool is_touching(Category c) {
  return c >= Category::kTouchingSingle;
}

bool has_free_form(Category c) {
  return c == Category::kPointingExplanation || c == Category::kPointingTransition ||
         c == Category::kTouchingExplanation || c == Category::kTouchingTransition;
}

bool is_deictic_gesture(Category c) {
  return c == Category::kPointingSingle || c == Category::kPointingTwoTargets ||
         c == Category::kTouchingSingle || c == Category::kTouchingTwoTargets;
}

bool is_speed_augmented(Category c) {
  return is_deictic_gesture(c);  // the single- and two-target categories (docs/dataset.md#files)
}

}  // namespace deixis::dataset
