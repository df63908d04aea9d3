"""Media from Blender: a material's Volume output fills the closed mesh it is on, the world's fills the
rest (export/volume.py), read as Cycles computes them, and rendered through F12.

The coefficients are checked against Cycles' formulas for each volume shader, through Mix and Add
shaders and node groups; the render against the closed form of an absorbing cube in front of a
uniform sky (exp(-sigma_a d), per channel). tests/core/test_media.py checks the core's transport."""

import math

import bpy
import numpy as np
import pytest
from test_forgiving_input import export_scene, floor_scene

import ppm_core
from conftest import add, camera_looking_down, node_material, render_file
from ppm_render.export import volume


def volume_material(name, shader, **inputs):
    """A material whose Volume output is one `shader` node with these inputs: (material, tree, node)."""
    mat, tree, out = node_material(name)
    node = add(tree, shader, **inputs)
    tree.links.new(node.outputs[0], out.inputs["Volume"])
    return mat, tree, node


def volume_world(name, shader, strength=1.0, **inputs):
    """The scene's new world: its Background of `strength`, its Volume one `shader` node with these inputs."""
    world = bpy.context.scene.world = bpy.data.worlds.new(name)
    if world.node_tree is None or bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    tree = world.node_tree
    next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBackground").inputs["Strength"].default_value = strength
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld")
    tree.links.new(add(tree, shader, **inputs).outputs[0], output.inputs["Volume"])
    return world


def read(mat):
    warnings = []
    return volume.material_medium(mat, warnings.append, None), warnings


def test_volume_absorption_and_scatter_are_cycles_coefficients():
    mat, _, _ = volume_material("ink", "ShaderNodeVolumeAbsorption", Color=(0.2, 0.5, 1.0, 1.0), Density=2.0)
    keywords, warnings = read(mat)
    assert warnings == []
    assert keywords["sigma_a"] == pytest.approx((1.6, 1.0, 0.0)) and keywords["sigma_s"] == (0.0, 0.0, 0.0)
    mat, _, _ = volume_material("fog", "ShaderNodeVolumeScatter", Color=(1.0, 0.5, 0.25, 1.0), Density=4.0,
                                Anisotropy=0.3)
    keywords, _ = read(mat)
    assert keywords["sigma_s"] == pytest.approx((4.0, 2.0, 1.0)) and keywords["sigma_a"] == (0.0, 0.0, 0.0)
    assert keywords["phase"] == "henyey_greenstein" and keywords["anisotropy"] == pytest.approx(0.3)


def test_principled_volume_defaults_are_cycles_coefficients():
    """Color 0.5, Density 1, Absorption Color black: sigma_s = 0.5, sigma_a = (1 - 0.5)(1 - 0) = 0.5."""
    mat, _, _ = volume_material("smoke", "ShaderNodeVolumePrincipled")
    keywords, warnings = read(mat)
    assert warnings == []
    assert keywords["sigma_s"] == pytest.approx((0.5,) * 3) and keywords["sigma_a"] == pytest.approx((0.5,) * 3)
    assert keywords["emission"] == (0.0, 0.0, 0.0)


def test_principled_volume_absorption_colour_emission_and_blackbody():
    mat, _, node = volume_material("fire", "ShaderNodeVolumePrincipled", Color=(0.8, 0.6, 0.4, 1.0), Density=2.0,
                                   **{"Absorption Color": (0.25, 0.0, 1.0, 1.0), "Emission Strength": 3.0,
                                      "Emission Color": (1.0, 0.5, 0.0, 1.0), "Blackbody Intensity": 1.0,
                                      "Temperature": 1500.0})
    keywords, warnings = read(mat)
    assert warnings == []  # it lights its surroundings: the core emits photons from the mesh it fills
    color, absorption = np.array([0.8, 0.6, 0.4]), np.array([0.25, 0.0, 1.0])
    assert keywords["sigma_a"] == pytest.approx(tuple((1 - color) * (1 - np.sqrt(absorption)) * 2.0))
    blackbody = np.array(volume.blackbody.blackbody_rgb(1500.0, volume.blackbody.kernel_rec709_to_scene_linear()))
    expected = 3.0 * np.array([1.0, 0.5, 0.0]) + 5.670373e-8 * 1e-6 / math.pi * 1500.0 ** 4 * blackbody
    assert keywords["emission"] == pytest.approx(tuple(expected), rel=1e-6)
    assert keywords["emission"][0] > 3.05  # the blackbody term is there (about 0.09 at 1500 K)


