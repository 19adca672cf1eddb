"""Builds a Firn run's caches into a Blender scene (docs/blender.md): one object per cache whose geometry follows
the frame, under one parent that turns Firn's Y-up into Blender's Z-up, with the run's frame rate on the scene.

Blender frame N shows Firn's frame N (the state at N / frame_rate); frame 0 is the initial state.

- The surface meshes (frame_NNNN_surface.ply): one mesh object. Its vertex count changes every frame, so no shape
  key or modifier can animate it: a frame-change handler gives the object the frame's mesh (read on first use,
  then kept), smooth-shaded with the file's normals and a `velocity` attribute (m/s), which Cycles' motion blur
  reads from a mesh whose topology changes.
- The VDB caches (frame_NNNN.vdb): one volume object on the file sequence, its velocity grid `v` set for motion
  blur, with a snow volume material.
- The point caches (frame_NNNN.ply): one object of points (a mesh of vertices drawn as points by a geometry
  nodes modifier) carrying the caches' `velocity`, `mass` and `plastic_j` as point attributes.
- The rigid bodies and moving colliders of bodies.csv: one object each, keyed at every frame with the row's
  position and quaternion; its mesh the object's first mesh file (OBJECT_NNNN.ply, with --mesh) taken back to the
  object's own frame, else the scene file's collider, else an empty.
- The scene file's colliders, when the scene is given: planes, spheres and boxes, moving at their velocities or
  following their keyframes (those bodies.csv holds come from it instead).
"""

import csv
import json
import math
import os
import re

import bpy
import numpy as np
from bpy.app.handlers import persistent
from mathutils import Matrix

from . import firn_ply

FRAME_FILE = re.compile(r"^frame_(\d{4,})(_surface)?\.(ply|vdb)$")
OBJECT_MESH_FILE = re.compile(r"^(colliders|rigid_bodies)_(\d+)_(\d{4,})\.ply$")  # colliders[1] → colliders_1_NNNN
KIND_SURFACE = "surface"
KIND_POINTS = "points"


class FirnRunError(ValueError):
    pass


class RunFolder:
    """What a Firn output folder holds: the frames of each cache, and the frame rate (from stats.csv)."""

    def __init__(self, folder, last_frame=None):
        self.frame_offset = 0  # the scene's frame of Firn's frame 0 (import_run)
        self.folder = os.path.abspath(bpy.path.abspath(folder))
        if not os.path.isdir(self.folder):
            raise FirnRunError(f"{self.folder}: not a folder")
        self.surfaces, self.points, self.volumes = {}, {}, {}
        self.object_meshes = {}  # by object ("colliders[1]"), by frame
        for name in os.listdir(self.folder):
            match = OBJECT_MESH_FILE.match(name)
            if match:
                frame = int(match.group(3))
                if last_frame is None or frame <= last_frame:
                    self.object_meshes.setdefault(f"{match.group(1)}[{match.group(2)}]", {})[frame] = name
                continue
            match = FRAME_FILE.match(name)
            if not match:
                continue
            frame = int(match.group(1))
            if last_frame is not None and frame > last_frame:
                continue  # an earlier, longer run's, in the same folder
            if match.group(3) == "vdb":
                self.volumes[frame] = name
            elif match.group(2):
                self.surfaces[frame] = name
            else:
                self.points[frame] = name
        if not (self.surfaces or self.points or self.volumes):
            raise FirnRunError(f"{self.folder}: no frame_NNNN.ply, frame_NNNN_surface.ply or frame_NNNN.vdb")
        self.frame_rate = read_frame_rate(os.path.join(self.folder, "stats.csv"))
        self.bodies = read_bodies(os.path.join(self.folder, "bodies.csv"), last_frame)

    def frames(self):
        every = set(self.surfaces) | set(self.points) | set(self.volumes)
        return min(every), max(every)


def read_frame_rate(stats_path):
    """Frame N is the state at N / frame_rate (docs/scene-format.md), so any later frame's row gives the rate."""
    if not os.path.exists(stats_path):
        raise FirnRunError(f"{stats_path}: missing (Firn writes it with every run; it holds the frames' times)")
    with open(stats_path, newline="") as f:
        for row in csv.DictReader(f):
            frame, time_s = int(row["frame"]), float(row["time_s"])
            if frame > 0 and time_s > 0:
                return frame / time_s
    raise FirnRunError(f"{stats_path}: fewer than two frames, so no frame rate")


