"""What the scene analysis saves: time per pass with it on and off.

    .venv/bin/python bench/skips.py [--passes 6] [--repeats 3]

Each row is a scene built to need less work; `scene_analysis=False` makes the
core do the full work anyway. Prints a markdown table and what stats() listed.
"""

from __future__ import annotations

import argparse
import os
import statistics
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


def cornell_no_revolve(**_):
    """The glass/mirror Cornell box: triangles and spheres, no revolve object, no DoF asked for."""
    return core_scenes.cornell_3spheres(W, H)


def zero_power_lights(**_):
    """The diffuse box with its point light and 200 lights switched off (power 0): points, spheres and panels."""
    scene = diffuse_box_point_light()
    rng = np.random.default_rng(3)
    for i in range(200):
        position = tuple(rng.uniform((-0.9, -0.9, 0.1), (0.9, 0.9, 1.9)))
        kind = ("point", "sphere", "rectangle")[i % 3]
        extra = {"radius": 0.05} if kind == "sphere" else {"size": (0.2, 0.2)} if kind == "rectangle" else {}
        scene.add_light(kind, name=f"off{i}", power=0.0, position=position, direction=(0.0, 0.0, -1.0), **extra)
    return scene


def mostly_background(**_):
    """One diffuse sphere on a black background, filling about 3% of the frame."""
    scene = ppm_core.Scene()
    white = scene.add_material("white", "diffuse", base_color=0.8)
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 0.25, white)
    scene.add_light("sun", name="sun", power=3.0, direction=(-0.3, 0.4, -1.0))
    scene.set_camera(core_scenes.look_at((0.0, -6.0, 0.0), (0.0, 0.0, 0.0)), W, H, fov=0.8)
    return scene


# (name, builder, settings). Each runs with the analysis on and off.
CASES = [
    ("diffuse box, point light", diffuse_box_point_light, {}),
    ("emission only", emission_only, {}),
    ("DoF POST, CoC < 1 px", cornell_tiny_aperture, {"dof_mode": "post"}),
    ("no DoF asked for, no revolve objects", cornell_no_revolve, {}),
    ("diffuse box + 200 zero-power lights", zero_power_lights, {}),
    ("97% of pixels see background", mostly_background, {}),
]
# A feature a scene does not use must cost nothing: the same scene without it, for comparison.
BASELINES = [
    ("diffuse box + 200 zero-power lights", "diffuse box, point light"),
]


def time_per_pass(build, passes, repeats=3, **settings):
    """Median over `repeats` renderers of the mean time per pass (eye pass and first pass excluded)."""
    times = []
    for _ in range(repeats):
        r = ppm_core.Renderer(build(), photons_per_pass=100_000, threads=2, seed=1, **settings)
        r.run(passes=1)
        start = time.perf_counter()
        r.run(passes=passes)
        r.image()  # the POST blur runs here
        times.append((time.perf_counter() - start) / passes)
    stats = r.stats()
    return statistics.median(times), (min(times), max(times)), stats, r.image()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--passes", type=int, default=6)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print(f"{W}x{H}, 100,000 photons per pass, 2 threads; median of {args.repeats} runs of {args.passes} passes "
          "(range in brackets)\n")
    print("| scene | hit points | s/pass, analysis on | s/pass, analysis off | same image | skipped (on) |")
    print("|---|---|---|---|---|---|")
    on_times = {}
    for name, build, settings in CASES:
        on, on_range, stats, img_on = time_per_pass(build, args.passes, args.repeats, **settings)
        off, off_range, _, img_off = time_per_pass(build, args.passes, args.repeats, scene_analysis=False, **settings)
        on_times[name] = (on, on_range)
        same = np.allclose(img_on, img_off, rtol=0.05, atol=1e-3) or "no (noise)"
        listed = "; ".join(s for s in stats["skipped"] if not s.startswith("hit points")) or "nothing"
        print(f"| {name} | {stats['hit_points']} | {on:.3f} [{on_range[0]:.3f}-{on_range[1]:.3f}] | "
              f"{off:.3f} [{off_range[0]:.3f}-{off_range[1]:.3f}] | {same} | {listed} |", flush=True)
    print("\n| scene | s/pass | the same without the unused feature | s/pass |")
    print("|---|---|---|---|")
    for name, baseline in BASELINES:
        (a, ar), (b, br) = on_times[name], on_times[baseline]
        print(f"| {name} | {a:.3f} [{ar[0]:.3f}-{ar[1]:.3f}] | {baseline} | {b:.3f} [{br[0]:.3f}-{br[1]:.3f}] |")


if __name__ == "__main__":
    main()
