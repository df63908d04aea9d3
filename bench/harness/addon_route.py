"""The route through Blender: a bundled .blend (blend_scenes/) opened in the bpy module and rendered
with bpy.ops.render.render, by the PPM add-on or by Cycles. Settings are scene.ppm properties (PPM)
or scene.cycles properties (Cycles); a key with a dot is a property path from the scene
("camera.data.dof.use_dof")."""

from __future__ import annotations

import os
import sys
import tempfile
import time
from dataclasses import dataclass

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))
import bpy  # noqa: E402

import ppm_render  # noqa: E402

from .exr_io import read_exr  # noqa: E402

SCENES_DIR = os.path.join(ROOT, "blend_scenes")
BLEND_SCENES = ("cornell_3spheres", "bezier_vase", "cornell_dof", "showcase", "cornell_diffuse")
WORKDIR = tempfile.mkdtemp(prefix="ppm_bench_")


@dataclass
class Render:
    image: np.ndarray  # (H, W, 3), top row first
    wall: float  # seconds of bpy.ops.render.render (export or sync, rendering, writing the image)
    passes: int | None  # PPM passes or Cycles samples asked for (None: a time limit)


def open_scene(name, width, height):
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()  # before loading, so the file's PPM engine setting is recognised
    bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, f"{name}.blend"))
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = width, height, 100
    scene.render.use_border = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    return scene


def apply(scene, owner, settings):
    """Sets `settings` on `owner`; dotted keys are paths from the scene, in which a name picks an item
    of a collection (`objects.spot.data.shadow_soft_size`)."""
    for key, value in settings.items():
        target, attribute = owner, key
        if "." in key:
            *path, attribute = key.split(".")
            target = scene
            for part in path:
                target = getattr(target, part) if hasattr(target, part) else target[part]
        if not hasattr(target, attribute):
            raise SystemExit(f"no setting {key!r} on {target!r}")
        setattr(target, attribute, value)


def _render(scene, tag):
    path = os.path.join(WORKDIR, f"{tag}_{time.monotonic_ns()}.exr")
    scene.render.filepath = path
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    wall = time.perf_counter() - start
    image, _ = read_exr(path)
    os.remove(path)
    return image, wall


def render_ppm(name, width, height, *, seed, passes=0, seconds=0.0, threads=2, **settings):
    """Through the PPM add-on until `passes` or `seconds` (0 = none: the other limits); the file's
    other settings (the add-on's defaults)."""
    scene = open_scene(name, width, height)
    scene.render.engine = "PPM"
    p = scene.ppm
    p.passes, p.time_limit, p.seed, p.threads = passes or 1_000_000, seconds, seed, threads
    apply(scene, p, settings)
    image, wall = _render(scene, f"ppm_{name}")
    return Render(image, wall, passes or None)


def render_cycles(name, width, height, *, seed, passes=0, seconds=0.0, threads=2, **settings):
    """Through Cycles on the CPU, `passes` samples or `seconds`: path tracing with the PPM engine's
    path length (12 bounces of every kind), no clamping, denoising, adaptive sampling or glossy
    filter, caustics on, a 1-pixel box filter (the PPM engine averages jittered samples inside each
    pixel). Ray visibility is the file's: both engines honour it (lights hide from the camera by
    Blender's default)."""
    scene = open_scene(name, width, height)
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.seed, c.time_limit = "CPU", passes or 1 << 20, seed, seconds
    c.use_adaptive_sampling = c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 12
    # Volume bounces too (Cycles' default is 0: fog lit by the lights alone, with no light scattered
    # twice or off a wall; the PPM engine has no volume limit of its own), and transparent ones.
    c.volume_bounces = c.transparent_max_bounces = 12
    c.pixel_filter_type, c.filter_width = "BOX", 1.0
    scene.render.threads_mode, scene.render.threads = "FIXED", threads
    apply(scene, c, settings)
    image, wall = _render(scene, f"cycles_{name}")
    return Render(image, wall, passes or None)
