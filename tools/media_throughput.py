"""Photon and eye throughput of the ppm_core on PYTHONPATH, on cornell_3spheres at 320x240 with
stochastic hit points, 12 passes of 200,000 photons on 2 threads; `--fog`: the same scene filled
with a world medium (sigma_s 0.25, sigma_a 0.05 per metre); `--box`: that fog in a box filling the
room (a boundary only); `--cloud`: the box's fog times twice a Noise texture (3-D fBm, scale 3,
detail 2, normalised: about the box's density on average), a medium that varies in space. One JSON
line per run:

    PYTHONPATH=build/py311 .venv/bin/python tools/media_throughput.py [--fog | --box | --cloud]

Alternate the cores being compared run by run, and time only on an idle machine."""

import json
import os
import sys

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


def fill_room(scene, cloud):
    """A box of fog (a boundary only) filling cornell_3spheres' room, x, y in (-1, 1), z in (0, 2)."""
    scene.add_medium("fog", **({"program": NOISE_TIMES_TWO, "terms": [{**FOG, "input": 0}]} if cloud else FOG))
    fog = scene.add_material("fog", "diffuse", medium="fog", surface=False)
    lo, hi = np.array([-0.99, -0.99, 0.01]), np.array([0.99, 0.99, 1.99])
    corners = np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)])
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    triangles = [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]
    scene.add_mesh("fog", corners, np.array(triangles), materials=fog, object_id=99)


def main():
    fog = next((a[2:] for a in sys.argv[1:] if a in ("--fog", "--box", "--cloud")), None)
    scene = core_scenes.cornell_3spheres(W, H)
    if fog == "fog":
        scene.add_medium("fog", **FOG)
        scene.set_world_medium("fog")
    elif fog:
        fill_room(scene, cloud=fog == "cloud")
    renderer = ppm_core.Renderer(scene, hit_points="stochastic", photons_per_pass=PHOTONS, threads=2, seed=1)
    renderer.run(passes=PASSES)
    s = renderer.stats()["seconds"]
    print(
        json.dumps(
            {
                "core": ppm_core.__file__,
                "fog": fog,
                "photon_paths_per_s": round(PASSES * PHOTONS / s["photon_trace"]),
                "eye_samples_per_s": round(PASSES * W * H / s["eye_pass"]),
                "seconds_per_pass": round(s["total"] / PASSES, 3),
            }
        )
    )


if __name__ == "__main__":
    main()
