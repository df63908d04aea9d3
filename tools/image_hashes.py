"""Fingerprints of the core's images: renders the bundled core scenes in each of the core's main
configurations for a few passes and prints one SHA-256 per image (and per pass kind asked for).
A change meant to leave the images alone (a refactor) must leave every line the same:

    .venv/bin/python tools/image_hashes.py > before.txt   # with the old core installed
    .venv/bin/python tools/image_hashes.py > after.txt    # with the new one
    diff before.txt after.txt

Each render's random numbers depend on the seed, the pass and the pixel, not on the thread that
draws them, so the hashes are the same with any number of threads.
"""

import hashlib
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "blend_scenes"))
from media_throughput import FOG, fill_room  # noqa: E402

import core_scenes  # noqa: E402
import ppm_core  # noqa: E402


def with_world_fog(scene):
    scene.add_medium("fog", **FOG)
    scene.set_world_medium("fog")
    return scene


def with_box(scene, kind):
    fill_room(scene, kind)
    return scene


def with_scene_setting(scene, name, value):
    setattr(scene, name, value)
    return scene


SCENES = {
    "cornell_3spheres": lambda: core_scenes.cornell_3spheres(96, 72),
    "cornell_3spheres_lens": lambda: core_scenes.cornell_3spheres(96, 72, aperture_radius=0.05),
    "cornell_diffuse": lambda: core_scenes.cornell_diffuse(96, 72),
    "open_caustic": lambda: core_scenes.open_caustic(96, 72),
    "bezier_vase": lambda: core_scenes.bezier_vase(96, 72),
    # The scene's own layouts of its geometry: an object-by-object BVH, triangles not copied.
    "cornell_3spheres_dynamic": lambda: with_scene_setting(core_scenes.cornell_3spheres(96, 72), "dynamic", True),
    "cornell_3spheres_compact": lambda: with_scene_setting(core_scenes.cornell_3spheres(96, 72), "geometry_layout",
                                                           "compact"),
    # Media: fog everywhere, fog in a box (a mesh bounds it), a cloud that varies in space.
    "cornell_fog_media": lambda: with_world_fog(core_scenes.cornell_3spheres(96, 72)),
    "cornell_box_media": lambda: with_box(core_scenes.cornell_3spheres(96, 72), "box"),
    "cornell_cloud_media": lambda: with_box(core_scenes.cornell_3spheres(96, 72), "cloud"),
}
BASE = {"photons_per_pass": 20_000, "seed": 7, "threads": 2}
CONFIGS = {
    "fixed": {"hit_points": "fixed"},  # the core's defaults: fixed hit points, photons indexed
    "stochastic": {"hit_points": "stochastic"},
    "streamed": {"hit_points": "fixed", "hit_point_storage": "streamed"},
    "hit_point_grid": {"gather": "hit_points", "grid": "hash"},
    "adaptive_guided": {"hit_points": "stochastic", "adaptive_samples": True, "photon_guiding": True},
    "passes": {"hit_points": "stochastic", "light_passes": True, "component_passes": True},
}
LENS_CONFIGS = {"dof_lens": {"dof_mode": "lens", "hit_points": "stochastic"}, "dof_post": {"dof_mode": "post"}}
LAYOUT_CONFIGS = {name: CONFIGS[name] for name in ("fixed", "stochastic")}
MEDIA_CONFIGS = {"stochastic": CONFIGS["stochastic"], "passes": CONFIGS["passes"]}


def digest(array):
    return hashlib.sha256(np.ascontiguousarray(array, dtype=np.float32).tobytes()).hexdigest()[:16]


def fingerprints(scene_name, make_scene, config_name, config, passes=4):
    renderer = ppm_core.Renderer(make_scene(), **BASE, **config)
    renderer.run(passes=passes)
    lines = [f"{scene_name} {config_name} image {digest(renderer.image())}"]
    if config.get("light_passes"):
        for name, pixels in sorted(renderer.light_passes().items()):
            lines.append(f"{scene_name} {config_name} {name} {digest(pixels)}")
    if config.get("component_passes"):
        for name, pixels in sorted(renderer.component_passes().items()):
            lines.append(f"{scene_name} {config_name} {name} {digest(pixels)}")
    return lines


def main():
    for scene_name, make_scene in SCENES.items():
        configs = {"_lens": LENS_CONFIGS, "_dynamic": LAYOUT_CONFIGS, "_compact": LAYOUT_CONFIGS,
                   "_media": MEDIA_CONFIGS}.get("_" + scene_name.rsplit("_", 1)[-1], CONFIGS)
        for config_name, config in configs.items():
            print("\n".join(fingerprints(scene_name, make_scene, config_name, config)), flush=True)


if __name__ == "__main__":
    main()
