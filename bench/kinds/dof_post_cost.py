"""Cost of the POST depth-of-field blur next to a photon pass.

    .venv/bin/python bench/run.py dof_post_cost [--quick]

cornell_3spheres at 640x480, `photons` photons per pass, 2 threads, for each aperture radius of
`apertures`: the best of `image_repeats` calls of image() with dof_mode="post" (after `passes`
passes) and without depth of field (after one pass), next to the mean time of one photon pass
(trace, index build, gather, direct light) of the POST render. The largest circle of confusion is
the thin-lens one the core computes.
"""

from __future__ import annotations

import time

import ppm_core
from harness.core_route import build_scene

W, H = 640, 480


def image_seconds(renderer, repeats):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        renderer.image()
        best = min(best, time.perf_counter() - start)
    return best


def largest_coc_pixels(aperture):
    # Thin lens as the core computes it (focus 3.4 m, f = 40 mm), largest over the box's near edge
    # (about 2.4 m) and the pixels that see nothing (infinitely far).
    pixel = 2 * (0.5 * 36.0 / 40.0) / W  # core_scenes: fov = 2 atan(18/40)
    return 2 * aperture * (3.4 / (3.4 - 0.04)) * max(abs(1 / 3.4 - 1 / 2.4), 1 / 3.4) / pixel


def run(experiment, results):
    photons, passes, repeats = experiment["photons"], experiment["passes"], experiment["image_repeats"]
    rows = []
    for aperture in experiment["apertures"]:
        r = ppm_core.Renderer(build_scene("cornell_3spheres", W, H, aperture_radius=aperture),
                              photons_per_pass=photons, threads=2, dof_mode="post")
        r.run(passes=passes)
        s = r.stats()["seconds"]
        per_pass = sum(s[k] for k in ("photon_trace", "index_build", "gather", "direct_light")) / passes
        plain = ppm_core.Renderer(build_scene("cornell_3spheres", W, H), photons_per_pass=photons, threads=2)
        plain.run(passes=1)
        coc, post, without = largest_coc_pixels(aperture), image_seconds(r, repeats), image_seconds(plain, repeats)
        results.row(aperture=aperture, largest_coc_px=coc, image_post_s=post, image_without_s=without,
                    photon_pass_s=per_pass)
        rows.append([f"{aperture} m", f"{coc:.0f}", f"{post:.3f}", f"{without:.3f}", f"{per_pass:.3f}"])
    results.table(["aperture radius", "largest CoC (px)", "image() with POST, s", "image() without, s",
                   "one photon pass, s"], rows)
