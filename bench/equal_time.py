"""PPM against Cycles at equal wall time, on the same .blend, through bpy.

    .venv/bin/python bench/equal_time.py [--quick] [--times 10 30 100] [--scenes NAME ...]

For cornell_3spheres (the caustic Cornell box: glass and mirror spheres, a
small sphere light) and cornell_diffuse (diffuse only, a square area light),
at 320x240 on 2 threads, renders for each time T:
- Cycles on the CPU with `cycles.time_limit = T` (settings in
  accuracy_common.render_cycles: path tracing, 12 bounces, no clamping,
  denoising or adaptive sampling, caustics on, lights visible to the camera),
  seed 11;
- the PPM add-on with `ppm.time_limit = T`, 200,000 photons per pass, seed 7,
  with fixed hit points and with stochastic ones (the add-on's AUTO).
Errors against the references of bench/references.py: the PPM reference on
cornell_3spheres (Cycles would need days there), both the Cycles and the PPM
reference on cornell_diffuse. Relative MSE overall and by region (caustic
patch, walls, glass, mirror, emitter: geometric masks, see accuracy_common.py;
bench/plots/regions.png shows them), RMSE, and the ratio of PPM's relative
MSE to Cycles'. The issue's target: at most 1/4 on cornell_3spheres.

The seeds differ from the references' so that errors are independent. Wall
time is that of bpy.ops.render.render; Cycles' limit excludes its scene sync,
the add-on's its export, so both are printed. Full run: about 15 minutes;
run it on a quiet machine. --quick: 2 and 5 s (checks the script).
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy_common as ac  # noqa: E402

SCENES = ("cornell_3spheres", "cornell_diffuse")
REGIONS = ("caustic", "walls", "glass", "mirror", "emitter")
PPM_SEED, CYCLES_SEED = 7, 11


def references(name):
    refs = {}
    if os.path.exists(ac.reference_path(name, "cycles")):
        refs["cycles"] = ac.load_reference(name, "cycles")
    refs["ppm"] = ac.load_reference(name)
    return refs


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=ac.SCENES)
    parser.add_argument("--times", type=float, nargs="+", default=[10, 30, 100])
    args = parser.parse_args()
    if args.quick:
        args.times = [2, 5]
        ac.PLOTS_DIR = ac.WORKDIR  # figures of a quick run are not the README's
    results = []
    for name in args.scenes:
        refs = references(name)
        masks = ac.region_masks(name, refs["ppm"][0])
        if name == "cornell_3spheres":
            plot_regions(name, refs["ppm"][0], masks)
        for seconds in args.times:
            renders = {"Cycles": ac.render_cycles(name, seconds=seconds, seed=CYCLES_SEED),
                       "PPM fixed": ac.render_ppm(name, seconds=seconds, seed=PPM_SEED, hit_points="FIXED"),
                       "PPM stochastic": ac.render_ppm(name, seconds=seconds, seed=PPM_SEED,
                                                       hit_points="STOCHASTIC")}
            for ref_name, (ref, meta) in refs.items():
                for engine, (image, wall) in renders.items():
                    row = {"scene": name, "reference": ref_name, "engine": engine, "time_limit": seconds,
                           "wall": wall, **ac.error_row(image, ref, meta, masks, REGIONS)}
                    results.append(row)
                    print(f"{name} vs {ref_name} ref.: {engine} {seconds:g} s (wall {wall:.1f} s): "
                          f"rel. MSE {row['rel_mse']:.2e}", flush=True)
    if not args.quick:
        ac.save_results(results, "equal_time.json")
    print_table(results)
    plot(results, os.path.join(ac.PLOTS_DIR, "equal_time.png"))


def print_table(results):
    print("\n| scene | reference | engine | time limit (s) | wall (s) | rel. MSE | PPM/Cycles | "
          + " | ".join(REGIONS) + " | RMSE |")
    print("|---|---|---|---|---|---|---|" + "---|" * len(REGIONS) + "---|")
    for r in results:
        cycles = next(c for c in results if c["engine"] == "Cycles" and c["scene"] == r["scene"]
                      and c["reference"] == r["reference"] and c["time_limit"] == r["time_limit"])
        ratio = "" if r["engine"] == "Cycles" else f"{r['rel_mse'] / cycles['rel_mse']:.3f}"
        regions = " | ".join(f"{r['regions'][k]:.2e}" if k in r["regions"] else "" for k in REGIONS)
        print(f"| {r['scene']} | {r['reference']} | {r['engine']} | {r['time_limit']:g} | {r['wall']:.1f} | "
              f"{r['rel_mse']:.2e} | {ratio} | {regions} | {r['rmse']:.4f} |")
    print("\nReferences' own noise (rel. MSE): " + ", ".join(sorted({f"{r['scene']} {r['reference']} "
                                                                   f"{r['ref_noise']:.1e}" for r in results})))


def plot(results, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = sorted({(r["scene"], r["reference"]) for r in results})
    fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys), 4), squeeze=False)
    for ax, (scene, ref) in zip(axes[0], keys):
        for i, engine in enumerate(("Cycles", "PPM fixed", "PPM stochastic")):
            rows = [r for r in results if r["scene"] == scene and r["reference"] == ref and r["engine"] == engine]
            ax.loglog([r["wall"] for r in rows], [r["rel_mse"] for r in rows], "o-", color=f"C{i}", label=engine)
        noise = next(r["ref_noise"] for r in results if r["scene"] == scene and r["reference"] == ref)
        ax.axhline(noise, color="gray", lw=0.8, ls=":", label="reference noise")
        ax.set_title(f"{scene} vs {ref} reference", fontsize=9)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("relative MSE")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"\nplot: {out}")


def plot_regions(name, reference, masks):
    """The reference (tone-mapped) and the region masks, for the README."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = [k for k in ("caustic", "walls", "glass", "mirror", "emitter") if k in masks]
    fig, axes = plt.subplots(1, len(shown) + 1, figsize=(2.6 * (len(shown) + 1), 2.3))
    axes[0].imshow(np.clip(reference / (1.0 + reference), 0.0, 1.0) ** (1 / 2.2))
    axes[0].set_title(f"{name} reference", fontsize=8)
    for ax, key in zip(axes[1:], shown):
        ax.imshow(masks[key], cmap="gray")
        ax.set_title(f"{key} ({int(masks[key].sum())} px)", fontsize=8)
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    os.makedirs(ac.PLOTS_DIR, exist_ok=True)
    fig.savefig(os.path.join(ac.PLOTS_DIR, "regions.png"), dpi=100)


if __name__ == "__main__":
    main()
