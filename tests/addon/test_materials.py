"""Materials as the exporter reads them (export/closure.py, export/material.py): Mix and Add
shaders fold into lobe weights, node groups, reroutes and muted nodes pass as in Blender, the
Principled BSDF becomes its layers, and bad graphs get one warning naming material and node."""

import numpy as np
import pytest

import ppm_core
from conftest import add, bpy, node_material
from ppm_render.export import material as material_export
from ppm_render.export import mesh


def describe(mat):
    warnings = []
    params = material_export.MaterialExporter(ppm_core.Scene(), warnings.append).describe(mat)
    return params, warnings


def added(mat):
    """Adds `mat` to a core scene as a render does; its warnings."""
    warnings = []
    material_export.MaterialExporter(ppm_core.Scene(), warnings.append).index(mat)
    return warnings


def input_channels(params):
    """What each material input is: 'rgb', 'alpha' or 'grey' of an image, else the name of the
    program operation that computes it."""
    writer = {}  # register -> (the instruction that wrote it last, which output, what wrote its first input)
    for ins in params["program"]["code"]:  # registers are reused: read in order
        source = writer.get(ins["in"][0]) if ins["in"] else None
        writer.update({reg: (ins, k, source) for k, reg in enumerate(ins["out"]) if reg})

    def kind(reg):
        ins, k, source = writer[reg]
        if ins["op"] == "image":
            return ("rgb", "alpha")[k]
        if ins["op"] == "convert" and source is not None and source[0]["op"] == "image":
            return "grey"
        return ins["op"]

    return [kind(reg) for reg in params["program"]["outputs"]]


def lobes_by_kind(params):
    return {lobe["kind"]: lobe for lobe in params["lobes"]}


