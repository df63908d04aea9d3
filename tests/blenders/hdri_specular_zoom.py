"""Whether PPM and Cycles agree on the light the sun of an HDRI sends through a specular chain once
its image is resolved: a case of hdri_specular_compare.py is rendered by Cycles, the brightest pixel
of one ball found (the sun's glint in the mirror ball, its image through the glass ball), and both
engines render again from the same camera position through a lens ZOOM times as long aimed through
that pixel (64x64), then through the brightest pixel of that view (Cycles, 64 samples), so that
the sun's image lies in the middle of the frame and spans many pixels. Prints the zoomed image's
mean for two seeds of each engine.

    .venv/bin/python tests/blenders/hdri_specular_zoom.py --case studio_front --ball glass [--zoom 24]
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/hdri_specular_zoom.py -- [...]
"""

import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np
from mathutils import Vector

import cycles_compare
import hdri_specular_compare as cases


def aim_through_pixel(scene, row, col):
    """Turns the scene camera (in place) to look through the centre of pixel (row from the bottom, col)."""
    cam = scene.camera
    frame = [Vector(v) for v in cam.data.view_frame(scene=scene)]
    top_right, bottom_left = frame[0], frame[2]
    w, h = scene.render.resolution_x, scene.render.resolution_y
    local = Vector((bottom_left.x + (col + 0.5) / w * (top_right.x - bottom_left.x),
                    bottom_left.y + (row + 0.5) / h * (top_right.y - bottom_left.y), bottom_left.z))
    direction = (cam.matrix_world.to_3x3() @ local).normalized()
    cam.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def zoom_compare(case, ball, zoom, workdir, samples, passes):
    cases.build(case, (96, 64))
    scene = bpy.context.scene
    masks = cases.regions(scene, cases.balls_of(case))
    cases.configure_cycles(scene, 256, 1)
    rgb = cycles_compare.render_to_array(scene, os.path.join(workdir, "full.exr")).mean(axis=2)
    row, col = np.unravel_index(np.where(masks[ball], rgb, -1.0).argmax(), rgb.shape)
    aim_through_pixel(scene, row, col)
    scene.camera.data.lens *= zoom
    scene.render.resolution_x = scene.render.resolution_y = 64
    bpy.context.view_layer.update()
    cases.configure_cycles(scene, 64, 1)
    rgb = cycles_compare.render_to_array(scene, os.path.join(workdir, "aim.exr")).mean(axis=2)
    aim_through_pixel(scene, *np.unravel_index(rgb.argmax(), rgb.shape))
    blend = os.path.join(workdir, "zoom.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    means = {}
    for engine, seed in (("CYCLES", 1), ("CYCLES", 2), ("PPM", 1), ("PPM", 2)):
        bpy.ops.wm.open_mainfile(filepath=blend)
        scene = bpy.context.scene
        if engine == "CYCLES":
            cases.configure_cycles(scene, samples, seed)
        else:
            cases.configure_ppm(scene, passes, seed)
        image = cycles_compare.render_to_array(scene, os.path.join(workdir, f"{engine}_{seed}.exr"))
        means[f"{engine.lower()}{seed}"] = float(image.mean())
    return (int(row), int(col)), means


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else \
        (sys.argv[1:] if os.path.basename(sys.argv[0]) == os.path.basename(__file__) else [])
    parser = argparse.ArgumentParser()
    parser.add_argument("--case", default="studio_front", choices=cases.CASES)
    parser.add_argument("--ball", default="glass")
    parser.add_argument("--zoom", type=float, default=24.0)
    parser.add_argument("--samples", type=int, default=1024)
    parser.add_argument("--passes", type=int, default=64)
    args = parser.parse_args(argv)
    try:
        with tempfile.TemporaryDirectory() as workdir:
            pixel, means = zoom_compare(args.case, args.ball, args.zoom, workdir, args.samples, args.passes)
    finally:
        cycles_compare.unregister_checkout_addon()
    cycles = 0.5 * (means["cycles1"] + means["cycles2"])
    ppm = 0.5 * (means["ppm1"] + means["ppm2"])
    print(f"hdri_specular_zoom: Blender {bpy.app.version_string} {args.case} {args.ball} pixel {pixel} x{args.zoom:g}: "
          + " ".join(f"{k} {v:.5f}" for k, v in means.items()) + f" ppm/cycles {ppm / cycles:.4f}", flush=True)


if __name__ == "__main__":
    main()
