"""Adaptive eye sampling (engine/ppm/adaptive_samples.h) against one eye sample a pixel per pass, at
equal time, on the core scenes with stored references (stochastic hit points); with the
experiment's `photon_guiding` list, photon guiding (engine/ppm/photon_guide.h) on and off as well.

    .venv/bin/python bench/run.py adaptive [--quick]
    .venv/bin/python bench/run.py photon_guiding [--quick]

For each scene, `adaptive_samples` value and seed, a renderer runs passes until `seconds` have
passed; its image is compared with the reference: relative MSE (linear RGB: the lamp and the
caustic's bright pixels weigh most), the mean absolute error over the mean luminance (the norm
target_error halts on) and the RMSE of the tone-mapped images (x / (1 + x)), over the image and on
the reference's edges (error_estimate.py's regions).
"""

from __future__ import annotations

import time

import numpy as np

import ppm_core
from harness.core_route import build_scene
from harness.references import load_reference
from kinds.error_estimate import LUMINANCE, regions


def measure(image, reference, mask):
    lum, truth = image @ LUMINANCE, reference @ LUMINANCE
    tone = image / (1.0 + image) - reference / (1.0 + reference)
    return {"rel_mse": float(((image - reference) ** 2)[mask].sum() / (reference ** 2)[mask].sum()),
            "mae": float(np.abs(lum - truth)[mask].sum() / truth[mask].sum()),
            "tone_rmse": float(np.sqrt((tone ** 2)[mask].mean()))}


def render(experiment, scene_name, samples, guiding, seed, reference, masks):
    height, width = reference.shape[:2]
    renderer = ppm_core.Renderer(build_scene(scene_name, width, height), threads=2, seed=seed,
                                 photons_per_pass=experiment["photons_per_pass"], hit_points="stochastic",
                                 adaptive_samples=samples, photon_guiding=guiding)
    seconds = 0.0
    while seconds < experiment["seconds"]:
        start = time.perf_counter()
        renderer.run(passes=1)
        seconds += time.perf_counter() - start
    image = np.asarray(renderer.image())[..., :3]
    row = {"scene": scene_name, "adaptive_samples": samples, "photon_guiding": guiding, "seed": seed,
           "seconds": seconds,
           "passes": renderer.stats()["passes"], "hit_points": renderer.stats()["hit_points"]}
    for name, mask in masks.items():
        row.update({f"{key}_{name}": value for key, value in measure(image, reference, mask).items()})
    return row


def summary(rows, key):
    values = [r[key] for r in rows]
    return f"{np.mean(values):.5f} ({min(values):.5f}-{max(values):.5f})"


def run(experiment, results):
    results.note(f"\nCore scenes at their references' size, {experiment['photons_per_pass']:,} photons per pass, "
                 f"stochastic hit points, 2 threads, {experiment['seconds']} s each, seeds {experiment['seeds']}; "
                 f"mean (min-max) over the seeds.")
    rows = []
    for scene_name in experiment["scenes"]:
        reference = load_reference(scene_name, "core")[0][..., :3]
        all_masks = regions(reference, experiment["edge_gradient"])
        masks = {"all": all_masks["all"], "edges": all_masks["edges"]}
        for samples in experiment["adaptive_samples"]:
            for guiding in experiment.get("photon_guiding", [False]):
                for seed in experiment["seeds"]:
                    row = render(experiment, scene_name, samples, guiding, seed, reference, masks)
                    results.row(**row)
                    rows.append(row)
    table = []
    for scene_name in experiment["scenes"]:
        scene_rows = [r for r in rows if r["scene"] == scene_name]
        base = [r for r in scene_rows if r["adaptive_samples"] == 1 and not r["photon_guiding"]]
        for samples in experiment["adaptive_samples"]:
            for guiding in experiment.get("photon_guiding", [False]):
                group = [r for r in scene_rows if r["adaptive_samples"] == samples and r["photon_guiding"] == guiding]
                ratio = np.mean([r["rel_mse_all"] for r in group]) / np.mean([r["rel_mse_all"] for r in base])
                mae_ratio = np.mean([r["mae_all"] for r in group]) / np.mean([r["mae_all"] for r in base])
                table.append([scene_name, samples, "on" if guiding else "off",
                              f"{np.mean([r['passes'] for r in group]):.0f}", summary(group, "rel_mse_all"),
                              f"{ratio:.2f}", summary(group, "mae_all"), f"{mae_ratio:.3f}",
                              summary(group, "tone_rmse_all"), summary(group, "rel_mse_edges"),
                              summary(group, "mae_edges")])
    results.table(["scene", "adaptive_samples", "photon guiding", "passes", "rel. MSE", "/ uniform",
                   "mean abs. error", "/ uniform", "tone-mapped RMSE", "edges: rel. MSE", "edges: mean abs. error"],
                  table, title="Equal time, against one eye sample a pixel and no guiding")
    return True