def read_bodies(bodies_path, last_frame=None):
    """bodies.csv's poses (docs/command-line.md, bodies.csv): by object ("colliders[1]", "rigid_bodies[0]"), its
    rows in frame order as (frame, kind, position, quaternion w x y z); {} when the run wrote none (a scene without
    moving objects)."""
    if not os.path.exists(bodies_path):
        return {}
    bodies = {}
    with open(bodies_path, newline="") as f:
        for row in csv.DictReader(f):
            frame = int(row["frame"])
            if last_frame is not None and frame > last_frame:
                continue
            position = tuple(float(row[c]) for c in ("x_m", "y_m", "z_m"))
            quaternion = tuple(float(row[c]) for c in ("qw", "qx", "qy", "qz"))
            bodies.setdefault(row["object"], {})[frame] = (row["kind"], position, quaternion)
    return {name: [(frame, *rows[frame]) for frame in sorted(rows)] for name, rows in bodies.items()}


def set_frame_rate(scene, frame_rate):
    """Blender's rate is fps / fps_base with an integer fps."""
    fps = max(1, math.ceil(frame_rate - 1e-6))
    scene.render.fps = fps
    scene.render.fps_base = fps / frame_rate


# --- Meshes from the caches ----------------------------------------------------------------------------------------

def _set_point_attribute(mesh, name, values):
    kind = "FLOAT_VECTOR" if values.ndim == 2 else "FLOAT"
    attribute = mesh.attributes.get(name) or mesh.attributes.new(name, kind, "POINT")
    attribute.data.foreach_set("vector" if kind == "FLOAT_VECTOR" else "value", values.astype(np.float32).ravel())


