"""PPM against Cycles through lenses from 35 mm to 5000 mm and a 1 cm orthographic window, on an open
scene: a diffuse floor, a diffuse 1 m cube on it and a 1000 W point light, the camera 6 m from what it
looks at and 20 degrees above it (the issue "a 5000 mm lens is 19% too bright").

`--target`: the middle of the cube's face turned to the camera (`cube`), the floor in front of the cube
(`floor`), the cube's bottom edge (`edge`) or its vertical front-right edge (`cube_corner`). `--light`:
`front` lights the face the camera sees, `back` leaves it lit only by the floor. Each case is saved once,
then rendered by Cycles (no clamping, denoising or adaptive sampling, box filter, 32 bounces) for each
`--cycles-seeds` and by PPM through the add-on (the add-on's stochastic hit points and 4 adaptive eye
samples) for each `--ppm-seeds`. Printed: PPM / Cycles (first Cycles seed) of the image's median, mean and
central quarter, as the mean over the PPM seeds with its standard error and the spread of one render;
and Cycles' second seed against its first.

Through a long lens every pixel's gather disc (the photons' spacing, about 8 cm here) covers the whole
field of view (4.3 cm at 5000 mm), so all pixels share their photons and one render's image is one
estimate: compare means over seeds, not one render.

    .venv/bin/python tests/blenders/telephoto_compare.py --target cube --light back --ppm-seeds $(seq 1 16)
    .venv/bin/python tests/blenders/telephoto_compare.py --target edge --light front --ppm-seeds 1 2 3 4
"""

import argparse
import json
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare

DISTANCE = 6.0  # metres from the camera to what it looks at
TARGETS = {"cube": (0.0, -0.5, 0.5), "floor": (0.0, -1.5, 0.0), "edge": (0.0, -0.5, 0.0),
           "cube_corner": (0.5, -0.5, 0.5)}
LIGHTS = {"front": (1.5, -2.0, 3.0), "back": (0.5, 2.5, 2.5)}  # "back": the face the camera sees is unlit
CASES = {"lens_35mm": ("lens", 35.0), "lens_50mm": ("lens", 50.0), "lens_200mm": ("lens", 200.0),
         "lens_1000mm": ("lens", 1000.0), "lens_5000mm": ("lens", 5000.0), "ortho_1cm": ("ortho", 0.01)}


def build(case, target, light="front"):
    camera_type, value = CASES[case]
    cycles_compare.reset()
    scene = bpy.context.scene
    grey = cycles_compare.diffuse_material("grey", (cycles_compare.ALBEDO,) * 3)
    cycles_compare.plane("floor", 10.0, 0.0, grey)
    cycles_compare.cube("cube", (0.0, 0.0, 0.5), 1.0, grey)
    cycles_compare.add_light("POINT", 1000.0, LIGHTS[light], shadow_soft_size=0.0)
    # The camera 6 m from the target, looking at it from the front and 20 degrees above.
    look = np.array(TARGETS[target])
    pitch = math.radians(20.0)
    eye = look + DISTANCE * np.array([0.0, -math.cos(pitch), math.sin(pitch)])
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location = eye
    cam.rotation_euler = (math.radians(90.0) - pitch, 0.0, 0.0)  # looks along +y, tilted down by the pitch
    if camera_type == "lens":
        cam.data.lens = value
    else:
        cam.data.type, cam.data.ortho_scale = "ORTHO", value
    cam.data.clip_start, cam.data.clip_end = 1e-3, 100.0
    scene.collection.objects.link(cam)
    scene.camera = cam
    cycles_compare.set_world(0.0)
    cycles_compare.set_exr_output(scene)
    return scene


