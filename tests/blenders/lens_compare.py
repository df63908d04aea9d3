"""PPM against Cycles in a closed room lit mostly indirectly, through lenses from 5 mm to 5000 mm and
orthographic cameras of tiny and huge scale, in the running Blender.

A cube room of diffuse walls (albedo 0.5) with a point light at its centre; the camera stands inside
by one wall and looks at the opposite one. Through a long lens or a small orthographic window a
pixel covers far less than the spacing of a pass's photons: before the initial radius followed the
photon density, PPM's indirect light there was missing or blotchy (a 5000 mm lens gave half of
Cycles' median). The image's mean and median must agree with Cycles' (no clamping, enough bounces
for a closed room) within 5%.

    .venv/bin/python tests/blenders/lens_compare.py                       # Blender 5.0 (bpy); likewise 4.2-5.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/lens_compare.py
"""

import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare

TOLERANCE = 0.05
# name -> (room side in metres, camera: ("lens", millimetres) or ("ortho", scale in room sides))
CASES = {
    "lens_5mm": (4.0, ("lens", 5.0)),
    "lens_35mm": (4.0, ("lens", 35.0)),
    "lens_5000mm": (4.0, ("lens", 5000.0)),
    "ortho_tiny": (4.0, ("ortho", 0.0025)),   # a 1 cm window
    "ortho_huge_room": (4000.0, ("ortho", 0.5)),  # a 2 km window on a 4 km room
}


def build(case):
    side, (camera_type, value) = CASES[case]
    cycles_compare.reset()
    scene = bpy.context.scene
    wall = cycles_compare.diffuse_material("wall", (cycles_compare.ALBEDO,) * 3)
    mesh = bpy.data.meshes.new("room")
    h = side / 2
    corners = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]  # facing in
    mesh.from_pydata(corners, [], faces)
    mesh.materials.append(wall)
    scene.collection.objects.link(bpy.data.objects.new("room", mesh))
    # A light off-centre, so that the wall the camera sees is not uniform.
    cycles_compare.add_light("POINT", 100.0 * side * side, (0.2 * h, 0.3 * h, 0.1 * h), shadow_soft_size=0.0)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.location = (0.0, -0.95 * h, 0.0)
    cam.rotation_euler = (math.radians(90), 0.0, 0.0)  # looks along +y at the far wall
    if camera_type == "lens":
        cam.data.lens = value
    else:
        cam.data.type, cam.data.ortho_scale = "ORTHO", value * side
    cam.data.clip_start, cam.data.clip_end = 1e-3 * side, 10.0 * side
    scene.collection.objects.link(cam)
    scene.camera = cam
    set_world_black()
    render = scene.render
    render.resolution_x, render.resolution_y, render.resolution_percentage = 32, 24, 100
    render.image_settings.file_format, render.image_settings.color_depth = "OPEN_EXR", "32"
    render.use_file_extension = False
    return scene


def set_world_black():
    world = bpy.data.worlds.new("black")
    world.color = (0.0, 0.0, 0.0)
    bpy.context.scene.world = world


def compare(case, workdir, samples=128, passes=24):
    build(case)
    # A closed room: 0.5^32 of the light is left after Cycles' last bounce.
    images = cycles_compare.render_with_both_engines(case, workdir, samples, passes, bounces=32)
    cycles, ppm = (images[engine].mean(axis=2) for engine in ("CYCLES", "PPM"))
    return {"case": case, "blender": bpy.app.version_string,
            "mean_error": float(ppm.mean() / cycles.mean() - 1.0),
            "median_error": float(np.median(ppm) / np.median(cycles) - 1.0),
            "ppm_peak_over_median": float(ppm.max() / np.median(ppm))}


def compare_cases(samples=128, passes=24):
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for case in CASES:
            row = compare(case, workdir, samples, passes)
            rows.append(row)
            print(f"lens_compare: Blender {row['blender']} {case:16s} mean {100 * row['mean_error']:+.2f}% "
                  f"median {100 * row['median_error']:+.2f}% PPM peak/median {row['ppm_peak_over_median']:.2f}",
                  flush=True)
    return rows


def main():
    try:
        rows = compare_cases()
    finally:
        cycles_compare.unregister_checkout_addon()
    failed = [r["case"] for r in rows if max(abs(r["mean_error"]), abs(r["median_error"])) > TOLERANCE]
    if failed:
        print(f"lens_compare: more than {100 * TOLERANCE:.0f}% off: {', '.join(failed)}", flush=True)
        sys.exit(1)


if __name__ == "__main__":
    main()
