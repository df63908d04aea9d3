"""What the scene analysis saves: time per pass with it on and off.

    .venv/bin/python bench/run.py skips [--quick] [--set 'parts=["skips"]']

Parts (the list `parts`):
- skips: scenes built to need less work, at 320x240, 100,000 photons per pass, 2 threads; each
  runs with the analysis on and with `scene_analysis=False`, which makes the core do the full work
  anyway: the median over `repeats` renderers of the time per pass of `passes` passes (the eye
  pass and the first pass left out), whether the two images agree and what stats() listed as
  skipped; then a scene with an unused feature against the same scene without it (the feature
  must cost nothing);
- analysis: the diffuse Cornell box (cornell_diffuse, area light and point light) at 160x120,
  50,000 photons per pass, 2 threads, with the analysis on and off: the best over
  `analysis_repeats` of the time per pass of `analysis_passes` passes after the first two.
"""

from __future__ import annotations

import statistics
import time

import numpy as np

import core_scenes
import ppm_core
from harness.core_route import build_scene

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


def with_range(seconds, spread):
    return f"{seconds:.3f} [{spread[0]:.3f}-{spread[1]:.3f}]"


def skips_part(experiment, results):
    passes, repeats = experiment["passes"], experiment["repeats"]
    results.note(f"\n{W}x{H}, 100,000 photons per pass, 2 threads; median of {repeats} runs of {passes} passes "
                 "(range in brackets)")
    rows, on_times = [], {}
    for name, build, settings in CASES:
        on, on_range, stats, img_on = time_per_pass(build, passes, repeats, **settings)
        off, off_range, _, img_off = time_per_pass(build, passes, repeats, scene_analysis=False, **settings)
        on_times[name] = (on, on_range)
        # A yes/no tolerance check, as the old table had it; not an error measure.
        same = "True" if np.allclose(img_on, img_off, rtol=0.05, atol=1e-3) else "no (noise)"
        listed = "; ".join(s for s in stats["skipped"] if not s.startswith("hit points")) or "nothing"
        results.row(part="skips", scene=name, hit_points=stats["hit_points"], on=on, on_range=on_range, off=off,
                    off_range=off_range, same_image=same, skipped=listed)
        rows.append([name, str(stats["hit_points"]), with_range(on, on_range), with_range(off, off_range), same,
                     listed])
    results.table(["scene", "hit points", "s/pass, analysis on", "s/pass, analysis off", "same image",
                   "skipped (on)"], rows)
    results.table(["scene", "s/pass", "the same without the unused feature", "s/pass"],
                  [[name, with_range(*on_times[name]), baseline, with_range(*on_times[baseline])]
                   for name, baseline in BASELINES])


# The analysis part: the ablations' image size and photon density.
ANALYSIS_W, ANALYSIS_H, ANALYSIS_PHOTONS = 160, 120, 50_000


def seconds_per_pass(scene_args, analysis, passes):
    scene = build_scene("cornell_diffuse", ANALYSIS_W, ANALYSIS_H, **scene_args)
    r = ppm_core.Renderer(scene, threads=2, seed=1, photons_per_pass=ANALYSIS_PHOTONS, scene_analysis=analysis)
    r.run(passes=2)  # eye pass and first index build not timed
    start = time.perf_counter()
    r.run(passes=passes)
    return (time.perf_counter() - start) / passes


def analysis_part(experiment, results):
    passes = experiment["analysis_passes"]
    scenes = {"cornell_diffuse (area light)": {}, "cornell_diffuse (point light)": {"light": "point"}}
    rows = []
    for label, scene_args in scenes.items():
        on, off = [], []
        for _ in range(experiment["analysis_repeats"]):  # alternate, so that load changes hit both alike
            on.append(seconds_per_pass(scene_args, True, passes))
            off.append(seconds_per_pass(scene_args, False, passes))
        results.row(part="analysis", scene=label, on=min(on), off=min(off))
        rows.append([label, f"{min(on):.4f}", f"{min(off):.4f}", f"{min(off) / min(on):.2f}"])
    results.table(["scene", "s/pass, on", "s/pass, off", "off/on"], rows,
                  title=f"Scene analysis on and off ({ANALYSIS_W}x{ANALYSIS_H}, {ANALYSIS_PHOTONS:,} photons per "
                        "pass, 2 threads; time per pass after the first two)")


# In this order, whatever the order of `parts`.
PARTS = {"skips": skips_part, "analysis": analysis_part}


def run(experiment, results):
    unknown = set(experiment["parts"]) - set(PARTS)
    if unknown:
        raise SystemExit(f"unknown parts {sorted(unknown)}; there are: {', '.join(PARTS)}")
    for name, part in PARTS.items():
        if name in experiment["parts"]:
            part(experiment, results)
