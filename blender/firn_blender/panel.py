"""The Firn panels (Properties editor: Object and Scene) and their settings: what each object is in a Firn scene, the
scene's step and solver, and the buttons that export, check and simulate it (docs/blender.md, Authoring a scene)."""

import subprocess

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, PointerProperty,
                       StringProperty)

from . import authoring


def _imported_material_edited(self, context):
    """A material edited in the panel is the panel's from then on, not the imported definition."""
    if self.material_json:
        self.material_json = ""


class FirnObjectSettings(bpy.types.PropertyGroup):
    role: EnumProperty(
        name="Firn",
        description="What the object is in the Firn scene",
        items=(("NONE", "None", "Not part of the Firn scene"),
               ("SNOW", "Snow", "A body filled with particles of its material"),
               ("EMITTER", "Emitter", "A body whose particles join over a span of frames"),
               ("COLLIDER", "Collider", "A solid the snow meets; moving with the object's animation"),
               ("RIGID_BODY", "Rigid body", "A solid moved by gravity, the snow and its contacts, pushing back"),
               ("DOMAIN", "Domain", "The box of the simulation's grid")),
        default="NONE")
    shape: EnumProperty(
        name="Shape",
        description="How Firn takes the object's geometry",
        items=(("MESH", "Mesh", "The object's mesh, as it is at the first frame (written as OBJ with the scene)"),
               ("SPHERE", "Sphere", "A sphere centred in the object's bounds, of half their largest extent"),
               ("BOX", "Box", "The object's bounds as a box"),
               ("PLANE", "Plane", "A collider's half-space behind the object's local +Z, through its origin"),
               ("POINTS", "Points", "An imported particle cloud, kept as the scene file gives it")),
        default="MESH")
    # Snow and emitters
    material_name: StringProperty(name="Material name",
                                  description="The material's name in the scene (empty: the preset's or the object's)")
    material_preset: EnumProperty(
        name="Material",
        items=[(p, p.capitalize(), f"Firn's {p} snow preset (docs/scene-format.md)") for p in authoring.PRESETS] +
              [("CUSTOM", "Custom", "A material model and its values, below")],
        default="stomakhin", update=_imported_material_edited)
    material_model: EnumProperty(
        name="Model",
        items=(("SNOW", "Snow", "Elastoplastic snow (Stomakhin et al. 2013)"),
               ("FIXED_COROTATED", "Fixed corotated", "An elastic solid"),
               ("NEO_HOOKEAN", "Neo-Hookean", "An elastic solid"),
               ("WATER", "Water", "A weakly compressible fluid"),
               ("DRUCKER_PRAGER", "Drucker-Prager", "Sand")),
        default="SNOW", update=_imported_material_edited)
    material_json: StringProperty(name="Imported material", description="The imported scene's definition, kept",
                                  options={"HIDDEN"})
    youngs_modulus: FloatProperty(name="Young's modulus (Pa)", default=1.4e5, min=1.0,
                                  update=_imported_material_edited)
    poisson_ratio: FloatProperty(name="Poisson's ratio", default=0.2, min=0.0, max=0.499,
                                 update=_imported_material_edited)
    density: FloatProperty(name="Density (kg/m³)", default=400.0, min=1e-3, update=_imported_material_edited)
    critical_compression: FloatProperty(name="θc", default=2.5e-2, min=0.0, max=0.999, precision=4,
                                        update=_imported_material_edited)
    critical_stretch: FloatProperty(name="θs", default=7.5e-3, min=0.0, precision=4, update=_imported_material_edited)
    hardening: FloatProperty(name="ξ", default=10.0, min=0.0, update=_imported_material_edited)
    bulk_modulus: FloatProperty(name="Bulk modulus (Pa)", default=1e5, min=1e-3, update=_imported_material_edited)
    gamma: FloatProperty(name="γ", default=7.0, min=1.0, update=_imported_material_edited)
    viscosity: FloatProperty(name="Viscosity (Pa·s)", default=0.0, min=0.0, update=_imported_material_edited)
    friction_angle_deg: FloatProperty(name="Friction angle (°)", default=30.0, min=0.0, max=89.9,
                                      update=_imported_material_edited)
    particles_per_cell: FloatProperty(name="Particles per cell", default=8.0, min=0.01, max=1000.0)
    velocity_source: EnumProperty(
        name="Initial velocity",
        items=(("FIELD", "Values", "The velocities below"),
               ("ANIMATION", "Animation", "The object's motion over the first frame of its animation")),
        default="FIELD")
    # Plain numbers in m/s and rad/s: a VELOCITY subtype would show them scaled by the scene's unit scale.
    velocity: FloatVectorProperty(name="Velocity (m/s)", size=3)
    angular_velocity: FloatVectorProperty(name="Angular velocity (rad/s)", size=3)
    emit_start: IntProperty(name="Start", default=0, min=0,
                            description="Frames after the scene's first frame at which its particles start joining")
    emit_frames: IntProperty(name="Frames", description="Over how many frames (0: all at once)", default=0, min=0)
    # Colliders and rigid bodies
    follow_animation: BoolProperty(name="Follow animation", default=True,
                                   description="A collider moves as its location and rotation keys (Firn keyframes)")
    friction: FloatProperty(name="Friction", default=0.0, min=0.0, description="Coulomb coefficient")
    boundary: EnumProperty(
        name="Boundary",
        items=(("STICKY", "Sticky", "The snow takes the surface's velocity"),
               ("SLIP", "Slip", "The snow loses its velocity into the surface"),
               ("SEPARATE", "Separate", "As slip, but the snow may leave the surface")),
        default="SLIP")
    resolution: FloatProperty(name="Field resolution", default=2.0, min=0.5, max=8.0,
                              description="A mesh's distance field: samples per grid cell and axis")
    mass_source: EnumProperty(
        name="Mass from",
        items=(("BLENDER", "Rigid Body", "Blender's Rigid Body settings, mass and friction, where the object has "
                "them (Physics > Rigid Body); else the mass and friction below"),
               ("MASS", "Mass", "The mass below"),
               ("DENSITY", "Density", "The density below times the shape's volume")),
        default="BLENDER")
    mass: FloatProperty(name="Mass (kg)", default=1.0, min=1e-6)
    body_friction: FloatProperty(name="Friction", default=0.3, min=0.0,
                                 description="Coulomb coefficient against the snow, the colliders and the walls")
    body_boundary: EnumProperty(
        name="Boundary",
        items=(("STICKY", "Sticky", "The snow takes the body's surface velocity"),
               ("SLIP", "Slip", "The snow loses its velocity into the body"),
               ("SEPARATE", "Separate", "As slip, but the snow may leave the body")),
        default="SEPARATE")
    # The domain
    cell_size: FloatProperty(name="Cell size (m)", default=0.02, min=1e-4, precision=4)
    # What an import carried (authoring.py), hidden
    entry: StringProperty(options={"HIDDEN"})
    order: IntProperty(options={"HIDDEN"})
    source_transform: FloatVectorProperty(size=16, options={"HIDDEN"})
    source_mesh: StringProperty(options={"HIDDEN"})
    source_motion: StringProperty(options={"HIDDEN"})
    source_kind: StringProperty(options={"HIDDEN"})


