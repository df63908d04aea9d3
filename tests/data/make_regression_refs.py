"""Makes the stored references of the regression guard (tests/core/test_regression.py).

    .venv/bin/python tests/data/make_regression_refs.py [--passes N] [--quick]

For each guarded scene (blend_scenes/core_scenes.py at 80x60): two independent
long renders through the core API, seeds 1001 and 1002, N passes each
(default 2000) of 50,000 photons, 2 threads, stochastic hit points (new eye
samples every pass, so anti-aliasing converges too), averaged and stored as
tests/data/regression_{scene}.npy (float32, (60, 80, 3), rows top-first). The
two halves' difference estimates the reference's own noise, printed at the
end (relative MSE, eps = 0.01, as in the test). A pass count and seeds fix
the result for a thread count, so machine load does not change it.

Made on 2026-11-22 with the default N: about 20 minutes on the 2-core machine
while other jobs were running. Rerun it (and re-measure the bounds in the test,
see its docstring) only when the renderer's answer is meant to change.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H = 80, 60
SCENES = {"cornell_3spheres": core_scenes.cornell_3spheres, "cornell_diffuse": core_scenes.cornell_diffuse}
SEEDS = (1001, 1002)
PHOTONS = 50_000


def render(name, passes, seed):
    r = ppm_core.Renderer(SCENES[name](W, H), photons_per_pass=PHOTONS, threads=2, seed=seed,
                          hit_points="stochastic")
    r.run(passes=passes)
    return r.image()[..., :3].astype(np.float32)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--passes", type=int, default=2000)
    parser.add_argument("--quick", action="store_true", help="20 passes, written to /tmp (checks the script)")
    args = parser.parse_args()
    out_dir = "/tmp" if args.quick else HERE
    passes = 20 if args.quick else args.passes
    for name in SCENES:
        start = time.perf_counter()
        a, b = (render(name, passes, seed) for seed in SEEDS)
        reference = 0.5 * (a + b)
        noise = float(np.mean((a - b) ** 2 / 4.0 / (reference ** 2 + 0.01)))
        path = os.path.join(out_dir, f"regression_{name}.npy")
        np.save(path, reference)
        print(f"{name}: 2 x {passes} passes in {time.perf_counter() - start:.0f} s -> {path}; "
              f"own noise, relative MSE: {noise:.2e}", flush=True)


if __name__ == "__main__":
    main()
