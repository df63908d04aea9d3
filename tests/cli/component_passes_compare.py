"""Diffuse, Glossy and Transmission Direct, Indirect and Color agree with Cycles' passes: a floor
under a large lamp, a mirror ball, a glass ball casting a caustic and a rough Principled ball, in a dim
world. Both engines render converged (Cycles: no clamping, no glossy filter, bounces as PPM's;
PPM: enough passes). Cycles stores Direct and Indirect divided by Color, as PPM's add-on does: the
figures compare each class's light times its colour, i.e. its part of Combined, region by region,
and the colours where both define them alike.

Runs inside Blender 3.4 (the bpy modules write only Combined into multilayer EXRs):

    blender -b --factory-startup --python-exit-code 1 -P tests/cli/component_passes_compare.py -- OUT_DIR

Writes OUT_DIR/component_passes.json with the figures; test_passes.py checks them.
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

KINDS = ("Diff", "Gloss", "Trans")
REGIONS = {"floor": 1, "mirror": 2, "glass": 3, "principled": 4}


def ball(name, location, radius, material, index):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=location, segments=64, ring_count=32)
    bpy.ops.object.shade_smooth()
    obj = bpy.context.object
    obj.name, obj.pass_index = name, index
    obj.data.materials.append(material)


def scene_with_component_passes():
    scene = fresh_scene()
    floor = add_quad(scene, "floor", [(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)],
                     node_material("floor", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.5, 0.4, 1.0)))
    floor.pass_index = REGIONS["floor"]
    ball("mirror", (-1.1, 1.2, 0.55), 0.55, node_material("mirror", "ShaderNodeBsdfGlossy", Color=(0.9, 0.9, 0.9, 1.0),
                                                          Roughness=0.0), REGIONS["mirror"])
    ball("glass", (0.2, 0.4, 0.5), 0.5, node_material("glass", "ShaderNodeBsdfGlass", Color=(1.0, 1.0, 1.0, 1.0),
                                                      Roughness=0.0, IOR=1.45), REGIONS["glass"])
    ball("principled", (1.3, 1.4, 0.5), 0.5,
         node_material("principled", "ShaderNodeBsdfPrincipled", **{"Base Color": (0.2, 0.4, 0.8, 1.0),
                                                                     "Roughness": 0.5}), REGIONS["principled"])
    # A large lamp: Cycles' paths find it through the mirror and the glass (a sun's caustics would be
    # fireflies in Cycles, and a delta sun's none at all).
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "AREA"))
    lamp.data.energy, lamp.data.size = 400.0, 2.0
    lamp.location = (1.0, -1.0, 4.0)
    scene.collection.objects.link(lamp)
    scene.world = bpy.data.worlds.new("sky")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.08, 0.12, 1.0)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location, cam.rotation_euler = (0.0, -3.2, 1.6), (math.radians(70), 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    multilayer_output(scene, 64, 48)
    layer = bpy.context.view_layer
    layer.use_pass_z = layer.use_pass_object_index = True
    for kind in ("diffuse", "glossy", "transmission"):
        for part in ("direct", "indirect", "color"):
            setattr(layer, f"use_pass_{kind}_{part}", True)
    return scene


def render(scene, engine, path):
    scene.render.engine = engine
    if engine == "CYCLES":
        plain_cycles(scene, 1024)
        c = scene.cycles
        c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
        c.blur_glossy = 0.0
        c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 12
        c.caustics_reflective = c.caustics_refractive = True
    else:
        scene.ppm.passes, scene.ppm.photons_per_pass, scene.ppm.seed = 256, 100_000, 3
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    out = {f"{k}{p}": read_pass(path, f"{k}{p}", "RGB") for k in KINDS for p in ("Dir", "Ind", "Col")}
    out["Depth"] = read_pass(path, "Depth", "Z")[..., 0]
    out["IndexOB"] = read_pass(path, "IndexOB", "X")[..., 0]
    out["Combined"] = read_pass(path, "Combined", "RGB")
    return out


def region_figures(cycles, ppm, mask):
    """Per class: the mean of its Direct and Indirect light times Color (its part of Combined) in both
    engines, and of its Color."""
    out = {"pixels": int(mask.sum()), "Combined": {"cycles": cycles["Combined"][mask].mean(axis=0).tolist(),
                                                   "ppm": ppm["Combined"][mask].mean(axis=0).tolist()}}
    for k in KINDS:
        for part in ("Dir", "Ind"):
            c = (cycles[k + part] * cycles[k + "Col"])[mask].mean(axis=0)
            p = (ppm[k + part] * ppm[k + "Col"])[mask].mean(axis=0)
            out[k + part] = {"cycles": c.tolist(), "ppm": p.tolist()}
        out[k + "Col"] = {"cycles": cycles[k + "Col"][mask].mean(axis=0).tolist(),
                          "ppm": ppm[k + "Col"][mask].mean(axis=0).tolist()}
    return out


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene = scene_with_component_passes()
    cycles = render(scene, "CYCLES", os.path.join(out, "cycles.exr"))
    ppm = render(scene, "PPM", os.path.join(out, "ppm.exr"))
    depth = cycles["Depth"]
    interior = (np.abs(neighbourhood(depth) - depth) <= 0.05 * np.abs(depth)).all(axis=0)
    same_object = (neighbourhood(cycles["IndexOB"]) == cycles["IndexOB"]).all(axis=0)
    figures = {"shape": list(depth.shape), "regions": {}}
    for name, index in REGIONS.items():
        figures["regions"][name] = region_figures(cycles, ppm, interior & same_object & (cycles["IndexOB"] == index))
    # Combined rebuilt from PPM's passes: the three classes' (Dir + Ind) * Col (no Emit or Env is in view
    # but the sky, which no region includes).
    rebuilt = sum((ppm[k + "Dir"] + ppm[k + "Ind"]) * ppm[k + "Col"] for k in KINDS)
    ground = cycles["IndexOB"] > 0
    figures["rebuilt_max_relative"] = float(np.abs(rebuilt - ppm["Combined"])[ground].max() /
                                            ppm["Combined"][ground].max())
    with open(os.path.join(out, "component_passes.json"), "w") as f:
        json.dump(figures, f, indent=1)
    print("component_passes_compare:", json.dumps(figures), flush=True)


main()
