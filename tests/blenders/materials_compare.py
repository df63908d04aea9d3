"""PPM against Cycles for every material of material_library.py, in the running Blender: each on a
ball under a small sun (or `--light`: see LIGHTS) and a grey world, seen through an orthographic
camera. The same saved file is rendered by both engines (Cycles 1024 samples, 16 bounces of each
kind; PPM 64 passes of 50,000 photons, 10,000 on a ball that stores next to none
(material_library.PHOTON_LIT), more passes for MORE_PASSES; in_blender.py, in every Blender version:
256 and 32). The mean colour over the ball
(pixels well inside its outline) must agree within 5% in each channel (absolute 0.005 for a
channel darker than 0.1) for every material but the documented approximations, which are reported
only. Prints one line per material and, with --table, a markdown table for the README; --sheet
PATH draws Cycles | PPM | difference for each (docs/materials_compare.png).

    .venv/bin/python tests/blenders/materials_compare.py [--table] [--sheet PATH] [--light L] [NAME ...]  # 5.0
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/materials_compare.py [-- NAME ...]
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare
import material_library

SIZE = 64
ORTHO_SCALE = 2.5  # the ball (radius 1) fills 80% of the frame
TOLERANCE = 0.05
DARK = 0.1
SHEET = {}  # name -> {"CYCLES": rgb, "PPM": rgb}, for the contact sheet


# The key light (`--light`): a sun of 5 degrees (a disc in the sky, met by sampled directions), or
# lights of no size, which only light sampling reaches: a sun of no angle and a point light.
LIGHTS = {
    "sun": lambda: cycles_compare.add_light("SUN", 3.0, (0.0, 0.0, 5.0), angle=math.radians(5),
                                            rotation=(math.radians(40), 0.0, math.radians(-30))),
    "sun0": lambda: cycles_compare.add_light("SUN", 3.0, (0.0, 0.0, 5.0), angle=0.0,
                                             rotation=(math.radians(40), 0.0, math.radians(-30))),
    "point": lambda: cycles_compare.add_light("POINT", 600.0, (2.0, -3.0, 3.0), shadow_soft_size=0.0),
}


def build(name, light="sun"):
    cycles_compare.reset()
    scene = bpy.context.scene
    cycles_compare.ball("ball", (0.0, 0.0, 0.0), 1.0, material_library.make_material(name))
    cycles_compare.set_world(0.5)
    LIGHTS[light]()
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location, cam.rotation_euler = (0.0, -5.0, 0.0), (math.radians(90), 0.0, 0.0)
    cam.data.type, cam.data.ortho_scale = "ORTHO", ORTHO_SCALE
    scene.collection.objects.link(cam)
    scene.camera = cam
    render = scene.render
    render.resolution_x = render.resolution_y = SIZE
    render.resolution_percentage = 100
    render.image_settings.file_format, render.image_settings.color_depth = "OPEN_EXR", "32"
    render.use_file_extension = False
    render.film_transparent = False


def ball_mask():
    """Pixels whose centre lies inside 90% of the ball's outline."""
    centres = (np.arange(SIZE) + 0.5) / SIZE * ORTHO_SCALE - ORTHO_SCALE / 2
    x, y = np.meshgrid(centres, centres)
    return x * x + y * y < 0.9 ** 2


def configure_for(name):
    """PPM's settings for material `name`: photons where they light the ball (PHOTON_LIT); elsewhere
    a fifth of them, which leaves the image alike (its eye samples and direct light are drawn from the
    seed, the pass and the pixel alone) at a fifth of the photon tracing, most of the render's time."""
    def configure(scene, engine):
        if engine == "PPM":
            scene.ppm.photons_per_pass = 50_000 if name in material_library.PHOTON_LIT else 10_000
            scene.ppm.max_bounces = 16
    return configure


# PPM's passes times this for materials whose picture converges slowly: the car paint's sun glint in
# a coat of roughness 0.05 over a metal both eye paths follow (measured in 5.0, Cycles at 256 and
# 1024 samples: PPM 6.5% dark in green at 32 passes, 2.6% at 128, 0.1% at 256).
MORE_PASSES = {"proc_car_paint": 4}


