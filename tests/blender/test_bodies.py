"""The moving objects of a run in Blender (docs/blender.md, Moving objects): Firn runs tests/blender/paddle.json (a
paddle keyframed to move and turn, a sphere that stays) and the add-on imports it; the paddle's object is keyed at
every frame with bodies.csv's pose, and its mesh is where Firn's own mesh file of the frame has it: built from the
first mesh file with --mesh, and from the scene's box without."""

import csv
import os
import subprocess
import sys
import unittest

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

SCENE = os.path.join(os.path.dirname(__file__), "paddle.json")
FRAMES = range(0, 5)  # the scene's frames 0-4
HALF_EXTENTS_M = np.array([0.1, 0.05, 0.1])  # the paddle's box about its centre, its pivot
# Blender keeps vertices, keys and matrices as 32-bit floats: within 1 m of the origin each rounds by 6e-8 m, and the
# few products from a file's vertex to its place in Blender stay far within 1e-5 m.
TOLERANCE_M = 1e-5


def run_firn(folder, *options):
    result = subprocess.run([harness.ARGS.firn, "run", SCENE, "--out", folder, *options], capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"firn run: exit {result.returncode}: {result.stdout}{result.stderr}")


def import_run(folder):
    """Imports into the window's scene, the one frame_set evaluates; returns it and the run's parent."""
    parent = harness.addon_module("importer").import_run(bpy.context, folder, SCENE)
    return bpy.context.scene, parent


def rows_of(folder):
    with open(os.path.join(folder, "bodies.csv"), newline="") as f:
        return {int(row["frame"]): row for row in csv.DictReader(f)}


def rotation(row):
    return harness.addon_module("importer").rotation_matrix([float(row[c]) for c in ("qw", "qx", "qy", "qz")])


def position(row):
    return np.array([float(row[c]) for c in ("x_m", "y_m", "z_m")])


def in_firn_axes(scene, parent, obj, frame):
    """The object's vertices at a frame in the run's own coordinates: undoing the parent's turn to Z-up."""
    scene.frame_set(frame)
    matrix = np.array(parent.matrix_world.inverted() @ obj.matrix_world)
    vertices = np.array([tuple(v.co) + (1.0,) for v in obj.data.vertices])
    return (vertices @ matrix.T)[:, :3]


class MovingObjects(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        harness.install_addon()
        cls.meshes = os.path.join(harness.ARGS.work, "with_meshes")
        cls.scene_only = os.path.join(harness.ARGS.work, "without_meshes")
        run_firn(cls.meshes, "--mesh", "--no-ply")
        run_firn(cls.scene_only, "--frames", "2")

    def tearDown(self):
        """Each test imports a run of its own into the one scene: the other's objects go."""
        for obj in list(bpy.context.scene.objects):
            if obj.name.startswith("Firn"):
                bpy.data.objects.remove(obj)

    def children(self, parent):
        return {child.name: child for child in parent.children}

    def test_paddle_follows_bodies_csv_with_the_mesh_of_its_files(self):
        scene, parent = import_run(self.meshes)
        children = self.children(parent)
        self.assertIn("Firn colliders[1]", children)
        self.assertNotIn("Firn collider 1 (box)", children, "bodies.csv's collider is not built twice")
        self.assertIn("Firn collider 0 (plane)", children)
        self.assertIn("Firn collider 2 (sphere)", children)
        paddle = children["Firn colliders[1]"]
        self.assertEqual(paddle.rotation_mode, "QUATERNION")
        rows = rows_of(self.meshes)
        read_ply = harness.addon_module("firn_ply").read_ply
        for frame in FRAMES:
            vertices, triangles = read_ply(os.path.join(self.meshes, f"colliders_1_{frame:04d}.ply"))
            expected = np.stack([vertices[c] for c in ("x", "y", "z")], axis=1)
            placed = in_firn_axes(scene, parent, paddle, frame)
            self.assertEqual(placed.shape, expected.shape)
            self.assertLess(np.abs(placed - expected).max(), TOLERANCE_M, f"frame {frame}")
            self.assertLess(np.abs(np.array(paddle.location) - position(rows[frame])).max(), TOLERANCE_M)
            quaternion = np.array(paddle.rotation_quaternion)
            file_quaternion = np.array([float(rows[frame][c]) for c in ("qw", "qx", "qy", "qz")])
            self.assertLess(np.abs(quaternion - file_quaternion).max(), 1e-6, f"frame {frame}: the row's quaternion")
        self.assertEqual(len(paddle.data.polygons), 12, "the box's 12 triangles")

    def test_without_mesh_files_the_scenes_box_follows_bodies_csv(self):
        scene, parent = import_run(self.scene_only)
        paddle = self.children(parent)["Firn colliders[1]"]
        rows = rows_of(self.scene_only)
        self.assertEqual(sorted(rows), [0, 1, 2])
        for frame in sorted(rows):
            placed = in_firn_axes(scene, parent, paddle, frame)
            # Back in the paddle's own frame every vertex is a corner of its box.
            local = (placed - position(rows[frame])) @ rotation(rows[frame])
            self.assertLess(np.abs(np.abs(local) - HALF_EXTENTS_M).max(), TOLERANCE_M, f"frame {frame}")


harness.run_tests(MovingObjects)