class FirnSceneSettings(bpy.types.PropertyGroup):
    scene_name: StringProperty(name="Name", description="The scene's name (empty: Blender's scene name)")
    dt: FloatProperty(name="Step (s)", default=2e-4, min=1e-8, precision=6,
                      description="time.dt: the step, or with adaptive steps the largest")
    adaptive: BoolProperty(name="Adaptive steps", default=False)
    kernel: EnumProperty(name="Kernel", items=(("CUBIC", "Cubic", ""), ("QUADRATIC", "Quadratic", "")),
                         default="CUBIC")
    transfer: EnumProperty(name="Transfer", items=(("PIC_FLIP", "PIC/FLIP", ""), ("APIC", "APIC", "")),
                           default="PIC_FLIP")
    integrator: EnumProperty(name="Integrator", items=(("EXPLICIT", "Explicit", ""),
                                                       ("SEMI_IMPLICIT", "Semi-implicit", "")), default="EXPLICIT")
    folder: StringProperty(name="Folder", subtype="DIR_PATH", default="//firn",
                           description="Where Simulate writes the scene and the run")
    document: StringProperty(options={"HIDDEN"})
    check_report: StringProperty(options={"HIDDEN"})
    check_ok: BoolProperty(options={"HIDDEN"})
    last_import: StringProperty(options={"HIDDEN"})


