"""Photon and eye throughput of the ppm_core on PYTHONPATH, on cornell_3spheres at 320x240 with
stochastic hit points, 12 passes of 200,000 photons on 2 threads; `--fog`: the same scene filled
with a world medium (sigma_s 0.25, sigma_a 0.05 per metre). One JSON line per run:

    PYTHONPATH=build/py311 .venv/bin/python tools/media_throughput.py [--fog]

Alternate the cores being compared run by run, and time only on an idle machine."""

import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402

W, H, PASSES, PHOTONS = 320, 240, 12, 200_000


def main():
    fog = "--fog" in sys.argv[1:]
    scene = core_scenes.cornell_3spheres(W, H)
    if fog:
        scene.add_medium("fog", sigma_a=0.05, sigma_s=0.25)
        scene.set_world_medium("fog")
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
