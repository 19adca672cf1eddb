"""The add-on in Debian's Blender, headless (docs/blender.md): installed from its zip and enabled, then the six-frame
run of tests/blender/sliding_block.json imported, and every object checked against the files Firn wrote."""

import math
import os
import sys
import types
import unittest

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

FRAMES = range(0, 6)  # the scene's frames 0-5
CELL_M = 0.04  # the scene's grid.cell_size
SPACING_M = CELL_M / 2  # the particles' spacing: 8 per cell


class ImportedRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.installed = harness.install_addon()
        cls.parent = harness.import_run()
        cls.scene = bpy.context.scene
        cls.children = {child.name: child for child in cls.parent.children}
        cls.ply = harness.addon_module("firn_ply")

    def child(self, prefix):
        matches = [obj for name, obj in self.children.items() if name.startswith(prefix)]
        self.assertEqual(len(matches), 1, f"one {prefix!r} under the parent: {sorted(self.children)}")
        return matches[0]

    def file(self, frame, suffix):
        return os.path.join(harness.ARGS.run, f"frame_{frame:04d}{suffix}")

    def test_addon_installs_from_its_zip_and_enables(self):
        self.assertEqual(self.installed, (True, True), "addon_utils.check: (default, loaded)")
        user_addons = os.path.join(os.environ["BLENDER_USER_SCRIPTS"], "addons", harness.ADDON, "__init__.py")
        self.assertTrue(os.path.isfile(user_addons), "the installer unpacked the zip into the user's add-ons")
        self.assertIn(harness.ADDON, bpy.context.preferences.addons)

    def test_scene_plays_at_the_runs_frame_rate(self):
        render = self.scene.render
        self.assertAlmostEqual(render.fps / render.fps_base, 30.0, places=9)
        self.assertEqual((self.scene.frame_start, self.scene.frame_end), (0, 5))

    def test_parent_turns_y_up_into_z_up(self):
        matrix = self.parent.matrix_world.to_3x3()
        for firn, blender in (((0, 1, 0), (0, 0, 1)), ((1, 0, 0), (1, 0, 0)), ((0, 0, 1), (0, -1, 0))):
            self.assertLess((matrix @ Vector(firn) - Vector(blender)).length, 1e-6)

    def test_surface_follows_the_frame_smooth_with_the_files_normals_and_velocities(self):
        surface = self.child("Firn surface")
        self.assertEqual(surface.material_slots[0].material.name, "Firn snow")
        self.assertEqual([obj.hide_render for obj in (surface, self.child("Firn volume"), self.child("Firn particles"))],
                         [False, True, True], "the surface renders; the volume and the particles are switched off")
        for frame in FRAMES:
            self.scene.frame_set(frame)
            vertices, triangles = self.ply.read_ply(self.file(frame, "_surface.ply"))
            mesh = surface.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
            self.assertEqual(len(mesh.vertices), len(vertices["x"]), f"frame {frame}")
            self.assertEqual(len(mesh.polygons), len(triangles), f"frame {frame}")
            positions = np.empty(3 * len(mesh.vertices), dtype=np.float32)
            mesh.vertices.foreach_get("co", positions)
            expected = np.stack([vertices[n] for n in ("x", "y", "z")], axis=1).ravel()
            self.assertEqual(np.abs(positions - expected).max(), 0.0, "the file's positions, as floats")
            smooth = np.empty(len(mesh.polygons), dtype=bool)
            mesh.polygons.foreach_get("use_smooth", smooth)
            self.assertTrue(smooth.all(), f"frame {frame}: smooth-shaded")
            # Custom normals are stored as 16-bit angles (Blender's short2 encoding), so each loop's normal is the
            # file's to about 1e-4; 0.9999 is a cosine of 0.8 degrees.
            mesh.calc_normals_split()
            loops = np.empty(len(mesh.loops), dtype=np.int32)
            mesh.loops.foreach_get("vertex_index", loops)
            normals = np.empty(3 * len(mesh.loops), dtype=np.float32)
            mesh.loops.foreach_get("normal", normals)
            file_normals = np.stack([vertices[n] for n in ("nx", "ny", "nz")], axis=1)[loops]
            cosines = np.sum(normals.reshape(-1, 3) * file_normals, axis=1)
            self.assertGreater(cosines.min(), 0.9999, f"frame {frame}: the file's normals")
            velocity = np.empty(3 * len(mesh.vertices), dtype=np.float32)
            mesh.attributes["velocity"].data.foreach_get("vector", velocity)
            expected = np.stack([vertices[n] for n in ("vx", "vy", "vz")], axis=1).ravel()
            self.assertEqual(np.abs(velocity - expected).max(), 0.0, f"frame {frame}: the file's velocities")
        self.scene.frame_set(0)

    def test_surface_counts_change_with_the_frame(self):
        counts = set()
        for frame in FRAMES:
            vertices, _ = self.ply.read_ply(self.file(frame, "_surface.ply"))
            counts.add(len(vertices["x"]))
        self.assertGreater(len(counts), 1, "a run whose mesh changes topology (what the handler is for)")

    def test_volume_holds_density_surface_and_velocity_grids_of_the_frame(self):
        volume = self.child("Firn volume")
        self.assertEqual(volume.data.materials[0].name, "Firn snow volume")
        self.assertEqual(volume.data.velocity_grid, "v")
        self.assertEqual(volume.data.velocity_unit, "SECOND")
        for frame in FRAMES:
            self.scene.frame_set(frame)
            grids = volume.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.grids
            self.assertTrue(grids.load(), grids.error_message)
            self.assertEqual(os.path.basename(grids.frame_filepath), f"frame_{frame:04d}.vdb")
            by_name = {grid.name: grid for grid in grids}
            self.assertEqual(set(by_name), {"density", "surface", "v"}, f"frame {frame}")
            self.assertEqual(by_name["v"].data_type, "VECTOR_FLOAT")
            self.assertEqual(by_name["density"].data_type, "FLOAT")
        self.scene.frame_set(0)

    def test_points_carry_the_caches_attributes(self):
        points = self.child("Firn particles")
        self.assertEqual(points.modifiers[0].node_group.name, "Firn particles")
        for frame in FRAMES:
            self.scene.frame_set(frame)
            vertices, _ = self.ply.read_ply(self.file(frame, ".ply"))
            mesh = points.data
            self.assertEqual(len(mesh.vertices), len(vertices["x"]), f"frame {frame}")
            for name, size, columns in (("velocity", 3, ("vx", "vy", "vz")), ("mass", 1, ("mass",)),
                                        ("plastic_j", 1, ("plastic_j",))):
                attribute = mesh.attributes[name]
                self.assertEqual(attribute.domain, "POINT")
                values = np.empty(size * len(mesh.vertices), dtype=np.float32)
                attribute.data.foreach_get("vector" if size == 3 else "value", values)
                expected = np.stack([vertices[c] for c in columns], axis=1).ravel()
                self.assertEqual(np.abs(values - expected).max(), 0.0, f"frame {frame}: {name}")
            # What geometry nodes make of them: points, each attribute carried through Mesh to Points.
            depsgraph = bpy.context.evaluated_depsgraph_get()
            clouds = [instance.object.data for instance in depsgraph.object_instances
                      if instance.object.original == points and instance.object.type == "POINTCLOUD"]
            self.assertEqual(len(clouds), 1, f"frame {frame}: the modifier's points")
            self.assertEqual(len(clouds[0].points), len(vertices["x"]))
            for name in ("velocity", "mass", "plastic_j"):
                self.assertIn(name, clouds[0].attributes, f"frame {frame}: {name} in geometry nodes")
        self.scene.frame_set(0)

    def test_snow_rests_on_the_ground_at_its_blender_height(self):
        """The block rests on the plane collider (Firn y = 0.12, Blender z = 0.12 after the parent's turn). A face
        of a body lies where the field is ½, the body's own face (docs/surfaces.md, The field), to within the
        jitter of the particles (a quarter spacing, s/4 = 5 mm) and the compression of the block under its own
        weight; marching cubes interpolates linearly between nodes 2 cm apart, which on a flat face is exact.
        So the lowest vertex is within a quarter of the particles' spacing (5 mm) of the ground (measured: 3.1 to
        3.4 mm below it)."""
        surface = self.child("Firn surface")
        ground = self.child("Firn collider 0 (plane)")
        for frame in FRAMES:
            self.scene.frame_set(frame)
            ground_z = [(ground.matrix_world @ v.co).z for v in ground.data.vertices]
            self.assertLess(max(ground_z) - min(ground_z), 1e-6, "the plane lies flat in Blender")
            self.assertAlmostEqual(ground_z[0], 0.12, places=6)
            matrix = surface.matrix_world
            lowest = min((matrix @ v.co).z for v in surface.data.vertices)
            self.assertLess(abs(lowest - ground_z[0]), SPACING_M / 4, f"frame {frame}: lowest {lowest}")
        self.scene.frame_set(0)

    def test_run_firn_runs_a_scene_and_follows_its_frames(self):
        """Run Firn's job (the operator's modal loop polls it on a timer, which a background Blender has not): one
        frame of the scene, its progress from stats.csv, then the folder imports."""
        runner = harness.addon_module("runner")
        folder = os.path.join(harness.ARGS.work, "run_firn")
        job = runner.FirnJob(harness.ARGS.firn, harness.ARGS.scene, folder, frames=1, volume=False)
        self.assertEqual(job.frames, 1)
        state = job.wait()
        self.assertTrue(state.finished)
        self.assertEqual(state.exit_code, 0, state.message)
        self.assertEqual(state.fraction, 1.0)
        for name in ("frame_0001.ply", "frame_0001_surface.ply", "firn.log"):
            self.assertTrue(os.path.isfile(os.path.join(folder, name)), name)
        self.assertFalse(os.path.exists(os.path.join(folder, "frame_0001.vdb")), "no VDB asked for")
        scene = bpy.data.scenes.new("Run Firn")  # a scene of its own, leaving the imported run's as it is
        context = types.SimpleNamespace(scene=scene, collection=scene.collection)
        parent = harness.addon_module("importer").import_run(context, folder, harness.ARGS.scene)
        self.assertEqual(len([c for c in parent.children if c.name.startswith("Firn surface")]), 1)
        self.assertEqual((scene.frame_start, scene.frame_end), (0, 1))
        with self.assertRaises(runner.FirnJobError):
            runner.FirnJob(os.path.join(harness.ARGS.work, "no-firn-here"), harness.ARGS.scene, folder)


harness.run_tests(ImportedRun)
