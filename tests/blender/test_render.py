"""A tiny Cycles render (CPU) of the imported surface of tests/blender/sliding_block.json's run: the picture is not
empty, and its snow lies where the particles project through the same camera."""

import math
import os
import sys
import unittest

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

sys.path.insert(0, os.path.dirname(__file__))
import harness  # noqa: E402

WIDTH, HEIGHT = 96, 64
FRAME = 5
SPACING_M = 0.02  # the particles' spacing: 8 per cell of 0.04 m
KERNEL_M = 3 * SPACING_M  # the surface's kernel radius (surface.smoothing 3 spacings)


class RenderedSurface(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for obj in list(bpy.data.objects):  # the factory startup's cube, light and camera
            bpy.data.objects.remove(obj)
        harness.install_addon()
        parent = harness.import_run()
        scene = bpy.context.scene
        scene.frame_set(FRAME)
        for obj in parent.children:
            obj.hide_render = not obj.name.startswith("Firn surface")
        cls.surface = next(obj for obj in parent.children if obj.name.startswith("Firn surface"))
        cls.points = next(obj for obj in parent.children if obj.name.startswith("Firn particles"))

        # An orthographic camera looking down Blender's −z onto the snow from above, 0.5 m across: a pixel is
        # 0.5 / 96 = 5.2 mm.
        camera = bpy.data.objects.new("Test camera", bpy.data.cameras.new("Test camera"))
        camera.data.type = "ORTHO"
        camera.data.ortho_scale = 0.5
        scene.collection.objects.link(camera)
        centre = sum((cls.surface.matrix_world @ v.co for v in cls.surface.data.vertices), Vector()) / len(
            cls.surface.data.vertices)
        camera.location = centre + Vector((0.0, 0.0, 1.0))
        camera.rotation_euler = (0.0, 0.0, 0.0)
        scene.camera = camera
        sun = bpy.data.objects.new("Test sun", bpy.data.lights.new("Test sun", "SUN"))
        sun.data.energy = 3.0
        sun.rotation_euler = (math.radians(30), 0.0, math.radians(20))
        scene.collection.objects.link(sun)

        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 4
        scene.cycles.use_denoising = False
        scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
        scene.render.resolution_percentage = 100
        scene.render.film_transparent = True
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGBA"
        cls.pixels = cls.render(scene, "surface.png", motion_blur=False)
        cls.blurred = cls.render(scene, "surface_blurred.png", motion_blur=True)

        # Where the particles project: the pixels holding one.
        cls.particle_pixels = np.zeros((HEIGHT, WIDTH), dtype=bool)
        matrix = cls.points.matrix_world
        for vertex in cls.points.data.vertices:
            view = world_to_camera_view(scene, camera, matrix @ vertex.co)
            x, y = int(view.x * WIDTH), int(view.y * HEIGHT)
            if 0 <= x < WIDTH and 0 <= y < HEIGHT:
                cls.particle_pixels[y, x] = True
        cls.pixel_m = camera.data.ortho_scale / WIDTH

    @staticmethod
    def render(scene, name, motion_blur):
        scene.render.use_motion_blur = motion_blur
        scene.render.filepath = os.path.join(harness.ARGS.work, name)
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        return np.array(image.pixels[:], dtype=np.float32).reshape(HEIGHT, WIDTH, 4)  # bottom row first

    @staticmethod
    def extent(alpha, axis):
        """The pixels along an axis that hold any snow (alpha above 2%, beyond the renders' noise)."""
        return int((alpha > 0.02).any(axis=axis).sum())

    def dilate(self, mask, pixels):
        grown = mask.copy()
        for _ in range(pixels):
            shifted = grown.copy()
            shifted[1:, :] |= grown[:-1, :]
            shifted[:-1, :] |= grown[1:, :]
            shifted[:, 1:] |= grown[:, :-1]
            shifted[:, :-1] |= grown[:, 1:]
            grown = shifted
        return grown

    def test_render_is_not_empty_and_lit(self):
        snow = self.pixels[..., 3] > 0.5
        self.assertGreater(snow.sum(), 0.1 * WIDTH * HEIGHT, "the block covers about a fifth of the picture")
        luminance = self.pixels[..., :3].mean(axis=2)
        self.assertGreater(luminance[snow].mean(), 0.2, "lit snow, not black")

    def test_snow_lies_where_the_particles_project(self):
        """The surface lies within a kernel radius of a particle (beyond it the field is 0), so every snow pixel is
        within that many pixels of a particle's (and a pixel more for the pixels' own size); and the particles lie
        inside the surface but for its rounded edges (within 0.24 R of a corner, docs/surfaces.md), so nearly all
        particle pixels are snow."""
        snow = self.pixels[..., 3] > 0.5
        reach = int(math.ceil(KERNEL_M / self.pixel_m)) + 1
        self.assertEqual(int((snow & ~self.dilate(self.particle_pixels, reach)).sum()), 0,
                         "no snow farther than a kernel radius from every particle")
        covered = (self.particle_pixels & snow).sum() / self.particle_pixels.sum()
        self.assertGreater(covered, 0.95, "the particles' pixels are snow")


    def test_motion_blur_smears_the_snow_along_its_velocity(self):
        """The block slides along Firn's x (Blender's x) at about 1 m/s (its mesh's `velocity`), so with Blender's
        default shutter of half a frame at 30 fps it moves 1/60 m = 3.2 pixels while the shutter is open: blurred,
        its picture is wider along x by about that (at least a pixel, at most 3.2 and a pixel for the alpha
        threshold on each side) and no taller along y, and it covers the same area (blur moves coverage, to 5%
        for 4 samples' noise)."""
        sharp, blurred = self.pixels[..., 3], self.blurred[..., 3]
        moved_px = 1.0 / 60.0 / self.pixel_m
        growth = self.extent(blurred, 0) - self.extent(sharp, 0)
        self.assertGreaterEqual(growth, 1, "wider along the motion")
        self.assertLessEqual(growth, math.ceil(moved_px) + 2)
        self.assertLessEqual(abs(self.extent(blurred, 1) - self.extent(sharp, 1)), 1, "not across it")
        self.assertLess(abs(blurred.sum() / sharp.sum() - 1.0), 0.05)


harness.run_tests(RenderedSurface)
