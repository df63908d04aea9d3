"""Numerical stress: extreme scales, grazing and coincident surfaces, degenerate
triangles, lights inside objects, very bright and very dim lights, long runs,
1 and 2 threads. Every test checks values against an answer (analytic, or the
same render without the stressor), not only that the render finished.

The long versions (10,000 passes, memory over time, fuzz for minutes): bench/run.py
stress.
"""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from render_checks import EXPECTED_R1, closed_sphere, cube_mesh, edge_targets, finite_rgb

# ------------------------------------------------------------------ scale

@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("radius", [1e-4, 1e-2, 1.0, 1e2, 1e5])
def test_scale_sweep_matches_analytic(radius, threads):
    """Radiance in a closed sphere scales as 1/R^2 over nine orders of magnitude of R."""
    renderer = ppm_core.Renderer(closed_sphere(radius), photons_per_pass=20_000, threads=threads, seed=1)
    renderer.run(passes=8)
    image = finite_rgb(renderer)
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, 100.0)
    assert image.mean() == pytest.approx(expected, rel=0.03)
    # Radii follow the scene: about two pixel footprints at distance ~R.
    assert 1e-3 * radius < renderer.stats()["radius_mean"] < 0.2 * radius


@pytest.mark.parametrize("radius,offset", [(1e-3, (1e3, -2e3, 5e2)), (1.0, (1e5, 1e5, -1e5)), (1e5, (-1e5, 0, 0))])
def test_scene_far_from_the_origin(radius, offset):
    """A small scene far from the origin: ray offsets grow with |p| but stay below the scene's size."""
    renderer = ppm_core.Renderer(closed_sphere(radius, offset), photons_per_pass=20_000, threads=2, seed=2)
    renderer.run(passes=8)
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, 100.0)
    assert finite_rgb(renderer).mean() == pytest.approx(expected, rel=0.03)


@pytest.mark.parametrize("radius", [1e-4, 1e5])
def test_scale_extremes_stochastic_streamed_and_photon_modes(radius):
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, 100.0)
    for settings in [dict(hit_points="stochastic"), dict(hit_point_storage="streamed"),
                     dict(direct_light="photons", gather="hit_points", grid="hash")]:
        renderer = ppm_core.Renderer(closed_sphere(radius), photons_per_pass=20_000, threads=2, seed=3, **settings)
        renderer.run(passes=10)
        assert finite_rgb(renderer).mean() == pytest.approx(expected, rel=0.05), settings


# ---------------------------------------------------------- bright and dim

@pytest.mark.parametrize("power", [1e12, 1e-12])
def test_very_bright_and_very_dim_lights_are_linear(power):
    """Same seed: the image is exactly proportional to the light's power (float rounding only)."""
    def render(p):
        renderer = ppm_core.Renderer(closed_sphere(1.0, power=p), photons_per_pass=5_000, threads=2, seed=4)
        renderer.run(passes=3)
        return finite_rgb(renderer)

    reference, scaled = render(1.0), render(power)
    assert reference.min() > 0.0
    np.testing.assert_allclose(scaled / power, reference, rtol=1e-5)


def test_bright_and_dim_light_together():
    scene = closed_sphere(1.0, power=1e12)
    scene.add_light("point", name="dim", power=1e-12, position=(0.1, 0.2, 0.0))
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=5)
    renderer.run(passes=4)
    expected = core_scenes.expected_closed_sphere_radiance(1.0, 0.5, 1e12)
    assert finite_rgb(renderer).mean() == pytest.approx(expected, rel=0.03)


@pytest.mark.parametrize("scale", [1e-4, 1e5])
def test_bright_light_at_extreme_scales(scale):
    renderer = ppm_core.Renderer(closed_sphere(scale, power=1e12), photons_per_pass=5_000, threads=2, seed=6)
    renderer.run(passes=3)
    expected = core_scenes.expected_closed_sphere_radiance(scale, 0.5, 1e12)
    assert finite_rgb(renderer).mean() == pytest.approx(expected, rel=0.05)


