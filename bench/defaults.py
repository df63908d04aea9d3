"""Measures the defaults the core ships with: alpha and the threshold P.

    .venv/bin/python bench/defaults.py [--seconds S] [--reference-seconds R]

Renders cornell_3spheres at 160x120: a long reference (alpha 0.7, P 10,
different seed), then each candidate for a fixed wall time, and prints the
relative RMSE against the reference (mean over 3 seeds). Lower is better.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H = 160, 120


def render(seconds, seed, **settings):
    r = ppm_core.Renderer(core_scenes.cornell_3spheres(W, H), threads=2, seed=seed,
                          photons_per_pass=50_000, **settings)
    r.run(seconds=seconds)
    return r.image()[..., :3]


def rel_rmse(image, reference):
    return float(np.sqrt(np.mean((image - reference) ** 2)) / np.mean(reference))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--seconds", type=float, default=8.0)
    p.add_argument("--reference-seconds", type=float, default=240.0)
    args = p.parse_args()
    reference = render(args.reference_seconds, 1000, alpha=0.7, threshold=10)
    print(f"reference: {args.reference_seconds:.0f} s; candidates: {args.seconds:.0f} s each, 3 seeds\n")
    print("| alpha | P | relative RMSE |")
    print("|---|---|---|")
    for alpha in (0.5, 2 / 3, 0.7, 0.8):
        for threshold in (1, 10):
            errors = [rel_rmse(render(args.seconds, seed, alpha=alpha, threshold=threshold), reference)
                      for seed in (1, 2, 3)]
            print(f"| {alpha:.3f} | {threshold} | {np.mean(errors):.4f} |", flush=True)


if __name__ == "__main__":
    main()
