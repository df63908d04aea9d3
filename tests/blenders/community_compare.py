"""PPM against Cycles for community_library.py's materials, in the running Blender (bpy 5.0): each
on a ball (radius 1) standing on a grey diffuse floor under a small sun and a grey world, seen by an
orthographic camera tilted 20 degrees down. Cycles renders twice (seeds 1 and 2: their spread says
how converged the reference is), unclamped, 16 bounces of each kind (cycles_compare.configure_cycles);
PPM once through the add-on. For each material: the ball's mean colour (pixels inside 90% of its
outline) in both, their ratio per channel, the Cycles seed spread, the floor's mean ratio (pixels
outside 110% of the ball's outline: light the ball sends onwards) and the add-on's warnings (the
scene exported as a render exports it). Reports only; a material more than TOLERANCE off without a
warning is listed as a silent mismatch at the end.

    nice -n 10 .venv/bin/python tests/blenders/community_compare.py [--json out.json] [--warnings-only]
        [--samples 1024] [--passes 256] [NAME ...]
"""

import argparse
import json
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import community_library
import numpy as np

import cycles_compare

SIZE = 48
ORTHO_SCALE = 2.5
TILT = math.radians(20)
TOLERANCE = 0.10
DARK = 0.02  # a channel darker than this is compared in absolute terms


def build(name):
    cycles_compare.reset()
    scene = bpy.context.scene
    cycles_compare.ball("ball", (0.0, 0.0, 0.0), 1.0, community_library.make_material(name))
    cycles_compare.plane("floor", 20.0, -1.0, cycles_compare.diffuse_material("floor", (0.5, 0.5, 0.5)))
    cycles_compare.set_world(0.5)
    cycles_compare.add_light("SUN", 3.0, (0.0, 0.0, 5.0), rotation=(math.radians(40), 0.0, math.radians(-30)),
                             angle=math.radians(5))
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location = (0.0, -5.0 * math.cos(TILT), 5.0 * math.sin(TILT))
    cam.rotation_euler = (math.radians(90) - TILT, 0.0, 0.0)
    cam.data.type, cam.data.ortho_scale = "ORTHO", ORTHO_SCALE
    scene.collection.objects.link(cam)
    scene.camera = cam
    render = scene.render
    render.resolution_x = render.resolution_y = SIZE
    render.resolution_percentage = 100
    render.image_settings.file_format, render.image_settings.color_depth = "OPEN_EXR", "32"
    render.use_file_extension = False
    render.film_transparent = False


def radius_map():
    """Each pixel centre's distance from the ball's centre in ball radii (the ball projects to a
    centred disc in an orthographic view aimed at it)."""
    centres = (np.arange(SIZE) + 0.5) / SIZE * ORTHO_SCALE - ORTHO_SCALE / 2
    x, y = np.meshgrid(centres, centres)
    return np.sqrt(x * x + y * y)


def export_warnings():
    """The add-on's warnings for the current scene, exported as a render exports it."""
    from ppm_render import core, export

    warnings = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    export.export_scene(core.load(), depsgraph, warnings.append)
    return warnings