def test_tiny_sphere_light_equals_a_point_light():
    """Regression: a sphere light far smaller than its distance sampled 1 - cos(theta_max) = 0
    (cancellation) and gave no direct light at all (r / d < 1e-8, e.g. 1 mm at 100 km)."""
    def plane_image(**light):
        scene = ppm_core.Scene()
        scene.add_material("white", base_color=(0.5, 0.5, 0.5))
        s = 1e3
        scene.add_mesh("plane", np.array([[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]], dtype=float),
                       np.array([[0, 1, 2], [0, 2, 3]]))
        scene.add_light(position=(0.0, 0.0, 100.0), power=1e4, **light)
        camera = np.eye(4)
        camera[2, 3] = 200.0
        scene.set_camera(camera, 8, 8, projection="orthographic", ortho_scale=400.0)
        renderer = ppm_core.Renderer(scene, photons_per_pass=100, threads=1, seed=7)
        renderer.run(passes=1)
        return finite_rgb(renderer)

    point = plane_image(kind="point")
    for radius in (1e-6, 1e-60):
        for soft in (False, True):
            sphere = plane_image(kind="sphere", radius=radius, soft_falloff=soft)
            np.testing.assert_allclose(sphere, point, rtol=1e-6, err_msg=f"radius {radius} soft {soft}")


# ------------------------------------------------------------------ grazing

def plane_with_sun(elevation, camera_elevation, width=16, height=8, **settings):
    scene = ppm_core.Scene()
    scene.add_material("white", base_color=(0.5, 0.5, 0.5))
    s = 1e4
    scene.add_mesh("plane", np.array([[-s, -s, 0], [s, -s, 0], [s, s, 0], [-s, s, 0]], dtype=float),
                   np.array([[0, 1, 2], [0, 2, 3]]))
    scene.add_light("sun", power=3.0, direction=(0.0, math.cos(elevation), -math.sin(elevation)))
    eye = (0.0, -10.0 * math.cos(camera_elevation), 10.0 * math.sin(camera_elevation))
    scene.set_camera(core_scenes.look_at(eye, (0.0, 0.0, 0.0)), width, height, fov=math.radians(20))
    renderer = ppm_core.Renderer(scene, threads=2, seed=8, samples_per_pixel=1, **settings)
    renderer.run(passes=1)
    return finite_rgb(renderer)


@pytest.mark.parametrize("elevation", [1e-3, 1e-6])
@pytest.mark.parametrize("camera_elevation", [0.3, 2e-2])
def test_grazing_sun_and_grazing_view(elevation, camera_elevation):
    """rho E sin(elevation) / pi on every pixel that sees the plane, whatever the angles."""
    image = plane_with_sun(elevation, camera_elevation, photons_per_pass=1000)
    expected = 0.5 * 3.0 * math.sin(elevation) / math.pi
    seen = image[..., 0] > 0.0
    assert seen.sum() >= image.shape[0] * image.shape[1] // 3  # the lower part of the view
    np.testing.assert_allclose(image[seen], expected, rtol=1e-6)


def test_rays_in_and_nearly_in_a_triangles_plane():
    scene = ppm_core.Scene()
    scene.add_material("white")
    scene.add_mesh("tri", np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float), np.array([[0, 1, 2]]))
    n = 200
    origins = np.zeros((n, 3))
    origins[:, 0] = -1.0
    origins[:, 1] = np.linspace(0.01, 0.5, n)
    tilt = np.concatenate([[0.0, 5e-324, 1e-300, -1e-300, 1e-200, 1e-160], np.logspace(-17, -1, n - 6)])
    directions = np.stack([np.ones(n), np.zeros(n), tilt], axis=1)
    origins[:, 2] = -0.5 * tilt  # crosses z = 0 at x = -0.5, i.e. before the triangle, or glides in its plane
    hits = scene.intersect(origins, directions)
    t = hits["t"]
    assert not np.isnan(t).any() and (t > 0).all()
    assert np.isfinite(hits["normal"]).all()
    # Rays lying in the plane (tilt 0 or below the float resolution of the origin) do not hit.
    assert np.isinf(t[0])


# --------------------------------------------------------------- coincident

