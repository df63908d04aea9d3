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
from blender_side import read_pass  # noqa: E402  (puts numpy and the add-on on the path first)

# isort: split
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import ppm_render  # noqa: E402

OBJECTS = {1: "floor", 2: "diffuse ball", 3: "mirror ball", 4: "glass ball"}


def node_material(name, kind, colour, **inputs):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    shader, output = nodes.new(kind), nodes.new("ShaderNodeOutputMaterial")
    shader.inputs["Color"].default_value = (*colour, 1.0)
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    material.node_tree.links.new(shader.outputs[0], output.inputs["Surface"])
    return material


def ball(location, material, index):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=location, segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    obj = bpy.context.object
    obj.pass_index = index
    obj.data.materials.append(material)


def scene_with_balls():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if not hasattr(bpy.types.Scene, "ppm"):
        ppm_render.register()
    scene = bpy.context.scene
    mesh = bpy.data.meshes.new("floor")
    mesh.from_pydata([(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)], [], [(0, 1, 2, 3)])
    floor = bpy.data.objects.new("floor", mesh)
    floor.pass_index = 1
    floor.data.materials.append(node_material("floor", "ShaderNodeBsdfDiffuse", (0.3, 0.6, 0.4)))
    scene.collection.objects.link(floor)
    ball((-1.1, 0.6, 0.5), node_material("red", "ShaderNodeBsdfDiffuse", (0.8, 0.1, 0.1)), 2)
    ball((0.0, 0.9, 0.5), node_material("mirror", "ShaderNodeBsdfGlossy", (0.9, 0.8, 0.5), Roughness=0.0), 3)
    ball((1.1, 0.6, 0.5), node_material("glass", "ShaderNodeBsdfGlass", (1.0, 1.0, 1.0), Roughness=0.0,
                                        IOR=1.45), 4)
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    lamp.location = (0.0, -1.0, 4.0)
    scene.collection.objects.link(lamp)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.2, 2.2), (math.radians(62), 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = 64, 48, 100
    r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    r.use_file_extension = False
    layer = bpy.context.view_layer
    layer.use_pass_object_index = True
    layer.cycles.denoising_store_passes = True
    return scene


def render(scene, engine, path):
    scene.render.engine = engine
    if engine == "CYCLES":
        c = scene.cycles
        c.samples, c.use_denoising, c.use_adaptive_sampling = 256, False, False
        c.pixel_filter_type, c.filter_width = "BOX", 1.0  # the pixel's square, as our eye samples
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
    padded = np.pad(index, 1, mode="edge")
    same = [padded[1 + dy:padded.shape[0] - 1 + dy, 1 + dx:padded.shape[1] - 1 + dx] == index
            for dy in (-1, 0, 1) for dx in (-1, 0, 1)]
    return np.logical_and.reduce(same)


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
