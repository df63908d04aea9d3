"""The noise of fog lit by a small light, at a fixed number of passes: a case of
tests/blenders/media_compare.py (world_fog: the World's fog around a 10 cm point light; fog_room: the
same fog in a box around the camera and the light) exported as the add-on does (bpy, Blender 5.0) at
160x120, rendered twice (seeds 7 and 8) with the add-on's settings, and the relative MSE of one
render estimated from the two's difference, mean((a - b)^2) / 2 / mean(image)^2. One JSON line per
case:

    .venv/bin/python tools/fog_light_noise.py world_fog fog_room --passes 64

Run it from a folder without files named like standard-library modules (bpy's rule)."""

import argparse
import json
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [os.path.join(ROOT, "tests", "blenders"), os.path.join(ROOT, "addon")]

import bpy  # noqa: E402

import media_compare  # noqa: E402
import ppm_core  # noqa: E402
import ppm_render  # noqa: E402
from ppm_render import export, properties  # noqa: E402
from ppm_render.export.camera import Frame  # noqa: E402

SEEDS = (7, 8)


def noise(case, passes):
    media_compare.build(case)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 160, 120, 100
    settings = properties.media_settings(properties.render_settings(scene), print)
    core, _, _ = export.build_scene(ppm_core, bpy.context.evaluated_depsgraph_get(),
                                    Frame.from_render_settings(scene.render), print)
    images, start = [], time.monotonic()
    for seed in SEEDS:
        renderer = ppm_core.Renderer(core, **{**settings, "seed": seed, "threads": 2})
        renderer.run(passes=passes)
        images.append(renderer.image()[..., :3])
    a, b = images
    mean = (a + b) / 2
    relative_mse = float(((a - b) ** 2).mean() / 2 / mean.mean() ** 2)
    return {"case": case, "passes": passes, "seconds": round(time.monotonic() - start, 1),
            "noise": round(relative_mse, 5), "mean": round(float(mean.mean()), 5)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("cases", nargs="+", choices=("world_fog", "fog_room", "smoke_in_fog_room", "fog_cube_spot"))
    parser.add_argument("--passes", type=int, default=64)
    args = parser.parse_args()
    ppm_render.register()
    for case in args.cases:
        print(json.dumps(noise(case, args.passes)), flush=True)


if __name__ == "__main__":
    main()
