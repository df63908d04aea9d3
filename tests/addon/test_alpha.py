"""Film > Transparent, Transparent Glass and Holdout reach the core and the render's alpha
(tests/blenders/alpha_compare.py checks the images against Cycles in every version)."""

import numpy as np
from test_forgiving_input import cube, floor_scene

from conftest import bpy, render_file
from ppm_render.properties import film_settings


def test_film_settings_follow_the_scene():
    scene = bpy.context.scene
    assert film_settings(scene) == {"transparent_background": False, "transparent_glass": False}
    scene.render.film_transparent = True
    scene.cycles.film_transparent_glass = True
    assert film_settings(scene) == {"transparent_background": True, "transparent_glass": True}


def test_a_holdout_object_is_a_hole_in_the_render(tmp_path):
    scene = floor_scene()
    cube("hole", location=(0.0, 0.0, 0.5)).is_holdout = True
    scene.render.image_settings.color_mode = "RGBA"
    rgba = render_file(scene, tmp_path / "holdout.exr", passes=1, photons_per_pass=2000, samples_per_pixel=1)
    alpha = rgba[..., 3]
    assert alpha.min() == 0.0 and alpha.max() == 1.0
    assert (rgba[alpha == 0.0][:, :3] == 0.0).all()  # premultiplied: nothing behind the hole
    assert alpha[12, 16] == 0.0 and alpha[0, 0] == 1.0  # the cube in the middle, the floor around it


def test_a_transparent_film_renders_the_background_transparent(tmp_path):
    scene = floor_scene()
    bpy.data.objects["cam"].rotation_euler = (1.2, 0.0, 0.0)  # towards the horizon: sky in the top rows
    scene.render.film_transparent = True
    scene.render.image_settings.color_mode = "RGBA"
    rgba = render_file(scene, tmp_path / "film.exr", passes=1, photons_per_pass=2000, samples_per_pixel=1)
    assert (rgba[0, :, 3] == 0.0).all() and (rgba[-1, :, 3] == 1.0).all()
    assert np.isfinite(rgba).all()
