// The remote people of a site (site/remote_people.h) allocate nothing per tick once everyone has
// met: three people on room C's spots (both deictic hands; one in their own avatar, the BCN test
// rig, the others in the site's), measured (completion states and
// gazes observed), their frames played batched, one of them missing frames, over 90 ticks of
// people_targets, tick and end_tick. Not built under ASan (tests/CMakeLists.txt).

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "allocation_counter.h"
#include "avatar/avatar_loader.h"
#include "avatar/bcn_rig.h"  // tests/avatar
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "site/avatar_cache.h"
#include "site/remote_people.h"
#include "test_support.h"

namespace deixis::site {
namespace {

TEST(RemotePeopleHotPath, TicksAllocateNothingOnceEveryoneHasMet) {
  SiteConfig c = read_site_config(deixis::testing::source_dir() / "assets/sites/c.json");
  c.spots.push_back(Placement{Vec3(1.3f, 0.0f, -1.4f), 140.0f});
  const ik::AvatarSolver solver = ik::AvatarSolver::build(avatar::load_avatar(c.avatar_path).rig);
  const std::array<MoeNetworks, 2> networks = {
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)};
  // Right-handed 172 and left-handed 173, pointing at objects 1 and 3 in room C.
  std::vector<capture::ScriptPerformance> performances;
  for (const char* subject : {"172", "173", "172"}) {
    std::vector<ScriptStep> script(2);
    script[0].action = script[1].action = ScriptStep::Action::kPoint;
    script[0].target = 1;
    script[1].target = 3;
    const capture::VirtualUserScene scene{c.user.T_world_floor(), c.target_map.objects,
                                          Vec3(0, 1.6f, -2.2f)};
    performances.push_back(
        capture::perform_script(capture::find_subject(subject), script, scene, 3, 6.0));
  }
  RemotePeople people(c, networks, solver, RemotePeopleOptions{256});
  // Person 2 wears their own avatar (the BCN test rig), the others the site's: two rigs.
  const std::shared_ptr<const PersonAvatar> bcn =
      load_person_avatar(deixis::testing::bcn_glb(), AvatarSource::kChosen);
  deixis::testing::AllocationCounter meeting;
  for (PersonId id = 1; id <= 3; ++id) {
    net::Hello hello;
    hello.site = std::string(1, static_cast<char>('A' + id - 1));
    hello.avatar.body = performances[id - 1].sequence.calibration;
    people.meet(id, hello);
  }
  EXPECT_GT(meeting.count(), 0u) << "the counter must see what meet() allocates";
  ASSERT_TRUE(people.wear(2, bcn));
  const auto tick = [&](std::size_t i) {
    LocalTargets room{&c.target_map, Vec3(0, 1.6f, 0)};
    room.people = people.people_targets(4, room.partner_head);
    std::array<PersonFrame, 3> frames;
    for (PersonId id = 1; id <= 3; ++id) {
      const auto& f = performances[id - 1].sequence.frames;
      const bool lost = id == 2 && i % 7 == 3;
      frames[id - 1] = PersonFrame{id, lost ? nullptr : &f[i % f.size()],
                                   static_cast<std::uint32_t>(i), &c.target_map};
    }
    people.tick(frames, room, static_cast<double>(i) / 30.0);
    people.end_tick();
  };
  std::size_t i = 0;
  for (; i < 30; ++i) {
    tick(i);
  }
  deixis::testing::AllocationCounter counter;
  for (; i < 120; ++i) {
    tick(i);
  }
  EXPECT_EQ(counter.count(), 0u) << "over 90 ticks of three people in two rigs";
  EXPECT_EQ(people.visible().size(), 3u);
  EXPECT_EQ(people.avatar(2)->model_pose().size(),
            static_cast<std::size_t>(bcn->solver.joint_count()));
  EXPECT_NE(bcn->solver.joint_count(), solver.joint_count());
  EXPECT_GT(people.stats(2)->frames_missed, 10u);
}

}  // namespace
}  // namespace deixis::site
