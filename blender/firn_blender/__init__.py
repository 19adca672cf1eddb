"""Firn in Blender (docs/blender.md): File > Import > Firn run, and File > Import > Run Firn scene, which runs a
scene file with the installed `firn` and imports what it writes; and scenes authored in Blender: the Firn panels
mark objects as snow, emitters, colliders, rigid bodies and the domain, File > Export > Firn scene writes them as a
scene file (checked with `firn run --check`), File > Import > Firn scene makes such objects of one, and Simulate
exports, runs and imports in one go."""

bl_info = {
    "name": "Firn snow",
    "author": "Firn",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Firn run / Run Firn scene / Firn scene, File > Export > Firn scene, "
                "Properties > Object and Scene > Firn",
    "description": "Imports Firn's snow caches (surface meshes, VDB volumes, point caches) as animated objects, "
                   "runs Firn scenes, and authors them from Blender's objects",
    "category": "Import-Export",
}

import os
import tempfile

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import authoring, importer, panel, runner


class FirnPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    firn_path: StringProperty(
        name="firn executable",
        description="The firn program Run Firn starts (empty: the one on the PATH)",
        subtype="FILE_PATH",
        default="",
    )

    def draw(self, context):
        self.layout.prop(self, "firn_path")


def firn_executable(context):
    preferences = context.preferences.addons[__package__].preferences
    return bpy.path.abspath(preferences.firn_path) if preferences.firn_path else "firn"


