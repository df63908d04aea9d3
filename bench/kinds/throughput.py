"""Core throughput on the Cornell box with a glass and a mirror sphere (cornell_3spheres) at 640x480.

    .venv/bin/python bench/run.py throughput [--quick] [--set 'parts=["eye", "photons"]']

Parts (the list `parts`), each a table:
- eye: eye rays per second of the eye pass on 1 and 2 threads (median of `eye_repeats`);
- photons: photon paths per second including the index build and the gather into the hit points,
  for each of `hit_points` (fixed: the core's default, 4 eye samples a pixel kept for the render;
  stochastic: the add-on's AUTO, one new eye sample a pixel each pass), on 1 and 2 threads, and
  the time per pass of each step (each the median of `repeats` runs of `passes` timed passes of
  `photons` photons);
- variants: the other gather organisation and grid, on 2 threads;
- large: photon tracing alone (no index, no gather) on a scene whose BVH does not fit in the
  caches: the 10^6-triangle terrain of the raycast kind under a point light, 100,000 photons per
  pass, 1 and 2 threads (median of `repeats`). This is where photons are traced in waves (see
  engine/ppm/photon_tracer.h);
- memory: resident memory after the passes `memory_marks` (default 1, 100, 1,000 and 10,000) of a
  smaller render (160x120, 2,000 photons per pass, so 10,000 passes take about two minutes), in a
  fresh process so the peak is its own: this module run as `python -m kinds.throughput MARK...`
  from bench/, which prints one JSON row per mark.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

import core_scenes
import ppm_core
from harness.core_route import build_scene
from kinds.raycast import SEED, terrain

W, H = 640, 480
STEPS = ("photon_trace", "index_build", "gather", "direct_light", "progressive_update")
BENCH_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def proc_status_mb(field: str) -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024
    raise RuntimeError(f"{field} not in /proc/self/status")


def eye_rays_per_second(threads, spp=4, repeats=3):
    rates = []
    for _ in range(repeats):
        r = ppm_core.Renderer(build_scene("cornell_3spheres", W, H), threads=threads, photons_per_pass=1,
                              samples_per_pixel=spp)
        r.run(passes=1)
        rates.append(W * H * spp / r.stats()["seconds"]["eye_pass"])
    return statistics.median(rates)


def photon_throughput(threads, photons, passes, **settings):
    r = ppm_core.Renderer(build_scene("cornell_3spheres", W, H), threads=threads, photons_per_pass=photons,
                          direct_light="sampled", **settings)
    r.run(passes=1)  # eye pass and first pass (first index build, buffer growth) not timed
    s0 = r.stats()
    start = time.perf_counter()
    r.run(passes=passes)
    wall = time.perf_counter() - start
    s1 = r.stats()
    step = {k: (s1["seconds"][k] - s0["seconds"][k]) / passes for k in STEPS}
    photon_s = step["photon_trace"] + step["index_build"] + step["gather"]
    return {"paths_per_s": photons / photon_s, "wall_per_pass": wall / passes, "step": step,
            "hit_points": s0["hit_points"]}


def median_run(runs):
    """Per figure, the median over runs of photon_throughput."""
    return {"paths_per_s": statistics.median(r["paths_per_s"] for r in runs),
            "wall_per_pass": statistics.median(r["wall_per_pass"] for r in runs),
            "step": {k: statistics.median(r["step"][k] for r in runs) for k in STEPS},
            "hit_points": runs[0]["hit_points"]}


def large_scene():
    """The raycast kind's terrain (10^6 triangles) under a point light."""
    vertices, tris = terrain(600, 280_000, np.random.default_rng(SEED))
    scene = ppm_core.Scene()
    scene.add_material("ground", base_color=(0.7, 0.7, 0.7))
    scene.add_mesh("terrain", vertices.astype(float), tris)
    lo, hi = vertices.min(0), vertices.max(0)
    centre, size = (lo + hi) / 2, float((hi - lo).max())
    scene.add_light("point", power=1000.0, position=tuple(centre + (0.0, 0.0, size)))
    scene.set_camera(core_scenes.look_at(tuple(centre + (0.0, -size, size)), tuple(centre)), 160, 120)
    return scene


def large_trace_seconds(scene, threads, passes=3):
    r = ppm_core.Renderer(scene, threads=threads, photons_per_pass=100_000, direct_light="sampled", seed=3)
    r.run(passes=1)  # first pass (buffer growth) not timed
    s0 = r.stats()
    r.run(passes=passes)
    return (r.stats()["seconds"]["photon_trace"] - s0["seconds"]["photon_trace"]) / passes


def memory_child(marks):
    """Runs in its own process: one renderer for max(marks) passes, a JSON row on stdout per mark."""
    r = ppm_core.Renderer(build_scene("cornell_3spheres", 160, 120), threads=2, photons_per_pass=2_000, seed=5)
    done, start = 0, time.perf_counter()
    for target in marks:
        r.run(passes=target - done)
        done = target
        s = r.stats()
        print(json.dumps({"after_pass": target, "resident_mb": proc_status_mb("VmRSS"),
                          "peak_resident_mb": proc_status_mb("VmHWM"), "core_mb": s["memory_bytes"] / 2**20,
                          "radius_mean": s["radius_mean"], "seconds": time.perf_counter() - start}), flush=True)


