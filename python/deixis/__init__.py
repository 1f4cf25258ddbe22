"""Deixis for Python: MPNet, UGNet and the translator of a remote person, NumPy in, NumPy out.

A thin layer over libdeixis.so's C API (include/deixis/deixis.h) through ctypes: the arrays you
pass are handed to the library without a copy when they are already C-contiguous float32, and
results come back as new NumPy arrays. Errors are DeixisError carrying the library's message.
See docs/embedding.md.

    import numpy as np, deixis
    mpnet = deixis.Mpnet()              # the shipped MoE weights; or Mpnet("path.safetensors")
    p = mpnet.run(np.zeros((30, 11), np.float32))          # (3,): gaze, deictic, idle
    ugnet = deixis.Ugnet()
    x = ugnet.run(np.zeros((64, 30, 32), np.float32))      # (64, 24)
"""

import ctypes as _ct
import os as _os

import numpy as _np

from . import _location

__all__ = [
    "DeixisError", "Mpnet", "Ugnet", "Avatar", "load_avatar", "Room", "Translator",
    "TargetSelector", "BodyCalibration", "calibrate_upright", "data_dir", "version",
    "WINDOW_ROWS", "MPNET_FEATURES", "UGNET_COLUMNS", "POSE_SIZE", "DIFFUSION_NOISE_SIZE",
]

ABI_VERSION = 2
WINDOW_ROWS = 30
MPNET_FEATURES = 11
PROGRESSION_SIZE = 3
UGNET_COLUMNS = 32
POSE_SIZE = 24
DIFFUSION_NOISE_SIZE = 720
ERROR_MESSAGE_SIZE = 512
HANDS = {"left": 0, "right": 1}
SPACES = {"world": 0, "model": 1, "local": 2}
TARGET_KINDS = {"sphere": 0, "box": 1, "screen": 2}
MIRRORS = {"auto": 0, "off": 1, "on": 2}


