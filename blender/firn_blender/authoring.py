"""Firn scenes authored in Blender (docs/blender.md, Authoring a scene): objects marked in the Firn panel become the
scene file's snow bodies, emitters, colliders, rigid bodies and domain; the scene's frame range, frame rate, gravity
and camera its time and camera. `export_scene` writes the scene file and the meshes it names, in Firn's Y-up metres;
`import_scene` makes marked objects of a scene file, so that exporting them again writes the same scene.

What an object carries from an imported scene (its entry, and the transform and mesh it had) is written back as it
was where the object still has that transform and mesh: numbers that went through Blender's 32-bit floats come back as
the scene wrote them, and keys the panel does not show (a body's `sampler`, `lambda_scale`, …) are kept."""

import hashlib
import json
import math
import os

import bpy
import numpy as np
from mathutils import Matrix, Vector

# Firn is Y-up, Blender Z-up: Firn's (x, y, z) is Blender's (x, −z, y).
TO_FIRN = Matrix(((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0)))
TO_BLENDER = TO_FIRN.transposed()

PRESETS = ("stomakhin", "dry", "wet", "icy", "slushy")
MOTION_PATHS = ("location", "rotation_euler", "rotation_quaternion")
# Each material model's keys (docs/scene-format.md, materials), as the panel's settings of the same names hold them.
MODEL_KEYS = {
    "snow": ("youngs_modulus", "poisson_ratio", "density", "critical_compression", "critical_stretch", "hardening"),
    "fixed_corotated": ("youngs_modulus", "poisson_ratio", "density"),
    "neo_hookean": ("youngs_modulus", "poisson_ratio", "density"),
    "water": ("density", "bulk_modulus", "gamma", "viscosity"),
    "drucker_prager": ("youngs_modulus", "poisson_ratio", "density", "friction_angle_deg"),
}
# Numbers that differ from an imported entry's by no more than this part of the larger are the entry's: what 32-bit
# floats round (about 6e-8) and a transform's arithmetic add to it. (Noise about 0 is 0 already: short.)
KEEP_TOLERANCE = 1e-6


class AuthoringError(ValueError):
    """A scene that cannot be written or read, said as '<object or key>: <problem>'."""


# ---------------------------------------------------------------------------------------------------------------
# Conversions


def firn_vector(v, unit_m=1.0):
    """A Blender vector (its axes, its units) in Firn's axes and metres, as a list of short floats."""
    return [short(c) for c in (TO_FIRN @ Vector(v)) * unit_m]


def blender_vector(v, unit_m=1.0):
    return TO_BLENDER @ Vector([float(c) for c in v]) / unit_m


def firn_rotation(rotation):
    """A rotation of Blender's axes as the same turn in Firn's axes."""
    return TO_FIRN @ rotation @ TO_BLENDER


def rotate_deg(rotation_firn):
    """Firn's rotate_deg of a rotation: R = R_z R_y R_x is Blender's XYZ Euler (a ten-thousandth of a degree is 0)."""
    return [short(math.degrees(a), zero=1e-4) for a in rotation_firn.to_euler("XYZ")]


def rotation_of(degrees):
    """Firn's R = R_z R_y R_x of rotate_deg, as a Matrix."""
    from mathutils import Euler
    return Euler([math.radians(float(d)) for d in degrees], "XYZ").to_matrix()


def short(value, zero=1e-7):
    """A number Blender held in 32-bit floats as the shortest decimal within four of their units (2⁻²¹ of it), and
    below `zero` as 0: 0.35 comes back as 0.35, not 0.3499999940395355, and a quarter turn as 90°, not 89.99999°."""
    value = float(value)
    if abs(value) < zero:
        return 0.0
    for digits in range(1, 10):
        candidate = float(f"{value:.{digits}g}")
        if abs(candidate - value) <= abs(value) * 2.0 ** -21:
            return candidate
    return value


def _close(a, b):
    return abs(float(a) - float(b)) <= max(KEEP_TOLERANCE * max(abs(float(a)), abs(float(b))), 1e-12)


def kept(value, original):
    """`value`, or `original` where they agree within 32-bit rounding (numbers and lists of numbers)."""
    def number(x):
        return isinstance(x, (int, float)) and not isinstance(x, bool)
    if isinstance(value, list) and isinstance(original, list) and len(original) == len(value) and \
            all(number(v) and number(o) and _close(v, o) for v, o in zip(value, original)):
        return original
    if number(value) and number(original) and _close(value, original):
        return original
    return value


def merged(entry, computed):
    """The entry's keys in their order, then the new ones; computed values kept as the entry's where they agree
    (kept); a computed None removes the key."""
    result = dict(entry)
    for key, value in computed.items():
        if value is None:
            result.pop(key, None)
        else:
            result[key] = kept(value, entry.get(key))
    return result


# ---------------------------------------------------------------------------------------------------------------
# What an object was when imported


def placed(obj):
    """Where the object is placed: its world matrix, but for an object Blender's own rigid-body world moves, where its
    own transform puts it (Blender's simulation, running from its cache's first frame, is not Firn's start)."""
    world = bpy.context.scene.rigidbody_world
    if obj.rigid_body is None or world is None or not world.enabled:
        return obj.matrix_world
    parent = obj.parent.matrix_world @ obj.matrix_parent_inverse if obj.parent else Matrix.Identity(4)
    return parent @ obj.matrix_basis


