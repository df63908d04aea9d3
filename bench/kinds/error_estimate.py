"""Is the error estimate honest? The estimate (engine/ppm/error_estimate.h) against the true error
measured with the stored references of the core scenes, pass by pass.

    .venv/bin/python bench/run.py error_estimate [--quick]

For each scene (core_scenes, with its reference bench/references/core_{scene}.exr) and hit-point
mode, one renderer runs pass by pass up to `passes`. After each pass, in luminance:
- true error: the mean over pixels of |image - reference| over the reference's mean (the norm the
  estimate states), and the estimate's `relative` and `bound` (stats()['error']);
- coverage: the share of pixels whose true error is at most their bound at `confidence`
  (Renderer.error(): |bias| + noise), overall and by region: "edges" (the reference's relative
  gradient over `edge_gradient` between neighbours: shadow and caustic edges), "bright" (the
  brightest 5%: the caustic and highlights), "smooth" (the rest);
- time to target: for each of `targets`, the first pass (and its seconds) at which the true error is
  at most the target, and at which the estimate's bound is (where run(target_error=...) stops).
The reference has noise of its own (its header's rel_mse_noise): true errors near it are
overestimated. Draws error_vs_passes.png.
"""

from __future__ import annotations

import time

import numpy as np

import ppm_core
from harness import plots
from harness.core_route import build_scene
from harness.references import load_reference, reference_noise

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def regions(reference, edge_gradient):
    """Masks of the reference's edges, its brightest 5% and the rest (smooth)."""
    lum = reference @ LUMINANCE
    padded = np.pad(lum, 1, mode="edge")
    neighbours = np.stack([padded[:-2, 1:-1], padded[2:, 1:-1], padded[1:-1, :-2], padded[1:-1, 2:]])
    gradient = np.abs(neighbours - lum).max(axis=0) / np.maximum(lum, 1e-3 * lum.mean())
    edges = gradient > edge_gradient
    bright = (lum >= np.quantile(lum, 0.95)) & ~edges
    return {"all": np.ones_like(edges), "edges": edges, "bright": bright, "smooth": ~edges & ~bright}


def first_pass_at(trace, key, target):
    """The first (pass, seconds) whose `key` is at most `target`, or (None, None)."""
    for row in trace:
        if row[key] <= target:
            return row["passes"], row["seconds"]
    return None, None


def trace_render(experiment, scene_name, mode):
    """Runs one renderer pass by pass; returns a row per pass."""
    reference, meta = load_reference(scene_name, "core")
    height, width = reference.shape[:2]
    truth = reference @ LUMINANCE
    masks = regions(reference, experiment["edge_gradient"])
    renderer = ppm_core.Renderer(build_scene(scene_name, width, height), threads=2, seed=experiment["seed"],
                                 photons_per_pass=experiment["photons_per_pass"], hit_points=mode,
                                 error_confidence=experiment["confidence"])
    trace, seconds = [], 0.0
    while len(trace) < experiment["passes"]:
        start = time.perf_counter()
        renderer.run(passes=1)
        seconds += time.perf_counter() - start
        image = np.asarray(renderer.image())[..., :3] @ LUMINANCE
        estimate = renderer.stats()["error"]
        error = renderer.error()
        true_error = np.abs(image - truth)
        covered = true_error <= np.abs(error["bias"]) + error["noise"]
        trace.append({"scene": scene_name, "hit_points": mode, "passes": len(trace) + 1, "seconds": seconds,
                      "true": float(true_error.sum() / truth.sum()), "estimate": estimate["relative"],
                      "bound": estimate["bound"], "bias": estimate["bias"], "noise": estimate["noise"],
                      "ref_noise": float(np.sqrt(reference_noise(meta))),
                      **{f"covered_{name}": float(covered[mask].mean()) if mask.any() else float("nan")
                         for name, mask in masks.items()},
                      **{f"true_{name}": float(true_error[mask].sum() / truth[mask].sum()) if mask.any()
                         else float("nan") for name, mask in masks.items()}})
    return trace