def test_mixes_adds_and_groups_weigh_each_shader():
    """Mix 0.25 of (absorption, a group holding Add(scatter, emission)): 0.75 of one, 0.25 of the others."""
    mat, tree, out = node_material("mixed")
    absorb = add(tree, "ShaderNodeVolumeAbsorption", Color=(0.0, 0.0, 0.0, 1.0), Density=1.0)
    group = bpy.data.node_groups.new("haze", "ShaderNodeTree")
    if hasattr(group, "interface"):  # Blender 4.0+
        group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    else:
        group.outputs.new("NodeSocketShader", "Shader")
    inner = group.nodes.new("NodeGroupOutput")
    scatter = add(group, "ShaderNodeVolumeScatter", Color=(1.0, 1.0, 1.0, 1.0), Density=8.0)
    glow = add(group, "ShaderNodeEmission", Color=(1.0, 0.0, 0.0, 1.0), Strength=4.0)
    both = group.nodes.new("ShaderNodeAddShader")
    group.links.new(scatter.outputs[0], both.inputs[0])
    group.links.new(glow.outputs[0], both.inputs[1])
    group.links.new(both.outputs[0], inner.inputs[0])
    holder = tree.nodes.new("ShaderNodeGroup")
    holder.node_tree = group
    mix = add(tree, "ShaderNodeMixShader", Fac=0.25)
    tree.links.new(absorb.outputs[0], mix.inputs[1])
    tree.links.new(holder.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Volume"])
    keywords, warnings = read(mat)
    assert warnings == []
    assert keywords["sigma_a"] == pytest.approx((0.75,) * 3)
    assert keywords["sigma_s"] == pytest.approx((2.0,) * 3)
    assert keywords["emission"] == pytest.approx((1.0, 0.0, 0.0))


def test_volume_scatter_phase_functions_are_read():
    """Every phase function the Blender's Volume Scatter offers (4.4+); before, Henyey-Greenstein only."""
    mat, _, node = volume_material("plain", "ShaderNodeVolumeScatter", Anisotropy=0.4)
    keywords, _ = read(mat)
    assert keywords["phase"] == "henyey_greenstein" and keywords["anisotropy"] == pytest.approx(0.4)
    expected = {"FOURNIER_FORAND": {"phase": "fournier_forand", "backscatter": 0.1, "ior": 1.33},
                "DRAINE": {"phase": "draine", "anisotropy": 0.0, "alpha": 0.5},
                "RAYLEIGH": {"phase": "rayleigh"}, "MIE": {"phase": "mie", "diameter": 20.0}}
    assert hasattr(node, "phase") == (bpy.app.version >= (4, 4, 0))
    for enum, keywords in (expected.items() if hasattr(node, "phase") else ()):
        mat, _, node = volume_material(enum.lower(), "ShaderNodeVolumeScatter")
        node.phase = enum
        read_keywords, _ = read(mat)
        assert {k: read_keywords[k] for k in keywords} == pytest.approx(keywords), enum


def read_with_program(mat):
    """read(mat) with a core scene, which compiles what textures drive into a node program."""
    warnings = []
    return volume.material_medium(mat, warnings.append, ppm_core.Scene()), warnings


def terms_by_coefficient(keywords):
    return {name: rgb for term in keywords["terms"] for name, rgb in term.items() if name != "input"}


def test_a_textured_density_makes_a_medium_that_varies_in_space():
    """A Noise cloud: Principled Volume (Color 0.5) whose Density a Noise drives. Nothing constant is
    left; sigma_s = 0.5 and sigma_a = (1 - 0.5)(1 - 0) per unit of the Noise's value, one output of the
    node program; no warning, and the export gives the cube's object its coordinates."""
    mat, tree, node = volume_material("cloud", "ShaderNodeVolumePrincipled", Density=3.0)
    noise = tree.nodes.new("ShaderNodeTexNoise")
    tree.links.new(noise.outputs["Fac"], node.inputs["Density"])
    keywords, warnings = read_with_program(mat)
    assert warnings == []
    assert keywords["sigma_s"] == (0.0, 0.0, 0.0) and keywords["sigma_a"] == (0.0, 0.0, 0.0)
    assert len(keywords["program"]["outputs"]) == 1 and {t["input"] for t in keywords["terms"]} == {0}
    assert terms_by_coefficient(keywords) == {"sigma_s": pytest.approx((0.5,) * 3),
                                              "sigma_a": pytest.approx((0.5,) * 3)}
    scene = floor_scene()
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.5))
    bpy.context.object.data.materials.append(mat)
    core_scene, warnings = export_scene(scene)
    assert warnings == [] and core_scene.media == ["material 'cloud'"] and core_scene.has_media