def test_coincident_quads_show_one_or_the_other():
    """z-fighting: each pixel shows one of the two surfaces, exactly (sampled sun)."""
    scene = ppm_core.Scene()
    dark = scene.add_material("dark", base_color=(0.2, 0.2, 0.2))
    light = scene.add_material("light", base_color=(0.8, 0.8, 0.8))
    quad = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    scene.add_mesh("a", quad, np.array([[0, 1, 2], [0, 2, 3]]), materials=dark, object_id=1)
    scene.add_mesh("b", quad, np.array([[0, 2, 3], [0, 1, 2]]), materials=light, object_id=2)
    scene.add_light("sun", power=2.0, direction=(0.3, 0.1, -1.0))
    camera = np.eye(4)
    camera[2, 3] = 1.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=1.5)
    cos = 1.0 / math.sqrt(1.1)
    for threads in (1, 2):
        renderer = ppm_core.Renderer(scene, photons_per_pass=2000, threads=threads, samples_per_pixel=1, seed=9)
        renderer.run(passes=2)
        image = finite_rgb(renderer)[..., 0]
        allowed = np.array([0.2, 0.8]) * 2.0 * cos / math.pi
        distance = np.min(np.abs(image[..., None] - allowed), axis=-1)
        assert distance.max() < 1e-5 * allowed.max(), image


def test_coincident_closed_spheres_keep_the_analytic_answer():
    """Two identical spheres: a ray leaving one must not stop on the other at t ~ 0."""
    scene = closed_sphere(1.0)
    scene.add_sphere("twin", (0.0, 0.0, 0.0), 1.0, 0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=10)
    renderer.run(passes=8)
    assert finite_rgb(renderer).mean() == pytest.approx(EXPECTED_R1, rel=0.03)


def test_coincident_closed_meshes_keep_the_analytic_answer():
    """A closed triangle cube twice (same vertices): the inside is as bright as with one copy."""
    def render(copies):
        scene = ppm_core.Scene()
        scene.add_material("wall", base_color=(0.5, 0.5, 0.5))
        for k in range(copies):
            cube_mesh(scene, name=f"cube{k}")
        scene.add_light("point", power=100.0, position=(0.1, 0.05, -0.02))
        scene.set_camera(core_scenes.look_at((0.0, -0.5, 0.0), (0.0, 1.0, 0.0)), 16, 16, fov=math.radians(60))
        renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=11)
        renderer.run(passes=8)
        return finite_rgb(renderer).mean()

    assert render(2) == pytest.approx(render(1), rel=0.03)


# ---------------------------------------------------------------- degenerate

def degenerate_triangles():
    """Zero-area, collinear, duplicate-vertex, needle and sub-1e-30 m^2 triangles."""
    p = np.array([
        [0.2, 0.3, 0.5], [0.2, 0.3, 0.5], [0.2, 0.3, 0.5],       # one point three times
        [0.0, 0.0, 0.4], [0.5, 0.5, 0.4], [1.0, 1.0, 0.4],       # collinear
        [-0.3, 0.1, 0.3], [0.4, 0.2, 0.3],                        # two distinct points (duplicate vertex)
        [-0.5, -0.5, 0.6], [0.5, 0.5, 0.6], [0.5, 0.5 + 1e-17, 0.6],  # needle
        [0.1, -0.1, 0.2], [0.1 + 1e-16, -0.1, 0.2], [0.1, -0.1 + 1e-16, 0.2],  # area 5e-33
    ])
    t = np.array([[0, 1, 2], [3, 4, 5], [6, 7, 6], [6, 6, 7], [8, 9, 10], [11, 12, 13], [0, 0, 0]])
    return p, t


@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_degenerate_triangles_change_nothing(direct_light):
    def render(with_degenerate):
        scene = ppm_core.Scene()
        white = scene.add_material("white", base_color=(0.5, 0.5, 0.5))
        hot = scene.add_material("hot", emission=5.0)
        core_scenes.quad(scene, "floor", [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], white)
        scene.add_light("point", power=50.0, position=(0.0, 0.0, 1.5))
        if with_degenerate:
            p, t = degenerate_triangles()
            scene.add_mesh("degenerate", p, t, materials=white,
                           normals=np.zeros_like(p), uvs=np.full((len(p), 2), 0.5))
            scene.add_mesh("degenerate_emitters", p, t, materials=hot)  # zero or ~1e-33 m^2 of emitter
        scene.set_camera(core_scenes.look_at((0.0, -3.0, 3.0), (0.0, 0.0, 0.0)), 16, 12)
        renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2, seed=12, direct_light=direct_light)
        renderer.run(passes=3)
        return finite_rgb(renderer)

    np.testing.assert_allclose(render(True), render(False), rtol=1e-5, atol=1e-6)