class DeixisError(RuntimeError):
    """A failure reported by libdeixis: `status` is the C API's deixis_status, the message its."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


# ---- the C structs (deixis.h), field for field ------------------------------------------------
class _Vec3(_ct.Structure):
    _fields_ = [("x", _ct.c_float), ("y", _ct.c_float), ("z", _ct.c_float)]


class _Quat(_ct.Structure):
    _fields_ = [("x", _ct.c_float), ("y", _ct.c_float), ("z", _ct.c_float), ("w", _ct.c_float)]


class _Pose(_ct.Structure):
    _fields_ = [("position", _Vec3), ("orientation", _Quat)]


class _Error(_ct.Structure):
    _fields_ = [("status", _ct.c_int), ("message", _ct.c_char * ERROR_MESSAGE_SIZE)]


class _TrackingFrame(_ct.Structure):
    _fields_ = [
        ("time", _ct.c_double), ("head", _Pose), ("gaze", _Vec3), ("wrist", _Pose * 2),
        ("index_tip", _Vec3 * 2), ("valid", _ct.c_uint32), ("head_target", _ct.c_int32),
        ("hand_target", _ct.c_int32), ("head_target_position", _Vec3),
        ("hand_target_position", _Vec3),
    ]


class _BodyCalibration(_ct.Structure):
    _fields_ = [
        ("height", _ct.c_float), ("arm_length", _ct.c_float), ("deictic_hand", _ct.c_int32),
        ("root", _Pose), ("rest_wrist_in_root", _Vec3 * 2),
    ]


class _UprightBody(_ct.Structure):
    _fields_ = [("deictic_hand", _ct.c_int32), ("height", _ct.c_float),
                ("arm_length", _ct.c_float)]


class _Target(_ct.Structure):
    _fields_ = [("id", _ct.c_int32), ("kind", _ct.c_int32), ("position", _Vec3), ("size", _Vec3)]


class _TranslatorConfig(_ct.Structure):
    _fields_ = [
        ("person", _BodyCalibration), ("avatar_floor", _Pose), ("noise_seed", _ct.c_uint32),
        ("mirror", _ct.c_int32), ("touch_contact", _ct.c_int32), ("gaze_settle", _ct.c_int32),
        ("pointing_settle", _ct.c_int32),
    ]


class _AvatarFrame(_ct.Structure):
    _fields_ = [
        ("visible", _ct.c_int32), ("held", _ct.c_int32), ("deictic_hand", _ct.c_int32),
        ("head", _Pose), ("gaze", _Vec3), ("wrist", _Pose), ("index_tip", _Vec3),
        ("eye_midpoint", _Vec3), ("fingertip", _Vec3), ("progression", _ct.c_float * 3),
        ("head_weight", _ct.c_float), ("hand_weight", _ct.c_float),
        ("head_target", _ct.c_int32), ("hand_target", _ct.c_int32),
    ]


class _Stats(_ct.Structure):
    _fields_ = [(name, _ct.c_uint64)
                for name in ("ticks", "held", "rejected_frames", "unknown_targets", "restarts")]


# ---- the library ------------------------------------------------------------------------------
def _load_library():
    path = _os.environ.get("DEIXIS_LIBRARY") or _location.library_path()
    try:
        return _ct.CDLL(path)
    except OSError as e:
        raise ImportError(f"deixis: cannot load libdeixis ({path}): {e}; set DEIXIS_LIBRARY to "
                          "its path") from e


_lib = _load_library()
_P = _ct.POINTER
_float_p = _P(_ct.c_float)
_c = _ct.c_void_p


def _declare(name, result, *args):
    function = getattr(_lib, name)
    function.restype = result
    function.argtypes = list(args)
    return function


_version = _declare("deixis_version", _ct.c_char_p)
_abi_version = _declare("deixis_abi_version", _ct.c_uint32)
_data_dir = _declare("deixis_data_dir", _ct.c_int, _ct.c_char_p, _ct.c_size_t,
                     _P(_ct.c_size_t))
_mpnet_load = _declare("deixis_mpnet_load", _ct.c_int, _ct.c_uint32, _ct.c_char_p, _P(_c),
                       _P(_Error))
_mpnet_destroy = _declare("deixis_mpnet_destroy", None, _c)
_mpnet_architecture = _declare("deixis_mpnet_architecture", _ct.c_char_p, _c)
_mpnet_run = _declare("deixis_mpnet_run", _ct.c_int, _c, _float_p, _ct.c_size_t, _float_p)
_ugnet_load = _declare("deixis_ugnet_load", _ct.c_int, _ct.c_uint32, _ct.c_char_p, _P(_c),
                       _P(_Error))
_ugnet_destroy = _declare("deixis_ugnet_destroy", None, _c)
_ugnet_architecture = _declare("deixis_ugnet_architecture", _ct.c_char_p, _c)
_ugnet_needs_noise = _declare("deixis_ugnet_needs_noise", _ct.c_int, _c)
_ugnet_run = _declare("deixis_ugnet_run", _ct.c_int, _c, _float_p, _float_p, _ct.c_size_t,
                      _float_p)
_avatar_load = _declare("deixis_avatar_load", _ct.c_int, _ct.c_uint32, _ct.c_char_p, _P(_c),
                        _P(_Error))
_avatar_destroy = _declare("deixis_avatar_destroy", None, _c)
_avatar_joint_count = _declare("deixis_avatar_joint_count", _ct.c_size_t, _c)
_avatar_joint_name = _declare("deixis_avatar_joint_name", _ct.c_char_p, _c, _ct.c_size_t)
_avatar_joint_parent = _declare("deixis_avatar_joint_parent", _ct.c_int32, _c, _ct.c_size_t)
_avatar_height = _declare("deixis_avatar_height", _ct.c_float, _c)
_room_create = _declare("deixis_room_create", _ct.c_int, _ct.c_uint32, _ct.c_char_p, _P(_c),
                        _P(_Error))
_room_destroy = _declare("deixis_room_destroy", None, _c)
_room_last_error = _declare("deixis_room_last_error", _ct.c_char_p, _c)
_room_set_target = _declare("deixis_room_set_target", _ct.c_int, _c, _P(_Target), _ct.c_char_p)
_room_target_count = _declare("deixis_room_target_count", _ct.c_size_t, _c)
_room_set_partner_head = _declare("deixis_room_set_partner_head", None, _c, _Vec3)
_room_set_person = _declare("deixis_room_set_person", _ct.c_int, _c, _ct.c_uint8, _Vec3)
_tracking_frame_init = _declare("deixis_tracking_frame_init", None, _P(_TrackingFrame))
_body_init = _declare("deixis_body_calibration_init", None, _P(_BodyCalibration))
_calibrate_upright = _declare("deixis_calibrate_upright", _ct.c_int, _P(_TrackingFrame),
                              _P(_UprightBody), _P(_BodyCalibration), _P(_Error))
_config_init = _declare("deixis_translator_config_init", None, _P(_TranslatorConfig))
_translator_create = _declare("deixis_translator_create", _ct.c_int, _ct.c_uint32, _c, _c, _c,
                              _P(_TranslatorConfig), _P(_c), _P(_Error))
_translator_destroy = _declare("deixis_translator_destroy", None, _c)
_translator_last_error = _declare("deixis_translator_last_error", _ct.c_char_p, _c)
_translator_tick = _declare("deixis_translator_tick", _ct.c_int, _c, _P(_TrackingFrame), _c,
                            _P(_AvatarFrame))
_translator_joint_poses = _declare("deixis_translator_joint_poses", _ct.c_int, _c, _ct.c_int32,
                                   _P(_Pose), _ct.c_size_t)
_translator_stats = _declare("deixis_translator_stats_get", _ct.c_int, _c, _P(_Stats))
_selector_create = _declare("deixis_target_selector_create", _ct.c_int, _ct.c_uint32,
                            _P(_BodyCalibration), _ct.c_uint8, _P(_c), _P(_Error))
_selector_destroy = _declare("deixis_target_selector_destroy", None, _c)
_selector_last_error = _declare("deixis_target_selector_last_error", _ct.c_char_p, _c)
_selector_select = _declare("deixis_target_selector_select", _ct.c_int, _c, _P(_TrackingFrame),
                            _c, _ct.c_int32)

if _abi_version() != ABI_VERSION:
    raise ImportError(f"deixis: libdeixis is ABI {_abi_version()}, this module ABI {ABI_VERSION}")


def version():
    """The library's version, "major.minor.patch"."""
    return _version().decode()


