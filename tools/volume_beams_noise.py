"""Beams against points at equal time on a bundled fog scene: the volumetric caustic (fog_caustic, its
spot's radius 1 m as in equal_time_caustic) or god rays without glass (--scene fog_shafts): for each
of volume_beams off and on, two renders of `seconds` each (seeds 7 and 8) through the core with the
add-on's export and settings, and per region (bench/harness/regions.py) their noise, the relative
MSE of one render estimated from the two's difference, mean((a - b)^2 / (reference^2 + EPS)) / 2,
and the mean of the two over the Cycles reference's (bench/references/<scene>_cycles.exr). One JSON
line per variant:

    .venv/bin/python tools/volume_beams_noise.py --seconds 10 [--scene fog_shafts]

Run it from a folder without files named like standard-library modules (bpy's rule), on an idle
machine: it is a timing."""

import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402

import ppm_core  # noqa: E402
from bench.harness import regions  # noqa: E402
from bench.harness.addon_route import open_scene  # noqa: E402
from bench.harness.exr_io import read_exr  # noqa: E402
from bench.harness.metrics import EPS  # noqa: E402
from ppm_render import export, properties  # noqa: E402
from ppm_render.export.camera import Frame  # noqa: E402

WIDTH, HEIGHT = 160, 120
SEEDS = (7, 8)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--scene", choices=("fog_caustic", "fog_shafts"), default="fog_caustic")
    args = parser.parse_args()
    reference, _ = read_exr(os.path.join(ROOT, "bench", "references", f"{args.scene}_cycles.exr"))
    reference = reference[..., :3]
    masks = regions.region_masks(args.scene, reference, WIDTH, HEIGHT)
    scene = open_scene(args.scene, WIDTH, HEIGHT)
    if args.scene == "fog_caustic":
        bpy.data.objects["spot"].data.shadow_soft_size = 1.0
    settings = properties.media_settings(properties.render_settings(scene), print)
    core, _, _ = export.build_scene(ppm_core, bpy.context.evaluated_depsgraph_get(),
                                    Frame.from_render_settings(scene.render), print)
    for beams in (False, True):
        images, passes = [], []
        for seed in SEEDS:
            renderer = ppm_core.Renderer(core, **{**settings, "seed": seed, "threads": 2, "volume_beams": beams})
            renderer.run(seconds=args.seconds)
            images.append(renderer.image()[..., :3])
            passes.append(renderer.stats()["passes"])
        a, b = images
        noise = ((a - b) ** 2 / (reference ** 2 + EPS)).mean(axis=2) / 2
        mean = (a + b) / 2
        print(json.dumps({"scene": args.scene, "seconds": args.seconds, "volume_beams": beams, "passes": passes,
                          "noise": {k: round(float(noise[m].mean()), 5) for k, m in masks.items()},
                          "mean_over_cycles": {k: round(float(mean[m].mean() / reference[m].mean()), 4)
                                               for k, m in masks.items()}}), flush=True)


if __name__ == "__main__":
    main()
