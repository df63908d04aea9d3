"""The world's export: an Environment Texture (with a Mapping node in front of it) becomes the core's
environment, what cannot be read falls back with a warning, and the HDRIs Blender ships export
without one (tests/blenders/world_compare.py checks the images against Cycles)."""

import math
import os

import bpy
import numpy as np
import pytest
from test_forgiving_input import export_scene, floor_scene

from ppm_render.export import world as world_export


def environment_world(image=None, rotation=None, location=(0.0, 0.0, 0.0), scale=(1.0, 1.0, 1.0)):
    world = bpy.data.worlds.new("sky")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    environment = nodes.new("ShaderNodeTexEnvironment")
    environment.image = image
    links.new(environment.outputs["Color"], background.inputs["Color"])
    if rotation is not None:
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = rotation
        mapping.inputs["Location"].default_value = location
        mapping.inputs["Scale"].default_value = scale
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], environment.inputs["Vector"])
    bpy.context.scene.world = world
    return world


def shipped_hdri(name):
    path = os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world", name + ".exr")
    return bpy.data.images.load(path)


def test_a_shipped_hdri_exports_without_a_warning():
    """Blender's own HDRIs hold small negative values (down to -0.004 in 4.2's sunrise.exr, whose sun
    is 32,000): clamped, not reported."""
    scene = floor_scene()
    environment_world(shipped_hdri("sunrise"))
    core_scene, warnings = export_scene(scene)
    assert warnings == []
    assert core_scene.light_count == 2  # the sun lamp of floor_scene and the environment


def test_a_mapping_rotation_is_applied_and_the_rest_is_warned_about():
    scene = floor_scene()
    environment_world(shipped_hdri("courtyard"), rotation=(0.0, 0.0, math.radians(90)), location=(1.0, 0.0, 0.0))
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and "only its rotation is applied" in warnings[0]


@pytest.mark.parametrize("angles", [(0.3, 0.0, 0.0), (0.0, -0.7, 0.0), (0.0, 0.0, 1.1), (0.3, -0.7, 1.1)])
def test_euler_xyz_is_blenders(angles):
    from mathutils import Euler

    np.testing.assert_allclose(world_export.euler_xyz(angles), np.array(Euler(angles, "XYZ").to_matrix()),
                               atol=1e-6)  # mathutils is float32


def test_an_environment_without_an_image_falls_back_to_the_background_colour():
    scene = floor_scene()
    world = environment_world(None)
    _, warnings = export_scene(scene)
    assert len(warnings) == 1 and f"world '{world.name}'" in warnings[0] and "has no image" in warnings[0]


def test_world_ray_visibility_is_read():
    world = environment_world(None)
    assert world_export.visibility(world) == ["camera", "diffuse", "glossy", "transmission", "shadow"]
    world.cycles_visibility.camera = False
    world.cycles_visibility.glossy = False
    assert world_export.visibility(world) == ["diffuse", "transmission", "shadow"]
