"""Ablations at equal time: each setting of the PPM core against its alternatives.

    .venv/bin/python bench/ablations.py [--quick] [--budget S] [--seeds N] [--p-budgets S ...]
    .venv/bin/python bench/ablations.py --make-references [--reference-passes N]

Core API (no Blender), 160x120, 50,000 photons per pass (the photon density of
the add-on's 200,000 at 320x240), 2 threads, on two scenes of
blend_scenes/core_scenes.py: `cornell_3spheres` (glass and mirror spheres, a
small sphere light: caustics) and `cornell_diffuse` (diffuse only, a square
area light). Every render gets the same wall time (`run(seconds=budget)`,
default 6 s, after the Renderer is built) and is compared with a stored
reference, bench/references/core_{scene}.exr: the mean of two stochastic-hit-
point renders of N passes each (default 1500, seeds 1001 and 1002), made by
--make-references (about 15 minutes on the 2-core machine).

Errors (mean over seeds, with the spread min-max):
- rel. MSE: per pixel and channel, (x - r)^2 / (r^2 + 0.01), every pixel;
- block rel. RMSE: relative RMSE of 4x4 block means, blocks that see the light
  left out (bench/defaults.py's measure: what the photon estimate controls,
  without the anti-aliasing noise of different eye samples).

Tables: alpha and the threshold P at equal time and at equal pass counts
(load-independent; both cost the same per pass, see the passes column), P at
several budgets; quantile vs hash grid; the
grid organising photons vs hit points; direct light by light sampling vs by
photons; fixed (PPM) vs stochastic (SPPM) hit points; and the time per pass
with the scene analysis on and off on diffuse scenes (no specular surface, no
depth of field, no revolve object). The baseline is the core's defaults
(alpha 0.7, P 10, quantile grid of photons, sampled direct light, fixed hit
points); each table varies one setting. The same seed gives every setting the
same fixed eye samples, so compare settings seed by seed (the column "rel. MSE
/ default's" does): the spread between seeds is mostly those eye samples
(anti-aliasing at the light's reflections).
The grid and the gather organisation change only the speed: a pass count and a
seed give the same estimate. Full run: about 12 minutes. --quick: 1.5 s
budgets, one seed, about a minute (checks the script, figures are noise).
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "blend_scenes"))
sys.path.insert(0, HERE)
from exr_io import read_exr, write_exr  # noqa: E402

import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H = 160, 120
PHOTONS = 50_000
SCENES = {"cornell_3spheres": core_scenes.cornell_3spheres, "cornell_diffuse": core_scenes.cornell_diffuse}
REF_DIR = os.path.join(HERE, "references")
REF_SEEDS = (1001, 1002)
BASELINE = {"alpha": 0.7, "threshold": 10, "grid": "quantile", "gather": "photons", "direct_light": "sampled",
            "hit_points": "fixed"}


def reference_path(scene):
    return os.path.join(REF_DIR, f"core_{scene}.exr")


def make_references(passes):
    for scene in SCENES:
        start = time.perf_counter()
        halves = []
        for seed in REF_SEEDS:
            r = ppm_core.Renderer(SCENES[scene](W, H), threads=2, seed=seed, photons_per_pass=PHOTONS,
                                  hit_points="stochastic")
            r.run(passes=passes)
            halves.append(r.image()[..., :3])
        ref = 0.5 * (halves[0] + halves[1])
        noise = float(np.mean((halves[0] - halves[1]) ** 2 / 4.0 / (ref ** 2 + 0.01)))
        seconds = time.perf_counter() - start
        write_exr(reference_path(scene), ref, {"passes_per_half": passes, "seeds": list(REF_SEEDS),
                                               "photons_per_pass": PHOTONS, "hit_points": "stochastic",
                                               "threads": 2, "seconds": round(seconds), "rel_mse_noise": noise})
        print(f"{scene}: 2 x {passes} passes in {seconds:.0f} s, own noise rel. MSE {noise:.2e} "
              f"-> {reference_path(scene)}", flush=True)


def blocks(image, k=4):
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


class Measure:
    """Errors of images against one scene's reference."""

    def __init__(self, scene):
        self.ref, self.meta = read_exr(reference_path(scene))
        b = blocks(self.ref)
        self.keep = b.max(axis=-1) < 10.0 * np.median(b)  # blocks without the visible light
        self.ref_blocks = b

    def __call__(self, image):
        rel_mse = float(np.mean((image - self.ref) ** 2 / (self.ref ** 2 + 0.01)))
        a, b = blocks(image)[self.keep], self.ref_blocks[self.keep]
        return rel_mse, float(np.sqrt(np.mean((a - b) ** 2)) / np.mean(b))


class Passes:
    """A budget of a number of passes instead of seconds (load-independent; for settings that do not change
    the cost of a pass)."""

    def __init__(self, n):
        self.n = n

    def __repr__(self):
        return f"{self.n} passes"

    def __eq__(self, other):
        return isinstance(other, Passes) and other.n == self.n

    def __hash__(self):
        return hash(("passes", self.n))


def budget_label(budget):
    return repr(budget) if isinstance(budget, Passes) else f"{budget:g} s"


