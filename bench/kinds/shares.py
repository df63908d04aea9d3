"""Sharded stills (engine/ppm/share.h): one still's passes rendered apart and merged.

    .venv/bin/python bench/run.py shares [--quick]

On the core scenes with stored references (stochastic hit points, at the references' size):
- schedules: the error against the reference after `checkpoints` passes for the radius schedules a
  share could use: 'progressive' (today's: per pixel, the threshold P), 'global' (Knaus & Zwicker
  2011, each alpha of `global_alphas`), and the naive split: `naive_shares` independent progressive
  renders with their own seeds, each of checkpoint / naive_shares passes, averaged (what merging
  shares without a global schedule gives: the noise of the total, the bias of one share), for each
  count in `naive_shares` and each checkpoint with at least 2 passes a share;
- splits: each of `split_passes` passes of the global schedule as 1, 2, 4 and 8 shares merged, against
  the same passes in one renderer: the error must depend on the passes, not on the split;
- overhead per share: its bytes pickled (what dask sends), the seconds to pickle and unpickle it,
  the seconds to merge it, and a share's fixed cost (renderer set-up and the photon-spacing pilot)
  as the time of a 1-pass share beyond a pass.
Errors are the relative MSE (linear RGB: the lamp's edges, the same eye samples in every schedule,
weigh most) and the mean absolute luminance error over the mean luminance (the norm target_error
halts on); mean (min-max) over `seeds`.
"""

from __future__ import annotations

import itertools
import pickle
import time

import numpy as np

import ppm_core
from harness.core_route import build_scene
from harness.references import load_reference
from kinds.error_estimate import LUMINANCE, regions


def errors(image, reference, masks):
    """Relative MSE over the image; the mean absolute luminance error over the mean luminance, over the
    image and in each region of `masks` (error_estimate.regions: edges, bright (the caustic and
    highlights), smooth), where the bias of a large radius shows first."""
    lum, truth = image @ LUMINANCE, reference @ LUMINANCE
    out = {"rel_mse": float(((image - reference) ** 2).sum() / (reference ** 2).sum())}
    for name, mask in masks.items():
        out["mae" if name == "all" else f"mae_{name}"] = float(np.abs(lum - truth)[mask].sum() / truth[mask].sum())
    return out


def renderer(experiment, scene, seed, **settings):
    return ppm_core.Renderer(scene, threads=2, seed=seed, photons_per_pass=experiment["photons_per_pass"],
                             hit_points="stochastic", **settings)


