"""When does denoising help? The add-on's Denoise (Blender's own Open Image Denoise, guided by the
Denoising Albedo and Normal: addon/ppm_render/denoise.py) against the noisy image, both measured with
the stored references of the core scenes.

    .venv/bin/python bench/run.py denoise [--quick]

For each scene and hit-point mode one renderer runs pass by pass up to `passes`. At each of the
`checkpoints` the image is denoised with features from `feature_samples` eye samples per pixel, and
both are compared with the reference:
- relative MSE (sum of squared errors over the reference's sum of squares, in linear RGB: bright
  pixels such as the lamp and the caustic dominate it) and the RMSE of the tone-mapped images
  (x / (1 + x): the error as the eye sees it), over the image and by region (error_estimate.py's:
  edges, which hold the caustic's and shadows' boundaries; the brightest 5%; the smooth rest);
- at equal time: the noisy image of the pass whose rendering time first reaches the denoised one's
  (its passes, the features and the denoiser).
"""

from __future__ import annotations

import time

import numpy as np

import ppm_core
from harness.core_route import build_scene
from harness.references import load_reference
from kinds.error_estimate import regions


def denoiser():
    """The add-on's denoise module; bpy is imported first, which loads Blender's OIDN library."""
    import os
    import sys

    import bpy  # noqa: F401

    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(__file__))), "addon"))
    from ppm_render import denoise

    ok, why = denoise.available()
    if not ok:
        raise SystemExit(f"denoise: {why}")
    return denoise


def errors(image, reference, masks):
    """{measure_region: value} for relative MSE and tone-mapped RMSE."""
    out = {}
    tone = image / (1.0 + image) - reference / (1.0 + reference)
    for name, mask in masks.items():
        out[f"mse_{name}"] = float(((image - reference) ** 2)[mask].sum() / (reference ** 2)[mask].sum())
        out[f"tm_{name}"] = float(np.sqrt((tone ** 2)[mask].mean()))
    return out


def trace_render(experiment, denoise, scene_name, mode):
    reference = load_reference(scene_name, "core")[0][..., :3]
    height, width = reference.shape[:2]
    masks = regions(reference, experiment["edge_gradient"])
    renderer = ppm_core.Renderer(build_scene(scene_name, width, height), threads=2, seed=experiment["seed"],
                                 photons_per_pass=experiment["photons_per_pass"], hit_points=mode)
    start = time.perf_counter()
    features = renderer.denoising_features(experiment["feature_samples"])
    feature_seconds = time.perf_counter() - start
    noisy, checkpoints, seconds = [], [], 0.0
    while len(noisy) < experiment["passes"]:
        start = time.perf_counter()
        renderer.run(passes=1)
        seconds += time.perf_counter() - start
        image = np.asarray(renderer.image())[..., :3]
        noisy.append({"passes": len(noisy) + 1, "seconds": seconds, **errors(image, reference, masks)})
        if len(noisy) in experiment["checkpoints"]:
            start = time.perf_counter()
            denoised = denoise.denoise(image, features["albedo"], features["normal"])
            denoise_seconds = time.perf_counter() - start
            checkpoints.append({"scene": scene_name, "hit_points": mode, "passes": len(noisy), "seconds": seconds,
                                "feature_seconds": feature_seconds, "denoise_seconds": denoise_seconds,
                                **{f"noisy_{k}": v for k, v in noisy[-1].items() if k[:3] in ("mse", "tm_")},
                                **{f"denoised_{k}": v for k, v in errors(denoised, reference, masks).items()}})
    for row in checkpoints:  # the noisy image at the denoised one's time, where the passes reach it
        spent = row["seconds"] + row["feature_seconds"] + row["denoise_seconds"]
        later = next((n for n in noisy if n["seconds"] >= spent), None)
        row["equal_time_passes"] = later["passes"] if later else None
        row["equal_time_tm_all"] = later["tm_all"] if later else float("nan")
        row["equal_time_mse_all"] = later["mse_all"] if later else float("nan")
    return checkpoints


def report(results, rows):
    table = []
    for r in rows:
        table.append([r["scene"], r["hit_points"], r["passes"], f"{r['seconds']:.2f}",
                      f"{r['feature_seconds'] + r['denoise_seconds']:.2f}",
                      f"{r['noisy_tm_all']:.4f}", f"{r['denoised_tm_all']:.4f}",
                      f"{r['denoised_tm_all'] / r['noisy_tm_all']:.2f}",
                      f"{r['equal_time_tm_all']:.4f} ({r['equal_time_passes']})" if r["equal_time_passes"] else "",
                      f"{r['denoised_mse_all'] / r['noisy_mse_all']:.2f}"])
    results.table(["scene", "hit points", "passes", "s", "features + denoise s", "tone-mapped RMSE: noisy",
                   "denoised", "denoised / noisy", "noisy at equal time (passes)", "rel. MSE: denoised / noisy"],
                  table, title="Denoised against noisy, whole image")
    table = []
    for r in rows:
        table.append([r["scene"], r["hit_points"], r["passes"],
                      *(f"{r[f'denoised_tm_{name}'] / r[f'noisy_tm_{name}']:.2f}"
                        for name in ("smooth", "bright", "edges")),
                      *(f"{r[f'denoised_mse_{name}'] / r[f'noisy_mse_{name}']:.2f}"
                        for name in ("smooth", "bright", "edges"))])
    results.table(["scene", "hit points", "passes", "tone-mapped RMSE ratio: smooth", "bright", "edges",
                   "rel. MSE ratio: smooth", "bright", "edges"], table,
                  title="Denoised over noisy error by region (under 1: denoising helps)")


def run(experiment, results):
    denoise = denoiser()
    results.note(f"\nCore scenes at their references' size, {experiment['photons_per_pass']:,} photons per pass, "
                 f"2 threads, seed {experiment['seed']}; features from {experiment['feature_samples']} eye samples "
                 f"per pixel; regions as bench/run.py error_estimate's (edge gradient "
                 f"{experiment['edge_gradient']:.0%}).")
    rows = []
    for scene_name in experiment["scenes"]:
        for mode in experiment["hit_points"]:
            for row in trace_render(experiment, denoise, scene_name, mode):
                results.row(**row)
                rows.append(row)
    report(results, rows)
    return True
