/* Deixis C API: the remote person's avatar in this room, for engines and apps that embed Deixis.
 *
 * A translator takes one remote person's tracking (their head, gaze, wrists and index fingertips
 * in *their* room) and this room's targets, and gives, tick by tick, where that person's avatar
 * has its head, eyes and deictic hand in *this* room, and the avatar's skeleton posed to match:
 * it looks, points and touches at this room's copies of the objects while free-form gestures
 * pass through (Kang et al., TVCG 2025). docs/embedding.md shows the per-tick call sequence and
 * how Unity, Godot and OpenXR apps call it.
 *
 * Conventions (docs/conventions.md):
 * - World frame: right-handed, +Y up, -Z forward; metres, seconds.
 * - A pose is a position and a unit quaternion (x, y, z, w) that rotates the pose's frame into
 *   its parent's (T_parent_child). H is the midpoint between the eyes, -Z its forward.
 * - Wrist frames (docs/decisions.md 7): x distal for the right hand and proximal for the left,
 *   y dorsal (the back of the hand), z ulnar (the little-finger side).
 * - Hands are indexed 0 = left, 1 = right. Target ids: 1..1000000 are objects (a room's target
 *   map), 0 is "the other person" of a two-site session, 1000001..1000254 are people of a room
 *   of several people (DEIXIS_PERSON_TARGET), -1 is nothing.
 *
 * Errors: every function returns a deixis_status. No C++ exception crosses this boundary.
 * Functions that create a handle write their error message into an optional deixis_error;
 * functions on a handle keep the message of its last failure (deixis_*_last_error).
 *
 * ABI: every create function takes DEIXIS_ABI_VERSION as its first argument and fails with
 * DEIXIS_ERROR_ABI when the library was built with another. Structs are plain data: fill them
 * with their *_init function before setting fields, so new defaults stay correct.
 *
 * Threads: network handles (deixis_mpnet, deixis_ugnet) and avatars are read-only once created
 * and may be used from any number of threads at once. A translator, room or target selector is
 * used by one thread at a time (different ones on different threads are fine). Every function
 * says when it allocates; the per-tick functions never do. */
#ifndef DEIXIS_DEIXIS_H
#define DEIXIS_DEIXIS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(DEIXIS_BUILDING_LIBRARY)
#define DEIXIS_API __attribute__((visibility("default")))
#else
#define DEIXIS_API
#endif

/* The version of this header. The library's own: deixis_version(), deixis_abi_version(). */
#define DEIXIS_VERSION_MAJOR 0
#define DEIXIS_VERSION_MINOR 1
#define DEIXIS_VERSION_PATCH 0
/* Changes whenever a struct's layout or a function's meaning changes. */
#define DEIXIS_ABI_VERSION 2

typedef enum deixis_status {
  DEIXIS_OK = 0,
  DEIXIS_ERROR_INVALID_ARGUMENT = 1, /* a null handle, a size that does not fit, NaN in input */
  DEIXIS_ERROR_FILE = 2,             /* a file missing, unreadable, corrupt or too large */
  DEIXIS_ERROR_ABI = 3,              /* the caller was built against another DEIXIS_ABI_VERSION */
  DEIXIS_ERROR_OUT_OF_MEMORY = 4,
  DEIXIS_ERROR_INTERNAL = 5 /* a bug in Deixis: please report it with the message */
} deixis_status;

#define DEIXIS_ERROR_MESSAGE_SIZE 512
typedef struct deixis_error {
  deixis_status status;
  char message[DEIXIS_ERROR_MESSAGE_SIZE]; /* NUL-terminated, UTF-8; empty when status is OK */
} deixis_error;

typedef struct deixis_vec3 {
  float x, y, z;
} deixis_vec3;
typedef struct deixis_quat {
  float x, y, z, w;
} deixis_quat;
typedef struct deixis_pose {
  deixis_vec3 position;
  deixis_quat orientation; /* unit */
} deixis_pose;

/* "major.minor.patch" of the library. Thread-safe. */
DEIXIS_API const char* deixis_version(void);
DEIXIS_API uint32_t deixis_abi_version(void);
/* A readable name for a status, e.g. "file error". Thread-safe. */
DEIXIS_API const char* deixis_status_name(deixis_status status);