def test_rays_at_degenerate_triangles_miss_cleanly():
    scene = ppm_core.Scene()
    scene.add_material("white")
    p, t = degenerate_triangles()
    scene.add_mesh("degenerate", p, t)
    origins = np.repeat([[0.0, 0.0, 5.0]], len(p), axis=0)
    hits = scene.intersect(origins, p - origins)  # straight at every vertex
    assert not np.isnan(hits["t"]).any() and not np.isnan(hits["normal"]).any()
    # Only the needle and the 5e-33 m^2 triangle have any area to hit.
    assert set(hits["primitive"][np.isfinite(hits["t"])].tolist()) <= {4, 5}


# ----------------------------------------------------- lights inside objects

def test_closed_triangle_mesh_is_watertight():
    """Rays from inside a closed 12-triangle cube at its edges and face diagonals (where two
    triangles meet) all hit: no gap between triangles that share an edge."""
    for half, center in [(1.0, (0, 0, 0)), (1e-4, (0, 0, 0)), (1e5, (0, 0, 0)), (1e-3, (1e3, 1e3, 1e3))]:
        scene = ppm_core.Scene()
        scene.add_material("white")
        cube_mesh(scene, half, center)
        targets = edge_targets(half) + center
        for inside in [(0.0, 0.0, 0.0), (0.3, -0.2, 0.1), (0.999, 0.5, -0.25)]:
            origins = np.tile(np.asarray(center, float) + np.multiply(inside, half), (len(targets), 1))
            hits = scene.intersect(origins, targets - origins)
            assert np.isfinite(hits["t"]).all(), (half, center, inside, int(np.isinf(hits["t"]).sum()))


@pytest.mark.parametrize("kind", ["point", "sphere", "spot", "rectangle", "disk"])
def test_lights_on_and_inside_surfaces(kind):
    """Lights exactly on a wall, half inside a wall, inside a solid sphere: finite, non-negative."""
    scene = ppm_core.Scene()
    white = scene.add_material("white", base_color=(0.7, 0.7, 0.7))
    cube_mesh(scene, 1.0, material=white)
    scene.add_sphere("solid", (0.5, 0.5, 0.5), 0.2, white)
    for name, position in [("on_wall", (0.0, 0.0, -1.0)), ("on_edge", (1.0, 1.0, 0.0)), ("in_solid", (0.5, 0.5, 0.5)),
                           ("at_vertex", (-1.0, -1.0, -1.0))]:
        scene.add_light(kind, name=name, power=10.0, position=position, direction=(0.0, 0.0, 1.0), radius=0.3,
                        size=0.5)
    scene.set_camera(core_scenes.look_at((0.0, -0.9, 0.0), (0.0, 1.0, -0.2)), 12, 8, fov=math.radians(80))
    for direct_light in ("sampled", "photons"):
        renderer = ppm_core.Renderer(scene, photons_per_pass=5_000, threads=2, seed=15, direct_light=direct_light)
        renderer.run(passes=2)
        image = finite_rgb(renderer)
        assert image.max() > 0.0


# ------------------------------------------------------- passes and threads

def test_many_passes_radius_shrinks_and_estimate_converges():
    """A short version of bench/run.py stress: radii shrink monotonically, stay positive, the image stays right."""
    renderer = ppm_core.Renderer(closed_sphere(1.0, width=8, height=8), photons_per_pass=500, threads=2,
                                 samples_per_pixel=1, seed=16)
    radii = []
    for _ in range(6):
        renderer.run(passes=50)
        radii.append(renderer.stats()["radius_mean"])
        finite_rgb(renderer)
    assert all(b < a for a, b in zip(radii, radii[1:])), radii
    assert finite_rgb(renderer).mean() == pytest.approx(EXPECTED_R1, rel=0.05)


