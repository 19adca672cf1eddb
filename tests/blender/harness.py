"""What the Blender tests share (run by ctest inside `blender -b --factory-startup --python test_*.py -- ARGS`):
their arguments, the add-on installed from its zip and enabled, the run imported, the caches read back, and a
unittest runner whose failures make Blender exit non-zero (--python-exit-code)."""

import argparse
import os
import sys
import unittest

import addon_utils
import bpy

ADDON = "firn_blender"


def arguments():
    parser = argparse.ArgumentParser()
    parser.add_argument("--zip", required=True, help="the add-on's zip (build/…/firn_blender.zip)")
    parser.add_argument("--run", required=True, help="the folder `firn run` wrote")
    parser.add_argument("--scene", required=True, help="its scene file")
    parser.add_argument("--work", required=True, help="a folder for what the test writes")
    parser.add_argument("--firn", required=True, help="the firn executable")
    return parser.parse_args(sys.argv[sys.argv.index("--") + 1:])


ARGS = arguments()
os.makedirs(ARGS.work, exist_ok=True)


def install_addon():
    """Installs the zip as Blender's add-on installer does (Preferences > Add-ons > Install) and enables it."""
    bpy.ops.preferences.addon_install(filepath=ARGS.zip, overwrite=True)
    addon_utils.modules_refresh()
    addon_utils.enable(ADDON, default_set=True, handle_error=None)
    return addon_utils.check(ADDON)


def import_run():
    """Imports the run with the add-on's operator, as File > Import > Firn run does; returns the parent."""
    before = set(bpy.data.objects)
    result = bpy.ops.import_scene.firn_run(directory=ARGS.run, scene_file=ARGS.scene)
    if result != {"FINISHED"}:
        raise RuntimeError(f"import_scene.firn_run: {result}")
    parents = [obj for obj in set(bpy.data.objects) - before if obj.get("firn_frame_rate")]
    return parents[0]


def addon_module(name):
    """One of the add-on's modules, from where the installer put it."""
    import importlib
    return importlib.import_module(ADDON + "." + name)


def run_tests(case):
    result = unittest.TextTestRunner(verbosity=2).run(unittest.defaultTestLoader.loadTestsFromTestCase(case))
    if not result.wasSuccessful():
        raise SystemExit(1)


def run_in_interface(name, start, check, limit_s):
    """A test of Blender's interface (under Xvfb): its event loop runs only once the script has returned, so `start`
    and then `check` run from timers. `check` returns seconds to wait before it looks again, or what it found when
    all is as it should be; an exception in either, or `limit_s` passing, fails the test. Blender exits with the
    test's status (its window would otherwise stay open)."""
    def finish(code, message):
        print(f"{name}: {message}", flush=True)
        os._exit(code)

    def guarded(step):
        def run():
            try:
                result = step()
            except Exception:
                import traceback
                finish(1, traceback.format_exc())
            if isinstance(result, str):
                finish(0, result)
            return result
        return run

    bpy.app.timers.register(guarded(start), first_interval=0.5)
    bpy.app.timers.register(guarded(check), first_interval=1.0)
    bpy.app.timers.register(lambda: finish(1, f"not done within {limit_s} s"), first_interval=limit_s)
