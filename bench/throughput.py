"""Core throughput on the Cornell box with a glass and a mirror sphere at 640x480.

    .venv/bin/python bench/throughput.py [--quick] [--parts eye photons variants memory large]

Prints markdown tables:
- eye: eye rays per second of the eye pass on 1 and 2 threads (median of 3);
- photons: photon paths per second including the index build and the gather
  into the hit points, with the default settings, on 1 and 2 threads, and the
  time per pass of each step (each the median of --repeats runs);
- variants: the other gather organisation and grid, on 2 threads;
- memory: resident memory after passes 1, 100, 1,000 and 10,000 of a smaller
  render (160x120, 2,000 photons per pass, so 10,000 passes take about two
  minutes), in a fresh process so the peak is its own;
- large: photon tracing alone (no index, no gather) on a scene whose BVH does
  not fit in the caches: the 10^6-triangle terrain of bench/raycast.py under a
  point light, 100,000 photons per pass, 1 and 2 threads (median of --repeats).
  This is where photons are traced in waves (see engine/ppm/photon_tracer.h).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H = 640, 480
STEPS = ("photon_trace", "index_build", "gather", "direct_light", "progressive_update")


def proc_status_mb(field: str) -> float:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024
    raise RuntimeError(f"{field} not in /proc/self/status")


def eye_rays_per_second(threads, spp=4, repeats=3):
    rates = []
    for _ in range(repeats):
        r = ppm_core.Renderer(core_scenes.cornell_3spheres(W, H), threads=threads, photons_per_pass=1,
                              samples_per_pixel=spp)
        r.run(passes=1)
        rates.append(W * H * spp / r.stats()["seconds"]["eye_pass"])
    return statistics.median(rates)


def photon_throughput(threads, photons, passes, **settings):
    r = ppm_core.Renderer(core_scenes.cornell_3spheres(W, H), threads=threads, photons_per_pass=photons,
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


def large_scene():
    """The terrain of bench/raycast.py (10^6 triangles) under a point light."""
    import numpy as np
    import raycast

    vertices, tris = raycast.terrain(600, 280_000, np.random.default_rng(raycast.SEED))
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


def median_run(runs):
    """Per figure, the median over runs of photon_throughput."""
    return {"paths_per_s": statistics.median(r["paths_per_s"] for r in runs),
            "wall_per_pass": statistics.median(r["wall_per_pass"] for r in runs),
            "step": {k: statistics.median(r["step"][k] for r in runs) for k in STEPS},
            "hit_points": runs[0]["hit_points"]}


def memory_child(marks):
    """Runs in its own process: one renderer for max(marks) passes."""
    r = ppm_core.Renderer(core_scenes.cornell_3spheres(160, 120), threads=2, photons_per_pass=2_000, seed=5)
    done, start = 0, time.perf_counter()
    for target in marks:
        r.run(passes=target - done)
        done = target
        s = r.stats()
        print(f"| {target} | {proc_status_mb('VmRSS'):.1f} | {proc_status_mb('VmHWM'):.1f} | "
              f"{s['memory_bytes'] / 2**20:.2f} | {s['radius_mean']:.3e} | {time.perf_counter() - start:.0f} |",
              flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="fewer passes (a smoke run)")
    parser.add_argument("--parts", nargs="+", default=["eye", "photons", "variants", "memory", "large"],
                        choices=["eye", "photons", "variants", "memory", "large"])
    parser.add_argument("--repeats", type=int, default=3, help="photon runs per thread count (median)")
    parser.add_argument("--memory-child", nargs="+", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_child:
        memory_child(args.memory_child)
        return
    photons, passes = (50_000, 2) if args.quick else (200_000, 6)
    if args.quick:
        args.repeats = 1
    print(f"machine: {os.cpu_count()} cores; cornell_3spheres {W}x{H}; {photons} photons per pass, "
          f"{passes} timed passes\n")

    if "eye" in args.parts:
        one, two = eye_rays_per_second(1), eye_rays_per_second(2)
        print("| threads | eye rays/s (4 spp, incl. specular chains) |")
        print("|---|---|")
        print(f"| 1 | {one / 1e6:.2f} M |")
        print(f"| 2 | {two / 1e6:.2f} M |")
        print(f"\neye pass scaling 1 -> 2 threads: {two / one:.2f}x\n", flush=True)

    if "photons" in args.parts:
        # Median of `repeats` runs, alternating 1 and 2 threads so that a slow spell of a shared
        # machine does not land on one thread count only; single runs varied by up to 10%.
        runs = {1: [], 2: []}
        for _ in range(args.repeats):
            for t in (1, 2):
                runs[t].append(photon_throughput(t, photons, passes))
        rows = {t: median_run(rs) for t, rs in runs.items()}
        print(f"hit points: {rows[1]['hit_points']}\n")
        print("| threads | photon paths/s (trace + index + gather) | s/pass | " + " | ".join(STEPS) + " |")
        print("|---|---|---|" + "---|" * len(STEPS))
        for t, r in rows.items():
            steps = " | ".join(f"{r['step'][k]:.3f}" for k in STEPS)
            print(f"| {t} | {r['paths_per_s'] / 1e6:.3f} M | {r['wall_per_pass']:.3f} | {steps} |")
        scaling = rows[2]["paths_per_s"] / rows[1]["paths_per_s"]
        per_step = ", ".join(f"{k} {rows[1]['step'][k] / max(rows[2]['step'][k], 1e-9):.2f}x" for k in STEPS)
        print(f"\nphoton pass scaling 1 -> 2 threads: {scaling:.2f}x; per step: {per_step}\n", flush=True)

    if "variants" in args.parts:
        print("| gather organisation | grid | photon paths/s, 2 threads | s/pass |")
        print("|---|---|---|---|")
        for gather in ("photons", "hit_points"):
            for grid in ("quantile", "hash"):
                r = photon_throughput(2, photons, passes, gather=gather, grid=grid)
                print(f"| {gather} | {grid} | {r['paths_per_s'] / 1e6:.3f} M | {r['wall_per_pass']:.3f} |", flush=True)
        print()

    if "large" in args.parts:
        scene = large_scene()
        print("| threads | photon_trace s/pass, 10^6-triangle terrain, 100,000 photons |")
        print("|---|---|")
        for t in (1, 2):
            print(f"| {t} | {statistics.median(large_trace_seconds(scene, t) for _ in range(args.repeats)):.3f} |",
                  flush=True)
        print()

    if "memory" in args.parts:
        marks = [1, 10, 100] if args.quick else [1, 100, 1000, 10000]
        print("| after pass | resident MB | peak resident MB | core-reported MB | mean radius | seconds |")
        print("|---|---|---|---|---|---|", flush=True)
        subprocess.run([sys.executable, os.path.abspath(__file__), "--memory-child", *map(str, marks)], check=True)


if __name__ == "__main__":
    main()
