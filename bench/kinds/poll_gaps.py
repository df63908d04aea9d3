"""Seconds between progress callbacks during photon passes of `photons` photons (default 2 M; the
Cornell box cornell_3spheres at 640x480, the renderer's default threads), for both hit-point modes
and both gather organisations, over `passes` passes after the first. The README promises a callback
about every `progress_interval` (0.1 s): it is where Esc is noticed.

    .venv/bin/python bench/run.py poll_gaps [--quick] [--set photons=2000000] [--set passes=2]
"""

from __future__ import annotations

import time

import ppm_core
from harness.core_route import build_scene


def gaps(mode, gather, photons, passes):
    renderer = ppm_core.Renderer(build_scene("cornell_3spheres", 640, 480), photons_per_pass=photons,
                                 hit_points=mode, gather=gather, seed=1)
    renderer.run(passes=1)  # the eye pass and the first pass, outside the measurement
    times = [time.perf_counter()]
    renderer.run(passes=passes, callback=lambda info: times.append(time.perf_counter()) or True)
    return sorted(b - a for a, b in zip(times, times[1:]))


def run(experiment, results):
    rows = []
    for mode in ("fixed", "stochastic"):
        for gather in ("photons", "hit_points"):
            g = gaps(mode, gather, experiment["photons"], experiment["passes"])
            median, p95, worst = g[len(g) // 2], g[int(0.95 * len(g))], g[-1]
            results.row(hit_points=mode, gather=gather, gaps=len(g), median=median, p95=p95, max=worst)
            rows.append([mode, gather, str(len(g)), f"{median:.3f}", f"{p95:.3f}", f"{worst:.3f}"])
    results.table(["hit points", "gather", "gaps", "median s", "95th percentile s", "max s"], rows,
                  title=f"Seconds between progress callbacks, {experiment['photons']:,} photons per pass")
