"""PPM against Cycles for stereo 3D (Output > Stereoscopy), in the running Blender: both views are
rendered, each from its own eye, as Cycles renders them.

cycles_compare's floor under a point light with a ball on it, seen through a stereo camera of a
large interocular distance (off-axis, so the views differ by parallax and shift). Each view is
written to its own file (`_L`, `_R`); the mean radiance of each view's 4x3 image blocks must agree
with Cycles' within 3%, and the two views must differ.

    .venv/bin/python tests/blenders/stereo_compare.py                 # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/stereo_compare.py
"""

import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare


def build():
    cycles_compare.build("point")
    cycles_compare.ball("ball", (0.3, 0.1, 0.3), 0.5, cycles_compare.diffuse_material("clay", (0.7, 0.4, 0.3)))
    scene = bpy.context.scene
    scene.render.use_multiview, scene.render.views_format = True, "STEREO_3D"
    scene.render.image_settings.views_format = "INDIVIDUAL"
    stereo = scene.camera.data.stereo
    stereo.convergence_mode, stereo.interocular_distance = "OFFAXIS", 0.3


def read_view(path):
    """RGB of one view's EXR, through OpenImageIO: Blender 3.4 to 4.5 load such a file as an empty
    image (the view's name in its header makes it a multi-view image of one view)."""
    import OpenImageIO as oiio

    pixels = oiio.ImageBuf(path).get_pixels(oiio.FLOAT)
    return np.asarray(pixels)[..., :3]


def render_views(workdir, samples, passes):
    """{engine: {"L": rgb, "R": rgb}} of the scene just built, saved once and opened for each engine."""
    blend = os.path.join(workdir, "stereo.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    images = {}
    for engine in ("CYCLES", "PPM"):
        bpy.ops.wm.open_mainfile(filepath=blend)
        scene = bpy.context.scene
        cycles_compare.configure_cycles(scene, samples) if engine == "CYCLES" else cycles_compare.configure_ppm(
            scene, passes)
        scene.render.filepath = os.path.join(workdir, f"stereo_{engine}.exr")
        bpy.ops.render.render(write_still=True)
        images[engine] = {eye: read_view(os.path.join(workdir, f"stereo_{engine}_{eye}.exr")) for eye in ("L", "R")}
    return images


def compare(samples=256, passes=32):
    build()
    with tempfile.TemporaryDirectory() as workdir:
        images = render_views(workdir, samples, passes)
    row = {"blender": bpy.app.version_string}
    for eye in ("L", "R"):
        cycles, ppm = (cycles_compare.block_means(images[e][eye]) for e in ("CYCLES", "PPM"))
        row[f"max_block_error_{eye}"] = float(np.abs((ppm - cycles) / np.maximum(cycles, cycles_compare.DARK)).max())
    row["views_differ"] = float(np.abs(images["PPM"]["L"] - images["PPM"]["R"]).mean())
    print(f"stereo_compare: Blender {row['blender']} worst block left {100 * row['max_block_error_L']:.2f}% "
          f"right {100 * row['max_block_error_R']:.2f}%, views differ by {row['views_differ']:.4f}", flush=True)
    return row


def main():
    try:
        row = compare()
    finally:
        cycles_compare.unregister_checkout_addon()
    if max(row["max_block_error_L"], row["max_block_error_R"]) > cycles_compare.TOLERANCE or not row["views_differ"]:
        sys.exit(1)


if __name__ == "__main__":
    main()
