"""Reference images for the accuracy benchmarks (convergence.py, equal_time.py).

    .venv/bin/python bench/references.py [--quick] [--scenes NAME ...] [--passes N] [--cycles-samples S]
                                         [--no-cycles] [--out DIR]

For every bundled scene (blend_scenes/*.blend) at 320x240: two independent
PPM renders through the add-on in the Blender 5.0 module, seeds 101 and 102,
N passes each (default 600) of 200,000 photons, 2 threads, stochastic hit
points (SPPM: new eye samples every pass, so anti-aliasing, glossy surfaces
and lens blur converge too; fixed hit points would freeze 4 eye samples per
pixel). Everything else is the file's settings. The reference is the mean of
the two; their difference estimates its own noise: for independent halves A
and B, Var((A+B)/2) = E[(A-B)^2]/4 per pixel, reported as the reference's
relative MSE ("noise floor"). A pass count and a seed fix the result for a
thread count, so the references do not depend on machine load.

For the scenes without caustics (cornell_diffuse) also two Cycles renders
(CPU, seeds 1 and 2, S samples each, default 2048; settings in
accuracy_common.render_cycles), averaged the same way; then the agreement of
the two references per region is printed.

Writes bench/references/{scene}_ppm.exr and {scene}_cycles.exr (half float,
ZIP; the settings, timings and noise estimates are in the EXR header and in
bench/references/references.json). --report prints the tables of the stored
references without rendering and draws bench/plots/reference_agreement_{scene}.png
(both references and their relative difference). --quick renders 4 passes / 16 samples
into a temporary directory (checks the pipeline; about a minute).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy_common as ac  # noqa: E402

PPM_SEEDS = (101, 102)
CYCLES_SEEDS = (1, 2)
PHOTONS = 200_000


def noise_estimates(a, b, reference, masks):
    """The mean's own error from two independent halves: relative MSE and RMSE, all and per region."""
    d2 = (a - b) ** 2 / 4.0
    rel = d2 / (reference ** 2 + ac.EPS)
    return {k: {"rel_mse": float(rel[m].mean()), "rmse": float(np.sqrt(d2[m].mean()))} for k, m in masks.items()}


def blocks(image, k=4):
    h, w = image.shape[0] // k * k, image.shape[1] // k * k
    return image[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))


def agreement(ppm, cycles, masks):
    """Per region: mean ratio PPM/Cycles, relative MSE of PPM against Cycles, and the relative RMSE of
    4x4 block means over the blocks wholly inside the region (less noise: shows a local bias)."""
    rows = {}
    for key, mask in masks.items():
        inside = blocks(mask[..., None].astype(float))[..., 0] == 1.0
        a, b = blocks(ppm)[inside], blocks(cycles)[inside]
        rows[key] = {"pixels": int(mask.sum()), "ppm_mean": float(ppm[mask].mean()),
                     "cycles_mean": float(cycles[mask].mean()),
                     "rel_mse": ac.rel_mse(ppm, cycles, mask),
                     "block_rel_rmse": float(np.sqrt(np.mean((a - b) ** 2)) / np.mean(b)) if inside.any() else None}
    return rows


def engine_version():
    import ppm_core

    path = ppm_core.__file__
    stamp = datetime.datetime.fromtimestamp(os.path.getmtime(path)).isoformat(timespec="seconds")
    return {"module": os.path.basename(path), "built": stamp}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--scenes", nargs="+", default=list(ac.SCENES), choices=ac.SCENES)
    parser.add_argument("--passes", type=int, default=600, help="PPM passes per half")
    parser.add_argument("--cycles-samples", type=int, default=2048, help="Cycles samples per half")
    parser.add_argument("--no-cycles", action="store_true")
    parser.add_argument("--cycles-scenes", nargs="+", default=list(ac.CYCLES_SCENES), choices=ac.SCENES,
                        help="scenes that also get a Cycles reference")
    parser.add_argument("--cycles-only", action="store_true",
                        help="keep the stored PPM references, (re)make only the Cycles ones")
    parser.add_argument("--out", default=ac.REF_DIR)
    parser.add_argument("--report", action="store_true", help="render nothing: print the stored references' tables")
    args = parser.parse_args()
    if args.quick:
        args.passes, args.cycles_samples = 4, 16
        if args.out == ac.REF_DIR:
            args.out = tempfile.mkdtemp(prefix="references_quick_")
    os.makedirs(args.out, exist_ok=True)
    engine = engine_version()  # the build this process loads (others may reinstall the module meanwhile)
    summary_path = os.path.join(args.out, "references.json")
    summary = json.load(open(summary_path)) if os.path.exists(summary_path) else {}
    for name in args.scenes:
        if args.report:
            if name not in summary:
                continue
            ppm, _ = ac.read_exr(os.path.join(args.out, f"{name}_ppm.exr"))
            cycles_path = os.path.join(args.out, f"{name}_cycles.exr")
            if os.path.exists(cycles_path):
                cycles = ac.read_exr(cycles_path)[0]
                summary[name]["agreement"] = agreement(ppm, cycles, ac.region_masks(name, ppm))
                plot_agreement(name, ppm, cycles)
            report(name, summary[name])
            continue
        if args.cycles_only:
            ppm, _ = ac.read_exr(os.path.join(args.out, f"{name}_ppm.exr"))
            entry = summary[name]
            masks = ac.region_masks(name, ppm)
            cycles_reference(name, args, ppm, masks, entry)
            summary[name] = entry
            with open(summary_path, "w") as f:
                json.dump(summary, f, indent=1)
            report(name, entry)
            continue
        halves, seconds = [], []
        for seed in PPM_SEEDS:
            image, took = ac.render_ppm(name, passes=args.passes, seed=seed, hit_points="STOCHASTIC", photons=PHOTONS)
            halves.append(image)
            seconds.append(took)
            print(f"{name}: PPM seed {seed}, {args.passes} passes in {took:.0f} s", flush=True)
        ppm = 0.5 * (halves[0] + halves[1])
        masks = ac.region_masks(name, ppm)
        entry = {
            "ppm": {"passes_per_half": args.passes, "photons_per_pass": PHOTONS, "seeds": list(PPM_SEEDS),
                    "hit_points": "STOCHASTIC", "threads": 2, "width": ac.W, "height": ac.H,
                    "seconds": seconds, "date": datetime.date.today().isoformat(), "engine": engine,
                    "noise": noise_estimates(*halves, ppm, masks)},
            "regions": {k: int(m.sum()) for k, m in masks.items()},
        }
        meta = {k: v for k, v in entry["ppm"].items() if k != "noise"}
        meta["rel_mse_noise"] = entry["ppm"]["noise"]["all"]["rel_mse"]
        ac.write_exr(os.path.join(args.out, f"{name}_ppm.exr"), ppm, meta)
        if name in args.cycles_scenes and not args.no_cycles:
            cycles_reference(name, args, ppm, masks, entry)
        summary[name] = entry
        with open(summary_path, "w") as f:
            json.dump(summary, f, indent=1)
        report(name, entry)
    print(f"\nwrote {args.out}")


