"""Depth of field: POST and LENS against a Cycles reference, error versus time; and fixed (PPM)
versus stochastic (SPPM) hit points with depth of field off.

Renders `scene` (blend_scenes/cornell_dof.blend) at `width` x `height` through the add-on (the
Blender 5.0 module, harness.addon_route) for each of `variants` (the camera's depth of field on or
off, the add-on's dof_mode and hit points) and each of `times` (seconds of rendering), with
`photons_per_pass` and 2 threads, against Cycles with `cycles_samples` samples and the same camera
(addon_route's Cycles settings: no clamping, denoising or adaptive sampling), one reference per
depth-of-field setting. Reports relative RMSE (harness.metrics.rel_rmse) over the image and by
region of the reference: edges (occlusion and texture edges: top 10% of its gradient), highlights
(top 2% of its luminance) and the rest; plots error against wall time to dof_modes.png."""

from __future__ import annotations

import numpy as np

from harness import addon_route, metrics

DOF = "camera.data.dof.use_dof"  # the setting, a property path from the scene
EDGE_QUANTILE, HIGHLIGHT_QUANTILE = 0.90, 0.98


def regions(reference):
    """Masks of the reference: all, edges (without highlights), highlights, the rest."""
    lum = reference.mean(axis=2)
    gy, gx = np.gradient(lum)
    grad = np.hypot(gx, gy)
    edges = grad >= np.quantile(grad, EDGE_QUANTILE)
    highlights = lum >= np.quantile(lum, HIGHLIGHT_QUANTILE)
    rest = ~(edges | highlights)
    return {"all": np.ones_like(edges), "edges": edges & ~highlights, "highlights": highlights, "rest": rest}


def cycles_reference(experiment, use_dof):
    return addon_route.render_cycles(experiment["scene"], experiment["width"], experiment["height"],
                                     seed=experiment["cycles_seed"], passes=experiment["cycles_samples"],
                                     threads=experiment["threads"], **{DOF: use_dof})


def ppm(experiment, variant, seconds):
    return addon_route.render_ppm(experiment["scene"], experiment["width"], experiment["height"],
                                  seed=experiment["ppm_seed"], seconds=seconds, threads=experiment["threads"],
                                  photons_per_pass=experiment["photons_per_pass"], dof_mode=variant["mode"],
                                  hit_points=variant["hit_points"].upper(), **{DOF: variant["dof"]})


def measure_variant(experiment, variant, reference, masks, results):
    """Renders `variant` for each time; its table rows and its (wall, error over all) points."""
    rows, points = [], []
    for seconds in experiment["times"]:
        render = ppm(experiment, variant, seconds)
        errors = {region: metrics.rel_rmse(render.image, reference, mask) for region, mask in masks.items()}
        points.append((render.wall, errors["all"]))
        results.row(dof=variant["dof"], mode=variant["mode"], hit_points=variant["hit_points"], seconds=seconds,
                    wall=render.wall, **{f"rel_rmse_{region}": e for region, e in errors.items()})
        rows.append([variant["mode"], variant["hit_points"], f"{render.wall:.1f}",
                     *(f"{errors[region]:.4f}" for region in ("all", "edges", "highlights", "rest"))])
    return rows, points


def plot(curves, experiment, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for label, points in curves.items():
        t, e = zip(*points)
        ax.loglog(t, e, "o-", label=label)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("relative RMSE vs Cycles")
    ax.set_title(f"{experiment['scene']}, {experiment['width']}x{experiment['height']}, "
                 f"{experiment['threads']} threads")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def run(experiment, results):
    curves = {}
    # One Cycles reference per depth-of-field setting, in the order the variants name them.
    for use_dof in dict.fromkeys(v["dof"] for v in experiment["variants"]):
        reference = cycles_reference(experiment, use_dof)
        masks = regions(reference.image)
        state = "on" if use_dof else "off"
        rows = []
        for variant in (v for v in experiment["variants"] if v["dof"] == use_dof):
            variant_rows, points = measure_variant(experiment, variant, reference.image, masks, results)
            rows += variant_rows
            curves[f"{variant['mode']} {variant['hit_points']} (DoF {state})"] = points
        results.table(["mode", "hit points", "seconds", "rel. RMSE all", "edges", "highlights", "rest"], rows,
                      title=f"DoF {state}: Cycles reference {experiment['cycles_samples']} spp in "
                            f"{reference.wall:.0f} s")
    plot(curves, experiment, results.path("dof_modes.png"))
    results.note(f"\nplot: {results.path('dof_modes.png')}")