def check_scene(executable, scene_path):
    """`firn run SCENE --check`: its exit code and its report (pre-flight on stderr, the result on stdout)."""
    try:
        done = subprocess.run([executable, "run", scene_path, "--check"], capture_output=True, text=True)
    except FileNotFoundError:
        return 127, f"{executable}: not found (install Firn, or set its path in the add-on's preferences)"
    except OSError as error:
        return 126, f"{executable}: cannot be run ({error})"
    return done.returncode, (done.stderr + done.stdout).strip()


def note_check(scene, code, report):
    scene.firn.check_ok = code == 0
    scene.firn.check_report = report


class FIRN_PT_object(bpy.types.Panel):
    bl_label = "Firn"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    def draw(self, context):
        layout = self.layout
        obj = context.object
        settings = obj.firn
        layout.prop(settings, "role")
        role = settings.role
        if role == "NONE":
            return
        if role == "DOMAIN":
            layout.prop(settings, "cell_size")
            return
        layout.prop(settings, "shape")
        if role in ("SNOW", "EMITTER"):
            if settings.material_json:
                layout.label(text=f"Material {settings.material_name!r} as imported")
            layout.prop(settings, "material_preset")
            layout.prop(settings, "material_name")
            if settings.material_preset == "CUSTOM":
                layout.prop(settings, "material_model")
                for key in authoring.MODEL_KEYS[settings.material_model.lower()]:
                    layout.prop(settings, key)
            layout.prop(settings, "particles_per_cell")
            layout.prop(settings, "velocity_source")
            if settings.velocity_source == "FIELD":
                layout.prop(settings, "velocity")
                layout.prop(settings, "angular_velocity")
            if role == "EMITTER":
                layout.prop(settings, "emit_start")
                layout.prop(settings, "emit_frames")
        elif role == "COLLIDER":
            layout.prop(settings, "follow_animation")
            layout.prop(settings, "velocity")
            layout.prop(settings, "friction")
            layout.prop(settings, "boundary")
            if settings.shape == "MESH":
                layout.prop(settings, "resolution")
        elif role == "RIGID_BODY":
            layout.prop(settings, "mass_source")
            from_blender = settings.mass_source == "BLENDER" and obj.rigid_body is not None
            if settings.mass_source == "DENSITY":
                layout.prop(settings, "density")
            elif not from_blender:
                layout.prop(settings, "mass")
            if not from_blender:
                layout.prop(settings, "body_friction")
            layout.prop(settings, "body_boundary")
            layout.prop(settings, "velocity")
            layout.prop(settings, "angular_velocity")
            if settings.shape == "MESH":
                layout.prop(settings, "resolution")


class FIRN_PT_scene(bpy.types.Panel):
    bl_label = "Firn"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.firn
        for key in ("scene_name", "dt", "adaptive", "kernel", "transfer", "integrator", "folder"):
            layout.prop(settings, key)
        row = layout.row()
        row.operator("export_scene.firn_scene", text="Export…")
        row.operator("firn.check", text="Check")
        row.operator("firn.simulate", text="Simulate")
        if settings.check_report:
            box = layout.box()
            for i, line in enumerate(report_lines(settings)):
                icon = "NONE" if i > 0 else "CHECKMARK" if settings.check_ok else "ERROR"
                box.label(text=line, icon="ERROR" if "warning:" in line else icon)


def report_lines(settings):
    """The check's report as the Scene panel shows it: the verdict, every warning, then the last lines."""
    lines = settings.check_report.splitlines()
    warnings = [line for line in lines if "warning:" in line]
    count = f", with {len(warnings)} warning{'s' if len(warnings) != 1 else ''}" if warnings else ""
    verdict = ("Ready to run" if settings.check_ok else "Firn refuses the scene") + count
    rest = [line for line in lines[-8:] if line not in warnings]
    return [verdict] + warnings + rest


CLASSES = (FirnObjectSettings, FirnSceneSettings, FIRN_PT_object, FIRN_PT_scene)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.firn = PointerProperty(type=FirnObjectSettings)
    bpy.types.Scene.firn = PointerProperty(type=FirnSceneSettings)


def unregister():
    del bpy.types.Scene.firn
    del bpy.types.Object.firn
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
