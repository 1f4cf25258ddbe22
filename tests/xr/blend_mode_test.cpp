// Which environment blend mode `deixis xr` submits in (xr/blend_mode.h): --blend auto prefers the
// see-through modes whatever order the system lists them in; an explicit choice must be offered
// and its refusal names what is; only ALPHA_BLEND takes the layer's alpha.

#include "xr/blend_mode.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"

namespace deixis::xr {
namespace {

constexpr XrEnvironmentBlendMode kOpaque = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
constexpr XrEnvironmentBlendMode kAlpha = XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND;
constexpr XrEnvironmentBlendMode kAdditive = XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;

TEST(BlendMode, AutoPrefersAlphaThenAdditiveThenOpaque) {
  using Modes = std::vector<XrEnvironmentBlendMode>;
  EXPECT_EQ(choose_blend_mode(Modes{kOpaque, kAdditive, kAlpha}, BlendChoice::kAuto), kAlpha);
  EXPECT_EQ(choose_blend_mode(Modes{kOpaque, kAdditive}, BlendChoice::kAuto), kAdditive);
  EXPECT_EQ(choose_blend_mode(Modes{kOpaque}, BlendChoice::kAuto), kOpaque);
  EXPECT_THROW(choose_blend_mode(Modes{}, BlendChoice::kAuto), Error);
}

TEST(BlendMode, AChoiceMustBeOfferedAndItsRefusalNamesWhatIs) {
  using Modes = std::vector<XrEnvironmentBlendMode>;
  const Modes both{kAlpha, kOpaque};
  EXPECT_EQ(choose_blend_mode(both, BlendChoice::kOpaque), kOpaque);
  EXPECT_EQ(choose_blend_mode(both, BlendChoice::kAlpha), kAlpha);
  try {
    choose_blend_mode(both, BlendChoice::kAdditive);
    FAIL() << "additive is not offered";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "--blend additive: the OpenXR system offers only alpha, opaque");
  }
}

TEST(BlendMode, ParsesTheFlagsValuesAndNothingElse) {
  EXPECT_EQ(parse_blend_choice("auto"), BlendChoice::kAuto);
  EXPECT_EQ(parse_blend_choice("opaque"), BlendChoice::kOpaque);
  EXPECT_EQ(parse_blend_choice("alpha"), BlendChoice::kAlpha);
  EXPECT_EQ(parse_blend_choice("additive"), BlendChoice::kAdditive);
  EXPECT_FALSE(parse_blend_choice("ALPHA_BLEND"));
  EXPECT_FALSE(parse_blend_choice(""));
}

TEST(BlendMode, OnlyAlphaBlendTakesTheLayersAlpha) {
  EXPECT_EQ(projection_layer_flags(kAlpha), XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT);
  EXPECT_EQ(projection_layer_flags(kAdditive), 0u);
  EXPECT_EQ(projection_layer_flags(kOpaque), 0u);
  EXPECT_TRUE(see_through(kAlpha));
  EXPECT_TRUE(see_through(kAdditive));
  EXPECT_FALSE(see_through(kOpaque));
}

}  // namespace
}  // namespace deixis::xr
