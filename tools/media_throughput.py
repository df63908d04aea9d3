"""Photon and eye throughput of the ppm_core on PYTHONPATH, on cornell_3spheres at 320x240 with
stochastic hit points, 12 passes of 200,000 photons on 2 threads; `--fog`: the same scene filled
with a world medium (sigma_s 0.25, sigma_a 0.05 per metre); `--box`: that fog in a box filling the
room (a boundary only); `--cloud`: the box's fog times twice a Noise texture (3-D fBm, scale 3,
detail 2, normalised: about the box's density on average), a medium that varies in space; `--smoke`:
the box's density a rising plume on a 128^3 grid (plume(): mostly empty space around it), sigma_s 4
and sigma_a 1 per unit, read at the Object coordinate as the add-on reads grids: a sparse cloud;
`--one-majorant` renders it with Scene.majorant_grids off; `--variance S` gives instead the image's
relative variance after S seconds at 160x120 (variance_at_equal_time). One JSON line per run:

    PYTHONPATH=build/py311 .venv/bin/python tools/media_throughput.py [--fog | --box | --cloud | --smoke]
        [--one-majorant] [--variance SECONDS]

Alternate the cores being compared run by run, and time only on an idle machine."""

import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H, PASSES, PHOTONS = 320, 240, 12, 200_000


FOG = {"sigma_a": 0.05, "sigma_s": 0.25}
# A Noise of the position (registers 1-8 constants: W, scale, detail, roughness, lacunarity, offset,
# gain, distortion; 9 the position), times 2.
NOISE_TIMES_TWO = {
    "constants": [(v,) * 3 for v in (0.0, 3.0, 2.0, 0.5, 2.0, 0.0, 1.0, 0.0, 2.0)],
    "code": [{"op": "coord", "mode": 7, "out": [10]},  # position
             {"op": "noise", "mode": 0, "extra": 3 | 32, "in": [10, 1, 2, 3, 4, 5, 6, 7, 8], "out": [11, 0, 0]},
             {"op": "math", "mode": 2, "in": [11, 9, 9], "out": [12]}],  # multiply
    "outputs": [12], "registers": 13}


# The object's grid in slot 0 read at its Object coordinate (as the add-on reads a Volume object's).
GRID_AT_OBJECT = {"constants": [], "code": [{"op": "coord", "mode": 3, "out": [1]},
                                            {"op": "grid", "in": [1], "out": [2, 3, 4], "data": 0}],
                  "outputs": [3], "registers": 5}
LO, HI = np.array([-0.99, -0.99, 0.01]), np.array([0.99, 0.99, 1.99])


def plume(n=128):
    """A smoke domain's density over n^3 voxels ((z, y, x), float32): a plume rising from a source
    at the bottom's centre, widening and thinning as it rises, 0 below 1% of its peak (most of the
    domain is empty, as around a simulated plume)."""
    axis = (np.arange(n, dtype=np.float32) + 0.5) / n
    z, y, x = axis[:, None, None], axis[None, :, None], axis[None, None, :]
    width = 0.04 + 0.2 * z
    density = np.exp(-((x - 0.5) ** 2 + (y - 0.5) ** 2) / width ** 2) * (0.04 / width) * (1.0 + 0.3 * np.sin(40.0 * z))
    return np.where(density > 0.01, density, 0.0).astype(np.float32)


def smoke_grid(scene):
    """The plume as a smoke domain's grid over the room's box (Object coordinates LO..HI)."""
    n = 128
    to_index = np.eye(4)
    to_index[:3, :3] = np.diag(np.full(3, n) / (HI - LO))
    to_index[:3, 3] = -0.5 - LO * n / (HI - LO)
    return scene.add_grid("density", plume(n), to_index=to_index)


def fill_room(scene, kind):
    """A box of fog (a boundary only) filling cornell_3spheres' room, x, y in (-1, 1), z in (0, 2)."""
    if kind == "cloud":
        scene.add_medium("fog", program=NOISE_TIMES_TWO, terms=[{**FOG, "input": 0}])
    elif kind == "smoke":
        scene.add_medium("fog", program=GRID_AT_OBJECT, terms=[{"sigma_s": 4.0, "sigma_a": 1.0, "input": 0}])
    else:
        scene.add_medium("fog", **FOG)
    fog = scene.add_material("fog", "diffuse", medium="fog", surface=False)
    lo, hi = LO, HI
    corners = np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)])
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    triangles = [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]
    scene.add_mesh("fog", corners, np.array(triangles), materials=fog, object_id=99)
    if kind == "smoke":
        scene.set_object_info(99, np.eye(4), grids=[smoke_grid(scene)])


def scene_of(fog, width=W, height=H):
    scene = core_scenes.cornell_3spheres(width, height)
    if "--one-majorant" in sys.argv:
        scene.majorant_grids = False
    if fog == "fog":
        scene.add_medium("fog", **FOG)
        scene.set_world_medium("fog")
    elif fog:
        fill_room(scene, fog)
    return scene


def variance_at_equal_time(fog, seconds):
    """The image's relative variance (the mean squared difference of two seeds' luminance over 2,
    over the mean squared), rendered at 160x120 with 50,000 photons a pass for `seconds` each, without
    the pixels above 10 times the median (the lamp, seen through the medium)."""
    images = []
    for seed in (1, 2):
        renderer = ppm_core.Renderer(scene_of(fog, 160, 120), hit_points="stochastic", photons_per_pass=50_000,
                                     threads=2, seed=seed)
        start, passes = time.monotonic(), 0
        while time.monotonic() - start < seconds:
            renderer.run(passes=1)
            passes += 1
        images.append((renderer.image().mean(axis=-1), passes))
    (a, pa), (b, pb) = images
    keep = (a + b) / 2 < 10 * np.median((a + b) / 2)
    variance = np.mean(((a - b) ** 2)[keep]) / 2 / np.mean((a + b)[keep] / 2) ** 2
    return {"passes": [pa, pb], "relative_variance": round(float(variance), 5)}


def main():
    fog = next((a[2:] for a in sys.argv[1:] if a in ("--fog", "--box", "--cloud", "--smoke")), None)
    if "--variance" in sys.argv:
        seconds = float(sys.argv[sys.argv.index("--variance") + 1])
        print(json.dumps({"fog": fog, "one_majorant": "--one-majorant" in sys.argv, "seconds": seconds,
                          **variance_at_equal_time(fog, seconds)}))
        return
    scene = scene_of(fog)
    renderer = ppm_core.Renderer(scene, hit_points="stochastic", photons_per_pass=PHOTONS, threads=2, seed=1)
    renderer.run(passes=PASSES)
    s = renderer.stats()["seconds"]
    print(
        json.dumps(
            {
                "core": ppm_core.__file__,
                "fog": fog,
                "majorant_grids": getattr(scene, "majorant_grids", False),
                "photon_paths_per_s": round(PASSES * PHOTONS / s["photon_trace"]),
                "eye_samples_per_s": round(PASSES * W * H / s["eye_pass"]),
                "seconds_per_pass": round(s["total"] / PASSES, 3),
            }
        )
    )


if __name__ == "__main__":
    main()