def ratios(ppm, cycles):
    h, w = ppm.shape
    centre = (slice(h // 4, 3 * h // 4), slice(w // 4, 3 * w // 4))
    return {"median": float(np.median(ppm) / np.median(cycles)), "mean": float(ppm.mean() / cycles.mean()),
            "centre": float(ppm[centre].mean() / cycles[centre].mean())}


def render(blend, engine, seed, workdir, samples, passes, photons, hit_points):
    """The mean of the channels of one render of the saved scene."""
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    if engine == "CYCLES":
        cycles_compare.configure_cycles(scene, samples, bounces=32)
        scene.cycles.seed = seed
    else:
        cycles_compare.configure_ppm(scene, passes)
        scene.ppm.photons_per_pass, scene.ppm.hit_points = photons, hit_points
        scene.ppm.adaptive_samples = 4  # the add-on's default, as a user renders
        scene.ppm.seed, scene.ppm.animated_seed = seed, False
    name = os.path.splitext(os.path.basename(blend))[0]
    return cycles_compare.render_to_array(scene, os.path.join(workdir, f"{name}_{engine}.exr")).mean(axis=2)


def compare(case, target, light, workdir, samples, passes, photons, cycles_seeds, ppm_seeds, hit_points, keep):
    """PPM / Cycles of the image's median, mean and centre for each PPM seed against the first Cycles
    seed; their mean over the seeds and its standard error; Cycles' second seed against its first."""
    build(case, target, light)
    blend = os.path.join(workdir, f"{case}_{target}_{light}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    images = {f"CYCLES{s}": render(blend, "CYCLES", s, workdir, samples, passes, photons, hit_points)
              for s in cycles_seeds}
    images.update({f"PPM{s}": render(blend, "PPM", s, workdir, samples, passes, photons, hit_points)
                   for s in ppm_seeds})
    if keep:
        np.savez(os.path.join(keep, f"{case}_{target}_{light}.npz"), **images)
    reference = images[f"CYCLES{cycles_seeds[0]}"]
    per_seed = [ratios(images[f"PPM{s}"], reference) for s in ppm_seeds]
    row = {"case": case, "target": target, "light": light, "ppm_seeds": list(ppm_seeds), "per_seed": per_seed}
    for key in ("median", "mean", "centre"):
        values = np.array([r[key] for r in per_seed])
        row[key] = float(values.mean())
        row[key + "_stderr"] = float(values.std(ddof=1) / math.sqrt(len(values))) if len(values) > 1 else 0.0
        row[key + "_spread"] = float(values.std(ddof=1)) if len(values) > 1 else 0.0
    if len(cycles_seeds) > 1:
        row["cycles_seed_ratio"] = ratios(images[f"CYCLES{cycles_seeds[1]}"], reference)
    return row


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("--cases", nargs="*", default=list(CASES))
    parser.add_argument("--target", choices=list(TARGETS), default="cube")
    parser.add_argument("--light", choices=list(LIGHTS), default="front")
    parser.add_argument("--samples", type=int, default=256)
    parser.add_argument("--passes", type=int, default=60)
    parser.add_argument("--photons", type=int, default=200_000)
    parser.add_argument("--hit-points", choices=["AUTO", "FIXED", "STOCHASTIC"], default="AUTO")
    parser.add_argument("--cycles-seeds", type=int, nargs="*", default=[1, 2])
    parser.add_argument("--ppm-seeds", type=int, nargs="*", default=[1])
    parser.add_argument("--keep", help="folder for the images (npz)")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    rows = []
    print(f"telephoto_compare: Blender {bpy.app.version_string}, ppm_core from "
          f"{__import__('ppm_core').__file__}", flush=True)
    try:
        with tempfile.TemporaryDirectory() as workdir:
            for case in args.cases:
                row = compare(case, args.target, args.light, workdir, args.samples, args.passes, args.photons,
                              args.cycles_seeds, args.ppm_seeds, args.hit_points, args.keep)
                rows.append(row)
                extra = ""
                if "cycles_seed_ratio" in row:
                    c = row["cycles_seed_ratio"]
                    extra = f"  (Cycles seed 2/1: median {c['median']:.4f} mean {c['mean']:.4f})"
                print(f"telephoto_compare: {case:12s} {args.target}/{args.light} PPM/Cycles over "
                      f"{len(args.ppm_seeds)} seeds: median {row['median']:.4f} +- {row['median_stderr']:.4f} "
                      f"mean {row['mean']:.4f} +- {row['mean_stderr']:.4f} centre {row['centre']:.4f}; "
                      f"one render's spread {row['median_spread']:.4f}{extra}", flush=True)
    finally:
        cycles_compare.unregister_checkout_addon()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