def schedule_rows(experiment, scene_name, scene, reference, masks, seed):
    """Error at each checkpoint for each schedule."""
    configs = [("progressive", {"radius_schedule": "progressive"})]
    configs += [(f"global a={a}", {"radius_schedule": "global", "alpha": a}) for a in experiment["global_alphas"]]
    for name, settings in configs:
        r, done = renderer(experiment, scene, seed, **settings), 0
        for checkpoint in experiment["checkpoints"]:
            r.run(passes=checkpoint - done)
            done = checkpoint
            yield {"part": "schedules", "scene": scene_name, "schedule": name, "seed": seed, "passes": done,
                   **errors(np.asarray(r.image())[..., :3], reference, masks)}
    for shares in experiment["naive_shares"]:
        for checkpoint in (c for c in experiment["checkpoints"] if c >= 2 * shares):
            images = []
            for k in range(shares):
                r = renderer(experiment, scene, seed * 1000 + k, radius_schedule="progressive")
                r.run(passes=checkpoint // shares)
                images.append(np.asarray(r.image())[..., :3])
            yield {"part": "schedules", "scene": scene_name, "schedule": f"naive split in {shares}", "seed": seed,
                   "passes": checkpoint, **errors(np.mean(images, axis=0), reference, masks)}


def split_rows(experiment, scene_name, scene, reference, masks, seed):
    """The same passes as 1, 2, 4, 8 shares; the overhead of each share."""
    for total in experiment["split_passes"]:
        yield from split_rows_of(experiment, scene_name, scene, reference, masks, seed, total)


def split_rows_of(experiment, scene_name, scene, reference, masks, seed, total):
    whole = None
    for count in experiment["split_counts"]:
        per = total // count
        shares, render_seconds, pickle_seconds, merge_seconds, size = [], 0.0, 0.0, 0.0, 0
        for k in range(count):
            start = time.perf_counter()
            r = renderer(experiment, scene, seed, radius_schedule="global", first_pass=k * per)
            r.run(passes=per)
            share = r.share()
            render_seconds += time.perf_counter() - start
            start = time.perf_counter()
            data = pickle.dumps(share)
            shares.append(pickle.loads(data))
            pickle_seconds += time.perf_counter() - start
            size = len(data)
        start = time.perf_counter()
        merged = ppm_core.merge_shares(shares)
        merge_seconds = time.perf_counter() - start
        image = merged.image()[..., :3]
        whole = image if whole is None else whole
        yield {"part": "splits", "scene": scene_name, "shares": count, "seed": seed, "passes": merged.passes,
               "render_seconds": render_seconds, "share_bytes": size, "pickle_seconds": pickle_seconds / count,
               "merge_seconds": merge_seconds / count,
               "max_rel_diff_to_one": float(np.abs(image - whole).max() / max(whole.max(), 1e-30)),
               "estimate": merged.error_stats()["relative"], **errors(image, reference, masks)}


def fixed_cost_row(experiment, scene_name, scene, seed):
    """A 1-pass share's time beyond a pass: what each share pays once."""
    times = []
    for passes in (1, 2):
        start = time.perf_counter()
        r = renderer(experiment, scene, seed, radius_schedule="global")
        r.run(passes=passes)
        r.share()
        times.append(time.perf_counter() - start)
    return {"part": "fixed_cost", "scene": scene_name, "seed": seed, "share_seconds": times[0] - (times[1] - times[0]),
            "pass_seconds": times[1] - times[0]}


def summary(rows, key, fmt="{:.5f}"):
    values = [r[key] for r in rows]
    return f"{fmt.format(np.mean(values))} ({fmt.format(min(values))}-{fmt.format(max(values))})"


def tables(experiment, results, rows):
    table = []
    for scene_name in experiment["scenes"]:
        schedules = dict.fromkeys(r["schedule"] for r in rows if r["part"] == "schedules")
        for schedule in schedules:
            for checkpoint in experiment["checkpoints"]:
                group = [r for r in rows if r["part"] == "schedules" and r["scene"] == scene_name
                         and r["schedule"] == schedule and r["passes"] == checkpoint]
                if group:
                    table.append([scene_name, schedule, checkpoint, summary(group, "rel_mse"), summary(group, "mae"),
                                  summary(group, "mae_edges"), summary(group, "mae_bright")])
    results.table(["scene", "schedule", "passes", "rel. MSE", "mean abs. error", "edges", "bright"], table,
                  title="Radius schedules: error against the reference over passes")
    table = []
    for scene_name, total, count in itertools.product(experiment["scenes"], experiment["split_passes"],
                                                      experiment["split_counts"]):
        group = [r for r in rows if r["part"] == "splits" and r["scene"] == scene_name and r["shares"] == count
                 and r["passes"] == total]
        if group:
            table.append([scene_name, count, total, summary(group, "rel_mse"), summary(group, "mae"),
                          summary(group, "estimate"), f"{max(r['max_rel_diff_to_one'] for r in group):.1e}",
                          f"{group[0]['share_bytes']:,}", summary(group, "pickle_seconds", "{:.4f}"),
                          summary(group, "merge_seconds", "{:.4f}")])
    results.table(["scene", "shares", "passes", "rel. MSE", "mean abs. error", "estimate", "max diff to 1 share",
                   "bytes a share", "pickle s a share", "merge s a share"], table,
                  title="The same passes split into shares (global schedule)")
    group = [r for r in rows if r["part"] == "fixed_cost"]
    results.table(["scene", "a share's fixed cost, s", "a pass, s"],
                  [[s, summary([r for r in group if r["scene"] == s], "share_seconds", "{:.3f}"),
                    summary([r for r in group if r["scene"] == s], "pass_seconds", "{:.3f}")]
                   for s in experiment["scenes"]], title="A share's fixed cost")


def run(experiment, results):
    results.note(f"\nCore scenes at their references' size, {experiment['photons_per_pass']:,} photons per pass, "
                 f"stochastic hit points, 2 threads, seeds {experiment['seeds']}; mean (min-max) over the seeds.")
    rows = []
    for scene_name in experiment["scenes"]:
        reference = load_reference(scene_name, "core")[0][..., :3]
        height, width = reference.shape[:2]
        scene = build_scene(scene_name, width, height)
        masks = regions(reference, experiment["edge_gradient"])
        for seed in experiment["seeds"]:
            for row in [*schedule_rows(experiment, scene_name, scene, reference, masks, seed),
                        *split_rows(experiment, scene_name, scene, reference, masks, seed),
                        fixed_cost_row(experiment, scene_name, scene, seed)]:
                results.row(**row)
                rows.append(row)
    tables(experiment, results, rows)
    return True
