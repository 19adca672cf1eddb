"""Firn in Blender (docs/blender.md): File > Import > Firn run, and File > Import > Run Firn scene, which runs a
scene file with the installed `firn` and imports what it writes."""

bl_info = {
    "name": "Firn snow",
    "author": "Firn",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Firn run / Run Firn scene",
    "description": "Imports Firn's snow caches (surface meshes, VDB volumes, point caches) as animated objects, "
                   "and runs Firn scenes",
    "category": "Import-Export",
}

import os

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from . import importer, runner


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


class IMPORT_OT_run_firn(bpy.types.Operator, ImportHelper):
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

    _job = None
    _timer = None

    def execute(self, context):
        folder = self.output_folder or os.path.splitext(self.filepath)[0] + "-firn"
        try:
            self._job = runner.FirnJob(firn_executable(context), self.filepath, bpy.path.abspath(folder),
                                       self.frames, self.volume)
        except (runner.FirnJobError, OSError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
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
        try:
            importer.import_run(context, self._job.output_folder, self.filepath, last_frame=self._job.frames)
        except (importer.FirnRunError, OSError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Firn: imported {self._job.output_folder}")
        return {"FINISHED"}


def menu_import(self, context):
    self.layout.operator(IMPORT_OT_firn_run.bl_idname, text="Firn run (folder)")
    self.layout.operator(IMPORT_OT_run_firn.bl_idname, text="Run Firn scene (.json)")


CLASSES = (FirnPreferences, IMPORT_OT_firn_run, IMPORT_OT_run_firn)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)
    importer.register()


def unregister():
    importer.unregister()
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
