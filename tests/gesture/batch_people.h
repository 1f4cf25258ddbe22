#pragma once
// A crowd of remote people for the batch tests (translator_batch_test, people_tick_test): each
// person of their own height and deictic hand, standing somewhere in their room, looking and
// reaching at one of three objects in turn, with their own rhythm, arriving at their own tick,
// and with frames that go missing (null) or arrive broken (a NaN) now and then.

#include <cmath>
#include <limits>

#include "core/target_map.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "tracking_frames.h"

namespace deixis::testing {

// One hand's pair of networks from a weight directory (MPNet GRU-MoE and the given UGNet).
struct CrowdNetworks {
  nn::Mpnet mpnet;
  nn::Ugnet ugnet;
};
inline CrowdNetworks load_networks(const std::filesystem::path& dir,
                                   const char* ugnet = "UGNet(MoE)(AC)120.safetensors") {
  return {nn::Mpnet::load(dir / "MPNet(MoE)(AC)80.safetensors"), nn::Ugnet::load(dir / ugnet)};
}

// The three objects, in a sender's room and in this (the receiving) room.
inline Vec3 sender_object(int id) {
  return Vec3(-0.8f + 0.8f * static_cast<float>(id - 1), 1.1f + 0.2f * static_cast<float>(id),
              -1.6f);
}
inline TargetMap receiving_room() {
  TargetMap room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(1.2f, 1.4f, -2.5f), Vec3(0.4f, 0.4f, 0.4f)});
  room.objects.push_back(
      {2, "Box", TargetKind::kBox, Vec3(-0.4f, 0.9f, -1.2f), Vec3(0.3f, 0.3f, 0.3f)});
  room.objects.push_back(
      {3, "Screen", TargetKind::kScreen, Vec3(0.0f, 1.6f, -3.0f), Vec3(1.2f, 0.7f, 0.02f)});
  return room;
}

struct CrowdPerson {
  int index = 0;
  StandingPerson standing;
  int arrives = 0;  // no frame before this tick

  explicit CrowdPerson(int k)
      : index(k),
        standing(k % 3 == 2 ? Hand::kLeft : Hand::kRight,
                 1.55f + 0.07f * static_cast<float>(k % 5)),
        arrives(k % 4 == 3 ? 17 : 0) {}

  Hand hand() const { return standing.body.deictic_hand; }

  // Tracking at tick t: the deictic hand rises toward the current object and back, the head
  // turns toward it; the object changes every 60 ticks.
  TrackingFrame frame(int t) const {
    TrackingFrame f = standing.frame;
    const float s =
        0.5f - 0.5f * std::cos(0.09f * static_cast<float>(t) + 0.7f * static_cast<float>(index));
    const int id = 1 + (t / 60 + index) % 3;
    const Vec3 target = sender_object(id);
    const Vec3 head = f.T_world_head.translation;
    f.T_world_head.rotation = yaw_rotation(-0.4f * s * (target.x() - head.x()));
    f.gaze = (target - head).normalized();
    const Hand h = hand();
    const Vec3 rest = f.T_world_wrist[index_of(h)].translation;
    const Vec3 reach = head + 0.55f * (target - head).normalized() + Vec3(0, -0.15f, 0);
    const Vec3 wrist = rest + s * (reach - rest);
    f.T_world_wrist[index_of(h)].translation = wrist;
    f.index_tip[index_of(h)] =
        wrist + 0.15f * ((1.0f - s) * Vec3(0, -1, 0) + s * (target - wrist).normalized());
    f.head_target = f.hand_target = id;
    f.head_target_position = f.hand_target_position = target;
    f.time = static_cast<double>(t) / 30.0;
    return f;
  }

  // Whether the frame of tick t is missing (null) or arrives with a NaN (rejected, held).
  bool missed(int t) const { return t < arrives || (t * 7 + index * 13) % 23 == 0; }
  bool broken(int t) const { return (t + 5 * index) % 97 == 50; }

  // The frame of tick t as a receiver gets it: null when missed; `storage` holds it otherwise.
  const TrackingFrame* received(int t, TrackingFrame& storage) const {
    if (missed(t)) {
      return nullptr;
    }
    storage = frame(t);
    if (broken(t)) {
      storage.gaze.x() = std::numeric_limits<float>::quiet_NaN();
    }
    return &storage;
  }

 private:
  static std::size_t index_of(Hand h) { return ::deixis::index(h); }
};

// Where person k's avatar stands in the receiving room (root O for the translator, floor point
// for the remote avatar): on a ring facing the middle.
inline float crowd_yaw(int k) {
  return 0.4f * static_cast<float>(k % 16);
}
inline Vec3 crowd_floor(int k) {
  const float a = crowd_yaw(k);
  return Vec3(2.5f * std::sin(a), 0.0f, 2.5f * std::cos(a) - 1.0f);
}

}  // namespace deixis::testing
