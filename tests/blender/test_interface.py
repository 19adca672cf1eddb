"""Run Firn in Blender's interface (under Xvfb): the operator as File > Import > Run Firn scene starts it, a modal
operator that polls the run on a timer, shows its frame in the status bar and imports the folder when the run
ends. A background Blender has no event loop for it, so this one runs with a window; it exits 0 when the run is
imported with the scene's frame rate and its own frames, 1 on a failed check or after 120 s."""

import os
import shutil
import sys

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

OUTPUT = os.path.join(harness.ARGS.work, "run_firn")


def start():
    # A longer run's frames left in the folder: Run Firn imports the frames of its own run only.
    os.makedirs(OUTPUT, exist_ok=True)
    for name in os.listdir(OUTPUT):
        os.remove(os.path.join(OUTPUT, name))
    shutil.copy(os.path.join(harness.ARGS.run, "frame_0005_surface.ply"), OUTPUT)
    harness.install_addon()
    bpy.context.preferences.addons[harness.ADDON].preferences.firn_path = harness.ARGS.firn
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, area=window.screen.areas[0]):
        result = bpy.ops.import_scene.run_firn("EXEC_DEFAULT", filepath=harness.ARGS.scene, output_folder=OUTPUT,
                                               frames=2, volume=False)
    assert result == {"RUNNING_MODAL"}, f"run_firn returned {result}"


def check():
    parents = [obj for obj in bpy.data.objects if obj.get("firn_frame_rate")]
    if not parents:
        return 0.5
    scene = bpy.context.scene
    names = sorted(child.name for child in parents[0].children)
    assert names == ["Firn collider 0 (plane)", "Firn particles", "Firn surface"], names
    assert abs(scene.render.fps / scene.render.fps_base - 30.0) < 1e-9
    assert (scene.frame_start, scene.frame_end) == (0, 2), (scene.frame_start, scene.frame_end)
    for name in ("frame_0002.ply", "frame_0002_surface.ply", "firn.log"):
        assert os.path.isfile(os.path.join(OUTPUT, name)), name
    return "imported " + ", ".join(names)


harness.run_in_interface("test_interface", start, check, 120.0)
