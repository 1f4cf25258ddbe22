// Deixis C++ interface: header-only RAII handles over the C API of deixis.h, for C++ programs
// that embed Deixis through libdeixis.so (docs/embedding.md). Failures throw deixis::lib::Error
// carrying the library's status and message; the per-tick calls (Translator::tick,
// joint_poses, TargetSelector::select) allocate nothing, as the C functions they call.
//
// The types live in deixis::lib so that they never meet the C++ classes of Deixis' own source
// tree, which are not part of the installed interface.
#ifndef DEIXIS_DEIXIS_HPP
#define DEIXIS_DEIXIS_HPP

#include <cstddef>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include "deixis/deixis.h"

namespace deixis::lib {

class Error : public std::runtime_error {
 public:
  Error(deixis_status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  deixis_status status() const noexcept { return status_; }

 private:
  deixis_status status_;
};

namespace detail {

inline void check(deixis_status status, const deixis_error& error) {
  if (status != DEIXIS_OK) {
    throw Error(status, error.message);
  }
}

inline void check(deixis_status status, const char* last_error) {
  if (status != DEIXIS_OK) {
    throw Error(status, last_error != nullptr && *last_error != '\0' ? last_error
                                                                     : deixis_status_name(status));
  }
}

template <class T, void (*Destroy)(T*)>
struct Deleter {
  void operator()(T* p) const noexcept { Destroy(p); }
};

template <class T, void (*Destroy)(T*)>
using Handle = std::unique_ptr<T, Deleter<T, Destroy>>;

}  // namespace detail

inline std::string data_dir() {
  std::size_t length = 0;
  deixis_data_dir(nullptr, 0, &length);
  std::string dir(length, '\0');
  if (length == 0 || deixis_data_dir(dir.data(), dir.size(), &length) != DEIXIS_OK) {
    throw Error(DEIXIS_ERROR_FILE, "no Deixis data directory (set DEIXIS_DATA_DIR)");
  }
  dir.resize(length - 1);
  return dir;
}

// MPNet; an empty path loads the shipped MoE weights.
class Mpnet {
 public:
  explicit Mpnet(const std::string& path = {}) {
    deixis_error error{};
    deixis_mpnet* p = nullptr;
    detail::check(
        deixis_mpnet_load(DEIXIS_ABI_VERSION, path.empty() ? nullptr : path.c_str(), &p, &error),
        error);
    handle_.reset(p);
  }
  const deixis_mpnet* get() const noexcept { return handle_.get(); }
  std::string architecture() const { return deixis_mpnet_architecture(get()); }
  // windows: count × 30 × 11 floats; out: count × 3.
  void run(std::span<const float> windows, std::span<float> out) const {
    const std::size_t count = windows.size() / (DEIXIS_WINDOW_ROWS * DEIXIS_MPNET_FEATURES);
    if (windows.size() != count * DEIXIS_WINDOW_ROWS * DEIXIS_MPNET_FEATURES ||
        out.size() != count * DEIXIS_PROGRESSION_SIZE) {
      throw Error(DEIXIS_ERROR_INVALID_ARGUMENT, "Mpnet::run: windows of 330 floats, 3 out each");
    }
    detail::check(deixis_mpnet_run(get(), windows.data(), count, out.data()), "Mpnet::run");
  }

 private:
  detail::Handle<deixis_mpnet, deixis_mpnet_destroy> handle_;
};

// UGNet; an empty path loads the shipped MoE weights.
class Ugnet {
 public:
  explicit Ugnet(const std::string& path = {}) {
    deixis_error error{};
    deixis_ugnet* p = nullptr;
    detail::check(
        deixis_ugnet_load(DEIXIS_ABI_VERSION, path.empty() ? nullptr : path.c_str(), &p, &error),
        error);
    handle_.reset(p);
  }
  const deixis_ugnet* get() const noexcept { return handle_.get(); }
  std::string architecture() const { return deixis_ugnet_architecture(get()); }
  // windows: count × 30 × 32 floats; noise: empty or count × 720; out: count × 24.
  void run(std::span<const float> windows, std::span<const float> noise,
           std::span<float> out) const {
    const std::size_t count = windows.size() / (DEIXIS_WINDOW_ROWS * DEIXIS_UGNET_COLUMNS);
    if (windows.size() != count * DEIXIS_WINDOW_ROWS * DEIXIS_UGNET_COLUMNS ||
        out.size() != count * DEIXIS_POSE_SIZE ||
        (!noise.empty() && noise.size() != count * DEIXIS_DIFFUSION_NOISE_SIZE)) {
      throw Error(DEIXIS_ERROR_INVALID_ARGUMENT,
                  "Ugnet::run: windows of 960 floats, 24 out and 720 draws (or none) each");
    }
    detail::check(deixis_ugnet_run(get(), windows.data(), noise.empty() ? nullptr : noise.data(),
                                   count, out.data()),
                  "Ugnet::run");
  }