@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
@pytest.mark.parametrize("power", [1e-30, 1e-58])
def test_microscopic_scene_with_a_very_dim_light(direct_light, power):
    """R = 1e-30 m: still the analytic answer, however dim the light. Regression: photon flux is
    float32, so a light below ~1e-38 W lost all its photons (the image kept only the sampled direct
    light, half the answer here, or nothing), and then such lights were refused; now photons carry
    their share of the total flux (about 1) and the gather multiplies by the total, in double. The
    r^2 floor of progressive.h (r^2 driven towards underflow) is tested in progressive_test.cpp."""
    radius = 1e-30
    renderer = ppm_core.Renderer(closed_sphere(radius, power=power, width=8, height=8), photons_per_pass=20_000,
                                 threads=2, seed=17, direct_light=direct_light)
    renderer.run(passes=6)
    expected = core_scenes.expected_closed_sphere_radiance(radius, 0.5, power)
    assert finite_rgb(renderer).mean() == pytest.approx(expected, rel=0.05)


def test_a_sun_over_a_large_scene_carries_all_its_light_in_photons():
    """A sun's photon flux grows with the scene's area (1e20 W/m^2 over 2e4 m: 1e29 W), which was
    refused while photons carried watts in float32. A lit floor's radiance is rho E / pi."""
    scene = ppm_core.Scene()
    floor = scene.add_material("floor", "diffuse", base_color=(0.5, 0.5, 0.5))
    core_scenes.quad(scene, "floor", [(-1e4, -1e4, 0), (1e4, -1e4, 0), (1e4, 1e4, 0), (-1e4, 1e4, 0)], floor)
    with_sun(scene, 1e20)
    scene.set_camera(core_scenes.look_at((0.0, 0.0, 100.0), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)), 8, 8)
    renderer = ppm_core.Renderer(scene, photons_per_pass=50_000, threads=2, seed=3, direct_light="photons")
    renderer.run(passes=8)
    assert finite_rgb(renderer).mean() == pytest.approx(0.5 * 1e20 / math.pi, rel=0.05)


# ------------------------------------------------------------- big inputs

def test_large_random_triangle_soup():
    rng = np.random.default_rng(19)
    n = 200_000
    centers = rng.uniform(-1.0, 1.0, size=(n, 1, 3))
    positions = (centers + rng.normal(scale=0.02, size=(n, 3, 3))).reshape(-1, 3)
    scene = ppm_core.Scene()
    scene.add_material("white", base_color=(0.6, 0.6, 0.6))
    scene.add_mesh("soup", positions, np.arange(3 * n).reshape(n, 3))
    scene.add_light("point", power=100.0, position=(0.0, 0.0, 3.0))
    scene.set_camera(core_scenes.look_at((0.0, -4.0, 1.0), (0.0, 0.0, 0.0)), 8, 6)
    assert scene.primitive_count == n
    origins = rng.uniform(-3.0, 3.0, size=(100_000, 3))
    hits = scene.intersect(origins, -origins)  # at the origin, through the soup
    assert not np.isnan(hits["t"]).any() and np.isfinite(hits["t"]).mean() > 0.9
    renderer = ppm_core.Renderer(scene, photons_per_pass=2_000, threads=2, seed=20)
    renderer.run(passes=1)
    assert finite_rgb(renderer).max() > 0.0


# ------------------------------------- regressions: inputs out of float range

def plane_under(light=None, normals=None, camera_scale=1.0, texture=None, base_color=0.5):
    scene = ppm_core.Scene()
    tex = scene.add_texture("t", texture) if texture is not None else -1
    scene.add_material("w", base_color=base_color, texture=tex)
    corners = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], dtype=float)
    scene.add_mesh("plane", corners, np.array([[0, 1, 2], [0, 2, 3]]), normals=normals, uvs=np.zeros((4, 2)))
    if light:
        scene.add_light(**light)
    camera = np.eye(4)
    camera[:3, :3] *= camera_scale
    camera[2, 3] = 2.0
    scene.set_camera(camera, 8, 6, projection="orthographic", ortho_scale=4.0)
    return scene


def render_small(scene, **settings):
    renderer = ppm_core.Renderer(scene, **{"photons_per_pass": 2000, "threads": 2, "seed": 21, **settings})
    renderer.run(passes=2)
    return finite_rgb(renderer)


