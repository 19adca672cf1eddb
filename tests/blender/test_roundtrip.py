"""Every scene in assets/scenes through Blender and back (docs/blender.md, Authoring a scene): File > Import > Firn
scene makes its objects, File > Export > Firn scene writes them again, and `firn run --check` gives the export the
scene fingerprint of the original (the grid, the step, the materials, the colliders and rigid bodies with their
distance fields, every particle: docs/command-line.md)."""

import glob
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


harness.run_tests(RoundTrip)
