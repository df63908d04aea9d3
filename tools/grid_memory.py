"""Memory and time of a smoke domain of `n`^3 voxels (256 by default) in cornell_3spheres at 640x480
through the ppm_core on PYTHONPATH: a density grid and a temperature grid (smooth blobs made with
numpy, as a simulation's), a box of Principled-like smoke (density 5 times the grid) glowing by a
temperature term, 3 passes of 200,000 photons on 2 threads after one untimed. Prints one JSON line:
the process's peak resident memory grown from the scene's build to the render's end (the grids'
numpy arrays included, as the add-on holds them while it exports), the grids' bytes in the core,
seconds a pass. n = 0: the scene without the domain, the baseline to subtract.

    PYTHONPATH=build/cp311-cp311-linux_x86_64 .venv/bin/python tools/grid_memory.py [n]
"""

import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H, PASSES, PHOTONS = 640, 480, 3, 200_000


def peak_bytes():
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) * 1024


def blobs(n):
    """Smooth blobs in [0, 1] over an n^3 grid, zero near its faces (float32, (z, y, x))."""
    axis = np.linspace(0.0, 1.0, n, dtype=np.float32)
    z, y, x = axis[:, None, None], axis[None, :, None], axis[None, None, :]
    shape = np.sin(3.0 * np.pi * x) * np.sin(2.0 * np.pi * y + 1.0) * np.sin(2.5 * np.pi * z + 0.5)
    envelope = np.sin(np.pi * x) * np.sin(np.pi * y) * np.sin(np.pi * z)
    return np.clip(shape * envelope, 0.0, None).astype(np.float32)


def smoke_box(scene, n):
    density = scene.add_grid("density", blobs(n))
    temperature = scene.add_grid("temperature", 2.0 * blobs(n))
    program = {"constants": [], "code": [{"op": "coord", "mode": 0, "out": [1]},
                                         {"op": "grid", "in": [1], "out": [2, 3, 4], "data": 0},
                                         {"op": "grid", "in": [1], "out": [5, 6, 7], "data": 1}],
               "outputs": [3, 6], "registers": 8}
    scene.add_medium("smoke", program=program, terms=[{"sigma_s": (2.5,) * 3, "sigma_a": (2.5,) * 3, "input": 0},
                                                      {"emission": (0.5, 0.2, 0.05), "input": 1}])
    material = scene.add_material("smoke", "diffuse", medium="smoke", surface=False)
    lo, hi = np.array([-0.5, -0.3, 0.0]), np.array([0.3, 0.5, 0.9])
    corners = np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)])
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    triangles = np.array([t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))])
    scene.add_mesh("smoke", corners, triangles, materials=material, object_id=90)
    scene.set_object_info(90, np.eye(4), texspace_location=tuple((lo + hi) / 2), texspace_size=tuple((hi - lo) / 2),
                          grids=[density, temperature])


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    scene = core_scenes.cornell_3spheres(W, H)
    before = peak_bytes()
    if n:
        smoke_box(scene, n)
    renderer = ppm_core.Renderer(scene, hit_points="stochastic", photons_per_pass=PHOTONS, threads=2, seed=1)
    renderer.run(passes=1)
    start = time.monotonic()
    renderer.run(passes=PASSES)
    seconds = (time.monotonic() - start) / PASSES
    grids = sum(scene.grid_info(i)["bytes"] for i in range(2 if n else 0))
    print(json.dumps({"voxels": n ** 3, "grids_bytes": grids, "peak_grown_bytes": peak_bytes() - before,
                      "seconds_per_pass": round(seconds, 3)}))


if __name__ == "__main__":
    main()