@pytest.mark.parametrize("kind,extra", [("spot", dict(spot_angle=1.5)), ("rectangle", dict(size=0.5)),
                                        ("sun", dict(power=2.0))])
def test_huge_and_tiny_direction_vectors_mean_the_same_direction(kind, extra):
    """Regression: a direction of length 1e300 was divided by its overflowed length (inf) and became
    (0, 0, 0): the light lit nothing. A length below 1e-154 underflowed to 0 and was refused."""
    def image(direction):
        return render_small(plane_under(dict(kind=kind, position=(0.0, 0.0, 1.0), direction=direction, **extra)))

    reference = image((0.1, 0.0, -1.0))
    assert reference.max() > 0.0
    for scale in (1e300, 1e-300):
        np.testing.assert_allclose(image((0.1 * scale, 0.0, -scale)), reference, rtol=1e-6, err_msg=str(scale))


def test_camera_matrix_with_huge_or_tiny_scale():
    """Regression: a camera matrix scaled by 1e300 gave NaN axes (an all-black image); 1e-300 was
    refused as singular. The camera's scale does not matter (Blender's camera object may be scaled)."""
    light = dict(kind="point", position=(0.0, 0.0, 1.0))
    reference = render_small(plane_under(light))
    for scale in (1e300, 1e-300):
        np.testing.assert_allclose(render_small(plane_under(light, camera_scale=scale)), reference, rtol=1e-6)


def test_huge_and_tiny_normal_vectors_are_normalised():
    """Regression: normals of length 1e300 (or 1e-200) overflowed (underflowed) in the length and
    were silently replaced by the flat face normal."""
    light = dict(kind="point", position=(0.0, 0.0, 1.0))
    tilted = np.tile([0.6, 0.0, 0.8], (4, 1))
    reference = render_small(plane_under(light, normals=tilted))
    assert not np.allclose(reference, render_small(plane_under(light)))  # the normals matter here
    for scale in (1e300, 1e-200):
        np.testing.assert_allclose(render_small(plane_under(light, normals=tilted * scale)), reference, rtol=1e-6)


def test_radiance_above_float_range_saturates():
    """A 1e20 W point light 1e-12 m above a wall: irradiance ~1e43 W/m^2, beyond float32. The
    image saturates at the largest float instead of holding inf (and NaN after any arithmetic)."""
    scene = ppm_core.Scene()
    scene.add_material("w")
    corners = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], dtype=float) * 1e-9
    scene.add_mesh("plane", corners, np.array([[0, 1, 2], [0, 2, 3]]))
    scene.add_light("point", position=(0.0, 0.0, 1e-12), power=1e20)
    camera = np.eye(4)
    camera[2, 3] = 1e-9
    scene.set_camera(camera, 8, 6, projection="orthographic", ortho_scale=1e-11, clip_start=0.0)
    image = render_small(scene)
    assert image.max() == np.finfo(np.float32).max


def test_colours_above_one_render_until_they_could_overflow():
    """An albedo of 2 creates energy: fine for 12 bounces (finite, brighter than albedo 0.99), refused
    for 1000 bounces, where the photon flux grew to inf (before: an all-inf image)."""
    scene = core_scenes.closed_sphere_with_point_light(albedo=2.0, width=8, height=6)
    bright = render_small(scene)
    assert bright.mean() > 10 * EXPECTED_R1
    with pytest.raises(ValueError, match="material 'wall': its colour 2 reflects more light than it receives"):
        ppm_core.Renderer(scene, max_bounces=1000)
    textured = plane_under(dict(kind="point", position=(0.0, 0.0, 1.0)), texture=np.full((2, 2, 4), 1e30))
    with pytest.raises(ValueError, match="reflects more light than it receives"):
        ppm_core.Renderer(textured)