/* Where the shipped weights and default avatar are: $DEIXIS_DATA_DIR if set, else the install's
 * share/deixis beside the library, else the source tree's assets/ the library was built from.
 * Copies the directory (NUL-terminated) into `buffer`; DEIXIS_ERROR_INVALID_ARGUMENT when it does
 * not fit (`*length` then says how many bytes it needs, terminator included) and
 * DEIXIS_ERROR_FILE when none exists. Under it: weights/right/MPNet(MoE)(AC)80.safetensors,
 * weights/right/UGNet(MoE)(AC)120.safetensors (and the other shipped architectures, and left/),
 * avatars/default.glb. Thread-safe; allocates. */
DEIXIS_API deixis_status deixis_data_dir(char* buffer, size_t capacity, size_t* length);

/* ---- tracking ---------------------------------------------------------------------------- */

enum { DEIXIS_HAND_LEFT = 0, DEIXIS_HAND_RIGHT = 1 };

/* Validity flags of a tracking frame: a part whose flag is clear is not read. */
enum {
  DEIXIS_TRACKED_HEAD = 1,
  DEIXIS_TRACKED_GAZE = 2,
  DEIXIS_TRACKED_LEFT_HAND = 4,  /* wrist pose and index fingertip */
  DEIXIS_TRACKED_RIGHT_HAND = 8, /* wrist pose and index fingertip */
  DEIXIS_TRACKED_ALL = 15
};

#define DEIXIS_NO_TARGET (-1)
#define DEIXIS_PARTNER_TARGET 0
#define DEIXIS_PERSON_TARGET(person) (1000000 + (int32_t)(person)) /* person 1..254 */

/* One tick of a tracked person, in their own room's world frame. */
typedef struct deixis_tracking_frame {
  double time;              /* the sender's clock, s */
  deixis_pose head;         /* H, the midpoint between the eyes */
  deixis_vec3 gaze;         /* combined eye gaze, unit */
  deixis_pose wrist[2];     /* by hand */
  deixis_vec3 index_tip[2]; /* by hand */
  uint32_t valid;           /* DEIXIS_TRACKED_* */
  /* What the person looks at and points at or touches, and where it is in their room
   * (deixis_target_selector_select fills these from the tracking). */
  int32_t head_target;
  int32_t hand_target;
  deixis_vec3 head_target_position;
  deixis_vec3 hand_target_position;
} deixis_tracking_frame;
/* Everything zero, head and wrists at identity, gaze -Z, targets DEIXIS_NO_TARGET. */
DEIXIS_API void deixis_tracking_frame_init(deixis_tracking_frame* frame);

/* A person's body and upright posture (paper section IV.A): the root O at H in the upright
 * posture, yaw only (its -Z is the facing direction). */
typedef struct deixis_body_calibration {
  float height;         /* m, standing */
  float arm_length;     /* m, shoulder to fingertip */
  int32_t deictic_hand; /* DEIXIS_HAND_*: the hand that points and touches */
  deixis_pose root;
  deixis_vec3 rest_wrist_in_root[2]; /* by hand, in the root frame */
} deixis_body_calibration;
/* 1.70 m, 0.74 m arm, right-handed, root at the origin, default rest wrists. */
DEIXIS_API void deixis_body_calibration_init(deixis_body_calibration* body);

/* What the site knows of the person beside the tracking; 0 means "estimate it". */
typedef struct deixis_upright_body {
  int32_t deictic_hand; /* DEIXIS_HAND_* */
  float height;         /* m; 0: from the eye height */
  float arm_length;     /* m; 0: from the height */
} deixis_upright_body;
DEIXIS_API void deixis_upright_body_init(deixis_upright_body* body);

/* The body calibration from one frame of the person standing upright, looking ahead, arms
 * hanging. Fails (DEIXIS_ERROR_INVALID_ARGUMENT, message in `error`) when the head is not
 * tracked or the body is out of human range. Thread-safe; allocates nothing. */
DEIXIS_API deixis_status deixis_calibrate_upright(const deixis_tracking_frame* upright,
                                                  const deixis_upright_body* body,
                                                  deixis_body_calibration* out,
                                                  deixis_error* error);

