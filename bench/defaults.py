"""Measures the defaults the core ships with: alpha and the threshold P.

    .venv/bin/python bench/defaults.py [--seconds S] [--reference-seconds R]

Renders cornell_3spheres at 160x120: a long reference (alpha 0.7, P 10,
different seed), then each candidate for a fixed wall time, and prints the
relative RMSE of 4x4 block means against the reference, light pixels masked
(mean over seeds). Lower is better.
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


def blocks(image, k=4):
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


def rel_rmse(image, reference):
    """Relative RMSE of 4x4 block means, leaving out blocks that see the light.

    Different seeds jitter the eye samples differently, so single pixels on
    edges (worst: the visible light, radiance ~250) differ by anti-aliasing
    noise that no number of photon passes removes; block means and the mask
    keep the measure on the photon estimate that alpha and P control."""
    a, b = blocks(image), blocks(reference)
    keep = b.max(axis=-1) < 10.0 * np.median(b)
    return float(np.sqrt(np.mean((a[keep] - b[keep]) ** 2)) / np.mean(b[keep]))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--seconds", type=float, default=5.0)
    p.add_argument("--reference-seconds", type=float, default=90.0)
    p.add_argument("--seeds", type=int, default=2)
    args = p.parse_args()
    reference = render(args.reference_seconds, 1000, alpha=0.7, threshold=10)
    seeds = range(1, args.seeds + 1)
    print(f"reference: {args.reference_seconds:.0f} s; candidates: {args.seconds:.0f} s each, {args.seeds} seeds\n")
    print("| alpha | P | relative RMSE |")
    print("|---|---|---|")
    for alpha in (0.5, 2 / 3, 0.7, 0.8):
        for threshold in (1, 10):
            errors = [rel_rmse(render(args.seconds, seed, alpha=alpha, threshold=threshold), reference)
                      for seed in seeds]
            print(f"| {alpha:.3f} | {threshold} | {np.mean(errors):.4f} |", flush=True)


if __name__ == "__main__":
    main()
