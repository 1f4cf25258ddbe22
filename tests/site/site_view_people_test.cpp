// A site's headless view (site/site_view.h) draws every visible remote person's avatar in the
// right view: with three people on three spots of room C, taking any one away changes that
// view's pixels where it stood and leaves the user's view (left) as it was. Needs EGL
// (surfaceless Mesa; llvmpipe without a GPU).

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#include "avatar/avatar_loader.h"
#include "site/remote_people.h"
#include "site/site_view.h"
#include "test_support.h"

namespace deixis::site {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 180;

// Pixels of one half (0 left, 1 right) that differ between two frames by more than a rounding.
int differing(const render::Image& a, const render::Image& b, int half) {
  int n = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = half * kWidth; x < (half + 1) * kWidth; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * 2 * kWidth + x) * 3;
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(int{a.rgb[i + c]} - int{b.rgb[i + c]}));
      }
      n += d > 8 ? 1 : 0;
    }
  }
  return n;
}

TEST(SiteViewPeople, EveryVisibleAvatarIsDrawn) {
  SiteConfig c = read_site_config(deixis::testing::source_dir() / "assets/sites/c.json");
  c.spots.push_back(Placement{Vec3(1.3f, 0.0f, -1.4f), 140.0f});
  const avatar::Avatar avatar = avatar::load_avatar(c.avatar_path);
  const ik::AvatarSolver solver = ik::AvatarSolver::build(avatar.rig);
  const std::array<MoeNetworks, 2> networks = {
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)};
  RemotePeople people(c, networks, solver);
  std::vector<AvatarPicture> remote;
  for (PersonId id = 1; id <= 3; ++id) {
    net::Hello hello;
    hello.site = std::string(1, static_cast<char>('A' + id - 1));
    const presence::RemoteAvatar& a = people.meet(id, hello);
    remote.push_back({a.T_world_model(), a.model_pose()});  // the rest pose on its spot
  }
  const Pose user_origin = presence::avatar_origin(solver, c.user.T_world_floor());
  const AvatarPicture user{ik::T_world_root_from_origin(solver, user_origin), solver.rest_model};

  SiteView view(c, avatar, kWidth, kHeight, {});
  view.draw(user, remote);
  const render::Image all = view.frame();
  ASSERT_EQ(all.width, 2 * kWidth);
  view.draw(user, std::span<const AvatarPicture>());
  const render::Image none = view.frame();
  EXPECT_GT(differing(all, none, 1), 3 * 200);
  for (std::size_t gone = 0; gone < remote.size(); ++gone) {
    std::vector<AvatarPicture> others = remote;
    others.erase(others.begin() + static_cast<std::ptrdiff_t>(gone));
    view.draw(user, others);
    EXPECT_GT(differing(all, view.frame(), 1), 200) << "avatar on spot " << gone << " not drawn";
    EXPECT_EQ(differing(all, view.frame(), 0), 0) << "the user's view changed";
  }
  // The one-avatar form draws the first.
  view.draw(user, &remote[0]);
  std::vector<AvatarPicture> first = {remote[0]};
  const render::Image one = view.frame();
  view.draw(user, first);
  EXPECT_EQ(differing(one, view.frame(), 1), 0);
}

}  // namespace
}  // namespace deixis::site