def transform_signature(obj):
    return [float(c) for row in placed(obj) for c in row]


def mesh_signature(obj):
    """A digest of the evaluated mesh (modifiers applied) in the object's own frame: its vertices and faces."""
    if obj.type != "MESH":
        return ""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        coordinates = np.empty(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", coordinates)
        corners = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corners)
    finally:
        evaluated.to_mesh_clear()
    return hashlib.sha1(coordinates.tobytes() + corners.tobytes()).hexdigest()


def motion_signature(obj):
    """The object's location and rotation keys, as text: whether its animation was edited since the import."""
    action = obj.animation_data.action if obj.animation_data else None
    if action is None:
        return ""
    return repr([(c.data_path, c.array_index, [(tuple(k.co), k.interpolation) for k in c.keyframe_points])
                 for c in action.fcurves if c.data_path in MOTION_PATHS])


def kind_of(obj):
    return f"{obj.firn.role}/{obj.firn.shape}"


def remember_source(obj):
    """What the object is as the import made it (at the scene's first frame), which the export compares with."""
    obj.firn.source_transform = transform_signature(obj)
    obj.firn.source_mesh = mesh_signature(obj)
    obj.firn.source_motion = motion_signature(obj)
    obj.firn.source_kind = kind_of(obj)


def unchanged_since_import(obj):
    """Whether the object is still what the import made: its entry's kind, placement and mesh."""
    if not obj.firn.entry or kind_of(obj) != obj.firn.source_kind:
        return False
    transform = all(_close(a, b) for a, b in zip(transform_signature(obj), obj.firn.source_transform))
    return transform and mesh_signature(obj) == obj.firn.source_mesh


def entry_of(obj):
    """The object's imported entry, whose keys the export keeps; none once the object is of another role or shape
    (the entry's keys would be of another kind)."""
    if not obj.firn.entry or kind_of(obj) != obj.firn.source_kind:
        return {}
    return json.loads(obj.firn.entry)