def test_mix_and_add_fold_into_weights():
    mat, tree, out = node_material()
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Color=(1.0, 0.0, 0.0, 1.0))
    glossy = add(tree, "ShaderNodeBsdfGlossy", Roughness=0.3)
    glass = add(tree, "ShaderNodeBsdfGlass", IOR=1.33)
    mix = add(tree, "ShaderNodeMixShader", Fac=0.25)
    add_shader = add(tree, "ShaderNodeAddShader")
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(glossy.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], add_shader.inputs[0])
    tree.links.new(glass.outputs[0], add_shader.inputs[1])
    tree.links.new(add_shader.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == []
    lobes = lobes_by_kind(params)
    assert params["kind"] == "mixture" and set(lobes) == {"diffuse", "glossy", "dielectric"}
    assert lobes["diffuse"]["weight"] == pytest.approx((0.75,) * 3)
    assert lobes["glossy"]["weight"] == pytest.approx((0.25,) * 3)
    assert lobes["glossy"]["roughness"] == pytest.approx(0.3)
    assert lobes["dielectric"]["weight"] == pytest.approx((1.0,) * 3)
    assert lobes["dielectric"]["ior"] == pytest.approx(1.33)


def test_microfacet_distributions_map_to_the_core():
    """Beckmann is Beckmann's; Multiscatter GGX restores energy, for glass too (not for Refraction,
    which has no such mode)."""
    mat, tree, out = node_material()
    glass = add(tree, "ShaderNodeBsdfGlass", IOR=1.5, Roughness=0.4)
    tree.links.new(glass.outputs[0], out.inputs["Surface"])
    for distribution, beckmann, multiscatter in (("BECKMANN", True, False), ("GGX", False, False),
                                                 ("MULTI_GGX", False, True)):
        glass.distribution = distribution
        (lobe,) = describe(mat)[0]["lobes"]
        assert (lobe["beckmann"], lobe["multiscatter"]) == (beckmann, multiscatter), distribution
    glossy = add(tree, "ShaderNodeBsdfGlossy", Roughness=0.4)
    glossy.distribution = "BECKMANN"
    tree.links.new(glossy.outputs[0], out.inputs["Surface"])
    (lobe,) = describe(mat)[0]["lobes"]
    assert lobe["kind"] == "glossy" and lobe["beckmann"] and lobe["roughness"] == pytest.approx(0.4)
    refraction = add(tree, "ShaderNodeBsdfRefraction", Roughness=0.4)
    refraction.distribution = "GGX"
    tree.links.new(refraction.outputs[0], out.inputs["Surface"])
    (lobe,) = describe(mat)[0]["lobes"]
    assert lobe["parts"] == "refraction" and not lobe["multiscatter"]


def test_zero_weight_branches_and_unconnected_inputs_are_dropped():
    mat, tree, out = node_material()
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1.0))
    glossy = add(tree, "ShaderNodeBsdfGlossy")
    mix = add(tree, "ShaderNodeMixShader", Fac=0.0)
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(glossy.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    params, _ = describe(mat)
    # Only diffuse is left: the cheap diffuse material, not a mixture.
    assert params["kind"] == "diffuse" and params["base_color"] == pytest.approx((0.5, 0.5, 0.5))
    mix.inputs["Fac"].default_value = 0.5
    tree.links.remove(mix.inputs[2].links[0])  # half of the surface is black, as in Cycles
    params, _ = describe(mat)
    assert params["kind"] == "diffuse" and params["base_color"] == pytest.approx((0.25, 0.25, 0.25))


def group_with_diffuse(color_default):
    """A node group whose shader output is a Diffuse BSDF of the group's Color input."""
    group = bpy.data.node_groups.new("tinted", "ShaderNodeTree")
    if hasattr(group, "interface"):
        group.interface.new_socket("Color", in_out="INPUT", socket_type="NodeSocketColor")
        group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    else:  # Blender 3.x
        group.inputs.new("NodeSocketColor", "Color")
        group.outputs.new("NodeSocketShader", "Shader")
    gin, gout = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    diffuse = group.nodes.new("ShaderNodeBsdfDiffuse")
    reroute = group.nodes.new("NodeReroute")
    group.links.new(gin.outputs[0], diffuse.inputs["Color"])
    group.links.new(diffuse.outputs[0], reroute.inputs[0])
    group.links.new(reroute.outputs[0], gout.inputs[0])
    return group


def test_node_groups_reroutes_and_group_inputs_pass_values():
    mat, tree, out = node_material()
    group = group_with_diffuse(None)
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.inputs[0].default_value = (0.1, 0.2, 0.3, 1.0)
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.6, 0.5, 0.4, 1.0)
    tree.links.new(node.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["base_color"] == pytest.approx((0.1, 0.2, 0.3))
    tree.links.new(rgb.outputs[0], node.inputs[0])  # an RGB node is a constant
    params, warnings = describe(mat)
    assert warnings == [] and params["base_color"] == pytest.approx((0.6, 0.5, 0.4))


def test_a_muted_mix_passes_its_first_shader():
    mat, tree, out = node_material()
    red = add(tree, "ShaderNodeBsdfDiffuse", Color=(1.0, 0.0, 0.0, 1.0))
    blue = add(tree, "ShaderNodeBsdfDiffuse", Color=(0.0, 0.0, 1.0, 1.0))
    mix = add(tree, "ShaderNodeMixShader", Fac=0.5)
    tree.links.new(red.outputs[0], mix.inputs[1])
    tree.links.new(blue.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    mix.mute = True
    params, _ = describe(mat)
    assert params["base_color"] == pytest.approx((1.0, 0.0, 0.0))


def test_a_cycle_of_links_renders_what_blender_keeps():
    """Blender refuses a group inside itself, and marks links that close a cycle invalid; Cycles
    drops those, and so does the exporter: the shaders outside the cycle still render."""
    mat, tree, out = node_material("loop")
    first, second = add(tree, "ShaderNodeMixShader", Fac=0.5), add(tree, "ShaderNodeMixShader", Fac=0.5)
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Color=(0.4, 0.4, 0.4, 1.0))
    tree.links.new(first.outputs[0], out.inputs["Surface"])
    tree.links.new(second.outputs[0], first.inputs[1])
    tree.links.new(first.outputs[0], second.inputs[1])  # closes the cycle
    tree.links.new(diffuse.outputs[0], first.inputs[2])
    params, warnings = describe(mat)
    assert params["kind"] == "diffuse" and params["base_color"] == pytest.approx((0.2, 0.2, 0.2))


def principled(**inputs):
    mat, tree, out = node_material("p")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled", **inputs)
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return describe(mat)[0]


def test_the_principled_bsdf_becomes_its_layers():
    plastic = lobes_by_kind(principled(**{"Base Color": (0.2, 0.3, 0.4, 1.0)}))
    assert plastic["dielectric"]["layer"] and plastic["dielectric"]["parts"] == "reflection"
    assert plastic["dielectric"]["ior"] == pytest.approx(1.5)
    assert plastic["diffuse"]["color"] == pytest.approx((0.2, 0.3, 0.4))
    metal = lobes_by_kind(principled(Metallic=1.0, Roughness=0.2))
    assert set(metal) == {"conductor"} and metal["conductor"]["roughness"] == pytest.approx(0.2)
    glass = lobes_by_kind(principled(**{"Transmission Weight": 1.0, "IOR": 1.33}))
    assert set(glass) == {"dielectric"} and glass["dielectric"]["ior"] == pytest.approx(1.33)
    coated = principled(**{"Coat Weight": 1.0, "Metallic": 1.0})["lobes"]
    assert [lobe["kind"] for lobe in coated] == ["dielectric", "conductor"] and coated[0]["layer"]
    glow = principled(**{"Emission Color": (1.0, 0.5, 0.0, 1.0), "Emission Strength": 4.0})
    assert glow["emission"] == pytest.approx((4.0, 2.0, 0.0))
    half = principled(Alpha=0.25)
    assert lobes_by_kind(half)["transparent"]["weight"] == pytest.approx((0.75,) * 3)
    dusty = principled(**{"Sheen Weight": 0.5, "Sheen Tint": (1.0, 0.5, 0.2, 1.0), "Sheen Roughness": 0.3})["lobes"]
    assert [lobe["kind"] for lobe in dusty] == ["microfiber_sheen", "dielectric", "diffuse"]
    assert dusty[0]["layer"] and dusty[0]["color"] == pytest.approx((0.5, 0.25, 0.1))
    assert dusty[0]["roughness"] == pytest.approx(0.3)


def test_a_value_driven_by_an_unsupported_node_warns_once_and_uses_its_own():
    mat, tree, out = node_material("skyward")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Color=(0.3, 0.3, 0.3, 1.0))
    sky = tree.nodes.new("ShaderNodeTexSky")  # a world's texture, on a material: not supported
    tree.links.new(sky.outputs["Color"], diffuse.inputs["Color"])
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert params["base_color"] == pytest.approx((0.3, 0.3, 0.3))
    assert len(warnings) == 1 and "'skyward'" in warnings[0] and sky.name in warnings[0]


