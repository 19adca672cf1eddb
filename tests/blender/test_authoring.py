"""A Firn scene authored in Blender (docs/blender.md, Authoring a scene): a scene built by a script — a sphere marked
snow, a plane collider, a keyframed cube turning a quarter turn, a rigid box whose mass and friction are Blender's
Rigid Body settings, a domain box — exported equals tests/blender/authored.json key by key (positions within float
rounding), and `firn run` of the export writes the same bytes as of that hand-written file. A mesh marked snow that
is not closed is reported on the Scene panel with the voxelizer's message."""

import json
import math
import os
import subprocess
import sys
import unittest

import bpy
from mathutils import Euler

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402
from authored_scene import HAND_WRITTEN, build_scene, empty_scene  # noqa: E402

def differences(expected, actual, path=""):
    """Where two scenes differ: keys, strings and integers exactly, numbers within 1e-6 of their size (what the
    export's 32-bit floats and their shortest decimals leave)."""
    if isinstance(expected, dict) and isinstance(actual, dict):
        found = [f"{path}: keys {sorted(set(expected) ^ set(actual))}"] if set(expected) != set(actual) else []
        for key in set(expected) & set(actual):
            found += differences(expected[key], actual[key], f"{path}.{key}")
        return found
    if isinstance(expected, list) and isinstance(actual, list) and len(expected) == len(actual):
        return [d for i, (e, a) in enumerate(zip(expected, actual)) for d in differences(e, a, f"{path}[{i}]")]
    numbers = (int, float)
    if isinstance(expected, numbers) and isinstance(actual, numbers) and not isinstance(expected, bool):
        return [] if abs(expected - actual) <= 1e-6 * max(1.0, abs(expected)) else [f"{path}: {expected} != {actual}"]
    return [] if expected == actual else [f"{path}: {expected!r} != {actual!r}"]


def panel_lines(scene):
    """The lines the Scene panel's report box shows."""
    from firn_blender import panel
    return panel.report_lines(scene.firn)


def run_firn(scene_path, out):
    done = subprocess.run([harness.ARGS.firn, "run", scene_path, "--frames", "2", "--out", out],
                          capture_output=True, text=True)
    if done.returncode != 0:
        raise AssertionError(f"firn run {scene_path}: exit {done.returncode}\n{done.stdout}{done.stderr}")