/* ---- networks ------------------------------------------------------------------------------
 * MPNet (paper IV.A): a 30 x 11 window of a person's features -> progression (gaze, deictic,
 * idle). UGNet (IV.B): a 30 x 32 window -> the avatar's 24 end-effector values at the next tick.
 * Any architecture Deixis runs loads (MoE, MLP, Transformer; UGNet also Diffusion), recognised
 * from the file's tensor names; the authors' checkpoints load as well as ours. */
typedef struct deixis_mpnet deixis_mpnet;
typedef struct deixis_ugnet deixis_ugnet;

#define DEIXIS_WINDOW_ROWS 30
#define DEIXIS_MPNET_FEATURES 11
#define DEIXIS_PROGRESSION_SIZE 3
#define DEIXIS_UGNET_COLUMNS 32
#define DEIXIS_POSE_SIZE 24
#define DEIXIS_DIFFUSION_NOISE_SIZE 720 /* 30 steps x 24 standard-normal draws a window */

/* `path`: a .safetensors file, or NULL for the shipped MoE (right-hand) weights under
 * deixis_data_dir(). Allocates (the weights). */
DEIXIS_API deixis_status deixis_mpnet_load(uint32_t abi_version, const char* path,
                                           deixis_mpnet** out, deixis_error* error);
DEIXIS_API deixis_status deixis_ugnet_load(uint32_t abi_version, const char* path,
                                           deixis_ugnet** out, deixis_error* error);
DEIXIS_API void deixis_mpnet_destroy(deixis_mpnet* mpnet); /* NULL is fine */
DEIXIS_API void deixis_ugnet_destroy(deixis_ugnet* ugnet);
/* "GRU-MoE", "MLP", "Transformer"; UGNet: "MoE", "MLP", "Transformer", "Diffusion". */
DEIXIS_API const char* deixis_mpnet_architecture(const deixis_mpnet* mpnet);
DEIXIS_API const char* deixis_ugnet_architecture(const deixis_ugnet* ugnet);
DEIXIS_API int deixis_ugnet_needs_noise(const deixis_ugnet* ugnet);

/* Runs `count` windows one after the other: window i at windows[i * 330] (row-major, 30 rows of
 * 11), its progression at out[i * 3]. Thread-safe; allocates nothing. Returns
 * DEIXIS_ERROR_INVALID_ARGUMENT for null pointers (count 0 is fine). */
DEIXIS_API deixis_status deixis_mpnet_run(const deixis_mpnet* mpnet, const float* windows,
                                          size_t count, float* out);
/* The same for UGNet: window i at windows[i * 960], its prediction at out[i * 24]. `noise` is
 * read by the diffusion UGNet only: DEIXIS_DIFFUSION_NOISE_SIZE draws per window at
 * noise[i * 720], or NULL to sample with every draw zero (deterministic). */
DEIXIS_API deixis_status deixis_ugnet_run(const deixis_ugnet* ugnet, const float* windows,
                                          const float* noise, size_t count, float* out);

/* ---- avatars -------------------------------------------------------------------------------
 * A skinned glTF/GLB humanoid with VRM, Mixamo or BCN bone names (docs/avatars.md), read as an
 * untrusted file (its size and contents bounded). */
typedef struct deixis_avatar deixis_avatar;

/* `path` NULL: the shipped default avatar. Allocates. */
DEIXIS_API deixis_status deixis_avatar_load(uint32_t abi_version, const char* path,
                                            deixis_avatar** out, deixis_error* error);
DEIXIS_API void deixis_avatar_destroy(deixis_avatar* avatar);
DEIXIS_API size_t deixis_avatar_joint_count(const deixis_avatar* avatar);
/* The joint's name in the file, or NULL when `joint` is out of range. */
DEIXIS_API const char* deixis_avatar_joint_name(const deixis_avatar* avatar, size_t joint);
/* The joint's parent (parents come before children), -1 for a root or an out-of-range joint. */
DEIXIS_API int32_t deixis_avatar_joint_parent(const deixis_avatar* avatar, size_t joint);
DEIXIS_API float deixis_avatar_height(const deixis_avatar* avatar);     /* m, rest pose */
DEIXIS_API float deixis_avatar_arm_length(const deixis_avatar* avatar); /* m, rest pose */

/* ---- a room's targets ----------------------------------------------------------------------
 * The objects of this room people look at, point at and touch (a target map,
 * docs/target-map.md), the other person's head in a two-site session, and the heads of the
 * people of a room of several people. Objects correspond across rooms by id. */
