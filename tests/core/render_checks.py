"""What several core tests share: the renders they compare and the checks every image passes."""

import itertools
import math

import numpy as np

import core_scenes
import ppm_core

EXPECTED_R1 = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 100.0)


def finite_rgb(renderer, hit_points=True):
    """The image's RGB, checked finite and non-negative; with `hit_points`, the render must have
    stored some (a scene seen only through glass and mirrors stores none)."""
    image = renderer.image()
    assert np.isfinite(image).all(), "NaN or Inf in the image"
    assert (image >= 0.0).all(), f"negative radiance {image.min()}"
    stats = renderer.stats()
    assert math.isfinite(stats["radius_mean"]) and (stats["radius_mean"] > 0.0 or not hit_points)
    return image[..., :3].astype(np.float64)



def closed_sphere(radius, offset=(0.0, 0.0, 0.0), power=100.0, albedo=0.5, width=16, height=16):
    """core_scenes.closed_sphere_with_point_light, moved by `offset`."""
    offset = np.asarray(offset, dtype=float)
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "diffuse", base_color=(albedo,) * 3)
    scene.add_sphere("room", offset, radius, wall)
    scene.add_light("point", name="lamp", power=power, position=offset)
    camera = core_scenes.look_at(offset + (0.0, -0.1 * radius, 0.0), offset + (0.0, radius, 0.0))
    scene.set_camera(camera, width, height, fov=math.radians(60), clip_start=1e-3 * radius)
    return scene



def cube_arrays(half=1.0, center=(0.0, 0.0, 0.0)):
    """(vertices, triangles) of a closed cube: 12 triangles sharing 8 vertices (every edge shared by two
    triangles), facing out."""
    v = np.array(list(itertools.product([-half, half], repeat=3)), dtype=float) + np.asarray(center, dtype=float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])


def cube_mesh(scene, half=1.0, center=(0.0, 0.0, 0.0), material=0, name="cube", object_id=0):
    """Adds cube_arrays' cube; returns its vertices."""
    v, triangles = cube_arrays(half, center)
    scene.add_mesh(name, v, triangles, materials=material, object_id=object_id)
    return v



def edge_targets(half=1.0):
    """Points on every edge and face diagonal of a cube: where two triangles meet."""
    ts = np.linspace(-1.0, 1.0, 41)
    out = []
    for a, b in itertools.product([-1.0, 1.0], repeat=2):
        for t in ts:
            out += [(t, a, b), (a, t, b), (a, b, t), (a, t, t * b), (t, a, t * b), (t, t * b, a)]
    return np.array(out) * half



def render_cornell(seed, threads, **settings):
    scene = core_scenes.cornell_3spheres(96, 72)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=threads, seed=seed, **settings)
    renderer.run(passes=4)
    return renderer.image()