def data_dir():
    """Where the shipped weights and default avatar are (deixis_data_dir)."""
    length = _ct.c_size_t(0)
    _data_dir(None, 0, _ct.byref(length))
    buffer = _ct.create_string_buffer(max(length.value, 1))
    status = _data_dir(buffer, len(buffer), _ct.byref(length))
    if status != 0:
        raise DeixisError(status, "no Deixis data directory: set DEIXIS_DATA_DIR")
    return buffer.value.decode()


def _create(function, *args):
    handle = _c()
    error = _Error()
    status = function(ABI_VERSION, *args, _ct.byref(handle), _ct.byref(error))
    if status != 0:
        raise DeixisError(status, error.message.decode("utf-8", "replace"))
    return handle


def _path(path):
    return None if path is None else _os.fsencode(path)


def _check(status, last_error):
    if status != 0:
        message = last_error().decode("utf-8", "replace") if callable(last_error) else last_error
        raise DeixisError(status, message or "invalid argument")


class _Handle:
    _destroy = None

    def __del__(self):
        handle = getattr(self, "_handle", None)
        if handle:
            type(self)._destroy(handle)
            self._handle = None


def _floats(array, name, row_shape):
    """`array` as C-contiguous float32 (no copy when it already is) and its batch size; a single
    window (row_shape) is a batch of one."""
    a = _np.ascontiguousarray(array, dtype=_np.float32)
    if a.shape == row_shape:
        return a, 1, True
    if a.ndim == len(row_shape) + 1 and a.shape[1:] == row_shape:
        return a, a.shape[0], False
    raise ValueError(f"{name}: expected shape {row_shape} or (B, {', '.join(map(str, row_shape))})"
                     f", got {a.shape}")