def test_a_textured_mix_factor_and_absorption_colour_vary_in_space():
    """Mix Shader (Fac: a Gradient texture) of Volume Scatter (density 2) and Volume Absorption (Color: a
    Checker, density 1): sigma_s = 2 (1 - fac) and sigma_a = (1 - colour) fac, each a term of its own
    program output."""
    mat, tree, out = node_material("mix")
    scatter = add(tree, "ShaderNodeVolumeScatter", Density=2.0, Color=(1.0, 1.0, 1.0, 1.0))
    absorb = add(tree, "ShaderNodeVolumeAbsorption", Density=1.0)
    mix = add(tree, "ShaderNodeMixShader")
    tree.links.new(scatter.outputs[0], mix.inputs[1])
    tree.links.new(absorb.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Volume"])
    tree.links.new(tree.nodes.new("ShaderNodeTexGradient").outputs["Fac"], mix.inputs["Fac"])
    tree.links.new(tree.nodes.new("ShaderNodeTexChecker").outputs["Color"], absorb.inputs["Color"])
    keywords, warnings = read_with_program(mat)
    assert warnings == []
    assert len(keywords["terms"]) == 2 and len({t["input"] for t in keywords["terms"]}) == 2
    assert terms_by_coefficient(keywords) == {"sigma_s": pytest.approx((2.0,) * 3),
                                              "sigma_a": pytest.approx((1.0,) * 3)}


def test_what_cannot_vary_takes_its_own_value_warned():
    """A textured Anisotropy (one phase per medium), and a World's textured density (the World's medium
    is homogeneous): each the socket's own value, one warning naming the socket."""
    mat, tree, node = volume_material("aniso", "ShaderNodeVolumeScatter", Anisotropy=0.5)
    tree.links.new(tree.nodes.new("ShaderNodeTexNoise").outputs["Fac"], node.inputs["Anisotropy"])
    keywords, warnings = read_with_program(mat)
    assert "terms" not in keywords and keywords["anisotropy"] == pytest.approx(0.5)
    assert len(warnings) == 1 and "'Anisotropy'" in warnings[0] and "varies in space" in warnings[0], warnings
    world = volume_world("foggy", "ShaderNodeVolumeScatter", Density=0.25)
    fog = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeVolumeScatter")
    world.node_tree.links.new(world.node_tree.nodes.new("ShaderNodeTexNoise").outputs["Fac"], fog.inputs["Density"])
    warnings = []
    keywords = volume.world_medium(world, warnings.append, ppm_core.Scene())
    assert "terms" not in keywords and keywords["sigma_s"] == pytest.approx((0.2,) * 3)
    assert len(warnings) == 1 and "World's medium is homogeneous" in warnings[0], warnings


@pytest.mark.parametrize("smoke_at, same, overlap", [((0.0, 0.0, 1.0), True, True), ((6.0, 0.0, 1.0), True, False),
                                                     ((0.0, 0.0, 1.0), False, False)])
def test_one_medium_on_objects_whose_bounds_overlap_is_warned_naming_both(smoke_at, same, overlap):
    """A ball inside a fog cube, of the cube's own Volume material: Cycles adds it twice inside the
    ball, the core once; warned once, naming both. The ball beside the cube, or of another medium
    (added to the fog as Cycles does): nothing."""
    scene = floor_scene()
    fog, _, _ = volume_material("fog", "ShaderNodeVolumeScatter", Density=0.1)
    smoke = fog if same else volume_material("smoke", "ShaderNodeVolumePrincipled", Density=2.0)[0]
    bpy.ops.mesh.primitive_cube_add(size=4.0, location=(0.0, 0.0, 2.0))
    bpy.context.object.name = "FogRoom"
    bpy.context.object.data.materials.append(fog)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=smoke_at)
    bpy.context.object.name = "Smoke"
    bpy.context.object.data.materials.append(smoke)
    _, warnings = export_scene(scene)
    overlapping = [w for w in warnings if "may overlap" in w]
    assert len(warnings) == len(overlapping), warnings
    if overlap:
        assert len(overlapping) == 1 and "'FogRoom'" in overlapping[0] and "'Smoke'" in overlapping[0], warnings
    else:
        assert overlapping == [], warnings


def test_scattering_with_two_phase_functions_is_warned():
    mat, tree, out = node_material("two")
    forward = add(tree, "ShaderNodeVolumeScatter", Density=1.0, Anisotropy=0.8)
    backward = add(tree, "ShaderNodeVolumeScatter", Density=3.0, Anisotropy=-0.4)
    both = tree.nodes.new("ShaderNodeAddShader")
    tree.links.new(forward.outputs[0], both.inputs[0])
    tree.links.new(backward.outputs[0], both.inputs[1])
    tree.links.new(both.outputs[0], out.inputs["Volume"])
    keywords, warnings = read(mat)
    assert len(warnings) == 1 and "phase functions" in warnings[0]
    assert keywords["anisotropy"] == pytest.approx((0.8 * 1 - 0.4 * 3) / 4)


