"""A saved .blend of an imported run, opened again (as on a render machine with the add-on enabled): the surface
still follows the frame, its meshes read again from the run's files (docs/blender.md, How the meshes follow the
frame)."""

import os
import sys
import unittest

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402


class ReopenedRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        harness.install_addon()
        harness.import_run()
        cls.path = os.path.join(harness.ARGS.work, "imported.blend")
        bpy.ops.wm.save_as_mainfile(filepath=cls.path)
        bpy.ops.wm.open_mainfile(filepath=cls.path)

    def test_surface_follows_the_frame_after_reopening(self):
        read_ply = harness.addon_module("firn_ply").read_ply
        scene = bpy.context.scene
        surface = next(obj for obj in scene.objects if obj.name.startswith("Firn surface"))
        for frame in (3, 5, 0):
            scene.frame_set(frame)
            vertices, triangles = read_ply(os.path.join(harness.ARGS.run, f"frame_{frame:04d}_surface.ply"))
            self.assertEqual(len(surface.data.vertices), len(vertices["x"]), f"frame {frame}")
            self.assertEqual(len(surface.data.polygons), len(triangles), f"frame {frame}")
            self.assertIn("velocity", surface.data.attributes)

    def test_volume_sequence_is_kept(self):
        volume = next(obj for obj in bpy.context.scene.objects if obj.name.startswith("Firn volume"))
        self.assertTrue(volume.data.is_sequence)
        self.assertEqual(volume.data.velocity_grid, "v")


harness.run_tests(ReopenedRun)
