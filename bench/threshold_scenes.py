"""The threshold P of the cross-generation rule on every bundled scene, at equal passes.

    .venv/bin/python bench/threshold_scenes.py [--quick] [--thresholds 1 10 30 100] [--passes 15 60]
                                               [--seeds 1 2 3] [--scenes NAME ...]

bench/ablations.py measures P on two core scenes at 160x120; this is the wider
test behind the default: each blend_scenes/*.blend at 320x240 through the
add-on (200,000 photons per pass, 2 threads, stochastic hit points, the file's
other settings) for a fixed number of passes, against its PPM reference
(bench/references.py). P costs nothing per pass, so equal passes is equal time
and the figures do not depend on the machine's load. Prints, per scene and
budget, the relative MSE of each P (mean over seeds, and each seed's ratio to
P = 10's, so a difference smaller than the seed-to-seed spread shows as
such) and per region. About 10 minutes; --quick: one scene, 4 passes, a minute.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy_common as ac  # noqa: E402

REGIONS = ("caustic", "walls", "glass", "mirror", "emitter")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--thresholds", type=int, nargs="+", default=[1, 10, 30, 100])
    parser.add_argument("--passes", type=int, nargs="+", default=[15, 60])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--scenes", nargs="+", default=list(ac.SCENES), choices=ac.SCENES)
    args = parser.parse_args()
    scenes = args.scenes
    if args.quick:
        scenes, args.passes, args.seeds = scenes[:1], [4], [1]
    if 10 not in args.thresholds:
        parser.error("--thresholds must include 10, the default the others are compared with")
    print("| scene | passes | P | rel. MSE (mean over seeds) | per seed, / P = 10's | " + " | ".join(REGIONS) + " |")
    print("|---|---|---|---|---|" + "---|" * len(REGIONS), flush=True)
    for name in scenes:
        ref, meta = ac.load_reference(name)
        masks = ac.region_masks(name, ref)
        for passes in args.passes:
            rows = {}
            for threshold in args.thresholds:
                rows[threshold] = [ac.error_row(ac.render_ppm(name, passes=passes, seed=seed, hit_points="STOCHASTIC",
                                                              threshold=threshold)[0], ref, meta, masks, REGIONS)
                                   for seed in args.seeds]
            for threshold, runs in rows.items():
                ratios = " ".join(f"{r['rel_mse'] / d['rel_mse']:.3f}" for r, d in zip(runs, rows[10]))
                regions = " | ".join(f"{np.mean([r['regions'][k] for r in runs]):.2e}" if k in runs[0]["regions"]
                                     else "" for k in REGIONS)
                print(f"| {name} | {passes} | {threshold} | {np.mean([r['rel_mse'] for r in runs]):.3e} | {ratios} | "
                      f"{regions} |", flush=True)


if __name__ == "__main__":
    main()
