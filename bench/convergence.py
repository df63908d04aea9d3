"""Error against wall time for every bundled scene, through the add-on.

    .venv/bin/python bench/convergence.py [--quick] [--scenes NAME ...] [--times 2 4 8 16 32 64]
                                          [--modes FIXED STOCHASTIC]

Renders each blend_scenes/*.blend at 320x240 through the add-on (Blender 5.0
module, 200,000 photons per pass, 2 threads, seed 7, the file's other
settings) with the time limit `scene.ppm.time_limit` set to each of --times,
once per hit-point mode: FIXED (PPM) and STOCHASTIC (SPPM, what the add-on's
AUTO picks). Compares
each image with bench/references/{scene}_ppm.exr (bench/references.py; for
cornell_diffuse also with the Cycles reference) and prints a markdown table
of RMSE (all pixels, and without the pixels that see a light, whose
anti-aliasing error dominates it) and relative MSE, overall and by region
(accuracy_common.py), the
least-squares slopes of log(error) against log(wall time), and writes
bench/plots/convergence.png (log-log) and bench/plots/convergence.json.

Wall time is that of bpy.ops.render.render (export, eye pass, passes, image
write), not just the time limit. Run on a quiet machine: the time limit turns
load into fewer passes. The reference's own noise (estimated from its two
halves) is printed: errors near it say more about the reference than about the
render. Full run: about 25 minutes. --quick: 1 and 2 s, FIXED only, about a
minute (checks the script).
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy_common as ac  # noqa: E402

SEED = 7  # the references use 101 and 102 (PPM), 1 and 2 (Cycles)
REGIONS = ("caustic", "walls", "glass", "mirror", "emitter")


def resolved_mode(name, mode):
    """'fixed' or 'stochastic': what the add-on does with hit_points=mode for this file."""
    return "fixed" if mode == "FIXED" else "stochastic"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--scenes", nargs="+", default=list(ac.SCENES), choices=ac.SCENES)
    parser.add_argument("--times", type=float, nargs="+", default=[2, 4, 8, 16, 32, 64])
    parser.add_argument("--modes", nargs="+", default=["FIXED", "STOCHASTIC"], choices=["AUTO", "FIXED", "STOCHASTIC"])
    args = parser.parse_args()
    if args.quick:
        args.times, args.modes = [1, 2], ["FIXED"]
        ac.PLOTS_DIR = ac.WORKDIR  # figures of a quick run are not the README's
    results = []
    for name in args.scenes:
        refs = {"ppm": ac.load_reference(name)}
        if name in ac.CYCLES_SCENES and os.path.exists(ac.reference_path(name, "cycles")):
            refs["cycles"] = ac.load_reference(name, "cycles")
        masks = ac.region_masks(name, refs["ppm"][0])
        lit = ~masks["emitter"] if "emitter" in masks else masks["all"]  # pixels that do not see a light
        done = set()
        for mode in args.modes:
            hit_points = resolved_mode(name, mode)
            if hit_points in done:
                continue
            done.add(hit_points)
            for seconds in args.times:
                image, wall = ac.render_ppm(name, seconds=seconds, seed=SEED, hit_points=mode)
                for ref_name, (ref, meta) in refs.items():
                    row = {"scene": name, "mode": mode, "hit_points": hit_points, "reference": ref_name,
                           "time_limit": seconds, "wall": wall, "rmse_lit": ac.rmse(image, ref, lit),
                           **ac.error_row(image, ref, meta, masks, REGIONS)}
                    results.append(row)
                    print(f"{name} {mode} ({hit_points}) vs {ref_name}: {seconds:g} s -> wall {wall:.1f} s, "
                          f"RMSE {row['rmse']:.4f}, rel. MSE {row['rel_mse']:.2e}", flush=True)
    os.makedirs(ac.PLOTS_DIR, exist_ok=True)
    if not args.quick:
        ac.save_results(results, "convergence.json")
    print_tables(results)
    plot(results, os.path.join(ac.PLOTS_DIR, "convergence.png"))


def curves(results):
    keys = []
    for r in results:
        key = (r["scene"], r["hit_points"], r["reference"])
        if key not in keys:
            keys.append(key)
    return {k: [r for r in results if (r["scene"], r["hit_points"], r["reference"]) == k] for k in keys}


def print_tables(results):
    print("\n| scene | hit points | reference | time limit (s) | wall (s) | RMSE | RMSE w/o emitter | rel. MSE | "
          + " | ".join(f"rel. MSE {k}" for k in REGIONS) + " |")
    print("|---|---|---|---|---|---|---|---|" + "---|" * len(REGIONS))
    for r in results:
        regions = " | ".join(f"{r['regions'][k]:.2e}" if k in r["regions"] else "" for k in REGIONS)
        print(f"| {r['scene']} | {r['hit_points']} | {r['reference']} | {r['time_limit']:g} | {r['wall']:.1f} | "
              f"{r['rmse']:.4f} | {r['rmse_lit']:.4f} | {r['rel_mse']:.2e} | {regions} |")
    print("\nSlopes of log(error) against log(wall time), and the reference's own noise (rel. MSE):\n")
    print("| scene | hit points | reference | RMSE slope | RMSE w/o emitter slope | rel. MSE slope | reference noise |")
    print("|---|---|---|---|---|---|---|")
    for (scene, hit_points, ref), rows in curves(results).items():
        if len(rows) < 2:
            continue
        t = [r["wall"] for r in rows]
        print(f"| {scene} | {hit_points} | {ref} | {ac.fit_slope(t, [r['rmse'] for r in rows]):.2f} | "
              f"{ac.fit_slope(t, [r['rmse_lit'] for r in rows]):.2f} | "
              f"{ac.fit_slope(t, [r['rel_mse'] for r in rows]):.2f} | {rows[0]['ref_noise']:.1e} |")


def plot(results, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    colors = {}
    for (scene, hit_points, ref), rows in curves(results).items():
        color = colors.setdefault(scene, f"C{len(colors)}")
        style = "o-" if hit_points == "fixed" else "s--"
        if ref == "cycles":
            style = "^:"
        label = f"{scene}, {hit_points}" + (" (vs Cycles ref.)" if ref == "cycles" else "")
        t = [r["wall"] for r in rows]
        axes[0].loglog(t, [r["rmse_lit"] for r in rows], style, color=color, label=label)
        axes[1].loglog(t, [r["rel_mse"] for r in rows], style, color=color, label=label)
        if ref == "ppm" and hit_points == rows[0]["hit_points"]:
            axes[1].axhline(rows[0]["ref_noise"], color=color, lw=0.6, alpha=0.5)
    axes[0].set_ylabel("RMSE without the emitter pixels (radiance)")
    axes[1].set_ylabel("relative MSE (eps 0.01); thin lines: reference noise")
    for ax in axes:
        ax.set_xlabel("wall time (s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7, loc="lower left")
    fig.suptitle("PPM add-on, 320x240, 200k photons/pass, 2 threads: error against the references")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"\nplot: {out}")


if __name__ == "__main__":
    main()
