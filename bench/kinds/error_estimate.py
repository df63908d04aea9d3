"""Is the error estimate honest? The estimate (engine/ppm/error_estimate.h) against the true error
measured with the stored references of the core scenes, pass by pass.

    .venv/bin/python bench/run.py error_estimate [--quick]

For each scene (core_scenes, with its reference bench/references/core_{scene}.exr) and hit-point
mode, one renderer runs pass by pass up to `passes`. After each pass, in luminance:
- true error: the mean over pixels of |image - reference| over the reference's mean (the norm the
  estimate states), and the estimate's `relative` and `bound` (stats()['error']);
- coverage: the share of pixels whose true error is at most their bound at `confidence`
  (Renderer.error(): |bias| + noise; plus 1e-4 of the reference for its rounding, where the bound
  is 0), overall and by region: "edges" (the reference's relative
  gradient over `edge_gradient` between neighbours: shadow and caustic edges), "bright" (the
  brightest 5%: the caustic and highlights), "smooth" (the rest);
- time to target: for each of `targets`, the first pass (and its seconds) at which the true error is
  at most the target, and at which the estimate's bound is (where run(target_error=...) stops).
The reference has noise of its own (its header's rel_mse_noise): true errors near it are
overestimated. Draws error_vs_passes.png.

`blend_scenes`: the bundled .blend files with a long PPM reference (bench/references/{scene}_ppm.exr),
exported as F12 exports them and rendered through ppm_core pass by pass with the add-on's settings at
the references' size; their regions are bench/harness/regions.py's (glass, mirror, caustic: the
glass's light, walls) plus the edges above. Draws error_vs_passes_blend.png.
"""

from __future__ import annotations

import math
import time
from statistics import NormalDist

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
    """A core scene, one renderer pass by pass; returns a row per pass."""
    reference, meta = load_reference(scene_name, "core")
    height, width = reference.shape[:2]
    renderer = ppm_core.Renderer(build_scene(scene_name, width, height), threads=2, seed=experiment["seed"],
                                 photons_per_pass=experiment["photons_per_pass"], hit_points=mode,
                                 error_confidence=experiment["confidence"])
    labels = {"scene": scene_name, "hit_points": mode, "ref_noise": float(np.sqrt(reference_noise(meta)))}
    return trace(renderer, reference, regions(reference, experiment["edge_gradient"]), experiment["passes"], labels)


def trace_blend_render(experiment, scene_name):
    """A bundled .blend exported as F12 does, rendered with the add-on's settings (stochastic hit
    points, its photons per pass) against its PPM reference; a row per pass."""
    from harness.addon_route import bpy, open_scene
    from harness.regions import region_masks
    from ppm_render import export
    from ppm_render.export.camera import Frame
    from ppm_render.properties import render_settings

    reference, meta = load_reference(scene_name, "ppm")
    height, width = reference.shape[:2]
    scene = open_scene(scene_name, width, height)
    core_scene = export.build_scene(ppm_core, bpy.context.evaluated_depsgraph_get(),
                                    Frame.from_render_settings(scene.render), lambda message: None)[0]
    settings = {**render_settings(scene), "threads": 2, "seed": experiment["seed"], "hit_points": "stochastic",
                "error_confidence": experiment["confidence"], "photons_per_pass": experiment["blend_photons_per_pass"]}
    masks = {**region_masks(scene_name, reference, width, height),
             "edges": regions(reference, experiment["edge_gradient"])["edges"]}
    labels = {"scene": scene_name, "hit_points": "stochastic", "ref_noise": float(np.sqrt(reference_noise(meta)))}
    return trace(ppm_core.Renderer(core_scene, **settings), reference, masks, experiment["blend_passes"], labels)


def trace(renderer, reference, masks, passes, labels):
    """Runs `renderer` pass by pass; after each, the true error (against `reference`) and the
    estimate, over the image and within each of `masks`."""
    truth = reference[..., :3] @ LUMINANCE
    rows, seconds = [], 0.0
    while len(rows) < passes:
        start = time.perf_counter()
        renderer.run(passes=1)
        seconds += time.perf_counter() - start
        image = np.asarray(renderer.image())[..., :3] @ LUMINANCE
        estimate = renderer.stats()["error"]
        error = renderer.error()
        true_error = np.abs(image - truth)
        # Pixels whose light is exact (the world or a lamp seen directly) have a bound of 0: within the
        # stored reference's rounding (1e-4 relative) they count as covered.
        covered = true_error <= np.abs(error["bias"]) + error["noise"] + 1e-4 * np.abs(truth)
        with np.errstate(invalid="ignore"):  # the first pass: noise and t are inf
            pixel_estimate = mean_absolute(error["bias"], error["noise"] / student_t(renderer, len(rows) + 1))
        rows.append({**labels, "passes": len(rows) + 1, "seconds": seconds,
                     "true": float(true_error.sum() / truth.sum()), "estimate": estimate["relative"],
                     "bound": estimate["bound"], "bias": estimate["bias"], "noise": estimate["noise"],
                     **{f"covered_{name}": float(covered[mask].mean()) for name, mask in masks.items()},
                     **{f"true_{name}": float(true_error[mask].sum() / truth[mask].sum())
                        for name, mask in masks.items()},
                     **{f"estimate_{name}": float(pixel_estimate[mask].sum() / truth[mask].sum())
                        for name, mask in masks.items()}})
    return rows