class Mpnet(_Handle):
    """MPNet (paper IV.A): windows (30, 11) or (B, 30, 11) -> progression (3,) or (B, 3)."""
    _destroy = staticmethod(_mpnet_destroy)

    def __init__(self, path=None):
        self._handle = _create(_mpnet_load, _path(path))

    @property
    def architecture(self):
        return _mpnet_architecture(self._handle).decode()

    def run(self, x):
        x, count, single = _floats(x, "Mpnet.run", (WINDOW_ROWS, MPNET_FEATURES))
        out = _np.empty((count, PROGRESSION_SIZE), _np.float32)
        _check(_mpnet_run(self._handle, x.ctypes.data_as(_float_p), count,
                          out.ctypes.data_as(_float_p)), "Mpnet.run")
        return out[0] if single else out


class Ugnet(_Handle):
    """UGNet (paper IV.B): windows (30, 32) or (B, 30, 32) -> end-effectors (24,) or (B, 24).

    The diffusion UGNet takes its draws as `noise`: (720,) or (30, 24) per window, (B, 720) or
    (B, 30, 24) for a batch (row 0 the initial sample, row s + 1 the noise added after step
    29 - s); without it, every draw is zero (deterministic). Other architectures ignore it."""
    _destroy = staticmethod(_ugnet_destroy)

    def __init__(self, path=None):
        self._handle = _create(_ugnet_load, _path(path))

    @property
    def architecture(self):
        return _ugnet_architecture(self._handle).decode()

    @property
    def needs_noise(self):
        return bool(_ugnet_needs_noise(self._handle))

    def run(self, x, noise=None):
        x, count, single = _floats(x, "Ugnet.run", (WINDOW_ROWS, UGNET_COLUMNS))
        noise_p = None
        if noise is not None:
            n = _np.ascontiguousarray(noise, dtype=_np.float32)
            if n.size != count * DIFFUSION_NOISE_SIZE:
                raise ValueError(f"Ugnet.run: noise must hold {DIFFUSION_NOISE_SIZE} draws per "
                                 f"window ({count * DIFFUSION_NOISE_SIZE}), got shape {n.shape}")
            noise_p = n.ctypes.data_as(_float_p)
        out = _np.empty((count, POSE_SIZE), _np.float32)
        _check(_ugnet_run(self._handle, x.ctypes.data_as(_float_p), noise_p, count,
                          out.ctypes.data_as(_float_p)), "Ugnet.run")
        return out[0] if single else out


class Avatar(_Handle):
    """A skinned glTF/GLB humanoid (VRM, Mixamo or BCN bone names)."""
    _destroy = staticmethod(_avatar_destroy)

    def __init__(self, path=None):
        self._handle = _create(_avatar_load, _path(path))
        count = _avatar_joint_count(self._handle)
        self.joint_names = [_avatar_joint_name(self._handle, j).decode() for j in range(count)]
        self.parents = _np.array([_avatar_joint_parent(self._handle, j) for j in range(count)],
                                 _np.int32)
        self.height = float(_avatar_height(self._handle))


def load_avatar(path=None):
    """The avatar in `path`, or the shipped default avatar."""
    return Avatar(path)


def _vec3(v, name):
    a = _np.asarray(v, dtype=_np.float64).reshape(-1)
    if a.shape != (3,):
        raise ValueError(f"{name}: expected 3 numbers, got {a.shape}")
    return _Vec3(*a)


def _pose(p, name):
    """A pose from 7 numbers (x, y, z, qx, qy, qz, qw)."""
    a = _np.asarray(p, dtype=_np.float64).reshape(-1)
    if a.shape != (7,):
        raise ValueError(f"{name}: expected 7 numbers (x, y, z, qx, qy, qz, qw), got {a.shape}")
    return _Pose(_Vec3(*a[:3]), _Quat(*a[3:]))


def _pose_array(p):
    return _np.array([p.position.x, p.position.y, p.position.z, p.orientation.x,
                      p.orientation.y, p.orientation.z, p.orientation.w], _np.float32)


def _vec_array(v):
    return _np.array([v.x, v.y, v.z], _np.float32)


