"""The world's export: an Environment Texture (with a Mapping node in front of it) becomes the core's
environment, what cannot be read falls back with a warning, and the HDRIs Blender ships export
without one (tests/blenders/world_compare.py checks the images against Cycles)."""

import math
import os

import bpy
import numpy as np
import pytest
from test_forgiving_input import export_scene, floor_scene

import ppm_core
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


def test_a_baked_worlds_texels_look_where_the_core_looks_them_up():
    # The bake runs the program at each texel's direction; the core's environment maps that direction
    # back to the texel's centre (EnvironmentUv is the core's equirectangular mapping).
    width, height = 16, 8
    directions = world_export.bake_directions(width, height)
    modes = ppm_core.node_modes()
    program = {"code": [{"op": "coord", "mode": modes["coord"].index("position"), "out": [1]},
                        {"op": "environment_uv", "in": [1], "out": [2]}], "outputs": [2], "registers": 3}
    uv = ppm_core.Scene().run_program(program, directions)[:, 0, :2]
    u, v = np.meshgrid((np.arange(width) + 0.5) / width, (np.arange(height) + 0.5) / height)
    np.testing.assert_allclose(uv, np.stack([u.ravel(), v.ravel()], axis=1), atol=1e-6)


def test_a_gradient_sky_lights_the_scene_from_above():
    world = bpy.data.worlds.new("sky")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    coordinates, split = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeSeparateXYZ")
    clamp = nodes.new("ShaderNodeClamp")
    links.new(coordinates.outputs["Generated"], split.inputs[0])
    links.new(split.outputs["Z"], clamp.inputs["Value"])
    links.new(clamp.outputs[0], background.inputs["Color"])  # the sky's height, 0 below the horizon
    scene = ppm_core.Scene()
    warnings = []
    world_export.add_world(scene, world, warnings.append)
    assert warnings == []
    # A floor facing up sees the upper sky: irradiance pi * mean(z over the upper hemisphere, cosine
    # weighted) = pi * 2/3; a floor facing down sees nothing.
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    scene.add_material("white", base_color=(1.0, 1.0, 1.0))
    scene.add_mesh("floor", corners, np.array([[0, 1, 2], [0, 2, 3]]))
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 8, 8, projection="orthographic", ortho_scale=1.0)
    renderer = ppm_core.Renderer(scene, photons_per_pass=2000, threads=2, seed=1)
    renderer.run(passes=8)
    assert renderer.image()[..., :3].mean() == pytest.approx(2.0 / 3.0, rel=0.03)


def test_a_world_that_tells_camera_rays_apart_shows_one_colour_and_lights_with_the_other():
    # The artists' backdrop: Mix(bright white, dark blue, Is Camera Ray). The camera sees blue where
    # nothing is in front, a white floor is lit by the white sky (irradiance pi: radiance 1).
    world = bpy.data.worlds.new("backdrop")
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = next(n for n in nodes if n.bl_idname == "ShaderNodeBackground")
    path, mix = nodes.new("ShaderNodeLightPath"), nodes.new("ShaderNodeMixRGB")
    mix.inputs["Color1"].default_value = (1.0, 1.0, 1.0, 1.0)
    mix.inputs["Color2"].default_value = (0.0, 0.0, 0.2, 1.0)
    links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    links.new(mix.outputs[0], background.inputs["Color"])
    scene = ppm_core.Scene()
    warnings = []
    world_export.add_world(scene, world, warnings.append)
    assert warnings == []
    scene.add_material("white", base_color=(1.0, 1.0, 1.0))
    corners = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=float)
    scene.add_mesh("floor", corners, np.array([[0, 1, 2], [0, 2, 3]]))
    camera = np.eye(4)
    camera[2, 3] = 2.0
    scene.set_camera(camera, 16, 16, projection="orthographic", ortho_scale=4.0)  # the floor fills the middle
    renderer = ppm_core.Renderer(scene, photons_per_pass=4000, threads=2, seed=1)
    renderer.run(passes=8)
    image = renderer.image()[..., :3]
    np.testing.assert_allclose(image[0, 0], (0.0, 0.0, 0.2), atol=1e-3)  # the backdrop, as camera rays see it
    assert image[6:10, 6:10].mean() == pytest.approx(1.0, rel=0.03)  # lit by the white sky only