class Runner:
    """Renders and caches (scene, settings, seed, budget) -> (rel. MSE, block rel. RMSE, passes)."""

    def __init__(self):
        self.cache = {}
        self.measures = {}

    def error(self, scene, budget, seed, **changes):
        settings = dict(BASELINE, **changes)
        key = (scene, budget, seed, tuple(sorted(settings.items())))
        if key not in self.cache:
            if scene not in self.measures:
                self.measures[scene] = Measure(scene)
            r = ppm_core.Renderer(SCENES[scene](W, H), threads=2, seed=seed, photons_per_pass=PHOTONS, **settings)
            if isinstance(budget, Passes):
                r.run(passes=budget.n)
            else:
                r.run(seconds=budget)
            self.cache[key] = (*self.measures[scene](r.image()[..., :3]), r.stats()["passes"])
        return self.cache[key]


def table(runner, title, column, values, scenes, budgets, seeds, label=str):
    print(f"\n### {title}\n")
    print(f"| scene | budget | {column} | passes | rel. MSE (min-max) | rel. MSE / default's, same seed | "
          "block rel. RMSE (min-max) |")
    print("|---|---|---|---|---|---|---|")
    for scene in scenes:
        for budget in budgets:
            for value in values:
                rows = [runner.error(scene, budget, seed, **{column: value}) for seed in seeds]
                m, b, p = (np.array(x) for x in zip(*rows))
                default = np.array([runner.error(scene, budget, seed)[0] for seed in seeds])
                print(f"| {scene} | {budget_label(budget)} | {label(value)} | {p.mean():.0f} | {m.mean():.4f} "
                      f"({m.min():.4f}-{m.max():.4f}) | {np.mean(m / default):.3f} | "
                      f"{b.mean():.4f} ({b.min():.4f}-{b.max():.4f}) |", flush=True)


def seconds_per_pass(scene, analysis, passes):
    r = ppm_core.Renderer(scene, threads=2, seed=1, photons_per_pass=PHOTONS, scene_analysis=analysis)
    r.run(passes=2)  # eye pass and first index build not timed
    start = time.perf_counter()
    r.run(passes=passes)
    return (time.perf_counter() - start) / passes


def analysis_table(passes, repeats):
    print("\n### Scene analysis on and off (time per pass after the first two)\n")
    print("| scene | s/pass, on | s/pass, off | off/on |")
    print("|---|---|---|---|")
    scenes = {"cornell_diffuse (area light)": lambda: core_scenes.cornell_diffuse(W, H),
              "cornell_diffuse (point light)": lambda: core_scenes.cornell_diffuse(W, H, light="point")}
    for label, build in scenes.items():
        on, off = [], []
        for _ in range(repeats):  # alternate, so that load changes hit both alike
            on.append(seconds_per_pass(build(), True, passes))
            off.append(seconds_per_pass(build(), False, passes))
        print(f"| {label} | {min(on):.4f} | {min(off):.4f} | {min(off) / min(on):.2f} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--budget", type=float, default=6.0)
    parser.add_argument("--p-budgets", type=float, nargs="+", default=[2.0, 6.0])
    parser.add_argument("--passes", type=int, nargs="+", default=[20, 200], help="equal-pass budgets (alpha, P)")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--make-references", action="store_true")
    parser.add_argument("--reference-passes", type=int, default=1500)
    args = parser.parse_args()
    if args.make_references:
        make_references(args.reference_passes)
        return
    if args.quick:
        args.budget, args.p_budgets, args.seeds, args.passes = 1.5, [1.0, 3.0], 1, [5, 20]
    budget, seeds = args.budget, list(range(1, args.seeds + 1))
    start = time.perf_counter()
    runner = Runner()
    both = list(SCENES)
    print(f"160x120, {PHOTONS} photons per pass, 2 threads, seeds {seeds}; references: "
          + ", ".join(f"{s} {2 * Measure(s).meta.get('passes_per_half', 0)} passes "
                      f"(own rel. MSE {Measure(s).meta.get('rel_mse_noise', float('nan')):.1e})" for s in both))
    alphas = [0.5, 2 / 3, 0.7, 0.8]
    table(runner, "alpha, equal time", "alpha", alphas, both, [budget], seeds, label=lambda a: f"{a:.3f}")
    table(runner, "alpha, equal passes", "alpha", alphas, ["cornell_3spheres"], [Passes(n) for n in args.passes],
          seeds[:2], label=lambda a: f"{a:.3f}")
    p_budgets = sorted(set(args.p_budgets) | {budget})
    table(runner, "Threshold P (1 = classic PPM), equal time", "threshold", [1, 3, 10, 30], ["cornell_3spheres"],
          p_budgets, seeds)
    table(runner, "Threshold P, equal passes", "threshold", [1, 3, 10, 30], ["cornell_3spheres"],
          [Passes(n) for n in args.passes], seeds[:2])
    table(runner, "Threshold P, diffuse scene, equal time", "threshold", [1, 3, 10, 30], ["cornell_diffuse"], [budget],
          seeds)
    table(runner, "Quantile vs hashed uniform grid", "grid", ["quantile", "hash"], both, [budget], seeds)
    table(runner, "Grid organises photons vs hit points", "gather", ["photons", "hit_points"], both, [budget], seeds)
    table(runner, "Direct light: light sampling vs photons", "direct_light", ["sampled", "photons"], both, [budget],
          seeds)
    table(runner, "Fixed (PPM) vs stochastic (SPPM) hit points", "hit_points", ["fixed", "stochastic"], both,
          [budget], seeds)
    analysis_table(5 if args.quick else 20, 1 if args.quick else 3)
    print(f"\ntotal {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