class Room(_Handle):
    """This room's targets (a target map file, docs/target-map.md, or none) and people."""
    _destroy = staticmethod(_room_destroy)

    def __init__(self, target_map=None):
        self._handle = _create(_room_create, _path(target_map))

    def set_target(self, id, position, size, kind="sphere", name=None):
        if kind not in TARGET_KINDS:
            raise ValueError(f"kind: one of {sorted(TARGET_KINDS)}, got {kind!r}")
        if not -2**31 <= int(id) < 2**31:  # ctypes would wrap it silently
            raise ValueError(f"id: an object id is 1..1000000, got {id}")
        t = _Target(int(id), TARGET_KINDS[kind], _vec3(position, "position"), _vec3(size, "size"))
        _check(_room_set_target(self._handle, _ct.byref(t), None if name is None else name.encode()),
               lambda: _room_last_error(self._handle))

    def __len__(self):
        return _room_target_count(self._handle)

    def set_partner_head(self, head):
        _room_set_partner_head(self._handle, _vec3(head, "head"))

    def set_person(self, person, head):
        if not 0 <= int(person) <= 255:  # ctypes would wrap it silently
            raise ValueError(f"person: a person id is 1..254, got {person}")
        _check(_room_set_person(self._handle, int(person), _vec3(head, "head")),
               lambda: _room_last_error(self._handle))


class BodyCalibration:
    """A person's body and upright posture: height, arm_length (m), deictic_hand ("left" or
    "right"), root (7: x, y, z, qx, qy, qz, qw), rest_wrists (2, 3) in the root frame."""

    def __init__(self, c=None):
        if c is None:
            c = _BodyCalibration()
            _body_init(_ct.byref(c))
        self._c = c

    height = property(lambda self: self._c.height)
    arm_length = property(lambda self: self._c.arm_length)
    deictic_hand = property(lambda self: "left" if self._c.deictic_hand == 0 else "right")
    root = property(lambda self: _pose_array(self._c.root))
    rest_wrists = property(lambda self: _np.stack([_vec_array(w)
                                                   for w in self._c.rest_wrist_in_root]))


def _frame(head=None, gaze=None, wrists=None, index_tips=None, valid=None, time=0.0,
           head_target=-1, hand_target=-1, head_target_position=(0, 0, 0),
           hand_target_position=(0, 0, 0)):
    """A tracking frame from arrays: head (7,), gaze (3,), wrists (2, 7), index_tips (2, 3),
    by hand 0 = left, 1 = right. `valid` defaults to the parts given."""
    f = _TrackingFrame()
    _tracking_frame_init(_ct.byref(f))
    flags = 0
    f.time = float(time)
    if head is not None:
        f.head = _pose(head, "head")
        flags |= 1
    if gaze is not None:
        f.gaze = _vec3(gaze, "gaze")
        flags |= 2
    if wrists is not None or index_tips is not None:
        w = _np.asarray(wrists, dtype=_np.float64)
        t = _np.asarray(index_tips, dtype=_np.float64)
        if w.shape != (2, 7) or t.shape != (2, 3):
            raise ValueError(f"wrists (2, 7) and index_tips (2, 3) by hand, got {w.shape} and "
                             f"{t.shape}")
        for h in range(2):
            f.wrist[h] = _pose(w[h], "wrists")
            f.index_tip[h] = _vec3(t[h], "index_tips")
        flags |= 4 | 8
    f.valid = flags if valid is None else int(valid)
    f.head_target = int(head_target)
    f.hand_target = int(hand_target)
    f.head_target_position = _vec3(head_target_position, "head_target_position")
    f.hand_target_position = _vec3(hand_target_position, "hand_target_position")
    return f


def calibrate_upright(deictic_hand="right", height=0.0, arm_length=0.0, **frame):
    """The body calibration from a frame of the person standing upright (keyword arrays as
    Translator.tick takes them); height and arm_length 0 are estimated."""
    if deictic_hand not in HANDS:
        raise ValueError(f"deictic_hand: 'left' or 'right', got {deictic_hand!r}")
    f = _frame(**frame)
    body = _UprightBody(HANDS[deictic_hand], height, arm_length)
    out = _BodyCalibration()
    error = _Error()
    status = _calibrate_upright(_ct.byref(f), _ct.byref(body), _ct.byref(out), _ct.byref(error))
    if status != 0:
        raise DeixisError(status, error.message.decode("utf-8", "replace"))
    return BodyCalibration(out)


