#pragma once
// Monado's `remote` driver, driven from a test: a headset user who moves, looks and points under
// the real runtime. monado-service with the remote builder (P_OVERRIDE_ACTIVE_CONFIG=remote, the
// port from config_v0.json's "remote" node; tools/monado-env run --remote-port) gives a remote
// HMD and two remote controllers, and listens on that TCP port for `struct r_remote_data`
// (Monado's src/xrt/drivers/remote/r_interface.h, version "mndrmt3", unchanged from Monado 21 to
// 25 and later): the head pose, and per controller a pose, velocities, five finger curls and
// buttons. The driver reads one whole struct at a time and keeps the latest; on a connection it
// first writes its reset pose back, which is checked here to know the layout agrees
// (docs/xr.md, "Monado"). Each controller also simulates a hand (XR_EXT_hand_tracking) from its
// curls, with the wrist joint at the controller's pose: so the controller pose sent is the wrist
// joint the front end reads (xr/input.h).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/math/pose.h"

namespace deixis::app::monado {

static_assert(std::endian::native == std::endian::little,
              "r_remote_data is sent in the host's byte order; Monado's is little-endian x86-64");

// sizeof(struct r_remote_data) for "mndrmt3": header 8, head 128 (two views of fov 16 + pose 28
// + pad 4, the centre pose 28, a bool and 3 pads), two controllers of 120 each.
inline constexpr std::size_t kPacketSize = 376;
inline constexpr char kHeader[8] = {'m', 'n', 'd', 'r', 'm', 't', '3', '\0'};
inline constexpr std::size_t kHeadCenter = 8 + 2 * 48;  // xrt_pose: quaternion xyzw, position
inline constexpr std::size_t kPerViewValid = kHeadCenter + 28;
inline constexpr std::size_t kLeft = 136;
inline constexpr std::size_t kRight = kLeft + 120;
// Within a controller: pose 0, linear velocity 28, angular velocity 40, hand_curl[5] 52 (little,
// ring, middle, index, thumb), analog inputs 72..104, then hand_tracking_active 104, active 105.
inline constexpr std::size_t kCurl = 52;
inline constexpr std::size_t kHandTrackingActive = 104;
inline constexpr std::size_t kActive = 105;

using Packet = std::array<std::uint8_t, kPacketSize>;

// One controller: its pose is the hand's XR_EXT_hand_tracking wrist joint (−Z to the fingers, +Y
// the back of the hand). Curls 0 (straight) to 1 (curled), in Monado's order.
struct RemoteHand {
  bool active = false;
  Pose T_world_joint;
  std::array<float, 5> curl = {1, 1, 1, 0, 1};  // little, ring, middle, index, thumb: pointing
};

struct RemoteUser {
  Pose T_world_head;  // the VIEW space: −Z forward, +Y up, at the eyes' midpoint
  RemoteHand left, right;
};

inline void put_floats(Packet& p, std::size_t at, std::span<const float> values) {
  std::memcpy(p.data() + at, values.data(), values.size_bytes());
}

inline void put_pose(Packet& p, std::size_t at, const Pose& pose) {
  const Quat q(pose.rotation);
  const Vec3& t = pose.translation;
  const std::array<float, 7> v = {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
  put_floats(p, at, v);
}

inline Packet encode(const RemoteUser& user) {
  Packet p{};
  std::memcpy(p.data(), kHeader, sizeof(kHeader));
  put_pose(p, kHeadCenter, user.T_world_head);
  p[kPerViewValid] = 0;  // the driver's own views around the centre
  for (const auto& [hand, at] : {std::pair{&user.left, kLeft}, std::pair{&user.right, kRight}}) {
    put_pose(p, at, hand->T_world_joint);
    put_floats(p, at + kCurl, hand->curl);
    p[at + kHandTrackingActive] = hand->active ? 1 : 0;
    p[at + kActive] = hand->active ? 1 : 0;
  }
  return p;
}

inline Vec3 position_at(const Packet& p, std::size_t pose_at) {
  std::array<float, 3> v{};
  std::memcpy(v.data(), p.data() + pose_at + 16, sizeof(v));
  return {v[0], v[1], v[2]};
}

// Checks the driver's first packet (its reset pose: head at 1.6 m, controllers at ±0.2, 1.3,
// −0.5; Monado's r_create_devices) so a layout that is not "mndrmt3" is found before anything is
// sent. Monado writes the header on newer builds and leaves it zero on older ones. Returns the
// reason it does not agree, empty when it does.
inline std::string check_reset(const Packet& p) {
  const bool zero = std::all_of(p.begin(), p.begin() + 8, [](std::uint8_t b) { return b == 0; });
  if (!zero && std::memcmp(p.data(), kHeader, sizeof(kHeader)) != 0) {
    return "header '" + std::string(reinterpret_cast<const char*>(p.data()), 7) +
           "' is not 'mndrmt3'";
  }
  const auto near = [](const Vec3& a, const Vec3& b) { return (a - b).norm() < 1e-4f; };
  if (!near(position_at(p, kHeadCenter), Vec3(0, 1.6f, 0)) ||
      !near(position_at(p, kLeft), Vec3(-0.2f, 1.3f, -0.5f)) ||
      !near(position_at(p, kRight), Vec3(0.2f, 1.3f, -0.5f))) {
    return "the reset pose is not where mndrmt3's layout puts it (head (0, 1.6, 0), controllers "
           "(±0.2, 1.3, −0.5))";
  }
  return {};
}

// A TCP connection to the driver on 127.0.0.1.
class RemoteConnection {
 public:
  // Connects within `wait` (the service may still be starting) unless `cancel` is set first,
  // then reads and checks the driver's reset packet within 5 s. Throws deixis::Error naming the
  // port and the reason.
  RemoteConnection(int port, std::chrono::milliseconds wait,
                   const std::atomic<bool>* cancel = nullptr)
      : port_(port) {
    const auto until = std::chrono::steady_clock::now() + wait;
    while (!try_connect()) {
      if (cancel != nullptr && *cancel) {
        throw Error(where() + ": given up (the test ended before the driver listened)");
      }
      if (std::chrono::steady_clock::now() > until) {
        throw Error(where() + ": nothing accepted a connection within " +
                    std::to_string(wait.count()) + " ms (is monado-service running with the " +
                    "remote driver?)");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    Packet reset{};
    if (!read_all(reset, std::chrono::seconds(5))) {
      throw Error(where() + ": the driver sent no reset packet of " + std::to_string(kPacketSize) +
                  " bytes within 5 s");
    }
    if (const std::string why = check_reset(reset); !why.empty()) {
      throw Error(where() + ": not Monado's mndrmt3 remote driver: " + why);
    }
  }
  ~RemoteConnection() {
    if (fd_ >= 0) {
      close(fd_);
    }
  }
  RemoteConnection(const RemoteConnection&) = delete;
  RemoteConnection& operator=(const RemoteConnection&) = delete;

  // False once the driver has gone (monado-service ended).
  bool send(const RemoteUser& user) {
    const Packet p = encode(user);
    std::size_t done = 0;
    while (done < p.size()) {
      const ssize_t n = ::send(fd_, p.data() + done, p.size() - done, MSG_NOSIGNAL);
      if (n <= 0) {
        return false;
      }
      done += static_cast<std::size_t>(n);
    }
    return true;
  }

 private:
  std::string where() const { return "Monado remote driver at 127.0.0.1:" + std::to_string(port_); }

  bool try_connect() {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ >= 0 && connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) == 0) {
      return true;
    }
    if (fd_ >= 0) {
      close(fd_);
      fd_ = -1;
    }
    return false;
  }

  bool read_all(Packet& p, std::chrono::milliseconds within) {
    const auto until = std::chrono::steady_clock::now() + within;
    std::size_t got = 0;
    while (got < p.size()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          until - std::chrono::steady_clock::now());
      pollfd pfd{fd_, POLLIN, 0};
      if (left.count() <= 0 || poll(&pfd, 1, static_cast<int>(left.count())) <= 0) {
        return false;
      }
      const ssize_t n = recv(fd_, p.data() + got, p.size() - got, 0);
      if (n <= 0) {
        return false;
      }
      got += static_cast<std::size_t>(n);
    }
    return true;
  }

  int port_;
  int fd_ = -1;
};

}  // namespace deixis::app::monado