def plot_agreement(name, ppm, cycles):
    """bench/plots/reference_agreement_{name}.png: both references and their relative difference of 4x4 block
    means (PPM / Cycles - 1), where a bias of the PPM reference would show as a pattern rather than noise."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def tone(x):
        return np.clip(x / (1.0 + x), 0.0, 1.0) ** (1 / 2.2)

    a, b = blocks(ppm).mean(axis=-1), blocks(cycles).mean(axis=-1)
    fig, axes = plt.subplots(1, 3, figsize=(11, 3))
    axes[0].imshow(tone(ppm))
    axes[0].set_title("PPM reference", fontsize=9)
    axes[1].imshow(tone(cycles))
    axes[1].set_title("Cycles reference", fontsize=9)
    ratio = np.where(b > 1e-3, a / np.maximum(b, 1e-3) - 1.0, np.nan)  # blank where both see nothing
    shown = axes[2].imshow(ratio, cmap="RdBu_r", vmin=-0.1, vmax=0.1)
    axes[2].set_title("PPM / Cycles - 1, 4x4 block means", fontsize=9)
    fig.colorbar(shown, ax=axes[2], fraction=0.04)
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    os.makedirs(ac.PLOTS_DIR, exist_ok=True)
    fig.savefig(os.path.join(ac.PLOTS_DIR, f"reference_agreement_{name}.png"), dpi=100)


def cycles_reference(name, args, ppm, masks, entry):
    runs, seconds = [], []
    for seed in CYCLES_SEEDS:
        image, took = ac.render_cycles(name, samples=args.cycles_samples, seed=seed)
        runs.append(image)
        seconds.append(took)
        print(f"{name}: Cycles seed {seed}, {args.cycles_samples} samples in {took:.0f} s", flush=True)
    cycles = 0.5 * (runs[0] + runs[1])
    entry["cycles"] = {"samples_per_half": args.cycles_samples, "seeds": list(CYCLES_SEEDS), "threads": 2,
                       "seconds": seconds, "date": datetime.date.today().isoformat(),
                       "noise": noise_estimates(*runs, cycles, masks)}
    entry["agreement"] = agreement(ppm, cycles, masks)
    if not args.quick:
        plot_agreement(name, ppm, cycles)
    meta = {k: v for k, v in entry["cycles"].items() if k != "noise"}
    meta["rel_mse_noise"] = entry["cycles"]["noise"]["all"]["rel_mse"]
    ac.write_exr(os.path.join(args.out, f"{name}_cycles.exr"), cycles, meta)


def report(name, entry):
    noise = entry["ppm"]["noise"]
    print(f"\n{name}: PPM reference, {2 * entry['ppm']['passes_per_half']} passes in "
          f"{sum(entry['ppm']['seconds']):.0f} s; own noise (relative MSE) by region:")
    print("| region | pixels | PPM ref. noise rel. MSE | Cycles ref. noise rel. MSE | PPM mean | Cycles mean | "
          "ratio | rel. MSE PPM vs Cycles | 4x4 blocks rel. RMSE |")
    print("|---|---|---|---|---|---|---|---|---|")
    for key, n in noise.items():
        row = f"| {key} | {entry['regions'][key]} | {n['rel_mse']:.2e} |"
        if "agreement" in entry:
            a = entry["agreement"][key]
            c = entry["cycles"]["noise"][key]["rel_mse"]
            row += (f" {c:.2e} | {a['ppm_mean']:.4f} | {a['cycles_mean']:.4f} | "
                    f"{a['ppm_mean'] / a['cycles_mean']:.4f} | {a['rel_mse']:.2e} | "
                    + (f"{a['block_rel_rmse']:.4f} |" if a.get("block_rel_rmse") is not None else " |"))
        else:
            row += " | | | | | |"
        print(row, flush=True)


if __name__ == "__main__":
    main()