def test_nodes_cycles_renders_simply_give_cycles_simplest_value_with_a_warning():
    mat, tree, out = node_material("dusty")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse")
    ao = add(tree, "ShaderNodeAmbientOcclusion", Color=(0.2, 0.4, 0.6, 1.0))
    mix = tree.nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    tree.links.new(ao.outputs["Color"], mix.inputs[1])
    tree.links.new(ao.outputs["AO"], mix.inputs[0])
    wire = tree.nodes.new("ShaderNodeWireframe")
    tree.links.new(wire.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], diffuse.inputs["Color"])
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    # AO: the colour unoccluded (AO 1); wireframe: 0; so the colour times 0.
    assert params["base_color"] == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    assert len(warnings) == 2 and all("'dusty'" in w for w in warnings)


def test_a_noise_through_a_color_ramp_becomes_a_program_and_a_constant_network_folds():
    mat, tree, out = node_material("grain")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse")
    noise, ramp = tree.nodes.new("ShaderNodeTexNoise"), tree.nodes.new("ShaderNodeValToRGB")
    tree.links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    tree.links.new(ramp.outputs["Color"], diffuse.inputs["Color"])
    # Roughness from Values through a Math node: constant, folded at export.
    a, b = tree.nodes.new("ShaderNodeValue"), tree.nodes.new("ShaderNodeValue")
    a.outputs[0].default_value, b.outputs[0].default_value = 0.3, 0.5
    times = add(tree, "ShaderNodeMath")
    times.operation = "MULTIPLY"
    tree.links.new(a.outputs[0], times.inputs[0])
    tree.links.new(b.outputs[0], times.inputs[1])
    tree.links.new(times.outputs[0], diffuse.inputs["Roughness"])
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "mixture" and input_channels(params) == ["table"]
    lobe = params["lobes"][0]
    assert lobe["color_input"] == 0 and lobe["roughness"] == pytest.approx(0.15)
    ops = [ins["op"] for ins in params["program"]["code"]]
    assert ops == ["coord", "noise", "table"] and "math" not in ops
    assert added(mat) == []


