"""Core throughput on the Cornell box with a glass and a mirror sphere at 640x480.

    .venv/bin/python bench/throughput.py [--quick]

Reports, for 1 and 2 threads: eye rays per second (eye pass), photon paths
per second including the gather into hit points, for each gather organisation
(hit points indexed / photons indexed) and each grid (quantile / hash); and
resident memory after pass 1 and pass 1000. Prints markdown tables.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402


def rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def photon_throughput(threads, gather, grid, photons, passes):
    scene = core_scenes.cornell_3spheres(640, 480)
    r = ppm_core.Renderer(scene, threads=threads, photons_per_pass=photons, gather=gather, grid=grid,
                          direct_light="sampled")
    r.run(passes=1)  # eye pass + first pass (index build) not timed below
    s0 = r.stats()
    start = time.perf_counter()
    r.run(passes=passes)
    wall = time.perf_counter() - start
    s1 = r.stats()
    photon_s = sum(s1["seconds"][k] - s0["seconds"][k] for k in ("photon_trace", "index_build", "gather"))
    return {
        "paths_per_s": (s1["photons_emitted"] - s0["photons_emitted"]) / photon_s,
        "wall_per_pass": wall / passes,
        "eye_s": s0["seconds"]["eye_pass"],
        "hit_points": s0["hit_points"],
    }


def eye_rays_per_second(threads, spp=4):
    scene = core_scenes.cornell_3spheres(640, 480)
    r = ppm_core.Renderer(scene, threads=threads, photons_per_pass=1, samples_per_pixel=spp)
    r.run(passes=1)
    return 640 * 480 * spp / r.stats()["seconds"]["eye_pass"]


def memory_over_passes(passes_list, photons):
    scene = core_scenes.cornell_3spheres(640, 480)
    r = ppm_core.Renderer(scene, threads=2, photons_per_pass=photons)
    rows, done = [], 0
    for target in passes_list:
        r.run(passes=target - done)
        done = target
        rows.append((target, rss_mb(), r.stats()["memory_bytes"] / 2**20))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return rows, peak


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="fewer passes (for a smoke run)")
    args = parser.parse_args()
    photons, passes = (50_000, 2) if args.quick else (200_000, 5)
    print(f"machine: {os.cpu_count()} cores; {photons} photons per pass, {passes} timed passes\n")

    print("| threads | eye rays/s (4 spp) |")
    print("|---|---|")
    for t in (1, 2):
        print(f"| {t} | {eye_rays_per_second(t) / 1e6:.2f} M |")

    print("\n| threads | gather organisation | grid | photon paths/s (trace + gather) | s per pass |")
    print("|---|---|---|---|---|")
    for gather in ("hit_points", "photons"):
        for grid in ("quantile", "hash"):
            for t in (1, 2):
                r = photon_throughput(t, gather, grid, photons, passes)
                print(f"| {t} | {gather} | {grid} | {r['paths_per_s'] / 1e6:.3f} M | {r['wall_per_pass']:.3f} |",
                      flush=True)

    marks = [1, 10, 100] if args.quick else [1, 100, 1000]
    rows, peak = memory_over_passes(marks, 10_000)
    print("\n| after pass | resident MB | core-reported MB |")
    print("|---|---|---|")
    for p, rss, core in rows:
        print(f"| {p} | {rss:.0f} | {core:.1f} |")
    print(f"\npeak resident: {peak:.0f} MB")


if __name__ == "__main__":
    main()
