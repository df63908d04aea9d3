"""Objects' and lights' ray visibility reach the core as Cycles reads them
(tests/blenders/visibility_compare.py checks the images against Cycles in every version)."""

import bpy
import numpy as np
import pytest
from test_forgiving_input import add_light, cube, export_scene, floor_scene

from ppm_render.export import visibility

DOWN = np.array([[0.0, 0.0, -1.0]])
ABOVE = np.array([[0.0, 0.0, 3.0]])  # over the cube (top at z = 1) and the floor (z = 0)


@pytest.mark.parametrize("flag,kind", [("visible_camera", "camera"), ("visible_diffuse", "diffuse"),
                                       ("visible_glossy", "glossy"), ("visible_transmission", "transmission"),
                                       ("visible_shadow", "shadow")])
def test_an_object_passes_rays_of_the_kinds_it_hides_from(flag, kind):
    scene = floor_scene()
    box = cube("box")
    setattr(box, flag, False)
    core_scene, _ = export_scene(scene)
    assert core_scene.intersect(ABOVE, DOWN, ray_kind=kind)["t"][0] == pytest.approx(3.0)  # the floor
    others = [k for k, _ in visibility.RAY_FLAGS if k != kind]
    for other in others:
        assert core_scene.intersect(ABOVE, DOWN, ray_kind=other)["t"][0] == pytest.approx(2.0), other


def test_lights_are_hidden_from_the_camera_as_blender_makes_them():
    light = add_light("bulb", "POINT", shadow_soft_size=0.2)
    assert visibility.ray_visibility(light) == ["diffuse", "glossy", "transmission", "shadow"]
    light.visible_camera, light.visible_glossy = True, False
    assert visibility.ray_visibility(light) == ["camera", "diffuse", "transmission", "shadow"]


def test_a_light_without_shadows_is_read_from_the_setting_cycles_of_this_blender_reads():
    light = add_light("bulb", "POINT").data
    assert visibility.casts_shadow(light)
    if bpy.app.version < (4, 0, 0):
        light.cycles.cast_shadow = False
    else:
        light.use_shadow = False
    assert not visibility.casts_shadow(light)
