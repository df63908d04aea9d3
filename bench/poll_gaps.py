"""Seconds between progress callbacks during photon passes of 2 M photons (the Cornell box at
640x480), for both hit-point modes and both gather organisations. The README promises a callback
about every `progress_interval` (0.1 s): it is where Esc is noticed.

    .venv/bin/python bench/poll_gaps.py [--photons 2000000] [--passes 2]
"""

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "blend_scenes"))

import core_scenes
import ppm_core


def gaps(mode, gather, photons, passes):
    renderer = ppm_core.Renderer(core_scenes.cornell_3spheres(), photons_per_pass=photons, hit_points=mode,
                                 gather=gather, seed=1)
    renderer.run(passes=1)  # the eye pass and the first pass, outside the measurement
    times = [time.perf_counter()]
    renderer.run(passes=passes, callback=lambda info: times.append(time.perf_counter()) or True)
    return sorted(b - a for a, b in zip(times, times[1:]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--photons", type=int, default=2_000_000)
    parser.add_argument("--passes", type=int, default=2)
    args = parser.parse_args()
    for mode in ("fixed", "stochastic"):
        for gather in ("photons", "hit_points"):
            g = gaps(mode, gather, args.photons, args.passes)
            print(f"poll_gaps: {mode:10s} gather={gather:10s} {len(g)} gaps, median {g[len(g) // 2]:.3f} s, "
                  f"95th percentile {g[int(0.95 * len(g))]:.3f} s, max {g[-1]:.3f} s")


if __name__ == "__main__":
    main()