typedef struct deixis_room deixis_room;

enum { DEIXIS_TARGET_SPHERE = 0, DEIXIS_TARGET_BOX = 1, DEIXIS_TARGET_SCREEN = 2 };

typedef struct deixis_target {
  int32_t id;           /* 1..1000000 */
  int32_t kind;         /* DEIXIS_TARGET_* */
  deixis_vec3 position; /* centre, this room's world frame */
  deixis_vec3 size;     /* extent along x, y, z; a sphere's diameter in all three */
} deixis_target;

#define DEIXIS_MAX_PEOPLE 254

/* An empty room, or the target map in `path` (JSON, docs/target-map.md) when not NULL.
 * Allocates. */
DEIXIS_API deixis_status deixis_room_create(uint32_t abi_version, const char* target_map_path,
                                            deixis_room** out, deixis_error* error);
DEIXIS_API void deixis_room_destroy(deixis_room* room);
DEIXIS_API const char* deixis_room_last_error(const deixis_room* room);
/* Adds an object, or moves and resizes the one with that id; `name` may be NULL. Allocates when
 * the object is new. */
DEIXIS_API deixis_status deixis_room_set_target(deixis_room* room, const deixis_target* target,
                                                const char* name);
DEIXIS_API deixis_status deixis_room_remove_target(deixis_room* room, int32_t id);
DEIXIS_API size_t deixis_room_target_count(const deixis_room* room);
/* The i-th object (in the order they were added); DEIXIS_ERROR_INVALID_ARGUMENT out of range. */
DEIXIS_API deixis_status deixis_room_target(const deixis_room* room, size_t i, deixis_target* out);
/* Where the other person's head is (two-site sessions: target 0); a non-finite position is
 * ignored. Allocates nothing. */
DEIXIS_API void deixis_room_set_partner_head(deixis_room* room, deixis_vec3 head);
/* Where person `person` (1..254) has their head in this room: a remote person's avatar's head
 * or this room's own user's. Allocates nothing. */
DEIXIS_API deixis_status deixis_room_set_person(deixis_room* room, uint8_t person,
                                                deixis_vec3 head);
DEIXIS_API deixis_status deixis_room_remove_person(deixis_room* room, uint8_t person);

/* ---- the translator of one remote person ------------------------------------------------- */
typedef struct deixis_translator deixis_translator;

enum {
  DEIXIS_MIRROR_AUTO = 0, /* left-handed people go through the right-hand weights mirrored
                             (docs/decisions.md 68); right-handed ones as they are */
  DEIXIS_MIRROR_OFF = 1,
  DEIXIS_MIRROR_ON = 2
};

typedef struct deixis_translator_config {
  deixis_body_calibration person; /* the remote person in their room (their calibration) */
  deixis_pose avatar_floor; /* where the avatar stands in this room: a floor point, yaw only */
  uint32_t noise_seed;      /* a diffusion UGNet's draws */
  int32_t mirror;           /* DEIXIS_MIRROR_* */
  int32_t touch_contact;    /* 1: a touch that arrived ends on the object's surface */
  int32_t gaze_settle;      /* 1: a gaze that nearly arrived ends on its target */
  int32_t pointing_settle;  /* 1: a point that nearly arrived ends on its target (ABI 2) */
} deixis_translator_config;
/* deixis_body_calibration_init's person, the avatar at the origin facing -Z, seed 1,
 * DEIXIS_MIRROR_AUTO, touch contact, gaze and pointing settling on. */
DEIXIS_API void deixis_translator_config_init(deixis_translator_config* config);

/* The networks and avatar must outlive the translator; several translators may share them.
 * Allocates (the per-person state: a few kilobytes, and the avatar's poses). */
DEIXIS_API deixis_status deixis_translator_create(uint32_t abi_version, const deixis_mpnet* mpnet,
                                                  const deixis_ugnet* ugnet,
                                                  const deixis_avatar* avatar,
                                                  const deixis_translator_config* config,
                                                  deixis_translator** out, deixis_error* error);
DEIXIS_API void deixis_translator_destroy(deixis_translator* translator);
DEIXIS_API const char* deixis_translator_last_error(const deixis_translator* translator);

/* What a tick gives: the avatar's end-effectors in this room's world frame and what drives them.
 * The skeleton's joint poses: deixis_translator_joint_poses. */