def test_a_missing_group_and_a_non_shader_on_a_shader_socket_warn_once_each():
    mat, tree, out = node_material("odd")
    group = bpy.data.node_groups.new("gone", "ShaderNodeTree")
    if hasattr(group, "interface"):
        group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    else:
        group.outputs.new("NodeSocketShader", "Shader")
    group_node = tree.nodes.new("ShaderNodeGroup")
    group_node.node_tree = group
    value = tree.nodes.new("ShaderNodeValue")
    mix = add(tree, "ShaderNodeMixShader", Fac=0.5)
    tree.links.new(group_node.outputs[0], mix.inputs[1])
    tree.links.new(value.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    bpy.data.node_groups.remove(group)  # up to 5.0 the node and its link stay, its group gone
    dangling = len(group_node.outputs) > 0 and len(group_node.outputs[0].links) > 0
    params, warnings = describe(mat)
    assert params["kind"] == "diffuse"  # the grey diffuse of the unsupported half; the missing half black
    assert len(warnings) == 1 + dangling, warnings
    assert not dangling or any(group_node.name in w and "missing" in w for w in warnings), warnings
    assert any(value.name in w for w in warnings) and all("'odd'" in w for w in warnings), warnings


def test_nan_in_a_shader_value_warns_naming_material_and_node():
    mat, tree, out = node_material("nan")
    glossy = add(tree, "ShaderNodeBsdfGlossy", Roughness=float("nan"))
    tree.links.new(glossy.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert len(warnings) == 1 and "'nan'" in warnings[0] and glossy.name in warnings[0], warnings
    assert params["lobes"][0]["roughness"] == 0.0


def test_a_holdout_mixed_with_a_shader_is_the_mixtures_holdout_weight():
    mat, tree, out = node_material("half_hole")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1.0))
    hole = tree.nodes.new("ShaderNodeHoldout")
    mix = add(tree, "ShaderNodeMixShader", Fac=0.25)
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(hole.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "mixture" and params["holdout"] == pytest.approx(0.25)
    assert params["lobes"][0]["weight"] == pytest.approx((0.75,) * 3)
    tree.links.remove(mix.inputs[1].links[0])  # holdout and black
    params, _ = describe(mat)
    assert params["kind"] == "mixture" and params["holdout"] == pytest.approx(0.25)
    mix.inputs["Fac"].default_value = 1.0  # all holdout
    assert describe(mat)[0]["kind"] == "holdout"


def image_node(tree, name, value=0.5):
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.new(name, 4, 4, alpha=True)
    node.image.pixels.foreach_set([value] * (4 * 4 * 4))
    return node


def test_images_on_roughness_metallic_and_a_mix_factor_become_inputs():
    mat, tree, out = node_material("textured")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled", **{"Base Color": (0.2, 0.3, 0.4, 1.0)})
    maps, mask = image_node(tree, "maps"), image_node(tree, "mask")
    tree.links.new(maps.outputs["Color"], bsdf.inputs["Roughness"])
    tree.links.new(maps.outputs["Color"], bsdf.inputs["Metallic"])  # the same input as Roughness
    glossy = add(tree, "ShaderNodeBsdfGlossy", Roughness=0.1)
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(mask.outputs["Color"], mix.inputs["Fac"])
    tree.links.new(bsdf.outputs[0], mix.inputs[1])
    tree.links.new(glossy.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == []
    assert params["kind"] == "mixture" and input_channels(params) == ["grey", "grey"]
    fac, grey = 0, 1  # the Mix factor is read first
    conductor, layer, diffuse, glossy_lobe = params["lobes"]
    assert conductor["kind"] == "conductor" and conductor["roughness_input"] == grey
    assert conductor["weight_inputs"] == [(fac, "complement"), (grey, "fraction")]
    assert layer["layer"] and layer["roughness_input"] == grey
    assert layer["weight_inputs"] == diffuse["weight_inputs"] == [(fac, "complement"), (grey, "complement")]
    assert diffuse["color"] == pytest.approx((0.2, 0.3, 0.4)) and "color_input" not in diffuse
    assert glossy_lobe["weight_inputs"] == [(fac, "fraction")] and "roughness_input" not in glossy_lobe
    assert added(mat) == []  # and the core takes them


def test_an_image_alpha_cuts_out_and_a_third_textured_factor_is_warned():
    mat, tree, out = node_material("leaf")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled")
    maps = image_node(tree, "maps")
    tree.links.new(maps.outputs["Color"], bsdf.inputs["Base Color"])
    tree.links.new(maps.outputs["Alpha"], bsdf.inputs["Alpha"])
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and input_channels(params) == ["rgb", "alpha"]
    transparent, _, diffuse = params["lobes"]
    assert transparent["kind"] == "transparent" and transparent["weight_inputs"] == [(1, "complement")]
    assert diffuse["weight_inputs"] == [(1, "fraction")] and diffuse["color_input"] == 0
    # Alpha and Metallic from images inside a textured Mix: the metal's weight would take three.
    tree.links.new(maps.outputs["Color"], bsdf.inputs["Metallic"])
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(maps.outputs["Color"], mix.inputs["Fac"])
    tree.links.new(bsdf.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert len(warnings) == 1 and "'leaf'" in warnings[0] and "Metallic" in warnings[0]
    assert all(len(lobe.get("weight_inputs", ())) <= 2 for lobe in params["lobes"])
    assert len(added(mat)) == 1


def test_an_images_colour_is_premultiplied_by_its_alpha_unless_its_alpha_is_used():
    # As Cycles: it keeps images premultiplied and divides by alpha again only for a node whose
    # Alpha output is linked.
    mat, tree, out = node_material("veil")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse")
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = bpy.data.images.new("veil", 2, 2, alpha=True, float_buffer=True)
    texture.image.pixels.foreach_set([0.5, 0.5, 0.5, 0.25] * 4)
    tree.links.new(texture.outputs["Color"], diffuse.inputs["Color"])
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])

    scene = ppm_core.Scene()
    material_export.MaterialExporter(scene, lambda w: None).index(mat)
    assert scene.texture_info(0)["max_rgb"] == pytest.approx(0.125)
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(texture.outputs["Alpha"], mix.inputs["Fac"])
    tree.links.new(diffuse.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    scene = ppm_core.Scene()
    material_export.MaterialExporter(scene, lambda w: None).index(mat)
    assert scene.texture_info(0)["max_rgb"] == pytest.approx(0.5)


def test_a_rough_diffuse_is_oren_nayar_with_its_blender_versions_energy():
    mat, tree, out = node_material("clay")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse", Roughness=0.7)
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    (lobe,) = params["lobes"]
    assert warnings == [] and params["kind"] == "mixture"  # not the core's plain Lambert material
    assert lobe["roughness"] == pytest.approx(0.7) and lobe["multiscatter"] == (bpy.app.version >= (4, 3, 0))
    diffuse.inputs["Roughness"].default_value = 0.0
    assert describe(mat)[0]["kind"] == "diffuse"
    if bpy.app.version >= (4, 3, 0):  # the Principled BSDF's Diffuse Roughness is 4.3's too
        plaster = lobes_by_kind(principled(**{"Diffuse Roughness": 0.5}))["diffuse"]
        assert plaster["roughness"] == pytest.approx(0.5) and plaster["multiscatter"]


def test_a_normal_map_image_becomes_the_materials_normal_map_and_its_meshes_get_tangents():
    mat, tree, out = node_material("bumpy")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled")
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    normal_map.inputs["Strength"].default_value = 0.7
    texture = image_node(tree, "normals")
    texture.image.colorspace_settings.name = "Non-Color"
    tree.links.new(texture.outputs["Color"], normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "mixture"
    assert params["normal_map"]["space"] == "direct" and input_channels(params) == ["normal_map"]
    normal = next(i for i in params["program"]["code"] if i["op"] == "normal_map")
    assert normal["mode"] == 0  # tangent space
    strength, color = normal["in"][:2]
    assert params["program"]["constants"][strength - 1] == pytest.approx((0.7,) * 3)
    assert next(i for i in params["program"]["code"] if color in i["out"])["op"] == "image"
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    ball = bpy.context.object
    ball.data.materials.append(mat)
    data = mesh.MeshData.from_object(ball.evaluated_get(bpy.context.evaluated_depsgraph_get()), "uv")
    assert data.tangents is not None and data.tangents.shape == (len(data.triangles), 3, 4)
    tangents = data.tangents[..., :3].reshape(-1, 3)
    assert np.allclose(np.linalg.norm(tangents, axis=1), 1.0, atol=1e-3)
    assert np.abs(np.sum(tangents * data.normals.reshape(-1, 3), axis=1)).max() < 1e-3  # in the surface
    assert set(np.unique(data.tangents[..., 3])) <= {-1.0, 1.0}
    # A Bump node without a height: the surface's own normal; with a noise height, its normal.
    bump = tree.nodes.new("ShaderNodeBump")
    tree.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    params, warnings = describe(mat)
    assert "normal_map" not in params and warnings == []
    tree.links.new(tree.nodes.new("ShaderNodeTexNoise").outputs["Fac"], bump.inputs["Height"])
    params, warnings = describe(mat)
    assert warnings == [] and params["normal_map"]["space"] == "direct" and input_channels(params) == ["bump"]
    offsets = [i["mode"] for i in params["program"]["code"] if i["op"] == "bump_offset"]
    assert offsets == [1, 2, 0]  # the height beside the point, along two directions, then back
    assert added(mat) == []


def bumped(mat, tree, shader):
    """`shader`'s Normal from a Bump of a Noise's height."""
    bump = tree.nodes.new("ShaderNodeBump")
    tree.links.new(tree.nodes.new("ShaderNodeTexNoise").outputs["Fac"], bump.inputs["Height"])
    tree.links.new(bump.outputs["Normal"], shader.inputs["Normal"])
    return mat


def test_bump_map_correction_off_is_warned():
    """A material's Cycles setting Bump Map Correction, off: Cycles skips the bumped diffuse's
    terminator softening but keeps refusing light from beyond the smooth normal, which the core
    cannot do apart (measured: a strongly bumped diffuse ball 8% darker than Cycles): warned."""
    mat, tree, out = node_material("rough")
    diffuse = add(tree, "ShaderNodeBsdfDiffuse")
    tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
    bumped(mat, tree, diffuse)
    params, warnings = describe(mat)
    assert warnings == [] and params["normal_map"]["softening"] != "none"
    mat.cycles.use_bump_map_correction = False
    params, warnings = describe(mat)
    assert len(warnings) == 1 and "'rough'" in warnings[0] and diffuse.name in warnings[0], warnings
    assert "Bump Map Correction is off" in warnings[0] and params["normal_map"]["softening"] != "none"


def test_a_bumped_glossy_metal_coat_or_glass_warns_that_cycles_turns_its_normal():
    """Cycles 4.0+ turns a bumped Glossy's, metal's, coat's, glass's or translucent's normal until the
    view's reflection is valid (Bump Map Correction), not a diffuse's: the core turns all or none, so
    such a material is warned (a Glossy on a strongly bumped ball measured 22% darker than Cycles);
    a bumped diffuse, or a Principled plastic (its specular layer alone), is not."""
    mat, tree, out = node_material("brushed")
    glossy = add(tree, "ShaderNodeBsdfAnisotropic", Roughness=0.3)
    tree.links.new(glossy.outputs[0], out.inputs["Surface"])
    bumped(mat, tree, glossy)
    _, warnings = describe(mat)
    assert len(warnings) == 1 and "'brushed'" in warnings[0] and glossy.name in warnings[0], warnings
    assert "Bump Map Correction" in warnings[0]
    mat.cycles.use_bump_map_correction = False  # Cycles leaves every normal as it is
    _, warnings = describe(mat)
    assert len(warnings) == 1 and "Bump Map Correction is off" in warnings[0], warnings
    mat, tree, out = node_material("plastic")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled", Roughness=0.4)
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    bumped(mat, tree, bsdf)
    assert describe(mat)[1] == []
    bsdf.inputs["Coat Weight"].default_value = 1.0
    _, warnings = describe(mat)
    assert len(warnings) == 1 and "'plastic'" in warnings[0] and bsdf.name in warnings[0], warnings


def test_an_ngon_mesh_gets_tangents_close_to_blenders():
    # Blender computes no tangents for n-gons; the exporter's own, on a mesh Blender does compute
    # them for (quads), agree with MikkTSpace's within a few degrees (it weights by corner angle).
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)
    ball = bpy.context.object
    data = mesh.MeshData.from_object(ball.evaluated_get(bpy.context.evaluated_depsgraph_get()), "uv")
    ours = mesh.triangle_tangents(data.positions, data.triangles, data.normals, data.uvs)
    agree = np.sum(ours[..., :3] * data.tangents[..., :3], axis=2)
    assert np.median(agree) > 0.99 and agree.min() > 0.9, (np.median(agree), agree.min())
    assert np.all(ours[..., 3] == data.tangents[..., 3])
    bpy.ops.mesh.primitive_circle_add(vertices=8, fill_type="NGON")
    disc = bpy.context.object
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.uv.smart_project()
    bpy.ops.object.mode_set(mode="OBJECT")
    data = mesh.MeshData.from_object(disc.evaluated_get(bpy.context.evaluated_depsgraph_get()), "uv")
    assert data.tangents is not None and not data.tangents_missing
    assert np.isfinite(data.tangents).all()


def test_anisotropy_stretches_the_metal_along_cycles_default_radial_tangent():
    mat, tree, out = node_material("brushed")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled", Metallic=1.0, Roughness=0.3, Anisotropic=0.9,
               **{"Anisotropic Rotation": 0.25})
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    exporter = material_export.MaterialExporter(ppm_core.Scene(), [].append)
    index = exporter.index(mat)
    (metal,) = exporter.describe(mat)["lobes"]
    aspect = (1.0 - 0.9 * 0.9) ** 0.5
    assert metal["stretch"] == pytest.approx((1.0 / aspect, aspect)) and metal["rotation"] == pytest.approx(0.25)
    assert exporter.tangents[index] == "radial_z"
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, location=(5.0, 0.0, 0.0))
    ball = bpy.context.object
    data = mesh.MeshData.from_object(ball.evaluated_get(bpy.context.evaluated_depsgraph_get()), "radial_z")
    corners = data.positions[data.triangles].reshape(-1, 3)
    tangents = data.tangents[..., :3].reshape(-1, 3)
    # About the object's own Z axis: horizontal and perpendicular to the corner's radius.
    assert np.abs(tangents[:, 2]).max() < 1e-6
    assert np.abs(np.sum(tangents[:, :2] * corners[:, :2], axis=1)).max() < 1e-5
    glossy = add(tree, "ShaderNodeBsdfAnisotropic", Anisotropy=-0.5)
    tree.links.new(glossy.outputs[0], out.inputs["Surface"])
    (lobe,) = describe(mat)[0]["lobes"]
    assert lobe["kind"] == "glossy" and lobe["stretch"] == pytest.approx((2.0, 0.5))


