"""Denoising Albedo and Denoising Normal agree with Cycles' (its Denoising Data passes) on a floor with
a diffuse, a mirror and a glass ball: the features of the first rough surface, seen through mirrors
and glass with their tint.

Runs inside Blender 3.4 (the bpy modules write only Combined into multilayer EXRs):

    blender -b --factory-startup --python-exit-code 1 -P tests/cli/denoising_compare.py -- OUT_DIR

Writes OUT_DIR/denoising.json with the figures per object; test_passes.py checks them.
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_side import (  # noqa: E402  (puts numpy and the add-on on the path first)
    add_quad,
    fresh_scene,
    multilayer_output,
    neighbourhood,
    node_material,
    plain_cycles,
    read_pass,
)

# isort: split
import bpy  # noqa: E402
import numpy as np  # noqa: E402

OBJECTS = {1: "floor", 2: "diffuse ball", 3: "mirror ball", 4: "glass ball"}


def ball(location, material, index):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=location, segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    obj = bpy.context.object
    obj.pass_index = index
    obj.data.materials.append(material)


def scene_with_balls():
    scene = fresh_scene()
    add_quad(scene, "floor", [(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)],
             node_material("floor", "ShaderNodeBsdfDiffuse", Color=(0.3, 0.6, 0.4, 1.0))).pass_index = 1
    ball((-1.1, 0.6, 0.5), node_material("red", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.1, 0.1, 1.0)), 2)
    ball((0.0, 0.9, 0.5), node_material("mirror", "ShaderNodeBsdfGlossy", Color=(0.9, 0.8, 0.5, 1.0),
                                        Roughness=0.0), 3)
    ball((1.1, 0.6, 0.5), node_material("glass", "ShaderNodeBsdfGlass", Color=(1.0, 1.0, 1.0, 1.0),
                                        Roughness=0.0, IOR=1.45), 4)
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.location = (0.0, -1.0, 4.0)
    scene.collection.objects.link(lamp)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.2, 2.2), (math.radians(62), 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    multilayer_output(scene, 64, 48)
    layer = bpy.context.view_layer
    layer.use_pass_object_index = True
    layer.cycles.denoising_store_passes = True
    return scene


def render(scene, engine, path):
    scene.render.engine = engine
    if engine == "CYCLES":
        plain_cycles(scene, 256)
        c = scene.cycles
        c.max_bounces = c.glossy_bounces = c.transmission_bounces = 12
    else:
        s = scene.ppm
        s.passes, s.photons_per_pass, s.samples_per_pixel, s.denoising_data = 1, 1000, 64, True
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return (read_pass(path, "Denoising Albedo", "RGB"), read_pass(path, "Denoising Normal", "XYZ"),
            read_pass(path, "IndexOB", "X")[..., 0])


def interior(index):
    """Pixels whose 3 x 3 neighbourhood is one object (no silhouette in the pixel's footprint)."""
    return (neighbourhood(index) == index).all(axis=0)


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene = scene_with_balls()
    albedo_c, normal_c, index_c = render(scene, "CYCLES", os.path.join(out, "cycles.exr"))
    albedo_p, normal_p, _ = render(scene, "PPM", os.path.join(out, "ppm.exr"))
    inside = interior(index_c)
    figures = {"shape": list(index_c.shape)}
    for value, name in OBJECTS.items():
        mask = inside & (index_c == value)
        c, p = albedo_c[mask].mean(axis=0), albedo_p[mask].mean(axis=0)
        unit_c = normal_c[mask] / np.maximum(np.linalg.norm(normal_c[mask], axis=-1, keepdims=True), 1e-6)
        unit_p = normal_p[mask] / np.maximum(np.linalg.norm(normal_p[mask], axis=-1, keepdims=True), 1e-6)
        figures[name] = {"pixels": int(mask.sum()), "albedo_cycles": c.tolist(), "albedo_ppm": p.tolist(),
                         "albedo_mean_difference": float(np.abs(albedo_p[mask] - albedo_c[mask]).mean()),
                         "normal_median_dot": float(np.median((unit_c * unit_p).sum(axis=-1))),
                         "normal_length_cycles": float(np.linalg.norm(normal_c[mask], axis=-1).mean()),
                         "normal_length_ppm": float(np.linalg.norm(normal_p[mask], axis=-1).mean())}
    with open(os.path.join(out, "denoising.json"), "w") as f:
        json.dump(figures, f, indent=1)
    print("denoising_compare:", json.dumps(figures, indent=1), flush=True)


main()
