"""Probe (not a test): tests/blenders/telephoto_compare.py's scene (a diffuse floor, a diffuse cube, a point
light; the camera 6 m from its target) built with ppm_core alone, rendered once per seed with chosen core
settings; prints each render's image mean and median, the photon spacing, and the mean over the seeds with
its standard error and one render's spread. Cycles' values come from telephoto_compare.py (its --keep images).

    PYTHONPATH=build .venv/bin/python tests/core/telephoto_probe.py --lens 5000 --seeds $(seq 1 64)
    PYTHONPATH=build .venv/bin/python tests/core/telephoto_probe.py --lens 5000 --seeds 1 2 --set density_radius=false
"""

import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "blend_scenes"))

import numpy as np

import core_scenes
import ppm_core

# What the camera looks at, and where the light is (as tests/blenders/telephoto_compare.py's TARGETS, LIGHTS).
TARGETS = {"cube": (0.0, -0.5, 0.5), "floor": (0.0, -1.5, 0.0), "edge": (0.0, -0.5, 0.0),
           "cube_corner": (0.5, -0.5, 0.5)}
LIGHTS = {"front": (1.5, -2.0, 3.0), "back": (0.5, 2.5, 2.5)}  # "back": the face the camera sees is unlit


def scene_with(lens=None, ortho=None, target="cube", light="back", width=64, height=48, pitch_degrees=20.0,
               distance=6.0):
    scene = ppm_core.Scene()
    grey = scene.add_material("grey", "diffuse", base_color=(0.5, 0.5, 0.5))
    core_scenes.quad(scene, "floor", [(-10, -10, 0), (10, -10, 0), (10, 10, 0), (-10, 10, 0)], grey)
    scene.add_mesh("cube", core_scenes.box_corners((0.0, 0.0), 1.0, 1.0, 0.0), core_scenes.BOX_TRIANGLES,
                   materials=grey)
    scene.add_light("point", name="lamp", power=1000.0, position=LIGHTS[light])
    pitch = math.radians(pitch_degrees)
    eye = np.array(TARGETS[target]) + distance * np.array([0.0, -math.cos(pitch), math.sin(pitch)])
    matrix = core_scenes.look_at(eye, TARGETS[target])
    if ortho is not None:
        scene.set_camera(matrix, width, height, projection="orthographic", ortho_scale=ortho)
    else:
        scene.set_camera(matrix, width, height, fov=2.0 * math.atan(18.0 / lens))
    return scene


def value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text.lower(), text)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--lens", type=float, default=5000.0)
    parser.add_argument("--ortho", type=float)
    parser.add_argument("--target", choices=list(TARGETS), default="cube")
    parser.add_argument("--light", choices=list(LIGHTS), default="back")
    parser.add_argument("--save", help="the mean image over the seeds to this .npy")
    parser.add_argument("--passes", type=int, default=60)
    parser.add_argument("--seeds", type=int, nargs="*", default=[1])
    parser.add_argument("--set", nargs="*", default=[], help="core settings, key=value")
    args = parser.parse_args()
    settings = {"photons_per_pass": 200_000, "hit_points": "stochastic", "adaptive_samples": 4, "threads": 2}
    settings.update({k: value(v) for k, v in (s.split("=", 1) for s in args.set)})
    means, images = [], []
    for seed in args.seeds:
        renderer = ppm_core.Renderer(scene_with(args.lens, args.ortho, args.target, args.light), seed=seed,
                                     **settings)
        renderer.run(passes=args.passes)
        image = renderer.image()[..., :3].mean(axis=2)
        stats = renderer.stats()
        means.append(float(image.mean()))
        images.append(image)
        print(f"seed {seed}: mean {image.mean():.5f} median {np.median(image):.5f} "
              f"spacing {stats['photon_spacing']:.4g} initial radius {stats['initial_radius_mean']:.4g} "
              f"widened {stats['radii_widened']}", flush=True)
    if args.save:
        np.save(args.save, np.mean(images, axis=0))
    spread = float(np.std(means, ddof=1)) if len(means) > 1 else float("nan")
    print(f"telephoto_probe: lens {args.lens} ortho {args.ortho} {args.target}/{args.light} {args.set}: "
          f"{len(means)} seeds: mean {np.mean(means):.5f} +- {spread / math.sqrt(len(means)):.5f} (standard error), "
          f"one render's spread {spread / np.mean(means):.1%}")


if __name__ == "__main__":
    main()
