#pragma once
// Sites, hellos, target maps and moving tracking frames for the net tests and net_peer: the same
// functions on both ends of a connection, so a receiver can check what it got against what the
// sender must have sent.

#include <cmath>
#include <string>

#include "core/target_map.h"
#include "core/tracking.h"
#include "net/messages.h"
#include "net/session.h"

namespace deixis::testing {

inline constexpr double kTick = 1.0 / 30.0;

inline net::Hello make_hello(const std::string& site, float height = 1.72f,
                             Hand hand = Hand::kRight, float yaw = 0.4f) {
  net::Hello h;
  h.site = site;
  h.avatar.model = "default";
  h.avatar.body.height = height;
  h.avatar.body.arm_length = 0.74f;
  h.avatar.body.deictic_hand = hand;
  h.avatar.body.T_world_root = Pose{yaw_rotation(yaw), Vec3(0.5f, 0.94f * height, -1.25f)};
  h.avatar.body.rest_wrist_in_root = {Vec3(-0.21f, -0.76f, 0.02f), Vec3(0.19f, -0.75f, 0.01f)};
  return h;
}

inline TargetMap make_target_map(const std::string& site, int objects = 3) {
  TargetMap m;
  m.site = site;
  const TargetKind kinds[3] = {TargetKind::kSphere, TargetKind::kBox, TargetKind::kScreen};
  for (int i = 0; i < objects; ++i) {
    const float f = static_cast<float>(i);
    m.objects.push_back({i + 1, "object " + std::to_string(i + 1) + " Jüpiter", kinds[i % 3],
                         Vec3(-1.5f + f, 1.0f + 0.1f * f, -2.0f - 0.3f * f),
                         Vec3(0.4f, 0.3f + 0.1f * f, 0.2f)});
  }
  return m;
}

// A person at `root` who looks around and raises and lowers the right hand; every part of the
// frame depends on `sequence`, so a frame that arrives out of place is noticed.
inline TrackingFrame moving_frame(std::uint32_t sequence, const Vec3& root) {
  const float t = static_cast<float>(sequence) * static_cast<float>(kTick);
  TrackingFrame f;
  f.time = static_cast<double>(sequence) * kTick;
  const Mat3 head_rotation = (Eigen::AngleAxisf(0.3f * std::sin(t), Vec3::UnitY()) *
                              Eigen::AngleAxisf(0.1f * std::cos(1.3f * t), Vec3::UnitX()))
                                 .toRotationMatrix();
  f.T_world_head = Pose{head_rotation, root + Vec3(0.02f * std::sin(t), 0.01f, 0.0f)};
  f.gaze = (head_rotation * Vec3(0.1f * std::sin(2.0f * t), -0.05f, -1.0f)).normalized();
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const float side = h == Hand::kRight ? 1.0f : -1.0f;
    const float lift = h == Hand::kRight ? 0.5f + 0.5f * std::sin(0.7f * t) : 0.0f;
    const Mat3 wrist_rotation =
        Eigen::AngleAxisf(side * (0.2f + lift), Vec3::UnitZ()).toRotationMatrix();
    f.T_world_wrist[index(h)] =
        Pose{wrist_rotation, root + Vec3(0.2f * side, -0.75f + 0.6f * lift, -0.4f * lift)};
    f.index_tip[index(h)] =
        f.T_world_wrist[index(h)].translation + wrist_rotation * Vec3(0.15f, 0, 0);
  }
  f.valid = tracked::kAll;
  f.head_target = 1 + static_cast<TargetId>(sequence / 60 % 3);
  f.hand_target = sequence % 200 < 100 ? 2 : kPartnerTarget;
  f.head_target_position = root + Vec3(-1.0f, 0.1f, -2.0f);
  f.hand_target_position = root + Vec3(0.5f, -0.4f, -1.2f);
  return f;
}

inline net::SessionConfig session_config(net::Role role, const std::string& site,
                                         const std::string& passphrase = "") {
  net::SessionConfig c;
  c.role = role;
  c.hello = make_hello(site, role == net::Role::kHost ? 1.72f : 1.64f,
                       role == net::Role::kHost ? Hand::kRight : Hand::kLeft,
                       role == net::Role::kHost ? 0.4f : -2.1f);
  c.target_map = make_target_map(site, role == net::Role::kHost ? 3 : 5);
  c.passphrase = passphrase;
  // The cheapest Argon2id, on the calling thread: unit tests check the protocol on a simulated
  // clock, not the KDF's cost (the joiner's floor is lowered to match; its own tests restore it).
  c.kdf = {1, 8};
  c.min_kdf = {1, 8};
  c.derive_on_this_thread = true;
  return c;
}

}  // namespace deixis::testing