def compare(name, workdir, samples=1024, passes=64, light="sun"):
    build(name, light)
    if name not in material_library.APPROXIMATED:  # (reported only: no need to converge further)
        passes *= MORE_PASSES.get(name, 1)
    images = cycles_compare.render_with_both_engines(name, workdir, samples, passes, bounces=16,
                                                     configure=configure_for(name))
    mask = ball_mask()
    SHEET[name] = images
    cycles, ppm = (images[e][mask].mean(axis=0) for e in ("CYCLES", "PPM"))
    error = np.where(cycles > DARK, np.abs(ppm - cycles) / np.maximum(cycles, 1e-9), np.abs(ppm - cycles) / DARK)
    return {"blender": bpy.app.version_string, "cycles": cycles.round(4).tolist(), "ppm": ppm.round(4).tolist(),
            "error": float(error.max()), "approximated": name in material_library.APPROXIMATED,
            **per_pixel(images, mask)}


def per_pixel(images, mask):
    """Relative RMSE of PPM against Cycles over the ball: of single pixels, and of 4x4 block means
    (blocks wholly on the ball), which leaves the noise of the two renders mostly out."""
    cycles, ppm = (images[e].mean(axis=2) for e in ("CYCLES", "PPM"))
    pixel = np.sqrt(np.mean((ppm[mask] - cycles[mask]) ** 2)) / cycles[mask].mean()
    k = 4
    blocks = lambda a: a.reshape(SIZE // k, k, SIZE // k, k).mean(axis=(1, 3))  # noqa: E731
    inside = blocks(mask.astype(float)) == 1.0
    a, b = blocks(ppm)[inside], blocks(cycles)[inside]
    return {"pixel_rel_rmse": float(pixel), "block_rel_rmse": float(np.sqrt(np.mean((a - b) ** 2)) / b.mean())}


def describe(row):
    return (f"cycles {row['cycles']} ppm {row['ppm']} worst channel {100 * row['error']:.1f}%"
            + (" (documented approximation)" if row["approximated"] else ""))


def failed(row):
    return not row["approximated"] and row["error"] > TOLERANCE


def table(rows):
    print("\n| material | Cycles mean RGB | PPM mean RGB | mean, worst channel | pixels, rel. RMSE | "
          "4x4 blocks, rel. RMSE |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        note = " (approximation)" if row["approximated"] else ""
        rgb = lambda c: "(" + ", ".join(f"{x:.3f}" for x in c) + ")"  # noqa: E731
        print(f"| {row['case']}{note} | {rgb(row['cycles'])} | {rgb(row['ppm'])} | {100 * row['error']:.1f}% | "
              f"{100 * row['pixel_rel_rmse']:.1f}% | {100 * row['block_rel_rmse']:.1f}% |")


def compare_cases(names=None, samples=1024, passes=64, light="sun"):
    """compare() for each material (all by default), printing a line each; the rows."""
    names = names or list(material_library.MATERIALS)
    return cycles_compare.run_cases("materials_compare", names,
                                    lambda name, workdir: compare(name, workdir, samples, passes, light), describe)


def contact_sheet(rows, path):
    """Cycles | PPM | 4 x |difference| for each material, four materials to a row (matplotlib)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def tone(x):
        return np.clip(x / (1.0 + x), 0.0, 1.0) ** (1 / 2.2)

    per_row = 4
    lines = (len(rows) + per_row - 1) // per_row
    fig, axes = plt.subplots(lines, 3 * per_row, figsize=(3 * per_row * 1.1, lines * 1.25), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    for i, row in enumerate(rows):
        images = SHEET[row["case"]]
        cycles, ppm = images["CYCLES"][::-1], images["PPM"][::-1]  # Blender's rows are bottom-up
        panels = (tone(cycles), tone(ppm), np.clip(4.0 * np.abs(ppm - cycles), 0.0, 1.0))
        for j, (panel, label) in enumerate(zip(panels, ("Cycles", "PPM", "4x diff"))):
            ax = axes[i // per_row][3 * (i % per_row) + j]
            ax.imshow(panel, interpolation="nearest")
            ax.set_title(f"{row['case']}\n{label}" if j == 0 else label, fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    if "--" in sys.argv:
        args = sys.argv[sys.argv.index("--") + 1:]
    else:  # the blender binary's own arguments are not ours
        args = [] if os.path.basename(sys.argv[0]).startswith("blender") else sys.argv[1:]
    sheet = args[args.index("--sheet") + 1] if "--sheet" in args else None
    light = args[args.index("--light") + 1] if "--light" in args else "sun"
    names = [a for a in args if not a.startswith("-") and a not in (sheet, light)] or list(material_library.MATERIALS)

    def run():
        rows = compare_cases(names, light=light)
        if "--table" in args:
            table(rows)
        if "--sheet" in args:
            contact_sheet(rows, args[args.index("--sheet") + 1])
        return rows

    cycles_compare.run_as_script("materials_compare", run, failed)


if __name__ == "__main__":
    main()