def eye_part(experiment, results):
    repeats = experiment.get("eye_repeats", 3)
    one, two = eye_rays_per_second(1, repeats=repeats), eye_rays_per_second(2, repeats=repeats)
    for threads, rate in ((1, one), (2, two)):
        results.row(part="eye", threads=threads, eye_rays_per_s=rate)
    results.table(["threads", "eye rays/s (4 spp, incl. specular chains)"],
                  [["1", f"{one / 1e6:.2f} M"], ["2", f"{two / 1e6:.2f} M"]])
    results.note(f"\neye pass scaling 1 -> 2 threads: {two / one:.2f}x")


def photons_part(experiment, results):
    photons, passes = experiment["photons"], experiment["passes"]
    rows = []
    for mode in experiment.get("hit_points", ["fixed"]):
        # Median of `repeats` runs, alternating 1 and 2 threads so that a slow spell of a shared
        # machine does not land on one thread count only; single runs varied by up to 10%.
        runs = {1: [], 2: []}
        for _ in range(experiment["repeats"]):
            for t in (1, 2):
                runs[t].append(photon_throughput(t, photons, passes, hit_points=mode))
        medians = {t: median_run(rs) for t, rs in runs.items()}
        results.note(f"\n{mode} hit points: {medians[1]['hit_points']}")
        for t, r in medians.items():
            results.row(part="photons", hit_point_mode=mode, threads=t, paths_per_s=r["paths_per_s"],
                        wall_per_pass=r["wall_per_pass"], hit_points=r["hit_points"], **r["step"])
            rows.append([mode, str(t), f"{r['paths_per_s'] / 1e6:.3f} M", f"{r['wall_per_pass']:.3f}",
                         *(f"{r['step'][k]:.3f}" for k in STEPS)])
        scaling = medians[2]["paths_per_s"] / medians[1]["paths_per_s"]
        per_step = ", ".join(f"{k} {medians[1]['step'][k] / max(medians[2]['step'][k], 1e-9):.2f}x" for k in STEPS)
        results.note(f"{mode}: photon pass scaling 1 -> 2 threads: {scaling:.2f}x; per step: {per_step}")
    results.table(["hit points", "threads", "photon paths/s (trace + index + gather)", "s/pass", *STEPS], rows)


def variants_part(experiment, results):
    rows = []
    for gather in ("photons", "hit_points"):
        for grid in ("quantile", "hash"):
            r = photon_throughput(2, experiment["photons"], experiment["passes"], gather=gather, grid=grid)
            results.row(part="variants", threads=2, gather=gather, grid=grid, paths_per_s=r["paths_per_s"],
                        wall_per_pass=r["wall_per_pass"])
            rows.append([gather, grid, f"{r['paths_per_s'] / 1e6:.3f} M", f"{r['wall_per_pass']:.3f}"])
    results.table(["gather organisation", "grid", "photon paths/s, 2 threads", "s/pass"], rows)


def large_part(experiment, results):
    scene = large_scene()
    rows = []
    for t in (1, 2):
        seconds = statistics.median(large_trace_seconds(scene, t) for _ in range(experiment["repeats"]))
        results.row(part="large", threads=t, photon_trace_per_pass=seconds)
        rows.append([str(t), f"{seconds:.3f}"])
    results.table(["threads", "photon_trace s/pass, 10^6-triangle terrain, 100,000 photons"], rows)


def memory_part(experiment, results):
    # A fresh process, so that its peak resident memory is this render's alone.
    child = subprocess.run([sys.executable, "-m", "kinds.throughput", *map(str, experiment["memory_marks"])],
                           cwd=BENCH_DIR, stdout=subprocess.PIPE, text=True, check=True)
    rows = []
    for line in child.stdout.splitlines():
        m = json.loads(line)
        results.row(part="memory", **m)
        rows.append([str(m["after_pass"]), f"{m['resident_mb']:.1f}", f"{m['peak_resident_mb']:.1f}",
                     f"{m['core_mb']:.2f}", f"{m['radius_mean']:.3e}", f"{m['seconds']:.0f}"])
    results.table(["after pass", "resident MB", "peak resident MB", "core-reported MB", "mean radius", "seconds"],
                  rows)


# In this order, whatever the order of `parts`.
PARTS = {"eye": eye_part, "photons": photons_part, "variants": variants_part, "large": large_part,
         "memory": memory_part}


def run(experiment, results):
    unknown = set(experiment["parts"]) - set(PARTS)
    if unknown:
        raise SystemExit(f"unknown parts {sorted(unknown)}; there are: {', '.join(PARTS)}")
    results.note(f"cornell_3spheres {W}x{H}; {experiment['photons']} photons per pass, "
                 f"{experiment['passes']} timed passes")
    for name, part in PARTS.items():
        if name in experiment["parts"]:
            part(experiment, results)


if __name__ == "__main__":
    # Only the memory part's child process (see memory_part), not a command line for people.
    memory_child([int(mark) for mark in sys.argv[1:]])