def surface_mesh(name, path):
    """The surface mesh of one frame: its triangles smooth-shaded with the file's normals, its `velocity`."""
    vertices, triangles = firn_ply.read_ply(path)
    positions = firn_ply.vectors(vertices, ("x", "y", "z"))
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    count = len(triangles)
    mesh.loops.add(3 * count)
    mesh.loops.foreach_set("vertex_index", triangles.astype(np.int32).ravel())
    mesh.polygons.add(count)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * count, 3, dtype=np.int32))
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:  # Blender before 4.0 sets it too
        mesh.polygons.foreach_set("loop_total", np.full(count, 3, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(count, dtype=bool))
    mesh.update(calc_edges=True)
    if "nx" in vertices:
        if hasattr(mesh, "use_auto_smooth"):  # Blender before 4.1 uses custom normals only with it
            mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(firn_ply.vectors(vertices, ("nx", "ny", "nz")))
    if "vx" in vertices:
        _set_point_attribute(mesh, "velocity", firn_ply.vectors(vertices, ("vx", "vy", "vz")))
    mesh.materials.append(None)  # one slot, which the object fills (it outlives the frame's mesh)
    return mesh


def points_mesh(name, path):
    """The point cache of one frame as vertices with the cache's attributes: velocity, mass, plastic_j."""
    vertices, _ = firn_ply.read_ply(path)
    positions = firn_ply.vectors(vertices, ("x", "y", "z"))
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.update()
    if "vx" in vertices:
        _set_point_attribute(mesh, "velocity", firn_ply.vectors(vertices, ("vx", "vy", "vz")))
    for attribute in ("mass", "plastic_j"):
        if attribute in vertices:
            _set_point_attribute(mesh, attribute, vertices[attribute])
    mesh.materials.append(None)
    return mesh


# --- Following the frame -------------------------------------------------------------------------------------------

def _frame_files(obj):
    return {int(frame): name for frame, name in obj["firn_files"].items()}


def shown_frame(frames, scene_frame):
    """The cache frame shown at a (possibly fractional) scene frame: the nearest frame, so that the motion blur's
    sub-frames around frame N all see frame N's mesh and its velocities carry the motion; before the first and
    after the last cache frame, those."""
    nearest = math.floor(scene_frame + 0.5)
    if nearest in frames:
        return nearest
    earlier = [f for f in frames if f <= nearest]
    return max(earlier) if earlier else min(frames)


def update_object(obj, scene_frame):
    files = _frame_files(obj)
    if not files:
        return
    frame = shown_frame(files, scene_frame - obj.get("firn_frame_offset", 0))
    path = os.path.join(obj["firn_folder"], files[frame])
    name = f"{obj.name} {frame:04d}"
    mesh = bpy.data.meshes.get(name)
    if mesh is None or mesh.get("firn_file") != path:
        mesh = (surface_mesh if obj["firn_kind"] == KIND_SURFACE else points_mesh)(name, path)
        mesh["firn_file"] = path
    if obj.data != mesh:
        obj.data = mesh


def update_scene(scene):
    for obj in scene.objects:
        if obj.get("firn_kind") in (KIND_SURFACE, KIND_POINTS):
            update_object(obj, scene.frame_current + scene.frame_subframe)


@persistent
def on_frame_change(scene, depsgraph=None):
    update_scene(scene)


@persistent
def on_load(_):
    for scene in bpy.data.scenes:
        update_scene(scene)


HANDLERS = ((bpy.app.handlers.frame_change_pre, on_frame_change), (bpy.app.handlers.load_post, on_load))


def register():
    for handlers, handler in HANDLERS:
        if handler not in handlers:
            handlers.append(handler)


def unregister():
    for handlers, handler in HANDLERS:
        if handler in handlers:
            handlers.remove(handler)


# --- Materials -----------------------------------------------------------------------------------------------------

SNOW_COLOR = (0.90, 0.93, 0.97, 1.0)  # fresh snow's albedo is about 0.9, a little bluer than white


def _set_inputs(node, values):
    """Sets the inputs a node has by name (Principled nodes renamed some between Blender 3.4 and 4)."""
    for names, value in values:
        for name in names:
            if name in node.inputs:
                node.inputs[name].default_value = value
                break


def snow_surface_material():
    material = bpy.data.materials.get("Firn snow") or bpy.data.materials.new("Firn snow")
    material.use_nodes = True
    bsdf = material.node_tree.nodes.get("Principled BSDF")
    _set_inputs(bsdf, [
        (("Base Color",), SNOW_COLOR),
        (("Roughness",), 0.6),
        (("Specular", "Specular IOR Level"), 0.3),
        (("Subsurface", "Subsurface Weight"), 0.25),
        (("Subsurface Color",), SNOW_COLOR),
        (("Subsurface Radius",), (0.02, 0.03, 0.05)),  # light spreads a few cm in snow, blue farthest
    ])
    material.diffuse_color = SNOW_COLOR
    return material


def snow_volume_material():
    """A scattering volume driven by the `density` grid (the volume fraction, 1 inside snow at rest): snow
    extinguishes light within a few centimetres, so each unit of volume fraction is 200 per metre, nearly white
    scattering, a little absorption that tints it blue."""
    material = bpy.data.materials.get("Firn snow volume") or bpy.data.materials.new("Firn snow volume")
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    nodes.clear()
    volume = nodes.new("ShaderNodeVolumePrincipled")
    _set_inputs(volume, [
        (("Color",), SNOW_COLOR),
        (("Density",), 200.0),
        (("Anisotropy",), 0.3),
        (("Absorption Color",), (0.02, 0.01, 0.0, 1.0)),
    ])
    volume.inputs["Density Attribute"].default_value = "density"
    output = nodes.new("ShaderNodeOutputMaterial")
    links.new(volume.outputs["Volume"], output.inputs["Volume"])
    return material


def particles_material():
    material = bpy.data.materials.get("Firn particles") or bpy.data.materials.new("Firn particles")
    material.diffuse_color = SNOW_COLOR
    material.use_nodes = True
    _set_inputs(material.node_tree.nodes.get("Principled BSDF"), [(("Base Color",), SNOW_COLOR)])
    return material


def _add_socket(group, in_out, name, socket_type):
    if hasattr(group, "interface"):  # Blender 4
        return group.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    return (group.inputs if in_out == "INPUT" else group.outputs).new(socket_type, name)


def particles_node_group():
    """Mesh vertices to points of a radius, with the particles' material; every attribute rides along."""
    group = bpy.data.node_groups.get("Firn particles")
    if group:
        return group
    group = bpy.data.node_groups.new("Firn particles", "GeometryNodeTree")
    _add_socket(group, "INPUT", "Geometry", "NodeSocketGeometry")
    _add_socket(group, "INPUT", "Radius", "NodeSocketFloat")
    _add_socket(group, "OUTPUT", "Geometry", "NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    to_points = nodes.new("GeometryNodeMeshToPoints")
    set_material = nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = particles_material()
    links.new(group_in.outputs["Geometry"], to_points.inputs["Mesh"])
    links.new(group_in.outputs["Radius"], to_points.inputs["Radius"])
    links.new(to_points.outputs["Points"], set_material.inputs["Geometry"])
    links.new(set_material.outputs["Geometry"], group_out.inputs["Geometry"])
    return group


def _radius_socket(group):
    if hasattr(group, "interface"):
        return next(item.identifier for item in group.interface.items_tree if item.name == "Radius")
    return group.inputs["Radius"].identifier


# --- Building the scene --------------------------------------------------------------------------------------------

def _sequence_object(context, name, folder, files, kind, parent, frame_offset):
    obj = bpy.data.objects.new(name, bpy.data.meshes.new(name))
    obj["firn_folder"] = folder
    obj["firn_frame_offset"] = frame_offset
    obj["firn_files"] = {str(frame): file for frame, file in files.items()}
    obj["firn_kind"] = kind
    obj.parent = parent
    context.collection.objects.link(obj)
    update_object(obj, context.scene.frame_current)
    return obj


def _particle_radius(obj):
    """Half the particles' spacing, from the first frame: the cube root of the volume per particle of their box
    (a body fills its box; this is a starting value for the modifier's Radius)."""
    positions = np.empty(3 * len(obj.data.vertices), dtype=np.float32)
    obj.data.vertices.foreach_get("co", positions)
    positions = positions.reshape(-1, 3)
    if len(positions) < 2:
        return 0.005
    extent = np.maximum(positions.max(axis=0) - positions.min(axis=0), 1e-6)
    return 0.5 * float(np.prod(extent) / len(positions)) ** (1.0 / 3.0)


def _volume_object(context, name, run, parent):
    first = min(run.volumes)
    volume = bpy.data.volumes.new(name)
    volume.filepath = os.path.join(run.folder, run.volumes[first])
    volume.is_sequence = len(run.volumes) > 1
    if volume.is_sequence:
        # Blender shows, at scene frame F, the file numbered (F − frame_start + 1) + frame_offset, the first
        # term held to [1, frame_duration] in EXTEND mode: file k at frame k + the run's offset, the first before
        # it, the last after.
        volume.frame_start = first + run.frame_offset
        volume.frame_duration = max(run.volumes) - first + 1
        volume.frame_offset = first - 1
        volume.sequence_mode = "EXTEND"
    volume.grids.load()  # Blender takes the name of a grid the file holds only
    volume.velocity_grid = "v"
    volume.velocity_unit = "SECOND"
    volume.velocity_scale = 1.0
    volume.materials.append(snow_volume_material())
    obj = bpy.data.objects.new(name, volume)
    obj.parent = parent
    context.collection.objects.link(obj)
    return obj


def _collider_mesh(name, collider, extent_m):
    """A collider's solid in Firn's coordinates, about its shape's centre (a plane's point) at rest."""
    import bmesh
    shape = bmesh.new()
    kind = collider["type"]
    if kind == "sphere":
        bmesh.ops.create_uvsphere(shape, u_segments=48, v_segments=24, radius=float(collider["radius"]))
    elif kind == "box":
        size = np.array(collider["max"], dtype=float) - np.array(collider["min"], dtype=float)
        bmesh.ops.create_cube(shape, size=1.0)
        for vertex in shape.verts:
            vertex.co.x *= size[0]
            vertex.co.y *= size[1]
            vertex.co.z *= size[2]
    elif kind == "plane":
        normal = np.array(collider["normal"], dtype=float)
        normal /= np.linalg.norm(normal)
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        u = np.cross(normal, helper)
        u /= np.linalg.norm(u)
        w = np.cross(normal, u)
        corners = [(su * u + sw * w) * extent_m for su, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        face = [shape.verts.new(tuple(c)) for c in corners]
        quad = shape.faces.new(face)
        quad.normal_update()
        if np.dot(np.array(quad.normal), normal) < 0:
            bmesh.ops.reverse_faces(shape, faces=[quad])
    else:
        raise FirnRunError(f"collider type {kind!r} is not one Firn knows")
    mesh = bpy.data.meshes.new(name)
    shape.to_mesh(mesh)
    shape.free()
    return mesh


def _collider_origin(collider):
    kind = collider["type"]
    if kind == "sphere":
        return np.array(collider["center"], dtype=float)
    if kind == "box":
        return 0.5 * (np.array(collider["min"], dtype=float) + np.array(collider["max"], dtype=float))
    return np.array(collider["point"], dtype=float)


def _key_collider_motion(obj, collider, origin, keyframes, frame_rate, frame_offset):
    """A keyframed collider's poses (docs/scene-format.md, colliders): at each keyframe's time the shape, built about
    `origin`, turned by rotate_deg about the pivot (Firn's R = R_z R_y R_x is Blender's XYZ Euler, in the parent's
    Firn axes) and moved by translate. Blender interpolates the Euler angles linearly: the same turn as Firn's slerp
    about one axis; a turn about several axes, or about a pivot away from the shape's centre, is drawn approximately
    between keyframes."""
    pivot = np.array(collider.get("pivot", origin), dtype=float)
    obj.rotation_mode = "XYZ"
    for key in keyframes:
        angles = np.radians(np.array(key.get("rotate_deg", [0, 0, 0]), dtype=float))
        translate = np.array(key.get("translate", [0, 0, 0]), dtype=float)
        cx, cy, cz = np.cos(angles)
        sx, sy, sz = np.sin(angles)
        rotate_x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        rotate_y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        rotate_z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        rotation = rotate_z @ rotate_y @ rotate_x
        frame = float(key["time_s"]) * frame_rate + frame_offset
        obj.location = tuple(pivot + translate + rotation @ (origin - pivot))
        obj.rotation_euler = tuple(angles)
        obj.keyframe_insert("location", frame=frame)
        obj.keyframe_insert("rotation_euler", frame=frame)


def _linear_constant(obj):
    """Keys joined by straight lines, the first and last poses held beyond them."""
    for curve in obj.animation_data.action.fcurves:
        curve.extrapolation = "CONSTANT"
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"


def rotation_matrix(quaternion):
    """The rotation of a unit quaternion (w, x, y, z), in double precision (mathutils' is single)."""
    w, x, y, z = quaternion
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rest_mesh_from_file(name, path, position, quaternion):
    """An object's mesh file of one frame taken back to the object's own frame, p = q⁻¹ (x − position), so that the
    object's keys put it where each frame's file has it (every frame's file has the same vertices and triangles)."""
    vertices, triangles = firn_ply.read_ply(path)
    world = firn_ply.vectors(vertices, ("x", "y", "z")).astype(np.float64)
    rest = (world - np.array(position)) @ rotation_matrix(quaternion)  # rows: (R⁻¹ (x − position))ᵀ = (x − position)ᵀ R
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(rest.tolist(), [], triangles.astype(np.int64).tolist())
    mesh.update()
    return mesh


def _moving_objects(context, run, parent, scene_colliders, extent_m):
    """bodies.csv's objects, each keyed at every frame with its row's position and quaternion (in the parent's Firn
    axes), interpolated linearly between frames: its mesh from its first mesh file, else (a collider, with the scene
    given) the scene's shape about the pivot, the point bodies.csv follows, else an empty at its frame."""
    objects = []
    for name, rows in run.bodies.items():
        object_name = f"Firn {name}"
        files = run.object_meshes.get(name, {})
        shown = [row for row in rows if row[0] in files]
        collider = None
        match = re.fullmatch(r"colliders\[(\d+)\]", name)
        if match and int(match.group(1)) < len(scene_colliders):
            collider = scene_colliders[int(match.group(1))]
        if shown:
            frame, _, position, quaternion = shown[0]
            data = _rest_mesh_from_file(object_name, os.path.join(run.folder, files[frame]), position, quaternion)
        elif collider is not None:
            data = _collider_mesh(object_name, collider, extent_m)
            origin = _collider_origin(collider)
            pivot = np.array(collider.get("pivot", origin), dtype=float)
            data.transform(Matrix.Translation(tuple(origin - pivot)))
        else:
            data = None
        obj = bpy.data.objects.new(object_name, data)
        if data is None:
            obj.empty_display_type = "ARROWS"
        obj.parent = parent
        obj.rotation_mode = "QUATERNION"
        for frame, _, position, quaternion in rows:
            obj.location = position
            obj.rotation_quaternion = quaternion
            obj.keyframe_insert("location", frame=frame + run.frame_offset)
            obj.keyframe_insert("rotation_quaternion", frame=frame + run.frame_offset)
        _linear_constant(obj)
        obj["firn_object"] = name
        obj["firn_object_kind"] = rows[0][1]
        context.collection.objects.link(obj)
        objects.append(obj)
    return objects


def _read_scene(scene_path):
    """The scene file's colliders and the length of its domain's diagonal (how far a plane is drawn)."""
    with open(scene_path) as f:
        scene = json.load(f)
    grid = scene.get("grid", {})
    cells = np.array(grid.get("cells", [64, 64, 64]), dtype=float)
    return scene.get("colliders", []), float(np.linalg.norm(cells * float(grid.get("cell_size", 0.02))))


def _collider_objects(context, colliders, extent_m, run, parent):
    """The scene's colliders that bodies.csv does not hold, each translating at its velocity from its position at
    t = 0, keyed linearly at the first and last frames, or following its keyframes (docs/scene-format.md,
    colliders)."""
    first, last = run.frames()
    objects = []
    for index, collider in enumerate(colliders):
        if f"colliders[{index}]" in run.bodies:
            continue
        name = f"Firn collider {index} ({collider['type']})"
        obj = bpy.data.objects.new(name, _collider_mesh(name, collider, extent_m))
        obj.parent = parent
        origin = _collider_origin(collider)
        keyframes = collider.get("keyframes", [])
        if keyframes:
            _key_collider_motion(obj, collider, origin, keyframes, run.frame_rate, run.frame_offset)
        else:
            velocity = np.array(collider.get("velocity", [0, 0, 0]), dtype=float)
            for frame in sorted({first, last}):
                obj.location = tuple(origin + velocity * frame / run.frame_rate)
                obj.keyframe_insert("location", frame=frame + run.frame_offset)
        if obj.animation_data and obj.animation_data.action:
            for curve in obj.animation_data.action.fcurves:
                # Keyframed motion holds its first and last poses beyond them; a velocity goes on.
                curve.extrapolation = "CONSTANT" if keyframes else "LINEAR"
                for key in curve.keyframe_points:
                    key.interpolation = "LINEAR"
        obj["firn_collider"] = collider["type"]
        context.collection.objects.link(obj)
        objects.append(obj)
    return objects


def import_run(context, folder, scene_path="", last_frame=None, frame_offset=0):
    """Builds the run in `folder` into the context's scene (its frames up to last_frame, when given), Firn's frame N
    at the scene's frame N + frame_offset; returns the parent object."""
    run = RunFolder(folder, last_frame)
    run.frame_offset = frame_offset
    scene = context.scene
    set_frame_rate(scene, run.frame_rate)
    first, last = run.frames()
    scene.frame_start, scene.frame_end = first + frame_offset, last + frame_offset
    scene.frame_set(first + frame_offset)

    parent = bpy.data.objects.new(f"Firn run ({os.path.basename(run.folder)})", None)
    parent.empty_display_type = "ARROWS"
    parent.rotation_euler = (math.pi / 2, 0.0, 0.0)  # Firn's (x, y, z) to Blender's (x, −z, y): Y-up to Z-up
    parent["firn_folder"] = run.folder
    parent["firn_frame_rate"] = run.frame_rate
    context.collection.objects.link(parent)

    if run.surfaces:
        surface = _sequence_object(context, "Firn surface", run.folder, run.surfaces, KIND_SURFACE, parent,
                                   frame_offset)
        surface.material_slots[0].link = "OBJECT"
        surface.material_slots[0].material = snow_surface_material()
    # The surface renders; the volume (the same snow) and the particles are there to switch on instead.
    if run.volumes:
        volume = _volume_object(context, "Firn volume", run, parent)
        volume.hide_render = bool(run.surfaces)
    if run.points:
        points = _sequence_object(context, "Firn particles", run.folder, run.points, KIND_POINTS, parent,
                                  frame_offset)
        points.hide_render = bool(run.surfaces or run.volumes)
        modifier = points.modifiers.new("Firn particles", "NODES")
        group = particles_node_group()
        modifier.node_group = group
        modifier[_radius_socket(group)] = _particle_radius(points)
    colliders, extent_m = _read_scene(bpy.path.abspath(scene_path)) if scene_path else ([], 0.0)
    _moving_objects(context, run, parent, colliders, extent_m)
    _collider_objects(context, colliders, extent_m, run, parent)
    register()
    return parent
