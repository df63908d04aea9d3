"""PPM against Cycles where a sun-bearing HDRI reaches the camera through specular chains only: a
mirror ball and a smooth glass ball (Principled BSDF, Transmission 1, IOR 1.5) under Blender's
sunrise.exr (its sun carries 57% of the light in 100 texels), turned by a Mapping node, optionally
over a grey floor; and the issue's studio scene (a diffuse, a rough gold, a smooth glass and a mirror
ball resting on a grey floor). Cycles is unclamped with 16 bounces of every kind and a box filter; it renders
with two seeds to show how converged it is. Compared: the mean radiance over each ball's pixels
(pixels whose four corners all see the ball, found by intersecting the camera's rays with the
spheres) and over the sky.

    .venv/bin/python tests/blenders/hdri_specular_compare.py [--case NAME ...] [--size W H]
        [--samples N] [--passes N] [--json out.json] [--keep DIR]
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/hdri_specular_compare.py -- [...]

Cases: "front" (the sun ahead of the camera, 8 degrees up: seen through the glass ball, a glint near
the mirror ball's rim), "behind" (the sun behind the camera: a glint in the middle of the mirror
ball, its reflection in the glass ball), each with "_floor" for a grey floor under the balls, and
"studio_front", "studio_behind", "studio_side", "studio_tilted" (a Mapping turn about every axis).

The sun's image in a ball (a glint in the mirror, the sun focused by the glass) covers a few percent
of one pixel or less: PPM's eye samples find it as a count of independent hits, so a render's ball
mean is noisy and skewed (its median below its mean) until hundreds of passes; Cycles' stratified
samples settle it much sooner. --ppm-seeds N averages N renders.
"""

import argparse
import json
import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy
import numpy as np

import cycles_compare

BALLS = {"mirror": ((-0.6, 0.0, 1.0), 0.5), "glass": ((0.6, 0.0, 1.0), 0.5)}
# The studio scene: balls resting on a grey floor, a diffuse one, rough gold, smooth glass and
# a mirror.
STUDIO_BALLS = {"diffuse": ((-1.35, 0.0, 0.4), 0.4), "gold": ((-0.45, 0.0, 0.4), 0.4),
                "glass": ((0.45, 0.0, 0.4), 0.4), "mirror": ((1.35, 0.0, 0.4), 0.4)}
# Mapping rotations (XYZ Euler, degrees) that put sunrise.exr's sun (texture azimuth -35.7, elevation
# 7.9 degrees) ahead of the camera, which looks along +Y, or behind it.
# "tilted" turns about every axis (the sun ahead, 29 degrees up).
TURNS = {"front": (0.0, 0.0, -130.0), "behind": (0.0, 0.0, 45.0), "side": (0.0, 0.0, -60.0),
         "tilted": (-20.0, 15.0, -120.0)}
CASES = ("front", "behind", "front_floor", "behind_floor", "studio_front", "studio_behind", "studio_side",
         "studio_tilted")


def balls_of(case):
    return STUDIO_BALLS if case.startswith("studio") else BALLS


def material_of(name):
    if name == "mirror":
        return principled("mirror", **{"Metallic": 1.0, "Roughness": 0.0, "Base Color": (0.9, 0.9, 0.9, 1.0)})
    if name == "glass":
        return principled("glass", **{"Transmission Weight": 1.0, "Roughness": 0.0, "IOR": 1.5,
                                      "Base Color": (1.0, 1.0, 1.0, 1.0)})
    if name == "gold":
        return principled("gold", **{"Metallic": 1.0, "Roughness": 0.3, "Base Color": (1.0, 0.77, 0.34, 1.0)})
    return principled("diffuse", **{"Roughness": 0.5, "Base Color": (0.6, 0.6, 0.6, 1.0),
                                    "Specular IOR Level" if bpy.app.version >= (4, 0, 0) else "Specular": 0.0})


