"""The `deixis` Python module (python/deixis) against the authors' parity fixtures and the C API.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH=<build>/python; by hand:
    PYTHONPATH=build/release/python python3 -m unittest discover -s tests/python -v
DEIXIS_REFERENCE_DIR chooses the reference data (default ../shared/reference): every MPNet and
UGNet fixture in its fixtures/ runs through the module against the checkpoint its metadata names.
"""

import csv
import json
import math
import os
import struct
import unittest

import numpy as np

import deixis

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REFERENCE_DIR = os.environ.get("DEIXIS_REFERENCE_DIR",
                               os.path.join(SOURCE_DIR, "..", "shared", "reference"))
EXAMPLES = os.path.join(SOURCE_DIR, "examples", "data")
# NOTES.md section 10.1: float32 ports agree with the authors' float32 outputs within these.
TOLERANCE = {"MPNet": 5e-5, "UGNet_Diffusion": 5e-5, "UGNet": 1e-5}


def read_safetensors(path):
    """The tensors (as NumPy arrays) and the metadata of a .safetensors file."""
    with open(path, "rb") as f:
        data = f.read()
    (header_size,) = struct.unpack("<Q", data[:8])
    header = json.loads(data[8:8 + header_size])
    metadata = header.pop("__metadata__", {})
    dtypes = {"F32": np.float32, "F64": np.float64, "I64": np.int64}
    tensors = {}
    for name, entry in header.items():
        begin, end = entry["data_offsets"]
        raw = data[8 + header_size + begin:8 + header_size + end]
        tensors[name] = np.frombuffer(raw, dtypes[entry["dtype"]]).reshape(entry["shape"])
    return tensors, metadata


def fixtures(prefix):
    directory = os.path.join(REFERENCE_DIR, "fixtures")
    if not os.path.isdir(directory):
        return []
    return sorted(os.path.join(directory, f) for f in os.listdir(directory)
                  if f.startswith(prefix) and f.endswith(".safetensors"))


def tracking_rows():
    """The examples' recording (the `deixis capture csv` layout) as Translator.tick arguments."""
    with open(os.path.join(EXAMPLES, "pointing.csv")) as f:
        for row in csv.DictReader(f):
            v = {k: float(x) for k, x in row.items() if k not in ("category",)}

            def pose(name):
                return [v[name + "_x"], v[name + "_y"], v[name + "_z"], v[name + "_q_x"],
                        v[name + "_q_y"], v[name + "_q_z"], v[name + "_q_w"]]

            def vec(name):
                return [v[name + "_x"], v[name + "_y"], v[name + "_z"]]

            yield dict(time=v["time"], valid=int(v["valid"]), head=pose("head"), gaze=vec("gaze"),
                       wrists=[pose("left_wrist"), pose("right_wrist")],
                       index_tips=[vec("left_tip"), vec("right_tip")],
                       head_target=int(v["head_target"]), hand_target=int(v["hand_target"]),
                       head_target_position=vec("head_target"),
                       hand_target_position=vec("hand_target"))


class AuthorsFixtures(unittest.TestCase):
    """The authors' networks through the module reproduce the authors' PyTorch outputs."""

    def check(self, prefix, network_class, run):
        paths = fixtures(prefix)
        self.assertTrue(paths, f"no {prefix}* fixtures in {REFERENCE_DIR}/fixtures")
        for path in paths:
            name = os.path.basename(path)
            with self.subTest(fixture=name):
                tensors, metadata = read_safetensors(path)
                network = network_class(os.path.join(REFERENCE_DIR, metadata["checkpoint"]))
                got = run(network, tensors)
                tolerance = TOLERANCE["UGNet_Diffusion" if "Diffusion" in name else
                                      name.split("_")[0]]
                np.testing.assert_allclose(got, tensors["output"], rtol=0, atol=tolerance,
                                           err_msg=name)

    def test_mpnet_fixtures_batched_and_one_window_at_a_time(self):
        def run(mpnet, t):
            batch = mpnet.run(t["input"])
            self.assertEqual(batch.shape, (t["input"].shape[0], 3))
            one = np.stack([mpnet.run(window) for window in t["input"]])
            np.testing.assert_array_equal(batch, one)
            return batch
        self.check("MPNet_", deixis.Mpnet, run)

    def test_ugnet_fixtures_with_the_diffusion_draws_they_used(self):
        def run(ugnet, t):
            noise = None
            if ugnet.needs_noise:
                # Row 0 the initial sample, row s + 1 the fixture's noise[s] (NOTES.md 10.1).
                noise = np.concatenate([t["noise_init"][:, None, :],
                                        np.transpose(t["noise"], (1, 0, 2))], axis=1)
                self.assertEqual(noise.shape, (t["input"].shape[0], 30, 24))
            out = ugnet.run(t["input"], noise)
            self.assertEqual(out.shape, (t["input"].shape[0], 24))
            first = ugnet.run(t["input"][0], None if noise is None else noise[0])
            np.testing.assert_array_equal(first, out[0])
            return out
        self.check("UGNet_", deixis.Ugnet, run)


