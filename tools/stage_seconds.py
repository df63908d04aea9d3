"""Where a pass's time goes for a .blend: exports it as the add-on does (bpy, Blender 5.0) and renders
`--passes` passes of `--photons` photons at `--size`, printing the core's seconds per stage
(Renderer.stats()["seconds"]) as one JSON line:

    .venv/bin/python tools/stage_seconds.py blend_scenes/cloud.blend --size 160 120 --passes 3

Run it from a folder without files named like standard-library modules (bpy's rule); time only on
an idle machine."""

import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import bpy  # noqa: E402

import ppm_core  # noqa: E402
import ppm_render  # noqa: E402
from ppm_render import export  # noqa: E402
from ppm_render.export.camera import Frame  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("blend")
    parser.add_argument("--size", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--passes", type=int, default=3)
    parser.add_argument("--photons", type=int, default=100_000)
    args = parser.parse_args()
    ppm_render.register()
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend))
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    warnings = []
    core, _, _ = export.build_scene(ppm_core, bpy.context.evaluated_depsgraph_get(),
                                    Frame.from_render_settings(scene.render), warnings.append)
    renderer = ppm_core.Renderer(core, hit_points="stochastic", photons_per_pass=args.photons, threads=2, seed=1)
    renderer.run(passes=args.passes)
    seconds = {k: round(v, 3) for k, v in renderer.stats()["seconds"].items() if isinstance(v, float) and v > 0.0}
    print(json.dumps({"blend": args.blend, "size": args.size, "passes": args.passes, "seconds": seconds,
                      "warnings": warnings}))


if __name__ == "__main__":
    main()
