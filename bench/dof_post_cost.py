"""Cost of the POST depth-of-field blur next to a photon pass.

    .venv/bin/python bench/dof_post_cost.py
"""

from __future__ import annotations

import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blend_scenes"))
import core_scenes  # noqa: E402
import ppm_core  # noqa: E402


def image_seconds(renderer, repeats=3):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        renderer.image()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    print("| aperture radius | largest CoC (px) | image() with POST, s | image() without, s | one photon pass, s |")
    print("|---|---|---|---|---|")
    for aperture in (0.01, 0.03):
        scene = core_scenes.cornell_3spheres(640, 480, aperture_radius=aperture)
        r = ppm_core.Renderer(scene, photons_per_pass=200_000, threads=2, dof_mode="post")
        r.run(passes=3)
        s = r.stats()["seconds"]
        per_pass = sum(s[k] for k in ("photon_trace", "index_build", "gather", "direct_light")) / 3
        plain = ppm_core.Renderer(core_scenes.cornell_3spheres(640, 480), photons_per_pass=200_000, threads=2)
        plain.run(passes=1)
        # Thin lens as the core computes it (focus 3.4 m, f = 40 mm), largest over the box's near edge
        # (about 2.4 m) and the pixels that see nothing (infinitely far).
        pixel = 2 * (0.5 * 36.0 / 40.0) / 640  # core_scenes: fov = 2 atan(18/40)
        coc = 2 * aperture * (3.4 / (3.4 - 0.04)) * max(abs(1 / 3.4 - 1 / 2.4), 1 / 3.4) / pixel
        print(f"| {aperture} m | {coc:.0f} | {image_seconds(r):.3f} | {image_seconds(plain):.3f} | {per_pass:.3f} |",
              flush=True)


if __name__ == "__main__":
    main()