typedef struct deixis_avatar_frame {
  int32_t visible; /* 0 until the person's first valid frame: do not show the avatar */
  int32_t held;    /* 1: this tick reused the last valid frame (missed or invalid tracking) */
  int32_t deictic_hand;
  deixis_pose head;               /* H, as the networks put it (before IK) */
  deixis_vec3 gaze;               /* unit: the eyes' direction given to IK */
  deixis_pose wrist;              /* the deictic wrist, before IK */
  deixis_vec3 index_tip;          /* the deictic index fingertip, before IK */
  deixis_vec3 eye_midpoint;       /* H after IK: where the avatar's eyes are */
  deixis_vec3 fingertip;          /* the deictic index fingertip after IK: what an observer sees */
  float progression[3];           /* MPNet's (gaze, deictic, idle) */
  float head_weight, hand_weight; /* how much the gaze and hand are retargeted, 0..1 */
  int32_t head_target, hand_target;
} deixis_avatar_frame;

/* One tick (30 Hz). `frame` NULL: no frame arrived in time (the avatar holds its last one).
 * A frame with NaN or infinity anywhere, or its parts untracked, is held over too and counted;
 * nothing non-finite reaches the output. Allocates nothing. */
DEIXIS_API deixis_status deixis_translator_tick(deixis_translator* translator,
                                                const deixis_tracking_frame* frame,
                                                const deixis_room* room, deixis_avatar_frame* out);

enum {
  DEIXIS_SPACE_WORLD = 0, /* this room's world frame */
  DEIXIS_SPACE_MODEL = 1, /* the avatar's model frame (T_model_joint) */
  DEIXIS_SPACE_LOCAL = 2  /* each joint in its parent's frame (T_parent_joint) */
};
/* The avatar's joint poses after the last tick, one per joint in the avatar's joint order;
 * `capacity` must be at least deixis_avatar_joint_count(). Allocates nothing. */
DEIXIS_API deixis_status deixis_translator_joint_poses(const deixis_translator* translator,
                                                       int32_t space, deixis_pose* out,
                                                       size_t capacity);
/* Where the avatar's model frame is in this room. */
DEIXIS_API deixis_status deixis_translator_model_pose(const deixis_translator* translator,
                                                      deixis_pose* out);

typedef struct deixis_translator_stats {
  uint64_t ticks;
  uint64_t held;            /* ticks that reused the last valid frame */
  uint64_t rejected_frames; /* frames with a non-finite number or missing parts */
  uint64_t unknown_targets; /* target ids this room lacks (the pose is copied instead) */
  uint64_t restarts;        /* a network produced a non-finite value and the loop restarted */
} deixis_translator_stats;
DEIXIS_API deixis_status deixis_translator_stats_get(const deixis_translator* translator,
                                                     deixis_translator_stats* out);

/* ---- target selection: what a live user looks at and points at --------------------------
 * For a headset user, whose targets nobody scripted (docs/decisions.md 44): tick by tick, the
 * object nearest the gaze ray, and the one the eye-fingertip ray points at or the fingertip
 * touches, with hysteresis. */
typedef struct deixis_target_selector deixis_target_selector;

/* For the calibrated user `user` (their deictic hand and reach). `self` is the user's own person
 * id in a room of several people (never a candidate), 0 in a two-site session. Allocates. */
DEIXIS_API deixis_status deixis_target_selector_create(uint32_t abi_version,
                                                       const deixis_body_calibration* user,
                                                       uint8_t self, deixis_target_selector** out,
                                                       deixis_error* error);
DEIXIS_API void deixis_target_selector_destroy(deixis_target_selector* selector);
DEIXIS_API const char* deixis_target_selector_last_error(const deixis_target_selector* selector);
/* Fills frame->head_target, hand_target and their positions from the frame's head, gaze and
 * deictic hand and the room's objects and people (and, when `two_site` is 1, the room's partner
 * head as target 0). Allocates nothing. */
DEIXIS_API deixis_status deixis_target_selector_select(deixis_target_selector* selector,
                                                       deixis_tracking_frame* frame,
                                                       const deixis_room* room, int32_t two_site);

#ifdef __cplusplus
}
#endif

#endif /* DEIXIS_DEIXIS_H */
