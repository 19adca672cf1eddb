"""Simulate in Blender's interface (under Xvfb; docs/blender.md, Authoring a scene): the Scene panel's Simulate
exports the scene built by script (authored_scene.py), checks it, runs Firn as a modal operator and imports the run
with Firn's frame 0 on the scene's first frame; a second Simulate replaces the first import. Exits 0 when both imports
are as they should be, 1 on a failed check or after 180 s."""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402
from authored_scene import build_scene  # noqa: E402

FOLDER = os.path.join(harness.ARGS.work, "simulated")
FRAMES = 2
imports = []


def simulate():
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, area=window.screen.areas[0]):
        result = bpy.ops.firn.simulate("EXEC_DEFAULT")
    assert result == {"RUNNING_MODAL"}, f"firn.simulate returned {result}: {bpy.context.scene.firn.check_report}"


def start():
    harness.install_addon()
    bpy.context.preferences.addons[harness.ADDON].preferences.firn_path = harness.ARGS.firn
    scene = build_scene()
    scene.frame_start, scene.frame_end = 5, 5 + FRAMES  # Firn's frame 0 at the scene's frame 5
    for obj in scene.objects:  # the paddle's keys moved with the start
        if obj.animation_data and obj.animation_data.action:
            for curve in obj.animation_data.action.fcurves:
                for key in curve.keyframe_points:
                    key.co.x += 4
                    key.handle_left.x += 4
                    key.handle_right.x += 4
    # The authored objects in a collection of their own, where Simulate puts the run too.
    authored = bpy.data.collections.new("Authored")
    scene.collection.children.link(authored)
    for obj in list(scene.collection.objects):
        authored.objects.link(obj)
        scene.collection.objects.unlink(obj)
    scene.firn.folder = FOLDER
    simulate()


def check():
    scene = bpy.context.scene
    parents = [obj for obj in bpy.data.objects if obj.get("firn_frame_rate")]
    if not scene.firn.last_import or all(p.get("test_seen") for p in parents):
        return 0.5  # Simulate's import not done yet
    assert len(parents) == 1, [p.name for p in parents]  # the second import replaced the first
    parent = parents[0]
    assert scene.firn.last_import == parent.name, (scene.firn.last_import, parent.name)
    assert [c.name for c in parent.users_collection] == ["Authored"], parent.users_collection[:]
    assert scene.firn.check_ok, scene.firn.check_report
    assert (scene.frame_start, scene.frame_end) == (5, 5 + FRAMES), (scene.frame_start, scene.frame_end)
    run = os.path.join(FOLDER, "run")
    for name in ("frame_0002.ply", "frame_0002_surface.ply", "bodies.csv", "firn.log"):
        assert os.path.isfile(os.path.join(run, name)), name
    surface = next(child for child in parent.children if child.name.startswith("Firn surface"))
    assert surface["firn_frame_offset"] == 5
    scene.frame_set(6)  # Firn's frame 1
    assert surface.data.get("firn_file", "").endswith("frame_0001_surface.ply"), surface.data.get("firn_file")
    parent["test_seen"] = True
    imports.append(parent.name)
    if len(imports) == 1:
        simulate()
        return 0.5
    names = sorted(child.name for child in parent.children)
    assert names == ["Firn collider 0 (plane)", "Firn colliders[1]", "Firn particles", "Firn rigid_bodies[0]",
                     "Firn surface", "Firn volume"], names  # the first import's names, freed for the second's
    return "simulated twice: " + ", ".join(names)


harness.run_in_interface("test_simulate", start, check, 180.0)