class Networks(unittest.TestCase):
    def test_shapes_dtypes_and_layouts(self):
        mpnet = deixis.Mpnet()  # the shipped MoE
        self.assertEqual(mpnet.architecture, "GRU-MoE")
        rng = np.random.default_rng(3)
        x = rng.normal(size=(5, 30, 11))
        reference = mpnet.run(x.astype(np.float32))
        np.testing.assert_array_equal(mpnet.run(x), reference)  # float64 in: converted
        strided = np.asfortranarray(x.astype(np.float32))  # not C-contiguous: copied
        np.testing.assert_array_equal(mpnet.run(strided), reference)
        self.assertEqual(mpnet.run(x[0].astype(np.float32)).shape, (3,))
        self.assertEqual(mpnet.run(np.zeros((0, 30, 11), np.float32)).shape, (0, 3))
        for bad in (np.zeros((30, 12)), np.zeros((2, 29, 11)), np.zeros(330)):
            with self.assertRaises(ValueError):
                mpnet.run(bad)
        ugnet = deixis.Ugnet()
        self.assertEqual(ugnet.run(np.zeros((3, 30, 32))).shape, (3, 24))
        with self.assertRaises(ValueError):
            ugnet.run(np.zeros((2, 30, 32)), noise=np.zeros((1, 720)))

    def test_file_errors_carry_the_librarys_message(self):
        with self.assertRaises(deixis.DeixisError) as caught:
            deixis.Mpnet("/nonexistent/MPNet.safetensors")
        self.assertEqual(caught.exception.status, 2)
        self.assertIn("/nonexistent/MPNet.safetensors", str(caught.exception))
        with self.assertRaises(deixis.DeixisError):
            deixis.Ugnet(os.path.join(SOURCE_DIR, "assets/weights/right/MPNet(MoE)(AC)80.safetensors"))
        with self.assertRaises(deixis.DeixisError):
            deixis.load_avatar(os.path.join(EXAMPLES, "room.json"))


class TranslatorThroughPython(unittest.TestCase):
    def test_the_recording_drives_the_avatar_toward_this_rooms_globe(self):
        avatar = deixis.load_avatar()
        self.assertGreater(len(avatar.joint_names), 20)
        self.assertTrue(all(p < j for j, p in enumerate(avatar.parents)))
        room = deixis.Room(os.path.join(EXAMPLES, "room.json"))
        self.assertEqual(len(room), 2)
        rows = list(tracking_rows())
        person = deixis.calibrate_upright(**rows[0])
        self.assertTrue(1.4 < person.height < 2.1, person.height)
        translator = deixis.Translator(deixis.Mpnet(), deixis.Ugnet(), avatar, person,
                                       avatar_floor=(0.3, 0, -1.0, 0, 0, 0, 1))
        globe = np.array([1.1, 1.25, -2.6])
        nearest = math.inf
        for row in rows:
            out = translator.tick(room, **row)
            self.assertTrue(out["visible"])
            self.assertTrue(np.all(np.isfinite(out["fingertip"])))
            # The fingertip after IK is where the skeleton's pose puts the deictic index.
            world = translator.joint_poses("world")
            self.assertEqual(world.shape, (len(avatar.joint_names), 7))
            self.assertLess(np.min(np.linalg.norm(world[:, :3] - out["fingertip"], axis=1)), 0.05)
            # How close the pointing ray from the eyes through the fingertip passes the globe.
            ray = out["fingertip"] - out["eye_midpoint"]
            ray /= np.linalg.norm(ray)
            to_globe = globe - out["eye_midpoint"]
            miss = np.linalg.norm(to_globe - np.dot(to_globe, ray) * ray)
            nearest = min(nearest, miss / np.linalg.norm(to_globe))
        # At the hold the ray passes within a few degrees of this room's globe (sin(5°) ≈ 0.087).
        self.assertLess(nearest, 0.087)
        self.assertEqual(translator.stats["ticks"], len(rows))
        missed = translator.tick(room)  # a frame that did not arrive
        self.assertTrue(missed["held"])
        with self.assertRaises(ValueError):
            translator.joint_poses("elsewhere")

    def test_bad_frames_and_configs_are_errors_not_crashes(self):
        avatar = deixis.load_avatar()
        with self.assertRaises(deixis.DeixisError) as caught:
            person = deixis.BodyCalibration()
            person._c.height = float("nan")
            deixis.Translator(deixis.Mpnet(), deixis.Ugnet(), avatar, person)
        self.assertIn("person.height", str(caught.exception))
        with self.assertRaises(deixis.DeixisError):
            deixis.calibrate_upright(gaze=(0, 0, -1))  # no head tracked
        with self.assertRaises(ValueError):
            deixis.calibrate_upright(head=(0, 1.6, 0))  # 3 numbers, not a pose
        room = deixis.Room()
        with self.assertRaises(deixis.DeixisError):
            room.set_target(0, (0, 1, -1), (0.2, 0.2, 0.2))  # id 0 is the other person
        with self.assertRaises(deixis.DeixisError):
            room.set_person(0, (0, 1.6, 0))
        with self.assertRaises(ValueError):  # not wrapped around to person 1
            room.set_person(257, (0, 1.6, 0))
        with self.assertRaises(ValueError):  # not wrapped around to id 1
            room.set_target(2**32 + 1, (0, 1, -1), (0.2, 0.2, 0.2))
        room.set_target(4, (0, 1.5, -2), (0.2, 0.2, 0.2), kind="box", name="cube")
        selector = deixis.TargetSelector(deixis.calibrate_upright(head=(0, 1.6, 0, 0, 0, 0, 1)))
        head_target, _, position, _ = selector.select(room, head=(0, 1.6, 0, 0, 0, 0, 1),
                                                      gaze=(0, -0.05, -1))
        self.assertEqual(head_target, 4)
        np.testing.assert_allclose(position, (0, 1.5, -2))


if __name__ == "__main__":
    unittest.main()
