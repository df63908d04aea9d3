"""The route through the core alone: a scene of blend_scenes/core_scenes.py rendered by
ppm_core.Renderer, whose keyword arguments are the settings. No Blender."""

from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402


@dataclass
class Render:
    image: np.ndarray  # (H, W, 3), top row first
    wall: float  # seconds of rendering (after the scene is built)
    passes: int


def build_scene(name, width, height, **scene_args):
    return getattr(core_scenes, name)(width, height, **scene_args)


def render(name, width, height, *, seed, passes=0, seconds=0.0, threads=2, scene_args=None, **settings):
    """Renders core_scenes.<name> until `passes` or `seconds` (0 = no limit); `settings` are
    ppm_core.Renderer arguments (photons_per_pass, alpha, threshold, hit_points, grid, ...)."""
    scene = build_scene(name, width, height, **(scene_args or {}))
    renderer = ppm_core.Renderer(scene, threads=threads, seed=seed, **settings)
    start = time.perf_counter()
    renderer.run(passes=passes, seconds=seconds)
    wall = time.perf_counter() - start
    return Render(np.asarray(renderer.image())[..., :3], wall, renderer.stats()["passes"])