def same_direction(a, b):
    """Whether two vectors point the same way within 32-bit rounding (1.4e-6 rad), in double precision."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    lengths = np.linalg.norm(a) * np.linalg.norm(b)
    return lengths > 0 and float(np.dot(a, b)) / lengths > 1 - 1e-12


def same_material(a, b):
    """Whether two material definitions say the same: a snow preset with or without its model named."""
    def plain(definition):
        return {k: v for k, v in definition.items() if not (k == "model" and v == "snow" and "preset" in definition)}
    return plain(a) == plain(b)


# ---------------------------------------------------------------------------------------------------------------
# Export


class Exporter:
    """One export: the scene's settings, and the folder the scene file and its meshes go to."""

    def __init__(self, context, scene_path):
        self.scene = context.scene
        self.depsgraph = context.evaluated_depsgraph_get()
        self.folder = os.path.dirname(os.path.abspath(scene_path))
        self.unit_m = self.scene.unit_settings.scale_length or 1.0
        self.frame_rate = self.scene.render.fps / self.scene.render.fps_base
        self.first_frame = self.scene.frame_start
        self.meshes = {}  # relative path → (vertices, triangles), written with the scene

    # Geometry, at the scene's first frame (Firn's rest and t = 0)

    def world_mesh(self, obj):
        """The evaluated mesh's vertices in Firn's axes and metres, and its triangles."""
        evaluated = obj.evaluated_get(self.depsgraph)
        mesh = evaluated.to_mesh()
        try:
            mesh.calc_loop_triangles()
            count = len(mesh.vertices)
            local = np.empty(3 * count, dtype=np.float64)
            mesh.vertices.foreach_get("co", local)
            local = local.reshape(-1, 3)
            triangles = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
            mesh.loop_triangles.foreach_get("vertices", triangles)
        finally:
            evaluated.to_mesh_clear()
        world = np.array(placed(obj), dtype=np.float64)
        homogeneous = np.hstack([local, np.ones((len(local), 1))]) @ world.T
        firn = homogeneous[:, :3] @ np.array(TO_FIRN, dtype=np.float64).T * self.unit_m
        return firn, triangles.reshape(-1, 3)

    def bounds(self, obj):
        vertices, _ = self.world_mesh(obj)
        if len(vertices) == 0:
            raise AuthoringError(f"{obj.name}: has no vertices")
        return vertices.min(axis=0), vertices.max(axis=0)

    def mesh_path(self, obj):
        """Writes the object's mesh, as it is at the first frame, for the scene; returns its path in the scene."""
        vertices, triangles = self.world_mesh(obj)
        if len(triangles) == 0:
            raise AuthoringError(f"{obj.name}: has no faces to export as a mesh")
        name = bpy.path.clean_name(obj.name)
        relative = f"meshes/{name}.obj"
        suffix = 1
        while relative in self.meshes:  # "Rock.001" and "Rock_001" clean to one name
            suffix += 1
            relative = f"meshes/{name}_{suffix}.obj"
        self.meshes[relative] = (vertices, triangles)
        return relative

    def source_path(self, entry):
        """An imported entry's file, as a path from the folder the scene is written to."""
        return os.path.relpath(entry["path"], self.folder)

    def placed_mesh(self, obj, entry):
        """The keys that place a mesh: the imported file and its placement where the object is as imported, else the
        object's mesh written out in the world's frame."""
        if unchanged_since_import(obj) and "path" in entry:
            return {"path": self.source_path(entry)}
        return {"path": self.mesh_path(obj), "scale": None, "rotate_deg": None, "translate": None}

    def pose(self, obj):
        """The object's origin (Firn, m) and rotation (Firn's axes) at the current frame."""
        world = placed(obj)
        return firn_vector(world.translation, self.unit_m), firn_rotation(world.to_3x3().normalized())

    def velocity(self, obj):
        """The velocity (m/s) of the centre of the object's bounds and its angular velocity (rad/s) over the first
        frame of its animation: a body's v₀ and ω (docs/scene-format.md, bodies)."""
        self.scene.frame_set(self.first_frame)
        x0, r0 = self.pose(obj)
        centre = Vector(0.5 * sum(self.bounds(obj)))
        self.scene.frame_set(self.first_frame + 1)
        x1, r1 = self.pose(obj)
        self.scene.frame_set(self.first_frame)
        axis, angle = (r1 @ r0.transposed()).to_quaternion().to_axis_angle()
        omega = Vector(axis) * angle * self.frame_rate
        # The origin's velocity, and the turn's at the centre beside it: v_c = v_o + ω × (c − o).
        linear = Vector([(b - a) * self.frame_rate for a, b in zip(x0, x1)]) + omega.cross(centre - Vector(x0))
        return [short(c) for c in linear], [short(c, zero=1e-5) for c in omega]

    def sphere(self, obj):
        low, high = self.bounds(obj)
        return {"center": [short(c) for c in 0.5 * (low + high)], "radius": short(0.5 * (high - low).max())}

    def box(self, obj):
        _, rotation = self.pose(obj)
        if rotation.to_quaternion().angle > 1e-6:
            raise AuthoringError(f"{obj.name}: a box is axis-aligned in Firn, and this one is turned at the scene's "
                                 "first frame; clear its rotation there or mark it as a mesh")
        low, high = self.bounds(obj)
        return {"min": [short(c) for c in low], "max": [short(c) for c in high]}

    # The scene's parts

    def material(self, obj, materials, defined):
        """The object's material's name, its definition added to `materials` (an imported one kept as it was)."""
        settings = obj.firn
        if settings.material_json:
            name = settings.material_name
            definition = json.loads(settings.material_json)
        elif settings.material_preset != "CUSTOM":
            name = settings.material_name or settings.material_preset
            definition = {"preset": settings.material_preset}
        else:
            name = settings.material_name or obj.name
            model = settings.material_model.lower()
            definition = {"model": model}
            for key in MODEL_KEYS[model]:
                definition[key] = short(getattr(settings, key))
        if name in defined and not same_material(defined[name][0], definition):
            raise AuthoringError(f"{obj.name}: material {name!r} is defined differently by {defined[name][1]}")
        defined[name] = (definition, obj.name)
        if not same_material(materials.get(name, {}), definition):
            materials[name] = definition
        return name

    def body(self, obj, materials, defined):
        settings = obj.firn
        entry = entry_of(obj)
        computed = {}
        shape = settings.shape
        if shape == "POINTS":
            if not unchanged_since_import(obj):
                raise AuthoringError(f"{obj.name}: a points body is kept as imported; move its cloud in the scene file")
            computed.update({"path": self.source_path(entry)})
        else:
            computed["shape"] = {"SPHERE": "sphere", "BOX": "box"}.get(shape, "mesh")
            if shape == "SPHERE":
                computed.update(self.sphere(obj))
            elif shape == "BOX":
                computed.update(self.box(obj))
            else:
                computed.update(self.placed_mesh(obj, entry))
            computed["particles_per_cell"] = short(settings.particles_per_cell)
        computed["material"] = self.material(obj, materials, defined)
        if settings.velocity_source == "ANIMATION":
            velocity, angular = self.velocity(obj)
        else:
            velocity = firn_vector(settings.velocity)
            angular = firn_vector(settings.angular_velocity)
        computed["velocity"] = velocity if any(velocity) or "velocity" in entry else None
        computed["angular_velocity"] = angular if any(angular) or "angular_velocity" in entry else None
        if settings.role == "EMITTER":
            computed["start_frame"] = settings.emit_start
            computed["duration_frames"] = settings.emit_frames
        else:
            computed["start_frame"] = computed["duration_frames"] = None
        if "particles_per_cell" in computed and "particles_per_cell" not in entry and computed["particles_per_cell"] == 8:
            computed["particles_per_cell"] = None  # the default, left out as a hand-written scene would
        ordered = {"shape": computed.pop("shape", entry.get("shape", "points"))}
        ordered.update(computed)
        return merged(entry, ordered)

    def animated_frames(self, obj):
        """The frames at which a collider's motion is keyed for Firn: its keys where every key is linear, else every
        frame between its first and last key (Blender's other interpolations baked at the scene's frame rate); and
        every frame between two keys that turn it about more than one axis or by 179° or more, where Blender's
        interpolation of the Euler angles and Firn's turn the shorter way at a constant rate would part."""
        action = obj.animation_data.action if obj.animation_data else None
        if action is None:
            return []
        curves = [c for c in action.fcurves if c.data_path in MOTION_PATHS]
        if not curves:
            return []
        keys = sorted({k.co.x for c in curves for k in c.keyframe_points})
        linear = all(k.interpolation == "LINEAR" for c in curves for k in c.keyframe_points)
        first = max(min(keys), self.first_frame)
        last = max(keys)
        if last <= first:
            return []
        frames = [f for f in keys if first <= f <= last] if linear else [float(f) for f in range(int(first),
                                                                                                  int(last) + 1)]
        if frames[0] != first:
            frames.insert(0, first)
        turning = [c for c in curves if c.data_path != "location"]
        sampled = [frames[0]]
        for a, b in zip(frames, frames[1:]):
            if not self._turns_alike(turning, a, b):
                sampled.extend(float(f) for f in range(int(math.floor(a)) + 1, int(math.ceil(b))) if a < f < b)
            sampled.append(b)
        return sampled

    @staticmethod
    def _turns_alike(curves, a, b):
        """Whether rotation curves turn the object from frame a to b as Firn does between two keyframes: about one
        axis, by less than 179°."""
        if any(c.data_path == "rotation_quaternion" for c in curves):
            from mathutils import Quaternion
            turn = [Quaternion([next((c.evaluate(f) for c in curves if c.array_index == i), 1.0 if i == 0 else 0.0)
                                for i in range(4)]) for f in (a, b)]
            return turn[0].rotation_difference(turn[1]).angle < math.radians(90.0)
        changes = [abs(c.evaluate(b) - c.evaluate(a)) for c in curves]
        return sum(d > 1e-6 for d in changes) <= 1 and max(changes, default=0.0) < math.radians(179.0)

    def keyframes(self, obj, frames, entry):
        """Firn's keyframes (docs/scene-format.md) of the object's motion at `frames`, about its origin at rest."""
        self.scene.frame_set(self.first_frame)
        rest_x, rest_r = self.pose(obj)
        previous = entry.get("keyframes", [])
        keys, last_rotation = [], None
        for i, frame in enumerate(frames):
            self.scene.frame_set(int(math.floor(frame)), subframe=frame - math.floor(frame))
            x, r = self.pose(obj)
            relative = r @ rest_r.transposed()
            if last_rotation is not None and (relative @ last_rotation.transposed()).to_quaternion().angle > \
                    math.radians(179.0):
                raise AuthoringError(f"{obj.name}: turns more than 179° between frames {frames[i - 1]:g} and {frame:g};"
                                     " key it more often")
            last_rotation = relative
            key = {"time_s": (frame - self.first_frame) / self.frame_rate}
            old = previous[i] if i < len(previous) else {}
            translate = [short(b - a) for a, b in zip(rest_x, x)]
            if any(abs(t) > 1e-9 for t in translate) or "translate" in old:
                key["translate"] = translate
            degrees = rotate_deg(relative)
            if "rotate_deg" in old and (rotation_of(old["rotate_deg"]) @ relative.transposed()).to_quaternion().angle < 1e-6:
                degrees = old["rotate_deg"]
            if any(abs(d) > 1e-6 for d in degrees) or "rotate_deg" in old:
                key["rotate_deg"] = degrees
            keys.append(merged(old, key))
        self.scene.frame_set(self.first_frame)
        return keys

    def collider(self, obj):
        settings = obj.firn
        entry = entry_of(obj)
        self.scene.frame_set(self.first_frame)
        shape = settings.shape
        computed = {"type": {"SPHERE": "sphere", "BOX": "box", "PLANE": "plane"}.get(shape, "mesh")}
        frames = self.animated_frames(obj) if settings.follow_animation else []
        if frames and "keyframes" in entry and unchanged_since_import(obj) and \
                motion_signature(obj) == settings.source_motion:
            # As imported: the entry's shape at rest, pivot and keyframes (the first frame shows the first keyframe's
            # pose, which need not be the rest).
            return merged(entry, dict(computed, **self.collider_response(settings, entry)))
        origin, rotation = self.pose(obj)
        if shape == "PLANE":
            normal = firn_vector(placed(obj).to_3x3().normalized() @ Vector((0.0, 0.0, 1.0)))
            old = entry.get("normal")
            if old is not None and same_direction(old, normal):
                normal = old  # Firn normalises it: the direction is what counts
            computed.update({"point": origin, "normal": normal})
        elif shape == "SPHERE":
            computed.update(self.sphere(obj))
        elif shape == "BOX":
            computed.update(self.box(obj))
        else:
            computed.update(self.placed_mesh(obj, entry))
        if frames:
            computed["keyframes"] = self.keyframes(obj, frames, entry)
            computed["velocity"] = None
            # The object turns about its origin; Firn's default pivot is the shape's centre (a plane's point).
            centre = computed["point"] if shape == "PLANE" else list(0.5 * sum(self.bounds(obj)))
            at_centre = all(_close(a, b) for a, b in zip(origin, centre))
            computed["pivot"] = None if at_centre and "pivot" not in entry else origin
        else:
            velocity = firn_vector(settings.velocity)
            computed["keyframes"] = None
            computed["velocity"] = velocity if any(velocity) or "velocity" in entry else None
        computed.update(self.collider_response(settings, entry))
        return merged(entry, computed)

    @staticmethod
    def collider_response(settings, entry):
        """A collider's keys of how it meets the snow (and a mesh's field's resolution), defaults left out."""
        return {
            "friction": short(settings.friction) if settings.friction or "friction" in entry else None,
            "boundary": settings.boundary.lower() if settings.boundary != "SLIP" or "boundary" in entry else None,
            "resolution": short(settings.resolution) if settings.shape == "MESH" and (
                settings.resolution != 2 or "resolution" in entry) else None,
        }

    def rigid_body(self, obj):
        settings = obj.firn
        entry = entry_of(obj)
        self.scene.frame_set(self.first_frame)
        shape = settings.shape
        computed = {"shape": {"SPHERE": "sphere", "BOX": "box"}.get(shape, "mesh")}
        origin, rotation = self.pose(obj)
        if shape == "SPHERE":
            computed.update(self.sphere(obj))
        elif shape == "BOX":
            corners = np.array([tuple(c) for c in obj.bound_box], dtype=np.float64)
            low, high = corners.min(axis=0), corners.max(axis=0)
            scale = np.array(placed(obj).to_scale(), dtype=np.float64)
            centre = placed(obj) @ Vector(tuple(0.5 * (low + high)))
            size = (high - low) * scale
            computed["center"] = firn_vector(centre, self.unit_m)
            computed["size"] = [short(size[0] * self.unit_m), short(size[2] * self.unit_m),
                                short(size[1] * self.unit_m)]
            computed["rotate_deg"] = self._rotation_kept(rotation, entry)
        else:
            computed.update(self.placed_mesh(obj, entry))
        # Blender's Rigid Body settings where the object has them, else the panel's.
        blender = obj.rigid_body if settings.mass_source == "BLENDER" else None
        if settings.mass_source == "DENSITY":
            computed.update({"density": short(settings.density), "mass": None})
        else:
            computed.update({"mass": short(blender.mass if blender else settings.mass), "density": None})
        friction = blender.friction if blender else settings.body_friction
        computed["friction"] = short(friction) if "friction" in entry or not _close(friction, 0.3) else None
        velocity = firn_vector(settings.velocity)
        angular = firn_vector(settings.angular_velocity)
        computed["velocity"] = velocity if any(velocity) or "velocity" in entry else None
        computed["angular_velocity"] = angular if any(angular) or "angular_velocity" in entry else None
        boundary = settings.body_boundary
        computed["boundary"] = boundary.lower() if boundary != "SEPARATE" or "boundary" in entry else None
        if shape == "MESH" and ("resolution" in entry or settings.resolution != 2):
            computed["resolution"] = short(settings.resolution)
        return merged(entry, computed)

    @staticmethod
    def _rotation_kept(rotation, entry):
        old = entry.get("rotate_deg")
        if old is not None and (rotation_of(old) @ rotation.transposed()).to_quaternion().angle < 1e-6:
            return old
        degrees = rotate_deg(rotation)
        return degrees if any(abs(d) > 1e-6 for d in degrees) or old is not None else None

    def grid(self, domain, document):
        entry = document.get("grid", {})
        cell_m = short(domain.firn.cell_size)  # in metres, as the panel says
        if entry.get("cell_size") is not None and _close(cell_m, entry["cell_size"]):
            cell_m = entry["cell_size"]
        low, high = self.bounds(domain)
        cells = [max(1, int(round((h - l) / cell_m))) for l, h in zip(low, high)]
        return merged(entry, {"origin": [short(c) for c in low], "cells": cells, "cell_size": cell_m})

    def time(self, document):
        entry = document.get("time", {})
        settings = self.scene.firn
        computed = {"dt": short(settings.dt), "frame_rate": float(self.frame_rate),
                    "frames": self.scene.frame_end - self.scene.frame_start}
        if settings.adaptive:
            computed["adaptive"] = True
        else:
            computed["adaptive"] = False if "adaptive" in entry else None
            computed["cfl"] = None  # allowed only with adaptive steps
        if "frame_rate" not in entry and computed["frame_rate"] == 30:
            computed["frame_rate"] = None
        return merged(entry, computed)

    def camera(self, document):
        camera = self.scene.camera
        if camera is None:
            return None
        entry = entry_of(camera) or document.get("camera", {})
        position, rotation = self.pose(camera)
        forward = rotation @ (TO_FIRN @ Vector((0.0, 0.0, -1.0)))
        old_target = entry.get("target")
        target = None
        if old_target is not None and "position" in entry:
            if same_direction(np.subtract(old_target, position), forward):
                target = old_target
        if target is None:
            distance = camera.data.dof.focus_distance * self.unit_m or 1.0
            target = [short(p + distance * f) for p, f in zip(position, forward.normalized())]
        data = camera.data
        width, height = self.scene.render.resolution_x, self.scene.render.resolution_y
        vertical = data.sensor_fit == "VERTICAL" or (data.sensor_fit == "AUTO" and height > width)
        fov = data.angle if vertical else 2 * math.atan(math.tan(data.angle / 2) * height / width)
        return merged(entry, {"position": position, "target": target, "fov_deg": short(math.degrees(fov))})

    def build(self, objects):
        """The scene (a dict in the scene file's order) of the marked `objects`."""
        settings = self.scene.firn
        document = json.loads(settings.document) if settings.document else {}
        frame = self.scene.frame_current
        self.scene.frame_set(self.first_frame)
        try:
            marked = [o for o in objects if o.firn.role != "NONE"]
            domains = [o for o in marked if o.firn.role == "DOMAIN"]
            if len(domains) != 1:
                raise AuthoringError(f"the scene needs one object marked as the domain (it has {len(domains)})")
            # Imported parts in the order they came, then new ones by name.
            marked.sort(key=lambda o: (o.firn.order if o.firn.entry else 1 << 30, o.name))
            scene = {"name": settings.scene_name or self.scene.name}
            for key in ("description",):
                if key in document:
                    scene[key] = document[key]
            scene["grid"] = self.grid(domains[0], document)
            scene["time"] = self.time(document)
            # Blender keeps gravity in its units per second squared.
            gravity = firn_vector(self.scene.gravity, self.unit_m) if self.scene.use_gravity else [0.0, 0.0, 0.0]
            if "gravity" in document or not all(_close(a, b) for a, b in zip(gravity, (0.0, -9.81, 0.0))):
                scene["gravity"] = kept(gravity, document.get("gravity"))
            solver = dict(document.get("solver", {}))
            for key, value in (("kernel", settings.kernel.lower()), ("transfer", settings.transfer.lower()),
                               ("integrator", settings.integrator.lower())):
                default = {"kernel": "cubic", "transfer": "pic_flip", "integrator": "explicit"}[key]
                if key in solver or value != default:
                    solver[key] = value
            if solver.get("integrator", "explicit") == "explicit":
                for key in ("implicit_ratio", "tolerance", "max_iterations"):  # the semi-implicit solve's only
                    solver.pop(key, None)
            if solver:
                scene["solver"] = solver
            materials = dict(document.get("materials", {}))
            defined = {}
            bodies = [self.body(o, materials, defined) for o in marked if o.firn.role in ("SNOW", "EMITTER")]
            if not bodies:
                raise AuthoringError("the scene needs at least one object marked as snow or an emitter")
            scene["materials"] = materials
            scene["bodies"] = bodies
            colliders = [self.collider(o) for o in marked if o.firn.role == "COLLIDER"]
            if colliders:
                scene["colliders"] = colliders
            rigid = [self.rigid_body(o) for o in marked if o.firn.role == "RIGID_BODY"]
            if rigid:
                scene["rigid_bodies"] = rigid
            camera = self.camera(document)
            if camera:
                scene["camera"] = camera
            for key, value in document.items():
                if key not in scene and key not in ("bodies", "colliders", "rigid_bodies", "camera", "gravity"):
                    scene[key] = value
            return scene
        finally:
            self.scene.frame_set(frame)

    def write(self, scene, scene_path):
        for relative, (vertices, triangles) in self.meshes.items():
            write_obj(os.path.join(self.folder, relative), vertices, triangles)
        with open(scene_path, "w") as f:
            json.dump(scene, f, indent=2)
            f.write("\n")


