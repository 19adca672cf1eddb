"""Authors a Firn scene in Blender, as docs/blender.md's walk-through does by hand, and exports it with the add-on:
a snowball thrown at a paddle that turns a quarter turn every 0.2 s, over a ground plane (docs/blender.md's picture).

    blender -b --factory-startup --python scripts/blender-author.py -- --out paddle/paddle.json [--firn build/release/firn]

Every object is an ordinary Blender object marked in the Firn panel (object.firn); the paddle's motion is Blender
keyframes. The add-on is loaded from blender/ in this repository; with --firn the export is checked with
`firn run --check` and the report printed."""

import argparse
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
import firn_blender  # noqa: E402
from firn_blender import authoring, panel  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--out", required=True)
parser.add_argument("--firn", default="")
args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:])

for obj in list(bpy.data.objects):  # the factory startup's cube, light and camera
    bpy.data.objects.remove(obj)
firn_blender.register()
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = 30, 1.0
scene.frame_start, scene.frame_end = 1, 19  # 18 frames, 0.6 s
scene.firn.scene_name = "paddle-throw"
scene.firn.dt = 2.5e-4  # within the snow's elastic bound h / c = 9e-4 s
scene.firn.kernel, scene.firn.transfer = "QUADRATIC", "APIC"

# The domain: a 1.2 × 0.8 m floor, 0.6 m high (Blender's z), 2 cm cells.
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.6, -0.4, 0.3))
domain = bpy.context.object
domain.name = "Domain"
domain.scale = (1.2, 0.8, 0.6)
domain.display_type = "WIRE"
domain.firn.role, domain.firn.cell_size = "DOMAIN", 0.02

# The snowball, thrown along x and a little up.
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.09, location=(0.25, -0.4, 0.22))
ball = bpy.context.object
ball.name = "Snowball"
ball.firn.role, ball.firn.shape, ball.firn.material_preset = "SNOW", "SPHERE", "stomakhin"
ball.firn.velocity = (5.0, 0.0, 1.0)

# The ground.
bpy.ops.mesh.primitive_plane_add(size=1.2, location=(0.6, -0.4, 0.06))
ground = bpy.context.object
ground.name = "Ground"
ground.firn.role, ground.firn.shape, ground.firn.friction = "COLLIDER", "PLANE", 0.4

# The paddle: a board standing on its edge, turning about the vertical a quarter turn every 6 frames.
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.8, -0.4, 0.22))
paddle = bpy.context.object
paddle.name = "Paddle"
paddle.scale = (0.04, 0.36, 0.24)
bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)  # a box of those edges, unscaled
paddle.firn.role, paddle.firn.shape, paddle.firn.boundary = "COLLIDER", "BOX", "STICKY"
for k in range(4):
    paddle.rotation_euler = (0.0, 0.0, math.radians(90.0 * k))
    paddle.keyframe_insert("rotation_euler", frame=1 + 6 * k)
for curve in paddle.animation_data.action.fcurves:
    for key in curve.keyframe_points:
        key.interpolation = "LINEAR"

# The camera, looking down across the throw at the paddle.
bpy.ops.object.camera_add(location=(0.45, -1.6, 0.8))
camera = bpy.context.object
camera.rotation_euler = (Vector((0.65, -0.4, 0.16)) - camera.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera
scene.frame_set(scene.frame_start)

os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
authoring.export_scene(bpy.context, args.out)
print(f"blender-author: wrote {args.out}")
if args.firn:
    code, report = panel.check_scene(args.firn, args.out)
    print(report)
    sys.exit(code)
