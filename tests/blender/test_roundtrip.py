"""Every scene in assets/scenes through Blender and back (docs/blender.md, Authoring a scene): File > Import > Firn
scene makes its objects, File > Export > Firn scene writes them again, and `firn run --check` gives the export the
scene fingerprint of the original (the grid, the step, the materials, the colliders and rigid bodies with their
distance fields, every particle: docs/command-line.md)."""

import glob
import json
import os
import sys
import unittest

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

SCENES = sorted(glob.glob(os.path.join(os.path.dirname(__file__), "..", "..", "assets", "scenes", "*.json")))


def fingerprint(report):
    """The fingerprint on the check's last line ('…, scene fingerprint 0123456789abcdef; nothing simulated …')."""
    last = report.splitlines()[-1]
    if "scene fingerprint " not in last:
        raise AssertionError(f"no fingerprint in the check's report:\n{report}")
    return last.split("scene fingerprint ")[1].split(";")[0]


def clear():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for collection in list(bpy.data.collections):
        bpy.data.collections.remove(collection)
    scene = bpy.context.scene
    scene.property_unset("firn")
    scene.frame_start = 1


class RoundTrip(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        assert harness.install_addon() == (True, True)
        bpy.context.preferences.addons[harness.ADDON].preferences.firn_path = harness.ARGS.firn

    def test_every_scene_exports_to_its_own_fingerprint(self):
        from firn_blender import panel
        self.assertGreaterEqual(len(SCENES), 15)
        for path in SCENES:
            name = os.path.splitext(os.path.basename(path))[0]
            with self.subTest(scene=name):
                clear()
                self.assertEqual(bpy.ops.import_scene.firn_scene(filepath=path), {"FINISHED"})
                exported = os.path.join(harness.ARGS.work, name, name + ".json")
                os.makedirs(os.path.dirname(exported), exist_ok=True)
                self.assertEqual(bpy.ops.export_scene.firn_scene(filepath=exported), {"FINISHED"},
                                 bpy.context.scene.firn.check_report)
                code, original = panel.check_scene(harness.ARGS.firn, path)
                self.assertEqual(code, 0, original)
                self.assertEqual(fingerprint(bpy.context.scene.firn.check_report), fingerprint(original))


    def test_a_collider_keyed_away_from_its_rest_from_the_start_keeps_its_keys(self):
        # The first frame shows the first keyframe's pose (turned 45°, moved 5 cm), not the box at rest.
        from firn_blender import panel
        with open(os.path.join(os.path.dirname(__file__), "authored.json")) as f:
            scene = json.load(f)
        scene["colliders"][1]["keyframes"] = [
            {"time_s": 0, "translate": [0, 0.05, 0], "rotate_deg": [0, 45, 0]},
            {"time_s": 0.2, "translate": [0, 0.05, 0], "rotate_deg": [0, 120, 0]}]
        path = os.path.join(harness.ARGS.work, "keyed", "keyed.json")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            json.dump(scene, f)
        clear()
        self.assertEqual(bpy.ops.import_scene.firn_scene(filepath=path), {"FINISHED"})
        exported = os.path.join(harness.ARGS.work, "keyed", "exported.json")
        self.assertEqual(bpy.ops.export_scene.firn_scene(filepath=exported), {"FINISHED"},
                         bpy.context.scene.firn.check_report)
        with open(exported) as f:
            self.assertEqual(json.load(f)["colliders"][1], scene["colliders"][1])
        code, original = panel.check_scene(harness.ARGS.firn, path)
        self.assertEqual(code, 0, original)
        self.assertEqual(fingerprint(bpy.context.scene.firn.check_report), fingerprint(original))


harness.run_tests(RoundTrip)