def write_obj(path, vertices, triangles):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("# written by Firn's Blender add-on: Firn's Y-up metres\n")
        for v in vertices:
            f.write(f"v {v[0]!r} {v[1]!r} {v[2]!r}\n")
        for t in triangles:
            f.write(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n")


def export_scene(context, scene_path, objects=None):
    """Writes the scene of the marked objects (all the scene's, or `objects`) to `scene_path`, with the meshes it
    names beside it in meshes/; returns the scene as written."""
    exporter = Exporter(context, scene_path)
    scene = exporter.build(list(objects if objects is not None else context.scene.objects))
    exporter.write(scene, scene_path)
    return scene


# ---------------------------------------------------------------------------------------------------------------
# Import


def read_obj(path):
    """An OBJ file's vertices and faces (fan-triangulated), enough to show and place a mesh."""
    vertices, faces = [], []
    with open(path, errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(c) for c in parts[1:4]])
            elif parts[0] == "f":
                corners = [int(p.split("/")[0]) for p in parts[1:]]
                corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
                faces.extend([corners[0], corners[k], corners[k + 1]] for k in range(1, len(corners) - 1))
    return np.array(vertices, dtype=np.float64).reshape(-1, 3), faces


def placed_vertices(entry, vertices):
    """p' = translate + R (scale · p), R = R_z R_y R_x (docs/scene-format.md, mesh bodies)."""
    rotation = np.array(rotation_of(entry.get("rotate_deg", [0, 0, 0])), dtype=np.float64)
    scale = float(entry.get("scale", 1.0))
    return (scale * vertices) @ rotation.T + np.array(entry.get("translate", [0, 0, 0]), dtype=np.float64)


