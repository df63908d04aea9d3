"""Emit and Env agree with Cycles' passes: a floor, an emissive panel standing on it, a mirror ball
showing both, and a world colour above the horizon. What camera rays see at no bounce is in them;
what the mirror shows is in neither (Cycles counts it as glossy light).

Runs inside Blender 3.4 (the bpy modules write only Combined into multilayer EXRs):

    blender -b --factory-startup --python-exit-code 1 -P tests/cli/light_passes_compare.py -- OUT_DIR

Writes OUT_DIR/light_passes.json with the figures; test_passes.py checks them.
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


def scene_with_light_passes():
    scene = fresh_scene()
    add_quad(scene, "floor", [(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)],
             node_material("floor", "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1.0)))
    add_quad(scene, "panel", [(-2.0, 2, 0.2), (-0.6, 2, 0.2), (-0.6, 2, 1.6), (-2.0, 2, 1.6)],
             node_material("glow", "ShaderNodeEmission", Color=(1.0, 0.6, 0.3, 1.0), Strength=3.0))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(0.9, 1.0, 0.6), segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    bpy.context.object.data.materials.append(
        node_material("mirror", "ShaderNodeBsdfGlossy", Color=(0.9, 0.9, 0.9, 1.0), Roughness=0.0))
    scene.world = bpy.data.worlds.new("sky")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.1, 0.2, 0.4, 1.0)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.0, 1.0), (math.radians(85), 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    multilayer_output(scene, 64, 48)
    layer = bpy.context.view_layer
    layer.use_pass_emit = layer.use_pass_environment = layer.use_pass_z = True
    return scene


def render(scene, engine, path):
    scene.render.engine = engine
    if engine == "CYCLES":
        plain_cycles(scene, 64)
    else:
        scene.ppm.passes, scene.ppm.photons_per_pass = 1, 1000
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    return read_pass(path, "Emit", "RGB"), read_pass(path, "Env", "RGB"), read_pass(path, "Depth", "Z")[..., 0]


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene = scene_with_light_passes()
    emit_c, env_c, depth_c = render(scene, "CYCLES", os.path.join(out, "cycles.exr"))
    emit_p, env_p, _ = render(scene, "PPM", os.path.join(out, "ppm.exr"))
    # Away from silhouettes (a pixel's samples straddling two surfaces, or a surface and the sky).
    interior = (np.abs(neighbourhood(depth_c) - depth_c) <= 0.05 * np.abs(depth_c)).all(axis=0)
    figures = {"shape": list(depth_c.shape), "interior_fraction": float(interior.mean())}
    for name, c, p in (("emit", emit_c, emit_p), ("env", env_c, env_p)):
        lit = interior & (c.max(axis=-1) > 0)
        figures[name] = {"pixels_lit_in_cycles": int(lit.sum()),
                         "max_relative_difference": float((np.abs(p - c)[lit] / c[lit].max(axis=-1)[:, None]).max()),
                         "lit_only_in_ppm": int((interior & (c.max(axis=-1) == 0) & (p.max(axis=-1) > 0)).sum()),
                         "mean_cycles": c[lit].mean(axis=0).tolist(), "mean_ppm": p[lit].mean(axis=0).tolist()}
    with open(os.path.join(out, "light_passes.json"), "w") as f:
        json.dump(figures, f, indent=1)
    print("light_passes_compare:", json.dumps(figures), flush=True)


main()