def principled(name, **inputs):
    """A Principled BSDF material; socket names of 4.0+ mapped back for 3.x."""
    renamed = {"Transmission Weight": "Transmission"} if bpy.app.version < (4, 0, 0) else {}
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    node = next(n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    for socket, value in inputs.items():
        node.inputs[renamed.get(socket, socket)].default_value = value
    return mat


def set_world(turn):
    world = bpy.data.worlds.new("World")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    environment = nodes.new("ShaderNodeTexEnvironment")
    path = os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world", "sunrise.exr")
    environment.image = bpy.data.images.load(path)
    links.new(environment.outputs["Color"], background.inputs["Color"])
    coordinates, mapping = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = tuple(math.radians(a) for a in turn)
    links.new(coordinates.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
    bpy.context.scene.world = world


def build(case, size):
    cycles_compare.reset()
    scene = bpy.context.scene
    for name, (center, radius) in balls_of(case).items():
        material = material_of(name)
        bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=radius, location=center)
        obj = bpy.context.object
        obj.name = name
        bpy.ops.object.shade_smooth()
        obj.data.materials.append(material)
    if case.endswith("_floor") or case.startswith("studio"):
        cycles_compare.plane("floor", 6.0, 0.0, cycles_compare.diffuse_material("floor", (0.5, 0.5, 0.5)))
    if case.startswith("studio"):
        cycles_compare.side_camera((0.0, -4.5, 1.2), 35.0)
    else:
        cycles_compare.side_camera((0.0, -4.0, 1.4), 35.0)
    set_world(TURNS[case.split("_")[-1] if case.startswith("studio") else case.split("_")[0]])
    cycles_compare.set_exr_output(scene)
    scene.render.resolution_x, scene.render.resolution_y = size


def regions(scene, balls):
    """{name: bool mask (H, W), rows bottom-up as Blender stores images}: each ball's pixels whose
    four corners see it, and the sky (pixels whose corners see neither ball, nor the floor)."""
    bpy.context.view_layer.update()  # the camera's matrix_world as its location and rotation say
    cam = scene.camera
    w, h = scene.render.resolution_x, scene.render.resolution_y
    frame = [np.array(v) for v in cam.data.view_frame(scene=scene)]  # top right, bottom right, bottom left, top left
    top_right, bottom_left = frame[0], frame[2]
    xs = np.linspace(bottom_left[0], top_right[0], w + 1)
    ys = np.linspace(bottom_left[1], top_right[1], h + 1)
    gx, gy = np.meshgrid(xs, ys)
    local = np.stack([gx, gy, np.full_like(gx, bottom_left[2])], axis=-1)
    m = np.array(cam.matrix_world)
    dirs = local @ m[:3, :3].T
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    origin = m[:3, 3]

    def corners_all(hit):
        return hit[:-1, :-1] & hit[1:, :-1] & hit[:-1, 1:] & hit[1:, 1:]

    def corners_none(hit):
        return ~(hit[:-1, :-1] | hit[1:, :-1] | hit[:-1, 1:] | hit[1:, 1:])

    out, any_hit = {}, np.zeros(gx.shape, bool)
    for name, (center, radius) in balls.items():
        oc = origin - np.array(center)
        b = dirs @ oc
        disc = b * b - (oc @ oc - radius * radius)
        hit = (disc > 0.0) & (-b - np.sqrt(np.maximum(disc, 0.0)) > 0.0)
        out[name] = corners_all(hit)
        any_hit |= hit
    any_hit |= dirs[..., 2] < 0.0  # below the horizon: the floor, where there is one
    out["sky"] = corners_none(any_hit)
    return out


def configure_cycles(scene, samples, seed):
    cycles_compare.configure_cycles(scene, samples, bounces=16)
    c = scene.cycles
    c.seed = seed
    c.transparent_max_bounces = 16
    c.volume_bounces = 0


def configure_ppm(scene, passes, seed):
    """The add-on's defaults (stochastic hit points, adaptive eye samples), a fixed seed and passes."""
    scene.render.engine = "PPM"
    scene.ppm.passes = passes
    scene.ppm.time_limit = 0.0
    scene.ppm.photons_per_pass = 50_000
    scene.ppm.seed = seed
    scene.ppm.threads = 2


def compare(case, workdir, size, samples, passes, keep=None, ppm_seeds=1):
    build(case, size)
    blend = os.path.join(workdir, f"{case}.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    masks = regions(bpy.context.scene, balls_of(case))
    row = {"case": case, "blender": bpy.app.version_string, "pixels": {k: int(v.sum()) for k, v in masks.items()}}
    runs = [("CYCLES", 1), ("CYCLES", 2)] + [("PPM", seed) for seed in range(1, ppm_seeds + 1)]
    for engine, seed in runs:
        bpy.ops.wm.open_mainfile(filepath=blend)
        scene = bpy.context.scene
        if engine == "CYCLES":
            configure_cycles(scene, samples, seed)
        else:
            configure_ppm(scene, passes, seed)
        path = os.path.join(keep or workdir, f"{case}_{engine}_{seed}.exr")
        rgb = cycles_compare.render_to_array(scene, path).mean(axis=2)
        row[f"{engine.lower()}{seed}"] = {k: float(rgb[v].mean()) for k, v in masks.items()}
    return row


def describe(row):
    parts = []
    for region in row["pixels"]:
        c1, c2 = row["cycles1"][region], row["cycles2"][region]
        ppm = [v[region] for k, v in row.items() if k.startswith("ppm")]
        p = float(np.mean(ppm))
        spread = f", ppm seeds {np.std(ppm, ddof=1) / p:.2%} sd" if len(ppm) > 1 else ""
        parts.append(f"{region}: ppm/cycles {p / (0.5 * (c1 + c2)):.4f} (cycles seeds {c1:.4f} {c2:.4f}, "
                     f"spread {abs(c1 - c2) / (0.5 * (c1 + c2)):.2%}; ppm {p:.4f}{spread})")
    return "; ".join(parts)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else \
        (sys.argv[1:] if os.path.basename(sys.argv[0]) == os.path.basename(__file__) else [])
    parser = argparse.ArgumentParser()
    parser.add_argument("--case", nargs="*", default=list(CASES))
    parser.add_argument("--size", type=int, nargs=2, default=(96, 64))
    parser.add_argument("--samples", type=int, default=2048)
    parser.add_argument("--passes", type=int, default=64)
    parser.add_argument("--ppm-seeds", type=int, default=1, help="PPM renders with seeds 1..N, their mean compared")
    parser.add_argument("--json")
    parser.add_argument("--keep", help="keep the rendered EXRs in this folder")
    args = parser.parse_args(argv)
    rows = []
    try:
        with tempfile.TemporaryDirectory() as workdir:
            for case in args.case:
                row = compare(case, workdir, tuple(args.size), args.samples, args.passes, args.keep, args.ppm_seeds)
                rows.append(row)
                print(f"hdri_specular: Blender {row['blender']} {case:13s} {describe(row)}", flush=True)
    finally:
        cycles_compare.unregister_checkout_addon()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
