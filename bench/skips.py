"""What the scene analysis saves: time per pass with it on and off.

    .venv/bin/python bench/skips.py

Each row is a scene built to need less work; `scene_analysis=False` makes the
core do the full work anyway. Prints a markdown table and what stats() listed.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H = 320, 240


def diffuse_box_point_light(**_):
    """Diffuse-only Cornell box lit by a point light: no specular chains, one exact direct sample."""
    scene = ppm_core.Scene()
    mats = core_scenes.cornell_box(scene)
    scene.add_sphere("ball", (0.3, 0.2, 0.4), 0.4, mats["white"])
    scene.add_light("point", name="lamp", power=25.0, position=(0.0, 0.0, 1.7))
    scene.set_camera(core_scenes.look_at((0.0, -4.4, 1.0), (0.0, 0.0, 1.0)), W, H, fov=0.8)
    return scene


def emission_only(**_):
    """A glowing panel on black walls: nothing scatters, so photon passes cannot add light."""
    scene = ppm_core.Scene()
    black = scene.add_material("black", "diffuse", base_color=0.0)
    glow = scene.add_material("glow", "emission", emission=2.0)
    core_scenes.quad(scene, "floor", [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], black)
    core_scenes.quad(scene, "panel", [(-0.5, 1, 0.2), (0.5, 1, 0.2), (0.5, 1, 1.2), (-0.5, 1, 1.2)], glow)
    scene.set_camera(core_scenes.look_at((0.0, -3.0, 1.0), (0.0, 0.0, 0.6)), W, H, fov=0.8)
    return scene


def cornell_tiny_aperture(**_):
    """The glass/mirror Cornell box asking for POST depth of field with an aperture too small to show."""
    return core_scenes.cornell_3spheres(W, H, aperture_radius=1e-5)


CASES = [
    ("diffuse box, point light", diffuse_box_point_light, {}),
    ("emission only", emission_only, {}),
    ("DoF POST, CoC < 1 px", cornell_tiny_aperture, {"dof_mode": "post"}),
]


def time_per_pass(build, passes=6, **settings):
    r = ppm_core.Renderer(build(), photons_per_pass=100_000, threads=2, seed=1, **settings)
    r.run(passes=1)  # eye pass and first pass excluded
    start = time.perf_counter()
    r.run(passes=passes)
    r.image()  # the POST blur runs here
    return (time.perf_counter() - start) / passes, r.stats()["skipped"], r.image()


def main():
    print("| scene | s/pass, analysis on | s/pass, analysis off | same image | skipped (on) |")
    print("|---|---|---|---|---|")
    for name, build, settings in CASES:
        on, skipped, img_on = time_per_pass(build, **settings)
        off, _, img_off = time_per_pass(build, scene_analysis=False, **settings)
        same = np.allclose(img_on, img_off, rtol=0.05, atol=1e-3) or "no (noise)"
        listed = "; ".join(s for s in skipped if not s.startswith("hit points"))
        print(f"| {name} | {on:.3f} | {off:.3f} | {same} | {listed} |", flush=True)


if __name__ == "__main__":
    main()