class Authoring(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        assert harness.install_addon() == (True, True)
        bpy.context.preferences.addons[harness.ADDON].preferences.firn_path = harness.ARGS.firn

    def export(self, folder):
        """The scene exported with File > Export > Firn scene into the work folder's `folder`, checked by firn: its
        path, and the scene as written."""
        path = os.path.join(harness.ARGS.work, folder, "authored.json")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        self.assertEqual(bpy.ops.export_scene.firn_scene(filepath=path), {"FINISHED"},
                         bpy.context.scene.firn.check_report)
        self.assertTrue(bpy.context.scene.firn.check_ok, bpy.context.scene.firn.check_report)
        with open(path) as f:
            return path, json.load(f)

    def test_exported_scene_equals_the_hand_written_one(self):
        build_scene()
        path, exported = self.export("authored")
        with open(HAND_WRITTEN) as f:
            expected = json.load(f)
        self.assertEqual(differences(expected, exported), [], json.dumps(exported, indent=1))

        # The same run, to the byte: every frame file of two frames.
        one, other = os.path.join(harness.ARGS.work, "run_exported"), os.path.join(harness.ARGS.work, "run_written")
        run_firn(path, one)
        run_firn(HAND_WRITTEN, other)
        frames = sorted(name for name in os.listdir(other) if name.endswith(".ply"))
        self.assertEqual(len(frames), 3)  # frames 0, 1 and 2
        for name in frames:
            with open(os.path.join(one, name), "rb") as a, open(os.path.join(other, name), "rb") as b:
                self.assertEqual(a.read(), b.read(), name)

    def test_a_scene_in_centimetres_exports_in_metres(self):
        scene = build_scene()
        scene.unit_settings.scale_length = 0.01  # a Blender unit is a centimetre
        scene.gravity = (0.0, 0.0, -981.0)  # which Blender shows as −9.81 m/s² (velocities are typed in m/s)
        for obj in scene.objects:
            obj.location *= 100.0
            obj.scale *= 100.0
        _, exported = self.export("centimetres")
        scene.unit_settings.scale_length = 1.0
        with open(HAND_WRITTEN) as g:
            self.assertEqual(differences(json.load(g), exported), [])

    def test_a_custom_material_exports_its_models_keys(self):
        build_scene()
        ball = bpy.data.objects["Ball"].firn
        ball.material_preset, ball.material_model = "CUSTOM", "WATER"
        ball.density, ball.bulk_modulus, ball.gamma, ball.viscosity = 1000.0, 2e5, 7.0, 0.01
        _, exported = self.export("water")
        self.assertEqual(exported["bodies"][0]["material"], "Ball")
        self.assertEqual(exported["materials"], {"Ball": {"model": "water", "density": 1000.0, "bulk_modulus": 2e5,
                                                          "gamma": 7.0, "viscosity": 0.01}})

    def test_keys_a_turn_apart_are_exported_frame_by_frame(self):
        # 0° to 270° in ten frames: Firn would take the shorter way, 90° back, between two keyframes so far apart.
        build_scene()
        paddle = bpy.data.objects["Paddle"]
        curve = paddle.animation_data.action.fcurves.find("rotation_euler", index=2)
        curve.keyframe_points[1].co.y = math.radians(270.0)
        keys = self.export("turn")[1]["colliders"][1]["keyframes"]
        self.assertEqual([round(30 * k["time_s"], 6) for k in keys], list(range(11)))  # every frame, 27° apart
        for k, key in enumerate(keys):
            turn = math.radians(27.0 * k)  # about Firn's y, as Blender's z
            expected = (math.cos(turn), -math.sin(turn))  # R's first column's x and z
            angles = [math.radians(a) for a in key.get("rotate_deg", [0, 0, 0])]
            rotation = Euler(angles, "XYZ").to_matrix()
            self.assertAlmostEqual(rotation[0][0], expected[0], places=5)
            self.assertAlmostEqual(rotation[2][0], expected[1], places=5)

    def test_a_rigid_body_without_blenders_settings_takes_the_panels_mass(self):
        build_scene()
        crate = bpy.data.objects["Crate"]
        bpy.context.view_layer.objects.active = crate
        bpy.ops.rigidbody.object_remove()
        crate.firn.mass, crate.firn.body_friction = 3.0, 0.3
        body = self.export("panel_mass")[1]["rigid_bodies"][0]
        self.assertEqual((body["mass"], "friction" in body), (3.0, False))  # 0.3, Firn's default, left out

    def test_an_imported_object_given_another_shape_is_written_anew(self):
        empty_scene()
        self.assertEqual(bpy.ops.import_scene.firn_scene(filepath=HAND_WRITTEN), {"FINISHED"})
        ball = next(obj for obj in bpy.data.objects if obj.firn.role == "SNOW")
        ball.firn.shape = "BOX"
        body = self.export("reshaped")[1]["bodies"][0]
        self.assertEqual(sorted(body), ["material", "max", "min", "shape", "velocity"])
        self.assertEqual(body["shape"], "box")

    def test_the_panels_draw_every_setting_they_name(self):
        # The panels' draw() as the Properties editor calls it, on a layout that checks each property and operator it
        # is given exists: a misspelt name would only show as a broken panel in the interface.
        from types import SimpleNamespace
        from firn_blender import panel
        drawn = set()

        class Layout:
            def prop(self, data, name, **_):
                assert name in data.bl_rna.properties, name
                drawn.add(name)

            def operator(self, idname, **_):
                module, name = idname.split(".")
                assert hasattr(getattr(bpy.ops, module), name), idname

            def label(self, **_):
                pass

            def row(self):
                return self

            def box(self):
                return self

        scene = build_scene()
        ball = bpy.data.objects["Ball"]
        for role in ("NONE", "SNOW", "EMITTER", "COLLIDER", "RIGID_BODY", "DOMAIN"):
            for shape in ("MESH", "SPHERE"):
                for preset in ("stomakhin", "CUSTOM"):
                    for model in ("SNOW", "WATER", "DRUCKER_PRAGER"):
                        for source in ("BLENDER", "MASS", "DENSITY"):
                            ball.firn.role, ball.firn.shape, ball.firn.mass_source = role, shape, source
                            ball.firn.material_preset, ball.firn.material_model = preset, model
                            panel.FIRN_PT_object.draw(SimpleNamespace(layout=Layout()), SimpleNamespace(object=ball))
        scene.firn.check_ok, scene.firn.check_report = True, "firn: warning: something\nfirn: check: ready to run"
        panel.FIRN_PT_scene.draw(SimpleNamespace(layout=Layout()), SimpleNamespace(scene=scene))
        settings = set(ball.firn.bl_rna.properties.keys()) - {"rna_type", "name"}
        hidden = {p for p in settings if ball.firn.bl_rna.properties[p].is_hidden}
        self.assertEqual(settings - hidden - drawn, set())  # every setting is on the panel

    def test_an_open_mesh_marked_snow_is_reported_with_the_voxelizers_message(self):
        scene = build_scene()
        ball = bpy.data.objects["Ball"]
        ball.firn.shape = "MESH"
        # Two faces of a cube that meet at an edge: open, and nowhere is its winding number ½.
        import bmesh
        shape = bmesh.new()
        shape.from_mesh(ball.data)
        bmesh.ops.delete(shape, geom=list(shape.verts), context="VERTS")
        bmesh.ops.create_cube(shape, size=0.2)
        corner = [f for f in shape.faces if f.normal.x > 0.5 or f.normal.y > 0.5]
        bmesh.ops.delete(shape, geom=[f for f in shape.faces if f not in corner], context="FACES_ONLY")
        shape.to_mesh(ball.data)
        shape.free()
        scene.firn.folder = os.path.join(harness.ARGS.work, "open")
        # Pre-flight warns (the voxelizer's words) and would still run it: the panel shows the warning.
        self.assertEqual(bpy.ops.firn.check(), {"FINISHED"})
        warnings = [line for line in scene.firn.check_report.splitlines() if "warning:" in line]
        self.assertEqual(len(warnings), 1, scene.firn.check_report)
        self.assertIn("warning: bodies[0]: meshes/Ball.obj: the mesh is open (6 edges border holes)", warnings[0])
        self.assertIn("fills as a sheet along its surface; close the mesh", warnings[0])
        self.assertEqual(panel_lines(scene)[:2], ["Ready to run, with 1 warning", warnings[0]])


harness.run_tests(Authoring)
