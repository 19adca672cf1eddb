"""The scene the authoring tests build in Blender by script (test_authoring.py, test_simulate.py): a domain box, a
sphere marked snow thrown at 2 m/s, a plane collider, a box collider keyed to turn a quarter turn over ten frames, and
a rigid box whose mass and friction are Blender's Rigid Body settings; tests/blender/authored.json is the same scene
written by hand."""

import math
import os

import bpy

HAND_WRITTEN = os.path.join(os.path.dirname(__file__), "authored.json")
# Firn's (x, y, z) is Blender's (x, −z, y).


def blender(x, y, z):
    return (x, -z, y)


def empty_scene():
    """The scene without objects, its Firn settings and frame range as new."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.property_unset("firn")
    scene.unit_settings.scale_length = 1.0
    scene.gravity = (0.0, 0.0, -9.81)
    scene.frame_start, scene.frame_end = 1, 13
    scene.render.fps, scene.render.fps_base = 30, 1.0
    scene.camera = None
    return scene


def box_object(name, size_firn, centre_firn):
    import bmesh
    shape = bmesh.new()
    bmesh.ops.create_cube(shape, size=1.0)
    sx, sy, sz = size_firn
    bmesh.ops.scale(shape, vec=(sx, sz, sy), verts=shape.verts)  # Firn's sizes along Blender's axes
    mesh = bpy.data.meshes.new(name)
    shape.to_mesh(mesh)
    shape.free()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = blender(*centre_firn)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def build_scene():
    scene = empty_scene()
    scene.firn.scene_name = "authored"
    scene.firn.dt = 5e-4
    scene.firn.kernel, scene.firn.transfer = "QUADRATIC", "APIC"

    domain = box_object("Domain", (1.2, 0.8, 1.2), (0.6, 0.4, 0.6))
    domain.firn.role, domain.firn.cell_size = "DOMAIN", 0.05

    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, location=blender(0.4, 0.4, 0.6))
    ball = bpy.context.object
    ball.name = "Ball"
    ball.firn.role, ball.firn.shape = "SNOW", "SPHERE"
    ball.firn.velocity = blender(2.0, 0.0, 0.0)

    bpy.ops.mesh.primitive_plane_add(size=0.5, location=blender(0.6, 0.1, 0.6))
    ground = bpy.context.object
    ground.name = "Ground"
    ground.firn.role, ground.firn.shape, ground.firn.friction = "COLLIDER", "PLANE", 0.3

    paddle = box_object("Paddle", (0.3, 0.1, 0.1), (0.8, 0.25, 0.6))
    paddle.firn.role, paddle.firn.shape, paddle.firn.boundary = "COLLIDER", "BOX", "STICKY"
    paddle.rotation_euler = (0.0, 0.0, 0.0)
    paddle.keyframe_insert("rotation_euler", frame=1)
    paddle.rotation_euler = (0.0, 0.0, math.radians(90.0))  # about Blender's z, Firn's y
    paddle.keyframe_insert("rotation_euler", frame=11)
    for curve in paddle.animation_data.action.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"

    crate = box_object("Crate", (0.1, 0.1, 0.1), (0.3, 0.2, 0.3))
    crate.firn.role, crate.firn.shape = "RIGID_BODY", "BOX"
    bpy.context.view_layer.objects.active = crate
    bpy.ops.rigidbody.object_add()
    crate.rigid_body.mass = 2.0
    crate.rigid_body.friction = 0.5
    scene.frame_set(1)
    return scene
