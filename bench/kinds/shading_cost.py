"""What node programs cost: per shading point, and per photon bounce in a render.

    .venv/bin/python bench/run.py shading_cost [--quick]

Per shading point: Scene.run_program over `points` points (one thread) for programs of a few sizes
(an image lookup at the UV; one Noise texture; a wood-like network: distorted rings, a ColorRamp,
a bump of them; a Voronoi), less the time of a program that only reads a coordinate (the call's own
cost). Per photon bounce: photon paths per second on the Cornell box with three spheres
(cornell_3spheres's geometry and light) whose five walls are diffuse with a constant colour (as
there), an image's colour, a noise, or the wood network (its bump a normal), with stochastic hit
points (the add-on's): the photon pass runs the program at every photon hit, the eye pass at every
hit point of every pass."""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

import ppm_core
from core_scenes import look_at, three_spheres

MODES = ppm_core.node_modes()


def op(name, mode=0, ins=(), out=(), **fields):
    if isinstance(mode, str):
        mode = MODES[name].index(mode)
    return {"op": name, "mode": mode, "in": list(ins), "out": list(out), **fields}


RAMP = [v for i in range(257) for v in ((0.35 + 0.3 * i / 256), 0.17 + 0.2 * i / 256, 0.06 + 0.1 * i / 256, 1.0)]


def programs():
    """name -> (program, needs an image). Registers 1..: constants."""
    noise_in = [1, 2, 3, 4, 5, 6, 7, 2]  # w, scale, detail, roughness, lacunarity, offset, gain, distortion
    constants = [(0.0,) * 3, (5.0,) * 3, (2.0,) * 3, (0.5,) * 3, (2.0,) * 3, (0.0,) * 3, (1.0,) * 3]
    # Rings (wave: vector, scale, distortion, detail, detail scale, detail roughness, phase), a
    # ramp of browns, and the rings' bump: its heights at the point (9) and beside it (12, 14).
    def rings(vector, fac):
        return [op("coord", "generated", out=[vector]),
                op("wave", mode=1, ins=[vector, 2, 3, 3, 7, 4, 1], out=[0, fac])]
    wood = rings(8, 9) + [op("table", ins=[9], out=[10, 0], data=0, extra=255, flags=1)]
    for side, (vector, fac) in ((1, (11, 12)), (2, (13, 14))):
        wood += [op("bump_offset", side, ins=[7])] + rings(vector, fac)
    wood += [op("bump_offset", 0, ins=[7]), op("coord", "shading_normal", out=[15]),
             op("bump", ins=[4, 4, 9, 12, 14, 15, 7], out=[16])]
    return {
        "coordinate only": ({"constants": constants, "code": [op("coord", "uv", out=[8])], "outputs": [8],
                             "registers": 9}, False),
        "image at the UV": ({"constants": constants, "code": [op("coord", "uv", out=[8]),
                                                              op("image", ins=[8], out=[9, 10], data=0)],
                             "outputs": [9], "registers": 11}, True),
        "Noise (3-D fBM, detail 2)": ({"constants": constants, "code": [
            op("coord", "generated", out=[8]), op("noise", "fbm", ins=[8, *noise_in], out=[9, 0], extra=3 | 32)],
            "outputs": [9], "registers": 10}, False),
        "Voronoi (3-D F1)": ({"constants": constants, "code": [
            op("coord", "generated", out=[8]),
            op("voronoi", "f1", ins=[8, 1, 2, 1, 4, 5, 7, 4, 7], out=[9, 10, 11], extra=3, data=12)],
            "outputs": [9], "registers": 13}, False),
        "wood: rings, ramp, bump": ({"constants": constants, "code": wood, "data": RAMP, "outputs": [10, 16],
                                     "registers": 17}, False),
    }


def add_image(scene):
    texels = np.random.default_rng(1).random((256, 256, 4)).astype(np.float32)
    texels[..., 3] = 1.0
    return scene.add_texture("noise", texels, storage="srgb8")


def per_point_ns(program, image, points):
    scene = ppm_core.Scene()
    if image:
        add_image(scene)
    rng = np.random.default_rng(2)
    p = rng.uniform(-1.0, 1.0, (points, 3))
    n = np.tile([0.0, 0.0, 1.0], (points, 1))
    uv = rng.random((points, 2))
    best = math.inf
    for _ in range(3):
        start = time.perf_counter()
        scene.run_program(program, p, normal=n, incoming=n, uv=uv)
        best = min(best, time.perf_counter() - start)
    return best / points * 1e9


