"""Depth of field: POST and LENS against a Cycles reference, error versus time;
and fixed (PPM) versus stochastic (SPPM) hit points with depth of field off.

    .venv/bin/python bench/dof_modes.py [--cycles-samples N] [--times 4 8 16 32]

Renders blend_scenes/cornell_dof.blend at 320x240 through the add-on (Blender
5.0 module) and through Cycles with the same camera (no clamping, denoising or
adaptive sampling). Writes bench/plots/dof_modes.png and prints markdown tables:
relative RMSE over the image and by region (occlusion and texture edges: top
10% of the reference's gradient; highlights: top 2% of its luminance; the rest).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
import bpy  # noqa: E402

import ppm_render  # noqa: E402

W, H = 320, 240
BLEND = os.path.join(ROOT, "blend_scenes", "cornell_dof.blend")


def open_scene(use_dof):
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()  # before loading, so the file's PPM engine setting is recognised
    bpy.ops.wm.open_mainfile(filepath=BLEND)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = W, H, 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.camera.data.dof.use_dof = use_dof
    return scene


def render(scene, path):
    scene.render.filepath = path
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    image = bpy.data.images.load(path, check_existing=False)
    pixels = np.empty(W * H * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(H, W, 4)[..., :3], seconds


def cycles_reference(use_dof, samples, workdir):
    scene = open_scene(use_dof)
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device, c.samples, c.seed = "CPU", samples, 7
    c.use_adaptive_sampling = c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = c.caustics_refractive = True
    scene.render.threads_mode, scene.render.threads = "FIXED", 2
    return render(scene, os.path.join(workdir, f"cycles_{use_dof}.exr"))


def ppm(dof_mode, hit_points, seconds, workdir, use_dof=True):
    scene = open_scene(use_dof)
    scene.render.engine = "PPM"
    p = scene.ppm
    p.dof_mode, p.time_limit, p.passes, p.threads, p.seed = dof_mode, seconds, 1_000_000, 2, 3
    p.photons_per_pass = 50_000
    p.hit_points = hit_points.upper()
    return render(scene, os.path.join(workdir, f"ppm_{dof_mode}_{hit_points}_{seconds}.exr"))


def regions(reference):
    lum = reference.mean(axis=2)
    gy, gx = np.gradient(lum)
    grad = np.hypot(gx, gy)
    edges = grad >= np.quantile(grad, 0.90)
    highlights = lum >= np.quantile(lum, 0.98)
    rest = ~(edges | highlights)
    return {"all": np.ones_like(edges), "edges": edges & ~highlights, "highlights": highlights, "rest": rest}


def rel_rmse(image, reference, mask):
    return float(np.sqrt(np.mean((image[mask] - reference[mask]) ** 2)) / np.mean(reference[mask]))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cycles-samples", type=int, default=1024)
    parser.add_argument("--times", type=float, nargs="+", default=[4, 8, 16, 32])
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    workdir = tempfile.mkdtemp(prefix="dof_modes_")
    curves = {}
    for use_dof, variants in ((True, [("POST", "fixed"), ("LENS", "stochastic")]),
                              (False, [("OFF", "fixed"), ("OFF", "stochastic")])):
        reference, ref_seconds = cycles_reference(use_dof, args.cycles_samples, workdir)
        masks = regions(reference)
        state = "on" if use_dof else "off"
        print(f"\nDoF {state}: Cycles reference {args.cycles_samples} spp in {ref_seconds:.0f} s\n")
        print("| mode | hit points | seconds | rel. RMSE all | edges | highlights | rest |")
        print("|---|---|---|---|---|---|---|")
        for dof_mode, hit_points in variants:
            points = []
            for seconds in args.times:
                image, took = ppm(dof_mode, hit_points, seconds, workdir, use_dof)
                errors = {k: rel_rmse(image, reference, m) for k, m in masks.items()}
                points.append((took, errors["all"]))
                print(f"| {dof_mode} | {hit_points} | {took:.1f} | {errors['all']:.4f} | {errors['edges']:.4f} | "
                      f"{errors['highlights']:.4f} | {errors['rest']:.4f} |", flush=True)
            curves[f"{dof_mode} {hit_points} (DoF {'on' if use_dof else 'off'})"] = points
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, points in curves.items():
        t, e = zip(*points)
        ax.loglog(t, e, "o-", label=label)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("relative RMSE vs Cycles")
    ax.set_title("cornell_dof, 320x240, 2 threads")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    os.makedirs(os.path.join(ROOT, "bench", "plots"), exist_ok=True)
    out = os.path.join(ROOT, "bench", "plots", "dof_modes.png")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"\nplot: {out}")


if __name__ == "__main__":
    main()