@pytest.mark.parametrize("build,message", [
    (lambda s: s.add_light("point", power=1e21), "power 1e+21 is above the supported 1e+20"),
    (lambda s: s.add_material("m", emission=(0.0, 1e39, 0.0)), "emission 1e+39 is above the supported 1e+20"),
    (lambda s: s.set_background(1e21), "radiance 1e+21 is above the supported 1e+20"),
    (lambda s: s.add_sphere("s", (0, 0, 0), 1e31, 0), "radius 1e+31 is outside the supported range"),
    (lambda s: s.add_sphere("s", (0, 0, 0), 1e-101, 0), "radius 1e-101 is outside the supported range"),
    (lambda s: s.add_sphere("s", (0, 0, 2e30), 1.0, 0), "center has a component of magnitude 2e+30"),
    (lambda s: s.add_mesh("m", np.array([[0, 0, 0], [1e31, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]])),
     "position 1 has a component of magnitude 1e+31"),
    (lambda s: s.add_light("sphere", radius=1e-300), "radius 1e-300 is outside the supported range"),
    (lambda s: s.add_light("rectangle", size=(1.0, 1e-120)), "size along y 1e-120 is outside the supported range"),
    (lambda s: s.add_light("spot", spot_angle=1e-9), "large enough that its cosine differs from 1"),
    (lambda s: s.add_texture("t", np.full((2, 2, 4), -0.5)), "pixel (x 0, y 0) has a negative colour component"),
    (lambda s: s.set_camera(np.eye(4), 8, 8, shift_x=1e308), "shift must be within"),
    (lambda s: s.set_camera(np.eye(4), 8, 8, focus_distance=1e300), "focus_distance is outside"),
    (lambda s: s.add_mesh("m", np.zeros((3, 3)), np.array([[0.5, 1.0, 2.0]])), "triangles entry 0 is not an integer"),
    (lambda s: s.add_mesh("m", np.zeros((3, 3)), np.array([[0, 1, np.nan]])), "triangles entry 2 is not an integer"),
    (lambda s: s.add_mesh("m", np.zeros((3, 3)), np.array([[0, 1, 2]]), materials=-1),
     "materials entry 0 is out of range"),
    (lambda s: s.add_light("rectangle", size="ab"), "size must be one number or (size_x, size_y)"),
    (lambda s: s.add_material(b"\xff"), "the name must be UTF-8 text"),
    (lambda s: s.add_material("m", kind=b"\xff"), r"not '\xff'"),
])
def test_out_of_range_inputs_are_refused_with_a_message(build, message):
    """Regression: each of these rendered inf/NaN/negative images, lost light silently, or raised an
    exception without saying where (RuntimeError 'Unable to cast', UnicodeDecodeError)."""
    scene = ppm_core.Scene()
    scene.add_material("white")
    with pytest.raises(ValueError) as err:
        build(scene)
    assert message in str(err.value)


def with_sun(scene, irradiance):
    scene.add_light("sun", name="sun", power=irradiance, direction=(0.0, 0.0, -1.0))
    return scene


@pytest.mark.parametrize("scene,settings,message", [
    (lambda: closed_sphere(1.0), dict(initial_radius=1e200, gather="hit_points"), "initial_radius must be at most"),
    (lambda: closed_sphere(1.0), dict(initial_radius_pixels=1e300), "initial_radius_pixels must be at most"),
])
def test_out_of_range_renders_are_refused_with_a_message(scene, settings, message):
    with pytest.raises(ValueError, match=message.replace("+", r"\+")):
        ppm_core.Renderer(scene(), **settings)


def test_callback_returning_a_non_flag_is_an_error_with_a_message():
    renderer = ppm_core.Renderer(closed_sphere(1.0, width=8, height=8), photons_per_pass=200_000, threads=2)
    with pytest.raises(ValueError, match="the callback must return None, True"):
        renderer.run(passes=2, callback=lambda info: "yes")
    assert renderer.run(passes=1, callback=lambda info: np.True_) == 1


def test_image_before_any_pass_is_black_with_alpha_one():
    """Regression (found by the fuzz): a Renderer whose run() raised before the eye pass returned
    alpha = 0, against the documented alpha = 1."""
    renderer = ppm_core.Renderer(closed_sphere(1.0, width=4, height=3), photons_per_pass=10)
    with pytest.raises(ValueError, match="seconds must be >= 0"):
        renderer.run(passes=1, seconds=-1.0)
    image = renderer.image()
    assert image.shape == (3, 4, 4)
    assert (image[..., :3] == 0.0).all() and (image[..., 3] == 1.0).all()
