"""Reference images for the accuracy experiments: each the mean of two independent renders (the
"halves"), whose difference estimates the reference's own noise: for independent halves A and B,
Var((A + B) / 2) = E[(A - B)^2] / 4 per pixel, reported as its relative MSE ("noise floor").

Parameters: route ("addon": the .blend files; "core": blend_scenes/core_scenes.py), scenes, size,
threads, and one table per engine to make ([ppm], [cycles] through Blender, [core] on the core
route), each with its seeds (two), its budget (`passes`, Cycles' samples) and settings; an engine
table's `scenes` limits it to those scenes. A pass count and a seed fix the result for a thread
count, so a reference does not depend on the machine's load.

Writes bench/references/ (a quick run: its results folder instead): the EXRs (half float, their
settings, timings and noise in the header) and references.json (noise by region; where a scene has
both a PPM and a Cycles reference, their agreement by region, printed and drawn as
agreement_{scene}.png). `report = true` renders nothing: it prints and draws the stored ones.
"""

from __future__ import annotations

import datetime
import json
import os
import time

import numpy as np

from harness import metrics, plots
from harness.exr_io import read_exr, write_exr
from harness.references import REF_DIR, reference_path

ENGINES = ("core", "ppm", "cycles")


def render_half(route, engine, scene, size, seed, budget, settings, threads):
    if route == "core":
        from harness import core_route

        return core_route.render(scene, *size, seed=seed, passes=budget, threads=threads, **settings)
    from harness import addon_route

    draw = addon_route.render_cycles if engine == "cycles" else addon_route.render_ppm
    return draw(scene, *size, seed=seed, passes=budget, threads=threads, **settings)


def make(experiment, engine, scene, folder, results):
    """Renders both halves, writes the mean; returns (the mean, its summary entry without noise, halves)."""
    table = experiment[engine]
    settings = table.get("settings", {})
    halves, seconds = [], []
    for seed in table["seeds"]:
        start = time.perf_counter()
        r = render_half(experiment["route"], engine, scene, experiment["size"], seed, table["passes"], settings,
                        experiment.get("threads", 2))
        halves.append(r.image)
        seconds.append(time.perf_counter() - start)
        results.note(f"{scene}: {engine} seed {seed}, {table['passes']} passes/samples in {seconds[-1]:.0f} s")
    mean = 0.5 * (halves[0] + halves[1])
    entry = {"passes_per_half": table["passes"], "seeds": list(table["seeds"]), "settings": settings,
             "threads": experiment.get("threads", 2), "width": experiment["size"][0],
             "height": experiment["size"][1], "seconds": seconds, "date": datetime.date.today().isoformat()}
    header = dict(entry, rel_mse_noise=metrics.halves_noise(*halves)["rel_mse"])
    write_exr(reference_path(scene, engine, folder), mean, header)
    return mean, entry, halves


def region_masks(experiment, scene, image):
    if experiment["route"] == "core":
        return {"all": np.ones(image.shape[:2], dtype=bool)}
    from harness.regions import region_masks as masks

    return masks(scene, image, *experiment["size"])


def agreement(ppm, cycles, masks):
    """Per region: means, relative MSE of PPM against Cycles, and the relative RMSE of 4x4 block means
    over the blocks wholly inside the region (less noise: shows a local bias)."""
    rows = {}
    for key, mask in masks.items():
        inside = metrics.blocks_inside(mask)
        rows[key] = {"pixels": int(mask.sum()), "ppm_mean": float(ppm[mask].mean()),
                     "cycles_mean": float(cycles[mask].mean()), "rel_mse": metrics.rel_mse(ppm, cycles, mask),
                     "block_rel_rmse": metrics.block_rel_rmse(ppm, cycles, inside) if inside.any() else None}
    return rows


def wanted(experiment, scene):
    return [e for e in ENGINES if e in experiment.params and scene in experiment[e].get("scenes", [scene])]


def run(experiment, results):
    folder = results.folder if experiment.quick else REF_DIR
    summary_path = os.path.join(folder, "references.json")
    summary = json.load(open(summary_path)) if os.path.exists(summary_path) else {}
    for scene in experiment["scenes"]:
        entry = summary.get(scene, {})
        if not experiment.get("report"):
            masks = None  # from the first engine's image, the same for every engine
            for engine in wanted(experiment, scene):
                image, entry[engine], halves = make(experiment, engine, scene, folder, results)
                masks = masks or region_masks(experiment, scene, image)
                entry[engine]["noise"] = {k: metrics.halves_noise(*halves, m) for k, m in masks.items()}
                entry["regions"] = {k: int(m.sum()) for k, m in masks.items()}
        both = all(os.path.exists(reference_path(scene, e, folder)) for e in ("ppm", "cycles"))
        if both and experiment["route"] != "core":
            ppm, cycles = (read_exr(reference_path(scene, e, folder))[0] for e in ("ppm", "cycles"))
            entry["agreement"] = agreement(ppm, cycles, region_masks(experiment, scene, ppm))
            plots.agreement(ppm, cycles, results.path(f"agreement_{scene}.png"))
        summary[scene] = entry
        with open(summary_path, "w") as f:
            json.dump(summary, f, indent=1)
        report(results, scene, entry)


def report(results, scene, entry):
    engines = [e for e in ENGINES if e in entry]
    header = ["region", "pixels"] + [f"{e} ref. noise rel. MSE" for e in engines]
    if "agreement" in entry:
        header += ["PPM mean", "Cycles mean", "ratio", "rel. MSE PPM vs Cycles", "4x4 blocks rel. RMSE"]
    rows = []
    for key, pixels in entry.get("regions", {}).items():
        row = [key, pixels] + [f"{entry[e]['noise'][key]['rel_mse']:.2e}" for e in engines]
        if "agreement" in entry and key in entry["agreement"]:
            a = entry["agreement"][key]
            block = a.get("block_rel_rmse")
            row += [f"{a['ppm_mean']:.4f}", f"{a['cycles_mean']:.4f}", f"{a['ppm_mean'] / a['cycles_mean']:.4f}",
                    f"{a['rel_mse']:.2e}", "" if block is None else f"{block:.4f}"]
        rows.append(row)
    made = ", ".join(f"{e} {2 * entry[e]['passes_per_half']} passes/samples in {sum(entry[e]['seconds']):.0f} s"
                     for e in engines)
    results.table(header, rows, title=f"{scene}: {made}")