 private:
  detail::Handle<deixis_ugnet, deixis_ugnet_destroy> handle_;
};

// A glTF/GLB humanoid; an empty path loads the shipped default avatar.
class Avatar {
 public:
  explicit Avatar(const std::string& path = {}) {
    deixis_error error{};
    deixis_avatar* p = nullptr;
    detail::check(
        deixis_avatar_load(DEIXIS_ABI_VERSION, path.empty() ? nullptr : path.c_str(), &p, &error),
        error);
    handle_.reset(p);
  }
  const deixis_avatar* get() const noexcept { return handle_.get(); }
  std::size_t joint_count() const noexcept { return deixis_avatar_joint_count(get()); }
  std::string joint_name(std::size_t joint) const {
    const char* name = deixis_avatar_joint_name(get(), joint);
    return name != nullptr ? name : "";
  }
  int joint_parent(std::size_t joint) const noexcept {
    return deixis_avatar_joint_parent(get(), joint);
  }
  float height() const noexcept { return deixis_avatar_height(get()); }

 private:
  detail::Handle<deixis_avatar, deixis_avatar_destroy> handle_;
};

// This room's targets; an empty path starts with no objects.
class Room {
 public:
  explicit Room(const std::string& target_map_path = {}) {
    deixis_error error{};
    deixis_room* p = nullptr;
    detail::check(
        deixis_room_create(DEIXIS_ABI_VERSION,
                           target_map_path.empty() ? nullptr : target_map_path.c_str(), &p, &error),
        error);
    handle_.reset(p);
  }
  const deixis_room* get() const noexcept { return handle_.get(); }
  void set_target(const deixis_target& target, const char* name = nullptr) {
    detail::check(deixis_room_set_target(handle_.get(), &target, name),
                  deixis_room_last_error(get()));
  }
  std::size_t target_count() const noexcept { return deixis_room_target_count(get()); }
  deixis_target target(std::size_t i) const {
    deixis_target t{};
    detail::check(deixis_room_target(get(), i, &t), "Room::target: out of range");
    return t;
  }
  void set_partner_head(const deixis_vec3& head) noexcept {
    deixis_room_set_partner_head(handle_.get(), head);
  }
  void set_person(std::uint8_t person, const deixis_vec3& head) {
    detail::check(deixis_room_set_person(handle_.get(), person, head),
                  deixis_room_last_error(get()));
  }

 private:
  detail::Handle<deixis_room, deixis_room_destroy> handle_;
};

inline deixis_body_calibration calibrate_upright(const deixis_tracking_frame& upright,
                                                 const deixis_upright_body& body) {
  deixis_error error{};
  deixis_body_calibration out{};
  detail::check(deixis_calibrate_upright(&upright, &body, &out, &error), error);
  return out;
}

inline deixis_translator_config default_translator_config() {
  deixis_translator_config config{};
  deixis_translator_config_init(&config);
  return config;
}

// One remote person's avatar in this room. The networks and the avatar must outlive it.
class Translator {
 public:
  Translator(const Mpnet& mpnet, const Ugnet& ugnet, const Avatar& avatar,
             const deixis_translator_config& config) {
    deixis_error error{};
    deixis_translator* p = nullptr;
    detail::check(deixis_translator_create(DEIXIS_ABI_VERSION, mpnet.get(), ugnet.get(),
                                           avatar.get(), &config, &p, &error),
                  error);
    handle_.reset(p);
  }
  // frame null: no frame arrived in time.
  deixis_avatar_frame tick(const deixis_tracking_frame* frame, const Room& room) {
    deixis_avatar_frame out{};
    detail::check(deixis_translator_tick(handle_.get(), frame, room.get(), &out),
                  deixis_translator_last_error(handle_.get()));
    return out;
  }
  void joint_poses(int32_t space, std::span<deixis_pose> out) const {
    detail::check(deixis_translator_joint_poses(handle_.get(), space, out.data(), out.size()),
                  "Translator::joint_poses: space unknown or the span holds fewer poses than "
                  "the avatar has joints");
  }
  deixis_translator_stats stats() const {
    deixis_translator_stats s{};
    deixis_translator_stats_get(handle_.get(), &s);
    return s;
  }

 private:
  detail::Handle<deixis_translator, deixis_translator_destroy> handle_;
};

// What a live user looks at and points at, tick by tick.
class TargetSelector {
 public:
  explicit TargetSelector(const deixis_body_calibration& user, std::uint8_t self = 0) {
    deixis_error error{};
    deixis_target_selector* p = nullptr;
    detail::check(deixis_target_selector_create(DEIXIS_ABI_VERSION, &user, self, &p, &error),
                  error);
    handle_.reset(p);
  }
  void select(deixis_tracking_frame& frame, const Room& room, bool two_site) {
    detail::check(
        deixis_target_selector_select(handle_.get(), &frame, room.get(), two_site ? 1 : 0),
        deixis_target_selector_last_error(handle_.get()));
  }

 private:
  detail::Handle<deixis_target_selector, deixis_target_selector_destroy> handle_;
};

}  // namespace deixis::lib

#endif  // DEIXIS_DEIXIS_HPP
