"""The photon pass (engine/ppm/photon_pass.*): which photons a hit point gathers. Light must not
leak out of closed objects through the gather radius (the rule against photons across a solid),
and the two organisations (photons or hit points indexed) and the two grids give the same image."""

import math

import numpy as np
import pytest

import core_scenes
import ppm_core
from render_checks import EXPECTED_R1, closed_sphere, cube_mesh, finite_rgb, render_cornell


def light_in_a_box(direct_light, **settings):
    scene = ppm_core.Scene()
    white = scene.add_material("white", base_color=(0.8, 0.8, 0.8))
    cube_mesh(scene, material=white, object_id=1)
    core_scenes.quad(scene, "ground", [(-10, -10, -1.5), (10, -10, -1.5), (10, 10, -1.5), (-10, 10, -1.5)],
                     white, object_id=2)
    scene.add_light("point", power=100.0, position=(0.0, 0.0, 0.0))
    camera = core_scenes.look_at((4.0, -6.0, 3.0), (0.0, 0.0, -1.0))
    scene.set_camera(camera, 32, 24)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=13, direct_light=direct_light,
                                 samples_per_pixel=1, **settings)
    renderer.run(passes=4)
    # Which object each pixel centre sees (rows top first, like the image).
    width, height = 32, 24
    fov = 0.8575560591178853
    xs = (np.arange(width) + 0.5 - width / 2) * (2 * math.tan(fov / 2) / width)
    ys = (height / 2 - np.arange(height) - 0.5) * (2 * math.tan(fov / 2) / width)
    local = np.stack([*np.meshgrid(xs, ys), -np.ones((height, width))], axis=-1).reshape(-1, 3)
    dirs = local @ camera[:3, :3].T
    seen = scene.intersect(np.tile(camera[:3, 3], (len(dirs), 1)), dirs)["object"].reshape(height, width)
    return finite_rgb(renderer), seen



@pytest.mark.parametrize("direct_light", ["sampled", "photons"])
def test_light_inside_a_closed_box_does_not_leak_to_the_ground(direct_light):
    image, seen = light_in_a_box(direct_light)
    ground = seen == 2
    assert ground.sum() > 100
    # Allow for pixels whose jittered sample hit the box instead: compare on pixels well inside the ground.
    inner = ground & np.roll(ground, 1, 0) & np.roll(ground, -1, 0) & np.roll(ground, 1, 1) & np.roll(ground, -1, 1)
    assert image[inner].max() == 0.0



@pytest.mark.parametrize("direct_light, settings", [
    ("sampled", {}), ("photons", {}), ("sampled", {"gather": "hit_points"}), ("photons", {"grid": "hash"})])
def test_light_inside_a_closed_box_leaves_its_outside_dark(direct_light, settings):
    """Regression: hit points on the outside of a face gathered photons deposited on the inside of the
    adjacent face within their radius (light leaked out along the box's edges), in every organisation."""
    image, seen = light_in_a_box(direct_light, **settings)
    assert (seen == 1).sum() > 50
    assert image[seen == 1].max() == 0.0



@pytest.mark.xfail(strict=True, reason="known: a surface parallel to another within the gather radius gathers its "
                   "photons. Here stochastic hit points keep radii of about 0.52 after 4 passes, and the ground "
                   "0.5 below the box's floor gathers photons from inside the box at the box's foot (2 pixels); "
                   "with the ground 3 below, nothing. A plane-distance test would also drop the photons that make "
                   "up for the disc's overhang at inside corners (see photon_pass.cpp).")
def test_light_inside_a_closed_box_with_the_ground_closer_than_the_radius():
    image, seen = light_in_a_box("photons", hit_points="stochastic")
    assert image[(seen == 1) | (seen == 2)].max() == 0.0



def test_light_inside_a_glass_ball_inside_a_closed_room():
    """Direct light is blocked by the glass, so photons carry it all, through the refractions, and
    by Cycles' rule (radiance passes an interface unscaled, shading/lobes.h) a light inside glass
    sends out eta^2 = 2.25 times what it would in air, as Cycles renders a lamp inside a glass bulb
    (a sphere light in a glass ball, Blender 5.0: Cycles' walls 1.8-2.2 times as bright as PPM's
    without the rule, at 128 samples)."""
    scene = closed_sphere(1.0)
    glass = scene.add_material("glass", "glass", base_color=(1.0, 1.0, 1.0), ior=1.5)
    scene.add_sphere("ball", (0.0, 0.0, 0.0), 0.02, glass)
    renderer = ppm_core.Renderer(scene, photons_per_pass=20_000, threads=2, seed=14, max_bounces=40)
    renderer.run(passes=8)
    assert finite_rgb(renderer).mean() == pytest.approx(1.5**2 * EXPECTED_R1, rel=0.04)



@pytest.mark.parametrize("gather", ["hit_points", "photons"])
@pytest.mark.parametrize("grid", ["quantile", "hash"])
def test_gather_organisations_and_grids_agree(gather, grid):
    reference = render_cornell(5, 2)
    image = render_cornell(5, 2, gather=gather, grid=grid)
    np.testing.assert_allclose(image, reference, rtol=2e-4, atol=1e-6)