def walls_scene(program, image, width, height):
    """cornell_3spheres with its walls diffuse in `program`'s first output (None: constant grey)."""
    scene = ppm_core.Scene()
    if image:
        add_image(scene)
    if program is None:
        wall = scene.add_material("wall", "diffuse", base_color=(0.75, 0.75, 0.75))
    else:
        extra = {"normal_map": {"input": 1, "space": "direct"}} if len(program["outputs"]) > 1 else {}
        wall = scene.add_material("wall", "mixture", lobes=[{"kind": "diffuse", "color": 0.75, "color_input": 0}],
                                  program=program, **extra)
    h = 1.0
    walls = [[(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [(-h, -h, 2), (-h, h, 2), (h, h, 2), (h, -h, 2)],
             [(-h, h, 0), (h, h, 0), (h, h, 2), (-h, h, 2)], [(-h, -h, 0), (-h, h, 0), (-h, h, 2), (-h, -h, 2)],
             [(h, -h, 0), (h, -h, 2), (h, h, 2), (h, h, 0)]]
    for i, corners in enumerate(walls):
        c = np.asarray(corners, dtype=float)
        uvs = (c[:, :2] + c[:, 2:3] * 0.5 + 1.0) / 3.0
        scene.add_mesh(f"wall{i}", c, np.array([[0, 1, 2], [0, 2, 3]]), uvs=uvs, materials=wall, object_id=i)
        scene.set_object_info(i, np.eye(4), texspace_location=(0.0, 0.0, 1.0), texspace_size=(1.0, 1.0, 1.0))
    three_spheres(scene)
    scene.add_light("sphere", name="lamp", power=25.0, position=(0.0, 0.0, 1.3), radius=0.05)
    fov = 2.0 * math.atan(0.5 * 36.0 / 40.0)
    scene.set_camera(look_at((0.0, -4.4, 1.0), (0.0, 0.0, 1.0)), width, height, fov=fov)
    return scene


def paths_per_s(program, image, experiment):
    scene = walls_scene(program, image, experiment["width"], experiment["height"])
    r = ppm_core.Renderer(scene, threads=2, photons_per_pass=experiment["photons"], direct_light="sampled",
                          hit_points="stochastic")  # the add-on's: an eye pass every pass
    r.run(passes=1)
    s0 = r.stats()
    r.run(passes=experiment["passes"])
    s1 = r.stats()
    photon_s = sum(s1["seconds"][k] - s0["seconds"][k] for k in ("photon_trace", "index_build", "gather"))
    eye_s = s1["seconds"]["eye_pass"] - s0["seconds"]["eye_pass"]
    return experiment["photons"] * experiment["passes"] / photon_s, eye_s / experiment["passes"]


def run(experiment, results):
    rows = []
    table = programs()
    base = per_point_ns(*table["coordinate only"], experiment["points"])
    for name, (program, image) in table.items():
        ns = per_point_ns(program, image, experiment["points"])
        results.row(part="per_point", program=name, ns=ns, ns_over_call=ns - base)
        rows.append([name, f"{ns:.0f}", f"{ns - base:.0f}"])
    results.table(["program", "ns per point (run_program, 1 thread)", "less the call's own"], rows)
    rows = []
    cases = {"constant (no program)": (None, False), "image at the UV": table["image at the UV"],
             "Noise (3-D fBM, detail 2)": table["Noise (3-D fBM, detail 2)"],
             "wood: rings, ramp, bump": table["wood: rings, ramp, bump"]}
    for name, (program, image) in cases.items():
        runs = [paths_per_s(program, image, experiment) for _ in range(experiment["repeats"])]
        paths = statistics.median(p for p, _ in runs)
        eye = statistics.median(e for _, e in runs)
        results.row(part="render", walls=name, paths_per_s=paths, eye_pass_s=eye)
        rows.append([name, f"{paths / 1e6:.3f} M", f"{eye:.3f}"])
    results.table(["walls", "photon paths/s (trace + index + gather, 2 threads)", "eye pass s/pass"], rows)
