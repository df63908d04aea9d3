"""Bundled scenes built directly through ppm_core (no Blender needed).

Used by the demo, the tests and the benchmarks. `blend_scenes/build_blend_scenes.py`
builds the same scenes as .blend files for the add-on. World space is Blender's:
metres, Z up; cameras look down their local -Z.
"""

from __future__ import annotations

import math

import numpy as np

import ppm_core


def look_at(eye, target, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """Camera-to-world matrix of a camera at `eye` looking at `target` (Blender convention)."""
    eye, target, up = (np.asarray(v, dtype=float) for v in (eye, target, up))
    back = eye - target
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    true_up = np.cross(back, right)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, true_up, back, eye
    return m


def quad(scene, name, corners, material, object_id=0):
    """Adds a planar quad (4 corners, counter-clockwise seen from the front)."""
    positions = np.asarray(corners, dtype=float)
    scene.add_mesh(name, positions, np.array([[0, 1, 2], [0, 2, 3]]), materials=material, object_id=object_id)


def cornell_box(scene, size=2.0, object_id_start=0, with_front=False):
    """Walls of a Cornell box spanning x, y in [-size/2, size/2], z in [0, size]; open towards -y."""
    h = size / 2.0
    white = scene.add_material("white", "diffuse", base_color=(0.75, 0.75, 0.75))
    red = scene.add_material("red", "diffuse", base_color=(0.75, 0.25, 0.25))
    blue = scene.add_material("blue", "diffuse", base_color=(0.25, 0.25, 0.75))
    z0, z1 = 0.0, size
    walls = [
        ("floor", [(-h, -h, z0), (h, -h, z0), (h, h, z0), (-h, h, z0)], white),
        ("ceiling", [(-h, -h, z1), (-h, h, z1), (h, h, z1), (h, -h, z1)], white),
        ("back", [(-h, h, z0), (h, h, z0), (h, h, z1), (-h, h, z1)], white),
        ("left", [(-h, -h, z0), (-h, h, z0), (-h, h, z1), (-h, -h, z1)], red),
        ("right", [(h, -h, z0), (h, -h, z1), (h, h, z1), (h, h, z0)], blue),
    ]
    if with_front:
        walls.append(("front", [(-h, -h, z0), (-h, -h, z1), (h, -h, z1), (h, -h, z0)], white))
    for i, (name, corners, mat) in enumerate(walls):
        quad(scene, name, corners, mat, object_id=object_id_start + i)
    return {"white": white, "red": red, "blue": blue}


def three_spheres(scene):
    """The report's figure 1's mirror, glass and diffuse spheres (object ids 10-12)."""
    mirror = scene.add_material("mirror", "mirror", base_color=(0.95, 0.95, 0.95))
    glass = scene.add_material("glass", "glass", base_color=(1.0, 1.0, 1.0), ior=1.5)
    matte = scene.add_material("matte", "diffuse", base_color=(0.8, 0.7, 0.3))
    scene.add_sphere("mirror_ball", (-0.45, 0.2, 0.35), 0.35, mirror, object_id=10)
    scene.add_sphere("glass_ball", (0.45, -0.25, 0.35), 0.35, glass, object_id=11)
    scene.add_sphere("matte_ball", (-0.3, 0.55, 1.45), 0.25, matte, object_id=12)


def cornell_3spheres(width=640, height=480, light="sphere", aperture_radius=0.0) -> ppm_core.Scene:
    """The report's figure 1: mirror, glass and diffuse spheres, light in the box's centre.

    With `aperture_radius` > 0 the camera focuses on the box's front edge (the
    report's figure 3 puts the focal plane there)."""
    scene = ppm_core.Scene()
    cornell_box(scene)
    three_spheres(scene)
    if light == "sphere":
        scene.add_light("sphere", name="lamp", power=25.0, position=(0.0, 0.0, 1.3), radius=0.05)
    else:
        scene.add_light("point", name="lamp", power=25.0, position=(0.0, 0.0, 1.3))
    fov = 2.0 * math.atan(0.5 * 36.0 / 40.0)
    scene.set_camera(look_at((0.0, -4.4, 1.0), (0.0, 0.0, 1.0)), width, height, fov=fov,
                     focus_distance=3.4, aperture_radius=aperture_radius, focal_length=0.04)
    return scene


def box_corners(center, size, height, angle):
    """The 8 corners of an upright box (bottom 4 then top 4, counter-clockwise from above), turned by `angle`."""
    c, s = math.cos(angle), math.sin(angle)
    h = size / 2.0
    ring = [(-h, -h), (h, -h), (h, h), (-h, h)]
    xy = [(center[0] + c * x - s * y, center[1] + s * x + c * y) for x, y in ring]
    return np.array([(x, y, 0.0) for x, y in xy] + [(x, y, height) for x, y in xy])


BOX_TRIANGLES = np.array([(0, 3, 2), (0, 2, 1), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
                          (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)])


def cornell_diffuse(width=640, height=480, light="area") -> ppm_core.Scene:
    """Diffuse only, the geometry of blend_scenes/cornell_diffuse.blend: the Cornell box walls, a tall and
    a short white block and a 0.5 m square light under the ceiling emitting 60 W (radiance 76; the .blend's
    light has radiance 60, i.e. 47.1 W here: its 60 W in Blender 3.4 units open as 47.1 W in 4+). With
    light="point" the light is a 60 W point light just below (no area sampling). The benchmarks' and the
    regression guard's references were made with these values."""
    scene = ppm_core.Scene()
    white = cornell_box(scene)["white"]
    scene.add_mesh("tall_block", box_corners((-0.35, 0.3), 0.6, 1.2, math.radians(20)), BOX_TRIANGLES,
                   materials=white, object_id=10)
    scene.add_mesh("short_block", box_corners((0.4, -0.3), 0.6, 0.6, math.radians(-18)), BOX_TRIANGLES,
                   materials=white, object_id=11)
    matrix = np.eye(4)
    matrix[:3, 3] = (0.0, 0.0, 1.98)
    if light == "area":
        scene.add_light("rectangle", name="lamp", power=60.0, matrix=matrix, size=0.5)
    else:
        scene.add_light("point", name="lamp", power=60.0, position=(0.0, 0.0, 1.9))
    fov = 2.0 * math.atan(0.5 * 36.0 / 40.0)
    scene.set_camera(look_at((0.0, -4.4, 1.0), (0.0, 0.0, 1.0)), width, height, fov=fov)
    return scene


def open_caustic(width=640, height=480) -> ppm_core.Scene:
    """A glass ball under a small sphere light on a 40 m floor before a far wall, the camera close on
    the ball and its caustic: most of the light's photons land where the camera does not look (the
    case photon guiding is for, photon_guide.h)."""
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", "diffuse", base_color=(0.7, 0.7, 0.7))
    wall = scene.add_material("wall", "diffuse", base_color=(0.6, 0.5, 0.4))
    glass = scene.add_material("glass", "glass", base_color=(1.0, 1.0, 1.0), ior=1.5)
    quad(scene, "floor", [(-20, -20, 0), (20, -20, 0), (20, 20, 0), (-20, 20, 0)], floor)
    quad(scene, "wall", [(-20, 15, 0), (20, 15, 0), (20, 15, 10), (-20, 15, 10)], wall)
    scene.add_sphere("ball", (0.0, 0.0, 0.6), 0.4, glass)
    scene.add_light("sphere", name="lamp", power=300.0, position=(0.3, 0.2, 2.5), radius=0.05)
    scene.set_camera(look_at((0.0, -2.0, 1.6), (0.0, 0.1, 0.2)), width, height, fov=math.radians(45))
    return scene


def closed_sphere_with_point_light(radius=1.0, albedo=0.5, power=100.0, width=32, height=32):
    """Analytic test scene: a point light at the centre of a closed diffuse sphere.

    The radiance on the inner wall is rho * Phi / (4 pi^2 R^2 (1 - rho)) everywhere.
    The camera sits inside, near the centre, so every pixel sees the wall.
    """
    scene = ppm_core.Scene()
    wall = scene.add_material("wall", "diffuse", base_color=(albedo, albedo, albedo))
    scene.add_sphere("room", (0.0, 0.0, 0.0), radius, wall)
    scene.add_light("point", name="lamp", power=power, position=(0.0, 0.0, 0.0))
    scene.set_camera(look_at((0.0, -0.1 * radius, 0.0), (0.0, 1.0, 0.0)), width, height, fov=math.radians(60))
    return scene


def expected_closed_sphere_radiance(radius, albedo, power):
    return albedo * power / (4.0 * math.pi**2 * radius**2 * (1.0 - albedo))


def bezier_point(points, t):
    """Point(s) of the Bezier curve with control points `points` (n+1, 2) at parameter(s) t (de Casteljau)."""
    p = np.repeat(np.asarray(points, dtype=float)[None], np.size(t), axis=0)
    t = np.reshape(t, (-1, 1))
    while p.shape[1] > 1:
        p = (1 - t)[..., None] * p[:, :-1] + t[..., None] * p[:, 1:]
    return p[:, 0]


def tessellate_revolve(points, kind="single", matrix=None, profile_steps=400, angle_steps=720):
    """A triangle mesh of the surface of revolution (for cross-checks); returns positions, triangles."""
    points = np.asarray(points, dtype=float)
    if kind == "single":
        profile = bezier_point(points, np.linspace(0.0, 1.0, profile_steps + 1))
    else:
        segments = (len(points) - 1) // 3
        per = max(2, profile_steps // segments)
        parts = [bezier_point(points[3 * k:3 * k + 4], np.linspace(0, 1, per + 1)[:-1]) for k in range(segments)]
        profile = np.vstack(parts + [points[-1:]])
    theta = np.linspace(0.0, 2 * np.pi, angle_steps, endpoint=False)
    r, z = profile[:, 0:1], profile[:, 1:2]
    pos = np.stack([r * np.cos(theta), r * np.sin(theta), np.repeat(z, angle_steps, axis=1)], axis=-1).reshape(-1, 3)
    if matrix is not None:
        m = np.asarray(matrix, dtype=float)
        pos = pos @ m[:3, :3].T + m[:3, 3]
    rows, cols = len(profile), angle_steps
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(cols), indexing="ij")
    a, b = i * cols + j, i * cols + (j + 1) % cols
    c, d = (i + 1) * cols + (j + 1) % cols, (i + 1) * cols + j
    tris = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return pos, tris


VASE_PROFILE = [(0.0, 0.0), (0.35, 0.0), (0.55, 0.15), (0.45, 0.45), (0.2, 0.65), (0.2, 0.85),
                (0.3, 0.95)]  # one degree-6 curve: closed base on the axis, open rim


def bezier_vase(width=640, height=480) -> ppm_core.Scene:
    """The report's figure 2, done better: a glass vase (a revolved degree-6 Bezier
    profile) on a table, lit by a small sphere light, with caustics on the table."""
    scene = ppm_core.Scene()
    table = scene.add_material("table", "diffuse", base_color=(0.7, 0.65, 0.55))
    wall = scene.add_material("wall", "diffuse", base_color=(0.6, 0.6, 0.65))
    glass = scene.add_material("glass", "glass", base_color=(0.95, 0.97, 1.0), ior=1.5)
    quad(scene, "table", [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)], table, object_id=0)
    quad(scene, "wall", [(-3, 2, 0), (3, 2, 0), (3, 2, 3), (-3, 2, 3)], wall, object_id=1)
    scene.add_bezier_revolve("vase", VASE_PROFILE, kind="single", matrix=np.eye(4), material=glass, object_id=2)
    scene.add_light("sphere", name="lamp", power=60.0, position=(-1.2, -0.8, 1.6), radius=0.05)
    scene.set_background(0.05)
    fov = 2.0 * math.atan(0.5 * 36.0 / 50.0)
    scene.set_camera(look_at((0.0, -3.2, 1.4), (0.0, 0.0, 0.45)), width, height, fov=fov)
    return scene