def test_a_physical_conductor_becomes_the_f82_model_through_its_fresnel():
    from ppm_render.export import closure
    gold_n, gold_k = np.array([0.18, 0.42, 1.37]), np.array([3.42, 2.35, 1.77])
    f0, tint = closure.f82_from_physical(gold_n, gold_k)

    def f82_model(mu):  # Hoffman's F82-tint model, as the core evaluates it
        schlick = f0 + (1.0 - f0) * (1.0 - mu) ** 5
        b = (f0 + (1.0 - f0) * (6.0 / 7.0) ** 5) * (1.0 - tint) / ((1.0 / 7.0) * (6.0 / 7.0) ** 6)
        return schlick - b * mu * (1.0 - mu) ** 6

    for mu in (1.0, 1.0 / 7.0):
        assert f82_model(mu) == pytest.approx(closure.conductor_fresnel(mu, gold_n, gold_k), rel=1e-9)
    for mu in np.linspace(0.05, 1.0, 20):
        assert f82_model(mu) == pytest.approx(closure.conductor_fresnel(mu, gold_n, gold_k), abs=0.025)
    assert f0 == pytest.approx((0.944, 0.776, 0.373), abs=0.01)  # gold's familiar colour


def test_the_sheen_bsdf_is_velvet_in_ashikhmin_mode_and_a_microfiber_sheen_in_its_default():
    mat, tree, out = node_material("cloth")
    sheen = add(tree, "ShaderNodeBsdfSheen", Color=(0.8, 0.3, 0.5, 1.0), Roughness=0.4)
    sheen.distribution = "ASHIKHMIN"
    tree.links.new(sheen.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    (velvet,) = params["lobes"]
    assert warnings == [] and velvet["kind"] == "velvet" and velvet["roughness"] == pytest.approx(0.4)
    assert velvet["color"] == pytest.approx((0.8, 0.3, 0.5))
    assert added(mat) == []
    sheen.distribution = "MICROFIBER"
    params, warnings = describe(mat)
    (microfiber,) = params["lobes"]
    assert warnings == [] and microfiber["kind"] == "microfiber_sheen" and not microfiber.get("layer")
    assert microfiber["roughness"] == pytest.approx(0.4) and microfiber["color"] == pytest.approx((0.8, 0.3, 0.5))


def test_an_image_on_an_emission_colour_textures_the_emission():
    mat, tree, out = node_material("screen")
    emission = add(tree, "ShaderNodeEmission", Strength=3.0)
    picture = image_node(tree, "picture")
    tree.links.new(picture.outputs["Color"], emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "emission" and params["emission"] == pytest.approx((3.0,) * 3)
    assert input_channels(params)[params["emission_input"]] == "rgb"
    assert added(mat) == []
    # The Principled BSDF's Emission Color too, in a mixture.
    mat, tree, out = node_material("sign")
    bsdf = add(tree, "ShaderNodeBsdfPrincipled", **{"Emission Strength": 2.0})
    tree.links.new(image_node(tree, "sign").outputs["Color"], bsdf.inputs["Emission Color"])
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "mixture" and params["emission_input"] == 0
    assert added(mat) == []


def test_light_path_drives_a_mix_by_the_kind_of_ray_and_transparent_depth_warns():
    # Glass to the camera, transparent to shadow rays (the artists' shadow trick): the factor is read per ray.
    mat, tree, out = node_material("shadow trick")
    glass, transparent = add(tree, "ShaderNodeBsdfGlass"), add(tree, "ShaderNodeBsdfTransparent")
    mix, path = add(tree, "ShaderNodeMixShader"), tree.nodes.new("ShaderNodeLightPath")
    tree.links.new(path.outputs["Is Shadow Ray"], mix.inputs["Fac"])
    tree.links.new(glass.outputs[0], mix.inputs[1])
    tree.links.new(transparent.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "mixture"
    scene = ppm_core.Scene()
    factor = {ray: scene.run_program(params["program"], np.zeros((1, 3)), ray=ray)[0, 0, 0]
              for ray in ("camera", "shadow", "diffuse")}
    assert factor == {"camera": 0.0, "shadow": 1.0, "diffuse": 0.0}
    tree.links.new(path.outputs["Transparent Depth"], mix.inputs["Fac"])
    assert any("Transparent Depth is not counted" in w for w in describe(mat)[1])


def test_a_chain_of_400_math_nodes_compiles_and_computes_as_blender():
    """Compiled without Python recursion growing with the chain, in a few registers (it refused the
    frame at ~250 nodes with a RecursionError, and ran out of the core's 256 registers)."""
    mat, tree, out = node_material("long chain")
    bsdf = add(tree, "ShaderNodeBsdfDiffuse")
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(tree.nodes.new("ShaderNodeNewGeometry").outputs["Position"], separate.inputs[0])
    value, count = separate.outputs["X"], 400
    for _ in range(count):
        math_node = tree.nodes.new("ShaderNodeMath")
        math_node.operation = "MULTIPLY_ADD"
        math_node.inputs[1].default_value, math_node.inputs[2].default_value = 0.999, 0.0001
        tree.links.new(value, math_node.inputs[0])
        value = math_node.outputs[0]
    tree.links.new(value, bsdf.inputs["Roughness"])
    params, warnings = describe(mat)
    assert warnings == [] and params["program"]["registers"] < 16
    x = np.array([0.1, 0.5, 0.9])
    computed = ppm_core.Scene().run_program(params["program"], np.stack([x, 0 * x, 0 * x], axis=1))[:, 0, 0]
    a = np.float32(0.999)
    expected = x * a ** count + np.float32(0.0001) * (1 - a ** count) / (1 - a)
    np.testing.assert_allclose(computed, expected, rtol=1e-3)


def test_deeply_nested_groups_and_long_reroute_chains_are_followed():
    """Groups nested 60 deep and 300 reroutes in a row are no cycle (they were reported as one and
    rendered black)."""
    inner = None
    for depth in range(60):
        group = bpy.data.node_groups.new(f"level {depth}", "ShaderNodeTree")
        if hasattr(group, "interface"):
            group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
        else:
            group.outputs.new("NodeSocketShader", "Shader")
        group_out = group.nodes.new("NodeGroupOutput")
        if inner is None:
            shader = add(group, "ShaderNodeBsdfDiffuse", Color=(0.2, 0.7, 0.3, 1.0))
        else:
            shader = group.nodes.new("ShaderNodeGroup")
            shader.node_tree = inner
        group.links.new(shader.outputs[0], group_out.inputs[0])
        inner = group
    mat, tree, out = node_material("nested")
    outer = tree.nodes.new("ShaderNodeGroup")
    outer.node_tree = inner
    socket = outer.outputs[0]
    for _ in range(300):
        reroute = tree.nodes.new("NodeReroute")
        tree.links.new(socket, reroute.inputs[0])
        socket = reroute.outputs[0]
    tree.links.new(socket, out.inputs["Surface"])
    params, warnings = describe(mat)
    assert warnings == [] and params["kind"] == "diffuse"
    assert params["base_color"] == pytest.approx((0.2, 0.7, 0.3))