def render(name, workdir, samples, passes):
    blend = os.path.join(workdir, f"{name}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    images = {}
    for engine, seed in (("CYCLES", 1), ("CYCLES", 2), ("PPM", 1)):
        bpy.ops.wm.open_mainfile(filepath=blend)
        scene = bpy.context.scene
        if engine == "CYCLES":
            cycles_compare.configure_cycles(scene, samples, bounces=16)
            scene.cycles.seed = seed
        else:
            cycles_compare.configure_ppm(scene, passes)
            scene.ppm.photons_per_pass = 50_000
            scene.ppm.max_bounces = 16
        key = f"{engine}{seed}"
        images[key] = cycles_compare.render_to_array(scene, os.path.join(workdir, f"{name}_{key}.exr"))
    return images


def ratio(a, b):
    """a / b per channel (a - b + 1 where b is darker than DARK)."""
    return np.where(b > DARK, a / np.maximum(b, 1e-9), 1.0 + (a - b) / DARK)


def compare(name, workdir, samples, passes, warnings_only=False):
    build(name)
    row = {"warnings": export_warnings()}
    if warnings_only:
        return row
    images = render(name, workdir, samples, passes)
    r = radius_map()
    ball, floor = r < 0.9, r > 1.1
    c1, c2, ppm = (images[k][ball].astype(float).mean(axis=0) for k in ("CYCLES1", "CYCLES2", "PPM1"))
    cycles = (c1 + c2) / 2
    f1, f2, f_ppm = (images[k][floor].astype(float).mean(axis=0) for k in ("CYCLES1", "CYCLES2", "PPM1"))
    f_cycles = (f1 + f2) / 2
    row.update(cycles=cycles.round(4).tolist(), ppm=ppm.round(4).tolist(),
               ratio=ratio(ppm, cycles).round(3).tolist(),
               seed_spread=float(np.max(np.abs(c1 - c2) / np.maximum(cycles, DARK))),
               floor_ratio=ratio(f_ppm, f_cycles).round(3).tolist())
    row["error"] = float(np.max(np.abs(np.array(row["ratio"]) - 1.0)))
    row.update(floor_blocks(images, floor))
    return row


def floor_blocks(images, floor, k=6):
    """The worst k x k block of floor (blocks wholly outside 110% of the ball's outline, grey = mean
    of the channels): PPM over Cycles, and the two Cycles seeds' largest difference there."""
    def blocks(image):
        grey = image.astype(float).mean(axis=2)
        return grey.reshape(SIZE // k, k, SIZE // k, k).mean(axis=(1, 3))
    inside = floor.astype(float).reshape(SIZE // k, k, SIZE // k, k).mean(axis=(1, 3)) == 1.0
    c1, c2, ppm = (blocks(images[key])[inside] for key in ("CYCLES1", "CYCLES2", "PPM1"))
    cycles = (c1 + c2) / 2
    worst = int(np.argmax(np.abs(ppm / cycles - 1.0)))
    return {"floor_block_ratio": round(float(ppm[worst] / cycles[worst]), 3),
            "floor_block_seed_spread": float(np.max(np.abs(c1 - c2) / cycles))}


def describe(row):
    flag = f"{len(row['warnings'])} warning(s)" if row["warnings"] else "no warning"
    if "ratio" not in row:
        return flag + "".join(f"\n    {w}" for w in row["warnings"])
    return (f"cycles {row['cycles']} ppm {row['ppm']} ratio {row['ratio']} worst {100 * row['error']:.1f}% "
            f"seeds {100 * row['seed_spread']:.1f}% floor {row['floor_ratio']} worst floor block "
            f"{row['floor_block_ratio']} (seeds {100 * row['floor_block_seed_spread']:.1f}%) {flag}"
            + "".join(f"\n    {w}" for w in row["warnings"]))


def table(rows):
    print("\n| material | PPM/Cycles ball mean (R, G, B) | worst | Cycles seed spread | floor ratio | "
          "worst floor block | warned |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        rgb = lambda c: "(" + ", ".join(f"{x:.3f}" for x in c) + ")"  # noqa: E731
        print(f"| {row['case']} | {rgb(row['ratio'])} | {100 * row['error']:.1f}% | {100 * row['seed_spread']:.1f}% | "
              f"{rgb(row['floor_ratio'])} | {row['floor_block_ratio']:.3f} | {'yes' if row['warnings'] else 'no'} |")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser()
    parser.add_argument("names", nargs="*")
    parser.add_argument("--json")
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--passes", type=int, default=256)
    parser.add_argument("--warnings-only", action="store_true")
    args = parser.parse_args(argv)
    names = args.names or list(community_library.MATERIALS)
    rows = []
    try:
        with tempfile.TemporaryDirectory() as workdir:
            for name in names:
                row = {"case": name, **compare(name, workdir, args.samples, args.passes, args.warnings_only)}
                rows.append(row)
                print(f"community_compare: {name:40s} {describe(row)}", flush=True)
                if args.json:
                    with open(args.json, "w") as f:
                        json.dump(rows, f, indent=1)
    finally:
        cycles_compare.unregister_checkout_addon()
    if args.warnings_only:
        return
    table(rows)
    silent = [row["case"] for row in rows if row["error"] > TOLERANCE and not row["warnings"]]
    print(f"\ncommunity_compare: more than {100 * TOLERANCE:.0f}% off without a warning: "
          f"{', '.join(silent) or 'none'}")


if __name__ == "__main__":
    main()