class Translator(_Handle):
    """One remote person's avatar in this room (deixis_translator): their tracking in, the
    avatar's end-effectors and skeleton out. Keep the networks, avatar and room alive while it
    is used."""
    _destroy = staticmethod(_translator_destroy)

    def __init__(self, mpnet, ugnet, avatar, person=None, avatar_floor=(0, 0, 0, 0, 0, 0, 1),
                 noise_seed=1, mirror="auto", touch_contact=True, gaze_settle=True,
                 pointing_settle=True):
        if mirror not in MIRRORS:
            raise ValueError(f"mirror: one of {sorted(MIRRORS)}, got {mirror!r}")
        config = _TranslatorConfig()
        _config_init(_ct.byref(config))
        if person is not None:
            config.person = person._c
        config.avatar_floor = _pose(avatar_floor, "avatar_floor")
        config.noise_seed = noise_seed
        config.mirror = MIRRORS[mirror]
        config.touch_contact = int(bool(touch_contact))
        config.gaze_settle = int(bool(gaze_settle))
        config.pointing_settle = int(bool(pointing_settle))
        self._networks = (mpnet, ugnet, avatar)  # they must outlive the translator
        self._handle = _create(_translator_create, mpnet._handle, ugnet._handle, avatar._handle,
                               _ct.byref(config))
        self._joint_count = len(avatar.joint_names)

    def tick(self, room, **arrays):
        """One tick. Pass the frame as keyword arrays (head=(7,), gaze=(3,), wrists=(2, 7),
        index_tips=(2, 3), valid=, time=, head_target=, hand_target=, head_target_position=,
        hand_target_position=), or nothing for a frame that did not arrive. Returns a dict of
        the avatar's state (NumPy arrays)."""
        f = _frame(**arrays) if arrays else None
        out = _AvatarFrame()
        _check(_translator_tick(self._handle, None if f is None else _ct.byref(f), room._handle,
                                _ct.byref(out)),
               lambda: _translator_last_error(self._handle))
        return {
            "visible": bool(out.visible), "held": bool(out.held),
            "head": _pose_array(out.head), "gaze": _vec_array(out.gaze),
            "wrist": _pose_array(out.wrist), "index_tip": _vec_array(out.index_tip),
            "eye_midpoint": _vec_array(out.eye_midpoint), "fingertip": _vec_array(out.fingertip),
            "progression": _np.array(out.progression[:], _np.float32),
            "head_weight": out.head_weight, "hand_weight": out.hand_weight,
            "head_target": out.head_target, "hand_target": out.hand_target,
        }

    def joint_poses(self, space="world"):
        """(joints, 7): x, y, z, qx, qy, qz, qw per joint, in "world", "model" or "local"."""
        if space not in SPACES:
            raise ValueError(f"space: one of {sorted(SPACES)}, got {space!r}")
        out = _np.empty((self._joint_count, 7), _np.float32)  # _Pose is 7 packed floats
        _check(_translator_joint_poses(self._handle, SPACES[space],
                                       out.ctypes.data_as(_P(_Pose)), self._joint_count),
               "joint_poses")
        return out

    @property
    def stats(self):
        s = _Stats()
        _translator_stats(self._handle, _ct.byref(s))
        return {name: getattr(s, name) for name, _ in _Stats._fields_}


class TargetSelector(_Handle):
    """What a live user looks at and points at (deixis_target_selector)."""
    _destroy = staticmethod(_selector_destroy)

    def __init__(self, user, self_id=0):
        self._handle = _create(_selector_create, _ct.byref(user._c), self_id)

    def select(self, room, two_site=True, **arrays):
        """The (head_target, hand_target) ids and positions for a frame given as keyword
        arrays (as Translator.tick takes them)."""
        f = _frame(**arrays)
        _check(_selector_select(self._handle, _ct.byref(f), room._handle, int(bool(two_site))),
               lambda: _selector_last_error(self._handle))
        return (f.head_target, f.hand_target, _vec_array(f.head_target_position),
                _vec_array(f.hand_target_position))