class Importer:
    def __init__(self, context, scene_path):
        self.context = context
        self.path = os.path.abspath(scene_path)
        self.folder = os.path.dirname(self.path)
        try:
            with open(self.path) as f:
                self.document = json.load(f)
        except (OSError, ValueError) as error:
            raise AuthoringError(f"{scene_path}: {error}")
        self.collection = bpy.data.collections.new("Firn " + (self.document.get("name") or
                                                             os.path.splitext(os.path.basename(scene_path))[0]))
        context.scene.collection.children.link(self.collection)
        self.order = 0

    def mesh_object(self, name, vertices_firn, faces, origin_firn):
        """An object at `origin_firn` whose mesh holds `vertices_firn` (Firn's frame) about it."""
        mesh = bpy.data.meshes.new(name)
        local = [tuple(blender_vector(np.asarray(v) - np.asarray(origin_firn))) for v in vertices_firn]
        mesh.from_pydata(local, [], faces)
        mesh.update()
        obj = bpy.data.objects.new(name, mesh)
        obj.location = blender_vector(origin_firn)
        self.collection.objects.link(obj)
        return obj

    def primitive(self, name, kind, size):
        """A UV sphere of radius size, a square plane of half-width size facing +z, or a box of edges size (Firn's
        axes), about the object's origin."""
        import bmesh
        shape = bmesh.new()
        if kind == "sphere":
            bmesh.ops.create_uvsphere(shape, u_segments=48, v_segments=24, radius=float(size))
        elif kind == "plane":
            bmesh.ops.create_grid(shape, x_segments=1, y_segments=1, size=float(size))
        else:
            bmesh.ops.create_cube(shape, size=1.0)
            edges = blender_vector(size)
            for vertex in shape.verts:
                vertex.co = Vector((vertex.co.x * abs(edges.x), vertex.co.y * abs(edges.y), vertex.co.z * abs(edges.z)))
        mesh = bpy.data.meshes.new(name)
        shape.to_mesh(mesh)
        shape.free()
        obj = bpy.data.objects.new(name, mesh)
        self.collection.objects.link(obj)
        return obj

    def file_mesh(self, name, entry):
        path = os.path.join(self.folder, entry["path"])
        if os.path.splitext(path)[1].lower() != ".obj":
            raise AuthoringError(f"{entry['path']}: only OBJ meshes are imported into Blender")
        vertices, faces = read_obj(path)
        placed = placed_vertices(entry, vertices)
        centre = 0.5 * (placed.min(axis=0) + placed.max(axis=0))
        return self.mesh_object(name, placed, faces, centre)

    def solid(self, name, shape, entry):
        """A sphere (center, radius), a box (min and max; a rigid body's center, size and rotate_deg) or a mesh file
        placed as the entry says."""
        if shape == "sphere":
            obj = self.primitive(name, "sphere", entry["radius"])
            obj.location = blender_vector(entry["center"])
        elif shape == "box" and "size" in entry:
            obj = self.primitive(name, "box", entry["size"])
            obj.location = blender_vector(entry["center"])
            obj.rotation_euler = (TO_BLENDER @ rotation_of(entry.get("rotate_deg", [0, 0, 0])) @ TO_FIRN).to_euler("XYZ")
        elif shape == "box":
            low, high = np.array(entry["min"], float), np.array(entry["max"], float)
            obj = self.primitive(name, "box", list(high - low))
            obj.location = blender_vector(0.5 * (low + high))
        else:
            obj = self.file_mesh(name, entry)
        return obj

    def points_object(self, name, entry):
        obj = bpy.data.objects.new(name, bpy.data.meshes.new(name))
        self.collection.objects.link(obj)
        return obj

    def mark(self, obj, role, entry, shape):
        obj.firn.role = role
        obj.firn.shape = shape
        stored = dict(entry)
        if "path" in stored:
            stored["path"] = os.path.join(self.folder, stored["path"])
        obj.firn.entry = json.dumps(stored)
        obj.firn.order = self.order
        self.order += 1

    def body(self, index, entry):
        shape = entry["shape"]
        obj = self.points_object(f"snow {index}", entry) if shape == "points" else self.solid(f"snow {index}", shape,
                                                                                              entry)
        emitter = entry.get("start_frame", 0) > 0 or entry.get("duration_frames", 0) > 0
        self.mark(obj, "EMITTER" if emitter else "SNOW", entry, shape.upper())
        settings = obj.firn
        settings.particles_per_cell = entry.get("particles_per_cell", 8)
        settings.velocity = blender_vector(entry.get("velocity", [0, 0, 0]))
        settings.angular_velocity = blender_vector(entry.get("angular_velocity", [0, 0, 0]))
        settings.emit_start = entry.get("start_frame", 0)
        settings.emit_frames = entry.get("duration_frames", 0)
        material = entry["material"]
        settings.material_name = material
        definition = self.document["materials"].get(material, {})
        preset = definition.get("preset")
        model = definition.get("model", "snow")
        if preset in PRESETS and set(definition) <= {"preset", "model"}:
            settings.material_preset = preset
            settings.material_json = ""
            return obj
        if preset is None and model in MODEL_KEYS and set(definition) - {"model"} <= set(MODEL_KEYS[model]):
            settings.material_preset, settings.material_model = "CUSTOM", model.upper()
            for key in MODEL_KEYS[model]:
                if key in definition:
                    setattr(settings, key, definition[key])
        # The definition as the file has it, for the export (set last: editing the values above clears it).
        settings.material_json = json.dumps(definition)
        return obj

    def collider(self, index, entry, extent_m):
        name = f"collider {index}"
        kind = entry["type"]
        if kind == "plane":
            normal = Vector(entry["normal"]).normalized()
            obj = self.primitive(name, "plane", extent_m)
            obj.location = blender_vector(entry["point"])
            obj.rotation_mode = "QUATERNION"
            obj.rotation_quaternion = Vector((0.0, 0.0, 1.0)).rotation_difference(TO_BLENDER @ normal)
            obj.rotation_mode = "XYZ"
        else:
            obj = self.solid(name, kind, entry)
        self.mark(obj, "COLLIDER", entry, "MESH" if kind == "mesh" else kind.upper())
        settings = obj.firn
        settings.friction = entry.get("friction", 0.0)
        settings.boundary = entry.get("boundary", "slip").upper()
        settings.resolution = entry.get("resolution", 2.0)
        settings.velocity = blender_vector(entry.get("velocity", [0, 0, 0]))
        if "keyframes" in entry:
            self.key_motion(obj, entry)
        return obj

    def key_motion(self, obj, entry):
        """A keyframed collider's keys, on an object whose origin is moved to the pivot: location pivot + translate,
        rotation the keyframe's turn after the rest pose's, linear between keys (Firn slerps: the same about one
        axis)."""
        rest_location = Vector(obj.location)
        rest_rotation = obj.rotation_euler.to_matrix()
        pivot = blender_vector(entry["pivot"]) if "pivot" in entry else rest_location
        # The object's origin moves to the pivot, the mesh staying where it is.
        shift = rest_rotation.transposed() @ (pivot - rest_location)
        obj.data.transform(Matrix.Translation(-shift))
        obj.location = pivot
        scene = self.context.scene
        frame_rate = scene.render.fps / scene.render.fps_base
        previous = obj.rotation_euler.copy()
        for key in entry["keyframes"]:
            turn = TO_BLENDER @ rotation_of(key.get("rotate_deg", [0, 0, 0])) @ TO_FIRN
            obj.location = pivot + blender_vector(key.get("translate", [0, 0, 0]))
            obj.rotation_euler = (turn @ rest_rotation).to_euler("XYZ", previous)
            previous = obj.rotation_euler.copy()
            frame = scene.frame_start + float(key["time_s"]) * frame_rate
            obj.keyframe_insert("location", frame=frame)
            obj.keyframe_insert("rotation_euler", frame=frame)
        for curve in obj.animation_data.action.fcurves:
            curve.extrapolation = "CONSTANT"
            for point in curve.keyframe_points:
                point.interpolation = "LINEAR"
        scene.frame_set(scene.frame_start)

    def rigid_body(self, index, entry):
        shape = entry["shape"]
        obj = self.solid(f"rigid body {index}", shape, entry)
        self.mark(obj, "RIGID_BODY", entry, shape.upper())
        settings = obj.firn
        if "density" in entry:
            settings.mass_source, settings.density = "DENSITY", entry["density"]
        else:
            settings.mass_source, settings.mass = "MASS", entry["mass"]
        settings.body_friction = entry.get("friction", 0.3)
        settings.body_boundary = entry.get("boundary", "separate").upper()
        settings.resolution = entry.get("resolution", 2.0)
        settings.velocity = blender_vector(entry.get("velocity", [0, 0, 0]))
        settings.angular_velocity = blender_vector(entry.get("angular_velocity", [0, 0, 0]))
        return obj

    def domain(self, grid):
        origin = np.array(grid.get("origin", [0, 0, 0]), float)
        extent = np.array(grid["cells"], float) * float(grid["cell_size"])
        obj = self.primitive("domain", "box", list(extent))
        obj.location = blender_vector(origin + 0.5 * extent)
        obj.display_type = "WIRE"
        obj.hide_render = True
        obj.firn.role = "DOMAIN"
        obj.firn.cell_size = float(grid["cell_size"])
        return obj

    def camera(self, entry):
        data = bpy.data.cameras.new("Firn camera")
        data.sensor_fit = "VERTICAL"
        data.angle = math.radians(entry.get("fov_deg", 40.0))
        obj = bpy.data.objects.new("Firn camera", data)
        self.collection.objects.link(obj)
        position, target = blender_vector(entry["position"]), blender_vector(entry["target"])
        obj.location = position
        obj.rotation_euler = (target - position).to_track_quat("-Z", "Y").to_euler()
        data.dof.focus_distance = (target - position).length
        obj.firn.entry = json.dumps(entry)
        self.context.scene.camera = obj
        bpy.context.view_layer.update()
        remember_source(obj)
        return obj

    def run(self):
        document = self.document
        scene = self.context.scene
        time = document.get("time", {})
        rate = float(time.get("frame_rate", 30))
        scene.render.fps = max(1, int(round(rate)))
        scene.render.fps_base = scene.render.fps / rate
        scene.frame_end = scene.frame_start + int(time.get("frames", 60))
        scene.unit_settings.scale_length = 1.0
        scene.use_gravity = True
        scene.gravity = blender_vector(document.get("gravity", [0, -9.81, 0]))
        settings = scene.firn
        settings.document = json.dumps({k: v for k, v in document.items()
                                        if k not in ("bodies", "colliders", "rigid_bodies", "camera")})
        settings.scene_name = document.get("name", "")
        settings.dt = float(time["dt"])
        settings.adaptive = bool(time.get("adaptive", False))
        solver = document.get("solver", {})
        settings.kernel = solver.get("kernel", "cubic").upper()
        settings.transfer = solver.get("transfer", "pic_flip").upper()
        settings.integrator = solver.get("integrator", "explicit").upper()
        self.domain(document["grid"])
        extent_m = float(max(document["grid"]["cells"])) * float(document["grid"]["cell_size"])
        objects = [self.body(i, e) for i, e in enumerate(document["bodies"])]
        objects += [self.collider(i, e, extent_m) for i, e in enumerate(document.get("colliders", []))]
        objects += [self.rigid_body(i, e) for i, e in enumerate(document.get("rigid_bodies", []))]
        scene.frame_set(scene.frame_start)
        bpy.context.view_layer.update()
        for obj in objects:
            remember_source(obj)
        if "camera" in document:
            self.camera(document["camera"])
        return self.collection


def import_scene(context, scene_path):
    """Makes marked objects of a Firn scene file in a new collection; returns it."""
    return Importer(context, scene_path).run()