def test_a_surface_shader_in_a_volume_output_is_left_out_with_a_warning():
    mat, _, _ = volume_material("odd", "ShaderNodeBsdfDiffuse")
    keywords, warnings = read(mat)
    assert keywords is None and len(warnings) == 1 and "not a volume shader" in warnings[0]


def test_the_world_volume_fills_the_scene_and_fixed_hit_points_give_way(tmp_path):
    scene = floor_scene()
    volume_world("hazy", "ShaderNodeVolumeScatter", Density=0.05)
    core_scene, warnings = export_scene(scene)
    assert len(warnings) == 1 and "sun lamps and the world's own light" in warnings[0], warnings
    assert core_scene.media == ["world 'hazy'"] and core_scene.has_media
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))  # the sun lights nothing here
    lamp.data.energy, lamp.location = 300.0, (0.0, 0.0, 2.0)
    scene.collection.objects.link(lamp)
    scene.ppm.hit_points = "FIXED"
    rgb = render_file(scene, tmp_path / "fog.exr", passes=2, photons_per_pass=5000, samples_per_pixel=1)[..., :3]
    assert np.isfinite(rgb).all() and rgb.mean() > 0.01


def test_an_emitting_world_volume_is_warned_an_emitting_material_volume_is_not():
    """The core emits no photons from the World's medium (infinite space, unbounded power): its
    emission is warned as lighting nothing; the same Volume in a material lights its surroundings."""
    world = volume_world("glowing", "ShaderNodeVolumePrincipled", **{"Emission Strength": 0.2})
    warnings = []
    keywords = volume.world_medium(world, warnings.append, None)
    assert keywords["emission"][0] > 0.0
    assert len(warnings) == 1 and "emits no photons" in warnings[0], warnings
    mat, _, _ = volume_material("glow", "ShaderNodeVolumePrincipled", **{"Emission Strength": 0.2})
    assert read(mat)[1] == []


def test_a_world_volume_in_the_dark_is_not_warned_about():
    """The warning that suns and the world's light reach nothing through a world Volume is for scenes
    that have them: a black world with a point light gets none."""
    scene = bpy.context.scene
    lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
    scene.collection.objects.link(lamp)
    camera_looking_down(scene, 3.0, 8, 8)
    volume_world("night", "ShaderNodeVolumeScatter", strength=0.0)
    core_scene, warnings = export_scene(scene)
    assert warnings == [] and core_scene.has_media


def absorbing_cube_scene(color, density, sky=1.0):
    """A 1 m cube of Volume Absorption (no surface) seen from above, filling the middle of a 32 x 32
    image, over nothing but a uniform sky of radiance `sky`."""
    scene = bpy.context.scene
    world = bpy.data.worlds.new("sky")
    world.color = (sky, sky, sky)
    if bpy.app.version >= (5, 0, 0):  # the tree is always used from 5.0 on
        background = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
        background.inputs["Color"].default_value = (sky, sky, sky, 1.0)
    scene.world = world
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.0))
    mat, _, _ = volume_material("ink", "ShaderNodeVolumeAbsorption", Color=(*color, 1.0), Density=density)
    bpy.context.object.data.materials.append(mat)
    cam = camera_looking_down(scene, 10.0, 32, 32)
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 2.0
    return scene


def test_an_absorbing_cube_transmits_exp_of_minus_sigma_a_times_its_depth(tmp_path):
    """Straight down through the 1 m cube: exp(-(1 - color) density) of the sky, per channel; around it
    the sky itself. The medium's surface is invisible (no Surface), as in Cycles."""
    scene = absorbing_cube_scene((0.2, 0.6, 0.9), 1.5)
    rgb = render_file(scene, tmp_path / "ink.exr", passes=2, photons_per_pass=1000, samples_per_pixel=1)[..., :3]
    centre = rgb[12:20, 12:20].reshape(-1, 3).mean(axis=0)
    assert centre == pytest.approx(np.exp(-np.array([0.8, 0.4, 0.1]) * 1.5), rel=0.01)
    assert rgb[1, 1] == pytest.approx((1.0, 1.0, 1.0), rel=1e-3)


def test_a_volume_only_material_of_no_density_is_a_clear_boundary(tmp_path):
    """Cycles renders a material with only an empty Volume as nothing at all."""
    scene = absorbing_cube_scene((0.2, 0.6, 0.9), 0.0)
    _, warnings = export_scene(scene)
    assert warnings == []
    rgb = render_file(scene, tmp_path / "none.exr", passes=1, photons_per_pass=1000, samples_per_pixel=1)[..., :3]
    assert rgb == pytest.approx(np.ones_like(rgb), rel=1e-3)
