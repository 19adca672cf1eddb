"""Renders one frame of a Firn run in Blender with the add-on (docs/blender.md's picture):

    blender -b --factory-startup --python scripts/blender-picture.py -- \
        --run firn-out --scene assets/scenes/snowman.json --frame 9 --out docs/images/blender.png --samples 64

The add-on is loaded from blender/ in this repository. The run's surface is rendered by Cycles on the CPU, with
motion blur (the meshes' velocities), lit by a sun and the sky, seen from the scene's camera (its `camera`
section, or one looking at the snow), the colliders grey."""

import argparse
import json
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
import firn_blender  # noqa: E402
from firn_blender import importer  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--run", required=True)
parser.add_argument("--scene", required=True)
parser.add_argument("--frame", type=int, required=True)
parser.add_argument("--out", required=True)
parser.add_argument("--width", type=int, default=640)
parser.add_argument("--height", type=int, default=360)
parser.add_argument("--samples", type=int, default=32)
args = parser.parse_args(sys.argv[sys.argv.index("--") + 1:])

for obj in list(bpy.data.objects):  # the factory startup's cube, light and camera
    bpy.data.objects.remove(obj)
firn_blender.register()
scene = bpy.context.scene
parent = importer.import_run(bpy.context, args.run, args.scene)
scene.frame_set(args.frame)
for obj in parent.children:
    obj.hide_render = obj.name.startswith(("Firn volume", "Firn particles"))
    if obj.name.startswith("Firn collider"):
        grey = bpy.data.materials.new("Collider grey")
        grey.diffuse_color = (0.35, 0.33, 0.3, 1.0)
        grey.use_nodes = True
        grey.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.35, 0.33, 0.3, 1.0)
        obj.data.materials.append(grey)

# The scene's camera, in Firn's coordinates, through the parent's turn to Blender's.
with open(args.scene) as f:
    firn_camera = json.load(f).get("camera")
surface = next(obj for obj in parent.children if obj.name.startswith("Firn surface"))
if firn_camera:
    position = parent.matrix_world @ Vector(firn_camera["position"])
    target = parent.matrix_world @ Vector(firn_camera["target"])
    fov_deg = firn_camera.get("fov_deg", 40)
else:
    target = sum((surface.matrix_world @ v.co for v in surface.data.vertices), Vector()) / len(surface.data.vertices)
    position = target + Vector((0.0, -1.5, 0.6))
    fov_deg = 40
camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = position
camera.rotation_euler = (target - position).to_track_quat("-Z", "Y").to_euler()
camera.data.sensor_fit = "VERTICAL"
camera.data.angle = math.radians(fov_deg)
scene.collection.objects.link(camera)
scene.camera = camera

sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
sun.data.energy = 4.0
sun.data.angle = math.radians(3)
sun.rotation_euler = (math.radians(50), math.radians(-20), math.radians(-30))
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("Sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.45, 0.55, 0.75, 1.0)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = args.samples
scene.cycles.use_denoising = False  # Debian's Blender is built without OpenImageDenoise
scene.render.use_motion_blur = True
scene.render.resolution_x, scene.render.resolution_y = args.width, args.height
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Filmic"
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.compression = 100
scene.render.filepath = os.path.abspath(args.out)
bpy.ops.render.render(write_still=True)
