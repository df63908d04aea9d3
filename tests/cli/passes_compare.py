"""Depth, Normal, Object Index and Material Index passes, when the view layer enables them, agree
with Cycles' passes.

Runs inside Blender 3.4 (the bpy 5.0 module writes only Combined into multilayer EXRs, even
for Cycles, so the passes cannot be read back there):

    blender -b --factory-startup --python-exit-code 1 -P tests/cli/passes_compare.py -- OUT_DIR

Writes OUT_DIR/passes.json with the agreement figures; test_passes.py checks them.
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_side import add_quad, fresh_scene, multilayer_output, read_pass  # noqa: E402  (numpy, add-on)

# isort: split
import bpy  # noqa: E402
import numpy as np  # noqa: E402


def scene_with_passes():
    scene = fresh_scene()
    floor = add_quad(scene, "floor", [(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)])
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(0.3, 0.8, 0.6), segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    sphere = bpy.context.object
    floor.pass_index, sphere.pass_index = 3, 9
    sphere.data.materials.append(bpy.data.materials.new("ball"))
    sphere.data.materials[0].pass_index = 6  # the floor has no material: index 0
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.0, 2.5), (math.radians(55), 0.0, 0.0)
    cam.data.shift_x = 0.05
    scene.collection.objects.link(cam)
    scene.camera = cam
    multilayer_output(scene, 48, 36)
    layer = bpy.context.view_layer
    layer.use_pass_z = layer.use_pass_normal = True
    layer.use_pass_object_index = layer.use_pass_material_index = True
    return scene


def render(scene, engine, path):
    scene.render.engine = engine
    if engine == "CYCLES":
        scene.cycles.samples, scene.cycles.use_denoising = 16, False
        scene.cycles.use_adaptive_sampling = False
        scene.cycles.filter_width = 0.01  # samples at pixel centres, like the pass rays
    else:
        scene.ppm.passes, scene.ppm.photons_per_pass = 1, 1000
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return (read_pass(path, "Depth", "Z")[..., 0], read_pass(path, "Normal", "XYZ"),
            read_pass(path, "IndexOB", "X")[..., 0], read_pass(path, "IndexMA", "X")[..., 0])



def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene = scene_with_passes()
    scene.cycles.use_denoising = False
    depth_c, normal_c, object_c, material_c = render(scene, "CYCLES", os.path.join(out, "cycles.exr"))
    depth_p, normal_p, object_p, material_p = render(scene, "PPM", os.path.join(out, "ppm.exr"))
    # Away from silhouettes (where a pixel's samples straddle two depths) the passes should agree.
    neighbours = np.stack([np.roll(depth_c, s, a) for s in (-1, 1) for a in (0, 1)])
    smooth = np.abs(depth_c - np.median(neighbours, axis=0)) < 0.05
    dots = (normal_p * normal_c).sum(axis=-1)[smooth]
    figures = {"shape": list(depth_p.shape), "smooth_fraction": float(smooth.mean()),
               "max_depth_error": float(np.abs(depth_p[smooth] / depth_c[smooth] - 1).max()),
               "median_normal_dot": float(np.median(dots)), "normals_within_11deg": float((dots > 0.98).mean()),
               "object_index_equal": float((object_p == object_c)[smooth].mean()),
               "material_index_equal": float((material_p == material_c)[smooth].mean()),
               "object_indices": sorted(set(np.unique(object_c).tolist())),
               "material_indices": sorted(set(np.unique(material_c).tolist()))}
    with open(os.path.join(out, "passes.json"), "w") as f:
        json.dump(figures, f)
    print("passes_compare:", figures, flush=True)


main()