def student_t(renderer, passes):
    """The t the core multiplied each pixel's noise sd by (two-sided, at the renderer's confidence;
    the core's Cornish-Fisher expansion, error_estimate.cpp)."""
    if passes < 2:
        return float("inf")
    z = NormalDist().inv_cdf(0.5 + 0.5 * renderer.settings["error_confidence"])
    z2, v = z * z, passes - 1.0
    g = (z * (z2 + 1) / 4, z * ((5 * z2 + 16) * z2 + 3) / 96, z * (((3 * z2 + 19) * z2 + 17) * z2 - 15) / 384,
         z * ((((79 * z2 + 776) * z2 + 1482) * z2 - 1920) * z2 - 945) / 92160)
    return z + sum(gi / v ** (i + 1) for i, gi in enumerate(g))


def mean_absolute(bias, sd):
    """Per pixel, the mean absolute value of a normal error of this bias and sd (PixelError's)."""
    b, sd = np.abs(bias), np.maximum(sd, 1e-30)
    erf = np.vectorize(math.erf, otypes=[float])
    with np.errstate(over="ignore", invalid="ignore"):  # the first pass: sd is inf
        return sd * math.sqrt(2 / math.pi) * np.exp(-0.5 * (b / sd) ** 2) + b * erf(b / (sd * math.sqrt(2)))


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


def report_blend(experiment, results, traces):
    rows = []
    for trace in traces:
        names = [k[len("covered_"):] for k in trace[0] if k.startswith("covered_")]
        for row in trace:
            if row["passes"] not in experiment["blend_checkpoints"]:
                continue
            for name in names:
                true, estimate = row[f"true_{name}"], row[f"estimate_{name}"]
                rows.append([row["scene"], row["passes"], f"{row['seconds']:.1f}", name, f"{true:.4f}",
                             f"{estimate:.4f}", f"{estimate / true:.2f}" if true > 0 else "",
                             f"{row[f'covered_{name}']:.3f}"])
    results.table(["scene", "passes", "s", "region", "true error", "estimate", "estimate / true", "covered"],
                  rows, title="Bundled .blend scenes by region (stochastic hit points; the error as above, "
                              "within the region; coverage at the same confidence)")
    rows = []
    for trace in traces:
        for target in experiment["targets"]:
            true_pass, true_seconds = first_pass_at(trace, "true", target)
            stop_pass, stop_seconds = first_pass_at(trace, "bound", target)
            rows.append([trace[0]["scene"], f"{target:.0%}", pass_cell(true_pass, true_seconds),
                         pass_cell(stop_pass, stop_seconds),
                         "" if None in (true_pass, stop_pass) else f"{stop_pass / true_pass:.2f}"])
    results.table(["scene", "target", "true error first meets it: pass (s)",
                   "the estimate does (target_error stops): pass (s)", "passes, stop / truth"], rows,
                  title="Bundled .blend scenes: time to target")
    results.note("\nThe references' own noise (relative rms): "
                 + ", ".join(f"{t[0]['scene']} {t[0]['ref_noise']:.4f}" for t in traces) + ".")


def plot_blend(traces, path):
    plt = plots.pyplot()
    fig, axes = plt.subplots(1, len(traces), figsize=(4.2 * len(traces), 3.8), squeeze=False)
    for ax, trace in zip(axes[0], traces):
        passes = [r["passes"] for r in trace]
        names = [k[len("covered_"):] for k in trace[0] if k.startswith("covered_") and k != "covered_emitter"]
        for i, name in enumerate(names):
            ax.loglog(passes, [r[f"true_{name}"] for r in trace], f"C{i}-", lw=1.0, label=f"{name}: true")
            ax.loglog(passes, [r[f"estimate_{name}"] for r in trace], f"C{i}--", lw=1.0, label=f"{name}: estimate")
        ax.set_title(trace[0]["scene"], fontsize=9)
        ax.set_xlabel("passes")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=5, ncol=2)
    axes[0][0].set_ylabel("mean abs. error / mean luminance, by region")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


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
    if experiment.get("blend_scenes"):
        results.note(f"\nBundled .blend scenes at their PPM references' size, exported as F12 does, "
                     f"{experiment['blend_photons_per_pass']:,} photons per pass (the references'), stochastic hit "
                     f"points, {experiment['blend_passes']} passes.")
        blend_traces = []
        for scene_name in experiment["blend_scenes"]:
            trace = trace_blend_render(experiment, scene_name)
            for row in trace:
                results.row(**row)
            blend_traces.append(trace)
        report_blend(experiment, results, blend_traces)
        plot_blend(blend_traces, results.path("error_vs_passes_blend.png"))
    return True