class IMPORT_OT_firn_run(bpy.types.Operator, ImportHelper):
    """Import a Firn output folder: the surface, the volume and the particles as animated objects"""

    bl_idname = "import_scene.firn_run"
    bl_label = "Import Firn run"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(subtype="DIR_PATH")
    filter_folder: BoolProperty(default=True, options={"HIDDEN"})
    filter_glob: StringProperty(default="*.csv;*.ply;*.vdb", options={"HIDDEN"})
    scene_file: StringProperty(
        name="Scene file",
        description="The run's scene file (optional): its colliders are imported too",
        subtype="FILE_PATH",
        default="",
    )

    def execute(self, context):
        folder = self.directory or os.path.dirname(self.filepath)
        try:
            parent = importer.import_run(context, folder, self.scene_file)
        except (importer.FirnRunError, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Firn: imported {parent.name}")
        return {"FINISHED"}


class FirnJobModal:
    """Runs a Firn job with its progress in the status bar (Esc cancels), then imports what it wrote."""

    _job = None
    _timer = None
    _scene_path = ""
    frame_offset = 0  # the scene's frame of Firn's frame 0

    def start_job(self, context, scene_path, folder, frames, volume):
        try:
            self._job = runner.FirnJob(firn_executable(context), scene_path, folder, frames, volume)
        except (runner.FirnJobError, OSError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self._scene_path = scene_path
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(0.25, window=context.window)
        window_manager.modal_handler_add(self)
        window_manager.progress_begin(0, 100)
        return {"RUNNING_MODAL"}

    def _finish(self, context):
        window_manager = context.window_manager
        window_manager.event_timer_remove(self._timer)
        window_manager.progress_end()
        context.workspace.status_text_set(None)

    def modal(self, context, event):
        if event.type == "ESC":
            self._job.cancel()
            self._finish(context)
            self.report({"WARNING"}, "Firn: run cancelled")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        state = self._job.poll()
        context.workspace.status_text_set(f"Firn: {state.message} (Esc cancels)")
        context.window_manager.progress_update(int(100 * state.fraction))
        if not state.finished:
            return {"RUNNING_MODAL"}
        self._finish(context)
        if state.exit_code != 0:
            self.report({"ERROR"}, f"Firn exited {state.exit_code}: {state.message}")
            return {"CANCELLED"}
        self.before_import(context)
        try:
            parent = importer.import_run(context, self._job.output_folder, self._scene_path,
                                         last_frame=self._job.frames, frame_offset=self.frame_offset)
        except (importer.FirnRunError, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.imported(context, parent)
        self.report({"INFO"}, f"Firn: imported {self._job.output_folder}")
        return {"FINISHED"}

    def before_import(self, context):
        pass

    def imported(self, context, parent):
        pass


class IMPORT_OT_run_firn(FirnJobModal, bpy.types.Operator, ImportHelper):
    """Run a Firn scene file with the installed firn, then import what it writes"""

    bl_idname = "import_scene.run_firn"
    bl_label = "Run Firn scene"

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    output_folder: StringProperty(
        name="Output folder",
        description="Where Firn writes (empty: a folder named after the scene, next to it)",
        subtype="DIR_PATH",
        default="",
    )
    frames: IntProperty(name="Frames", description="Frames to simulate (0: the scene's own)", default=0, min=0)
    volume: BoolProperty(name="VDB volume", description="Also write and import the VDB caches", default=True)

    def execute(self, context):
        folder = self.output_folder or os.path.splitext(self.filepath)[0] + "-firn"
        return self.start_job(context, self.filepath, bpy.path.abspath(folder), self.frames, self.volume)


def _export_and_check(operator, context, scene_path):
    """Writes the scene of the marked objects and checks it with `firn run --check`, the report on the Scene panel."""
    try:
        authoring.export_scene(context, scene_path)
    except (authoring.AuthoringError, OSError, ValueError) as error:  # ValueError: a path or a JSON it cannot take
        panel.note_check(context.scene, 2, str(error))
        operator.report({"ERROR"}, f"Firn: {error}")
        return False
    code, report = panel.check_scene(firn_executable(context), scene_path)
    panel.note_check(context.scene, code, report)
    if code != 0:
        operator.report({"ERROR"}, f"Firn refuses {scene_path} (exit {code}): {report.splitlines()[-1]}")
        return False
    return True


class EXPORT_OT_firn_scene(bpy.types.Operator, ExportHelper):
    """Write the objects marked in the Firn panel as a Firn scene file (and its meshes), and check it with firn"""

    bl_idname = "export_scene.firn_scene"
    bl_label = "Export Firn scene"

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        if not _export_and_check(self, context, self.filepath):
            return {"CANCELLED"}
        self.report({"INFO"}, f"Firn: wrote {self.filepath}")
        return {"FINISHED"}


class IMPORT_OT_firn_scene(bpy.types.Operator, ImportHelper):
    """Make marked objects of a Firn scene file: its snow, colliders, rigid bodies, domain and camera"""

    bl_idname = "import_scene.firn_scene"
    bl_label = "Import Firn scene"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        try:
            collection = authoring.import_scene(context, self.filepath)
        except (authoring.AuthoringError, OSError, KeyError, ValueError) as error:
            self.report({"ERROR"}, f"Firn: {error}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Firn: imported {collection.name}")
        return {"FINISHED"}


def _layer_collection(layer, collection):
    """The view layer's entry of `collection`, found from `layer` down."""
    if layer.collection == collection:
        return layer
    for child in layer.children:
        found = _layer_collection(child, collection)
        if found is not None:
            return found
    return None


def _scene_folder(context):
    folder = bpy.path.abspath(context.scene.firn.folder)
    if folder.startswith("//") or not os.path.isabs(folder):  # an unsaved file: no folder of its own
        folder = os.path.join(tempfile.gettempdir(), "firn-" + bpy.path.clean_name(context.scene.name))
    return folder


def _export_to_folder(operator, context):
    """The scene exported and checked into the scene's Folder: its path, or None where that failed."""
    name = bpy.path.clean_name(context.scene.firn.scene_name or context.scene.name)
    path = os.path.join(_scene_folder(context), name + ".json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    return path if _export_and_check(operator, context, path) else None


class FIRN_OT_check(bpy.types.Operator):
    """Export the Firn scene to the scene's folder and check it with `firn run --check`"""

    bl_idname = "firn.check"
    bl_label = "Check Firn scene"

    def execute(self, context):
        if _export_to_folder(self, context) is None:
            return {"CANCELLED"}
        self.report({"INFO"}, "Firn: " + context.scene.firn.check_report.splitlines()[-1])
        return {"FINISHED"}


class FIRN_OT_simulate(FirnJobModal, bpy.types.Operator):
    """Export the Firn scene, run it with firn (progress in the status bar, Esc cancels) and import the run,
    replacing the last one Simulate imported"""

    bl_idname = "firn.simulate"
    bl_label = "Simulate with Firn"

    def execute(self, context):
        path = _export_to_folder(self, context)
        if path is None:
            return {"CANCELLED"}
        # The run's frames on the scene's own: Firn's frame 0 is the scene's first frame, as the export took it.
        self.frame_offset = context.scene.frame_start
        return self.start_job(context, path, os.path.join(os.path.dirname(path), "run"), 0, True)

    def before_import(self, context):
        previous = bpy.data.objects.get(context.scene.firn.last_import)
        if previous is not None:
            for obj in [previous] + list(previous.children_recursive):
                bpy.data.objects.remove(obj, do_unlink=True)
        # The run goes into the collection of the objects it was made of (the domain's).
        domain = next((o for o in context.scene.objects if o.firn.role == "DOMAIN"), None)
        if domain is not None and domain.users_collection:
            layer = _layer_collection(context.view_layer.layer_collection, domain.users_collection[0])
            if layer is not None:
                context.view_layer.active_layer_collection = layer

    def imported(self, context, parent):
        context.scene.firn.last_import = parent.name


def menu_import(self, context):
    self.layout.operator(IMPORT_OT_firn_run.bl_idname, text="Firn run (folder)")
    self.layout.operator(IMPORT_OT_run_firn.bl_idname, text="Run Firn scene (.json)")
    self.layout.operator(IMPORT_OT_firn_scene.bl_idname, text="Firn scene (.json)")


def menu_export(self, context):
    self.layout.operator(EXPORT_OT_firn_scene.bl_idname, text="Firn scene (.json)")


CLASSES = (FirnPreferences, IMPORT_OT_firn_run, IMPORT_OT_run_firn, EXPORT_OT_firn_scene, IMPORT_OT_firn_scene,
           FIRN_OT_check, FIRN_OT_simulate)


def register():
    panel.register()
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_export)
    importer.register()


def unregister():
    importer.unregister()
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
    panel.unregister()