def report(experiment, results, traces):
    checkpoints = [p for p in experiment["checkpoints"] if p <= experiment["passes"]]
    rows = []
    for trace in traces:
        for row in trace:
            if row["passes"] in checkpoints:
                rows.append([row["scene"], row["hit_points"], row["passes"], f"{row['seconds']:.1f}",
                             f"{row['true']:.4f}", f"{row['estimate']:.4f}", f"{row['bound']:.4f}",
                             f"{row['bias']:.4f}", f"{row['noise']:.4f}", f"{row['estimate'] / row['true']:.2f}",
                             *(f"{row[f'covered_{n}']:.3f}" for n in ("all", "edges", "bright", "smooth"))])
    results.table(["scene", "hit points", "passes", "s", "true error", "estimate", "bound", "bias part",
                   "noise part", "estimate / true", "covered: all", "edges", "bright", "smooth"], rows,
                  title=f"Estimate against the truth (mean absolute error over mean luminance; coverage at "
                        f"confidence {experiment['confidence']})")
    rows = []
    for trace in traces:
        for target in experiment["targets"]:
            true_pass, true_seconds = first_pass_at(trace, "true", target)
            stop_pass, stop_seconds = first_pass_at(trace, "bound", target)
            rows.append([trace[0]["scene"], trace[0]["hit_points"], f"{target:.0%}",
                         pass_cell(true_pass, true_seconds), pass_cell(stop_pass, stop_seconds),
                         "" if None in (true_pass, stop_pass) else f"{stop_pass / true_pass:.2f}"])
    results.table(["scene", "hit points", "target", "true error first meets it: pass (s)",
                   "the estimate does (target_error stops): pass (s)", "passes, stop / truth"], rows,
                  title="Time to target")
    results.note("\nThe references' own noise (relative rms, from their halves): "
                 + ", ".join(f"{t[0]['scene']} {t[0]['ref_noise']:.4f}" for t in traces[::2]) + ".")


def pass_cell(passes, seconds):
    return "not within the passes" if passes is None else f"{passes} ({seconds:.1f} s)"


def plot(traces, path):
    plt = plots.pyplot()
    fig, axes = plt.subplots(1, len(traces), figsize=(4.2 * len(traces), 3.8), squeeze=False)
    for ax, trace in zip(axes[0], traces):
        passes = [r["passes"] for r in trace]
        ax.loglog(passes, [r["true"] for r in trace], "k-", label="true (vs reference)")
        ax.loglog(passes, [r["estimate"] for r in trace], "C0-", label="estimate")
        ax.loglog(passes, [r["bias"] for r in trace], "C1--", lw=0.8, label="bias part")
        ax.loglog(passes, [r["noise"] for r in trace], "C2--", lw=0.8, label="noise part (sd)")
        ax.axhline(trace[0]["ref_noise"], color="grey", lw=0.6, label="reference noise")
        ax.set_title(f"{trace[0]['scene']}, {trace[0]['hit_points']}", fontsize=9)
        ax.set_xlabel("passes")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("mean abs. error / mean luminance")
    axes[0][-1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(experiment, results):
    results.note(f"\nCore scenes at their references' size, {experiment['photons_per_pass']:,} photons per pass, "
                 f"2 threads, seed {experiment['seed']}, {experiment['passes']} passes; regions: edges where the "
                 f"reference changes by over {experiment['edge_gradient']:.0%} between neighbours.")
    traces = []
    for scene_name in experiment["scenes"]:
        for mode in experiment["hit_points"]:
            trace = trace_render(experiment, scene_name, mode)
            for row in trace:
                results.row(**row)
            traces.append(trace)
    report(experiment, results, traces)
    plot(traces, results.path("error_vs_passes.png"))
    return True
