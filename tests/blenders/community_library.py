"""Node materials built the way Blender users build them (community_compare.py renders them): node
groups wrapping a Principled BSDF with exposed sockets, frames and reroutes, mixes of mixes with
textured factors, Layer Weight and Fresnel mixes (car paint, rim light, glazes), anisotropic
metals with Tangent nodes and textured rotations, Geometry outputs (Backfacing, Incoming, Normal,
Pointiness), ColorRamps on Noise and Voronoi, colour adjustments, Math and Map Range on
roughness, Bump and Normal Map chains, textured coat, sheen and specular tint, glass, translucent,
transparent and emission mixes. Blender 4.0+ socket names (the bpy module is 5.0).

`MATERIALS` maps a name to a builder(tree, out) as in material_library.py.
"""

import bpy

GLOSSY = "ShaderNodeBsdfAnisotropic"  # Blender 4+'s Glossy BSDF


def new(tree, kind, parent=None, **settings):
    """A node; keyword arguments set inputs (`in_` prefixed, `_` for spaces) or properties."""
    n = tree.nodes.new(kind)
    for key, value in settings.items():
        if key.startswith("in_"):
            n.inputs[key[3:].replace("_", " ")].default_value = value
        else:
            setattr(n, key, value)
    if parent is not None:
        n.parent = parent
    return n


def rgba(r, g, b):
    return (r, g, b, 1.0)


def ln(tree, output, node, socket):
    """Links `output` to input `socket` (a name or index) of `node`."""
    tree.links.new(output, node.inputs[socket])


def reroute(tree, output, count=1):
    """`output` through a chain of `count` reroutes; the last reroute's output."""
    for _ in range(count):
        r = tree.nodes.new("NodeReroute")
        tree.links.new(output, r.inputs[0])
        output = r.outputs[0]
    return output


def ramp(tree, stops, interpolation="LINEAR"):
    r = tree.nodes.new("ShaderNodeValToRGB")
    r.color_ramp.interpolation = interpolation
    elements = r.color_ramp.elements
    while len(elements) < len(stops):
        elements.new(0.5)
    for element, (position, rgb) in zip(elements, stops):
        element.position, element.color = position, (*rgb, 1.0)
    return r


def surface(tree, out, shader_node):
    tree.links.new(shader_node.outputs[0], out.inputs["Surface"])


def mix_shader(tree, first, second, fac=None, fac_output=None):
    m = new(tree, "ShaderNodeMixShader")
    if fac is not None:
        m.inputs["Fac"].default_value = fac
    if fac_output is not None:
        ln(tree, fac_output, m, "Fac")
    ln(tree, first.outputs[0], m, 1)
    ln(tree, second.outputs[0], m, 2)
    return m


def group(name, inputs, outputs):
    """A new shader node group with interface sockets [(name, socket type, default)], its input and
    output nodes: (tree, group input, group output)."""
    g = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for socket_name, kind, default in inputs:
        item = g.interface.new_socket(socket_name, in_out="INPUT", socket_type=kind)
        if default is not None:
            item.default_value = default
    for socket_name, kind in outputs:
        g.interface.new_socket(socket_name, in_out="OUTPUT", socket_type=kind)
    return g, g.nodes.new("NodeGroupInput"), g.nodes.new("NodeGroupOutput")


def group_node(tree, node_group):
    n = tree.nodes.new("ShaderNodeGroup")
    n.node_tree = node_group
    return n


# ---------------------------------------------------------------- brushed metals

def brushed_tangent_radial(tree, out):
    """Brushed steel: a Glossy BSDF with Anisotropy, its Tangent a radial-Z Tangent node through
    reroutes, Rotation a constant network (Value times Math)."""
    glossy = new(tree, GLOSSY, in_Color=rgba(0.85, 0.85, 0.88), in_Roughness=0.35, in_Anisotropy=0.8)
    tangent = new(tree, "ShaderNodeTangent", direction_type="RADIAL", axis="Z")
    ln(tree, reroute(tree, tangent.outputs[0], 2), glossy, "Tangent")
    value = new(tree, "ShaderNodeValue")
    value.outputs[0].default_value = 0.5
    half = new(tree, "ShaderNodeMath", operation="MULTIPLY")
    half.inputs[1].default_value = 0.5
    ln(tree, value.outputs[0], half, 0)
    ln(tree, half.outputs[0], glossy, "Rotation")
    surface(tree, out, glossy)


def brushed_tangent_uv(tree, out):
    """Brushed aluminium along the UV map's tangent (a Tangent node in UV Map mode)."""
    glossy = new(tree, GLOSSY, in_Color=rgba(0.9, 0.9, 0.9), in_Roughness=0.3, in_Anisotropy=0.7)
    tangent = new(tree, "ShaderNodeTangent", direction_type="UV_MAP")
    ln(tree, tangent.outputs[0], glossy, "Tangent")
    surface(tree, out, glossy)


def brushed_rotation_noise(tree, out):
    """Anisotropic Glossy whose Rotation comes from a Noise texture (swirled brushing)."""
    glossy = new(tree, GLOSSY, in_Color=rgba(0.9, 0.8, 0.6), in_Roughness=0.4, in_Anisotropy=0.9)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    ln(tree, noise.outputs["Fac"], glossy, "Rotation")
    surface(tree, out, glossy)


def brushed_tangent_vector_math(tree, out):
    """Anisotropic Glossy whose Tangent is a Vector Math cross product of the Geometry Normal and Z
    (a hand-made circular brushing direction)."""
    glossy = new(tree, GLOSSY, in_Color=rgba(0.8, 0.8, 0.85), in_Roughness=0.3, in_Anisotropy=0.8)
    geometry = new(tree, "ShaderNodeNewGeometry")
    cross = new(tree, "ShaderNodeVectorMath", operation="CROSS_PRODUCT")
    cross.inputs[1].default_value = (0.0, 0.0, 1.0)
    ln(tree, geometry.outputs["Normal"], cross, 0)
    ln(tree, cross.outputs[0], glossy, "Tangent")
    surface(tree, out, glossy)


def principled_brushed_voronoi(tree, out):
    """Principled metal with Anisotropic 0.8, its Anisotropic Rotation from Voronoi cells (a
    machined 'spot-faced' finish) and its Tangent from a radial-X Tangent node in a frame."""
    frame = new(tree, "NodeFrame", label="brushing")
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.95, 0.93, 0.9)}, in_Metallic=1.0,
            in_Roughness=0.3, in_Anisotropic=0.8)
    voronoi = new(tree, "ShaderNodeTexVoronoi", frame, in_Scale=4.0)
    tangent = new(tree, "ShaderNodeTangent", frame, direction_type="RADIAL", axis="X")
    ln(tree, voronoi.outputs["Distance"], p, "Anisotropic Rotation")
    ln(tree, tangent.outputs[0], p, "Tangent")
    surface(tree, out, p)


def principled_brushed_textured_anisotropy(tree, out):
    """Principled metal whose Anisotropic comes from a Noise through a Map Range."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.9, 0.7, 0.5)}, in_Metallic=1.0,
            in_Roughness=0.35)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    remap = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.5, "in_To Max": 1.0})
    ln(tree, noise.outputs["Fac"], remap, "Value")
    ln(tree, remap.outputs["Result"], p, "Anisotropic")
    surface(tree, out, p)


# ---------------------------------------------------------------- car paints and rims

def car_paint_layer_weight(tree, out):
    """Two glossies (a sharp clear and a rough tinted one) mixed by Layer Weight's Fresnel, over a
    diffuse base mixed in by Facing: the 'old-school' car paint."""
    base = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.6, 0.05, 0.05))
    flake = new(tree, GLOSSY, in_Color=rgba(0.8, 0.2, 0.2), in_Roughness=0.4)
    clear = new(tree, GLOSSY, in_Color=rgba(1.0, 1.0, 1.0), in_Roughness=0.05)
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.4)
    under = mix_shader(tree, base, flake, fac_output=weight.outputs["Facing"])
    fresnel = new(tree, "ShaderNodeLayerWeight", in_Blend=0.15)
    top = mix_shader(tree, under, clear, fac_output=fresnel.outputs["Fresnel"])
    surface(tree, out, top)


def car_paint_flip_flop(tree, out):
    """A Principled coat over a base colour that shifts with the view: Layer Weight Facing through a
    ColorRamp (purple to green), flakes of Voronoi on the metallic."""
    p = new(tree, "ShaderNodeBsdfPrincipled", in_Roughness=0.35, **{"in_Coat Weight": 1.0, "in_Coat Roughness": 0.03})
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.5)
    r = ramp(tree, [(0.0, (0.3, 0.05, 0.4)), (1.0, (0.05, 0.4, 0.15))])
    ln(tree, weight.outputs["Facing"], r, "Fac")
    ln(tree, r.outputs["Color"], p, "Base Color")
    flakes = new(tree, "ShaderNodeTexVoronoi", in_Scale=60.0)
    metal = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.3, "in_To Max": 0.8})
    ln(tree, flakes.outputs["Distance"], metal, "Value")
    ln(tree, metal.outputs["Result"], p, "Metallic")
    surface(tree, out, p)


def fresnel_plastic(tree, out):
    """The classic pre-Principled plastic: Mix(Diffuse, Glossy) by a Fresnel of IOR 1.45 whose
    Normal is the bumped normal (the same Bump feeds both shaders)."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=8.0, in_Detail=4.0)
    bump = new(tree, "ShaderNodeBump", in_Strength=0.3)
    ln(tree, noise.outputs["Fac"], bump, "Height")
    normal = reroute(tree, bump.outputs["Normal"])
    diffuse = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.1, 0.35, 0.7))
    glossy = new(tree, GLOSSY, in_Roughness=0.15)
    fresnel = new(tree, "ShaderNodeFresnel", in_IOR=1.45)
    for node in (diffuse, glossy, fresnel):
        ln(tree, normal, node, "Normal")
    surface(tree, out, mix_shader(tree, diffuse, glossy, fac_output=fresnel.outputs["Fac"]))


def rim_light_emission(tree, out):
    """A rim glow: Layer Weight Facing, raised to a power, mixes an Emission into a dark diffuse."""
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.5)
    power = new(tree, "ShaderNodeMath", operation="POWER")
    power.inputs[1].default_value = 3.0
    ln(tree, weight.outputs["Facing"], power, 0)
    dark = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.05, 0.05, 0.08))
    glow = new(tree, "ShaderNodeEmission", in_Color=rgba(0.2, 0.7, 1.0), in_Strength=2.0)
    surface(tree, out, mix_shader(tree, dark, glow, fac_output=power.outputs[0]))


def fresnel_ramp_glaze(tree, out):
    """Fresnel through a ColorRamp (pushed towards the rim) mixing a glossy over a textured diffuse."""
    fresnel = new(tree, "ShaderNodeFresnel", in_IOR=1.6)
    r = ramp(tree, [(0.1, (0.0, 0.0, 0.0)), (0.5, (1.0, 1.0, 1.0))])
    ln(tree, fresnel.outputs["Fac"], r, "Fac")
    checker = new(tree, "ShaderNodeTexChecker", in_Scale=6.0, in_Color1=rgba(0.7, 0.5, 0.2),
                  in_Color2=rgba(0.2, 0.3, 0.5))
    diffuse = new(tree, "ShaderNodeBsdfDiffuse")
    ln(tree, checker.outputs["Color"], diffuse, "Color")
    glossy = new(tree, GLOSSY, in_Roughness=0.1)
    surface(tree, out, mix_shader(tree, diffuse, glossy, fac_output=r.outputs["Color"]))


# ---------------------------------------------------------------- Geometry node

def leaf_backfacing(tree, out):
    """A two-sided leaf: Backfacing picks a yellow back from a green front, half transparent (the
    ball's inside, seen through it, is its back)."""
    front = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.1, 0.5, 0.05))
    back = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.7, 0.6, 0.05))
    geometry = new(tree, "ShaderNodeNewGeometry")
    sides = mix_shader(tree, front, back, fac_output=geometry.outputs["Backfacing"])
    clear = new(tree, "ShaderNodeBsdfTransparent")
    surface(tree, out, mix_shader(tree, sides, clear, fac=0.5))


def leaf_backfacing_translucent(tree, out):
    """A leaf with translucency: Mix(Diffuse, Translucent) whose colours Backfacing swaps (MixRGB)."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    swap = new(tree, "ShaderNodeMix", data_type="RGBA")
    swap.inputs[6].default_value = rgba(0.15, 0.45, 0.05)
    swap.inputs[7].default_value = rgba(0.5, 0.55, 0.1)
    ln(tree, geometry.outputs["Backfacing"], swap, 0)
    diffuse = new(tree, "ShaderNodeBsdfDiffuse")
    translucent = new(tree, "ShaderNodeBsdfTranslucent")
    ln(tree, swap.outputs[2], diffuse, "Color")
    ln(tree, swap.outputs[2], translucent, "Color")
    surface(tree, out, mix_shader(tree, diffuse, translucent, fac=0.4))


def incoming_dot_normal(tree, out):
    """A hand-made facing ratio: Dot(Geometry Incoming, Normal) through a ColorRamp to Base Color."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    dot = new(tree, "ShaderNodeVectorMath", operation="DOT_PRODUCT")
    ln(tree, geometry.outputs["Incoming"], dot, 0)
    ln(tree, geometry.outputs["Normal"], dot, 1)
    r = ramp(tree, [(0.0, (0.9, 0.3, 0.05)), (1.0, (0.05, 0.2, 0.6))])
    ln(tree, dot.outputs["Value"], r, "Fac")
    p = new(tree, "ShaderNodeBsdfPrincipled", in_Roughness=0.5)
    ln(tree, r.outputs["Color"], p, "Base Color")
    surface(tree, out, p)


def incoming_roughness(tree, out):
    """Roughness rising towards grazing view: 1 - |Dot(Incoming, True Normal)| on a glossy metal."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    dot = new(tree, "ShaderNodeVectorMath", operation="DOT_PRODUCT")
    ln(tree, geometry.outputs["Incoming"], dot, 0)
    ln(tree, geometry.outputs["True Normal"], dot, 1)
    inv = new(tree, "ShaderNodeMath", operation="SUBTRACT", in_Value=1.0)
    ln(tree, dot.outputs["Value"], inv, 1)
    glossy = new(tree, GLOSSY, in_Color=rgba(0.9, 0.75, 0.4))
    ln(tree, inv.outputs[0], glossy, "Roughness")
    surface(tree, out, glossy)


def worn_edges_pointiness(tree, out):
    """Worn paint: Pointiness through a sharp ColorRamp mixes bare metal into a painted diffuse."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    r = ramp(tree, [(0.48, (0.0, 0.0, 0.0)), (0.52, (1.0, 1.0, 1.0))])
    ln(tree, geometry.outputs["Pointiness"], r, "Fac")
    paint = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.1, 0.4, 0.2))
    metal = new(tree, "ShaderNodeBsdfPrincipled", in_Metallic=1.0, in_Roughness=0.3)
    surface(tree, out, mix_shader(tree, paint, metal, fac_output=r.outputs["Color"]))


def snow_on_top(tree, out):
    """Snow where the surface faces up: Geometry Normal's Z through Map Range mixes white into rock."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    sep = new(tree, "ShaderNodeSeparateXYZ")
    ln(tree, geometry.outputs["Normal"], sep, 0)
    remap = new(tree, "ShaderNodeMapRange", **{"in_From Min": 0.3, "in_From Max": 0.6})
    ln(tree, sep.outputs["Z"], remap, "Value")
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=6.0)
    rock_color = ramp(tree, [(0.3, (0.15, 0.13, 0.12)), (0.7, (0.35, 0.3, 0.28))])
    ln(tree, noise.outputs["Fac"], rock_color, "Fac")
    rock = new(tree, "ShaderNodeBsdfPrincipled", in_Roughness=0.8)
    ln(tree, rock_color.outputs["Color"], rock, "Base Color")
    snow = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.9, 0.92, 0.95)}, in_Roughness=0.4)
    surface(tree, out, mix_shader(tree, rock, snow, fac_output=remap.outputs["Result"]))


# ---------------------------------------------------------------- groups, frames, reroutes, mixes

def wrapped_principled_group(tree, out):
    """A node group wrapping a Principled BSDF, exposing Base Color, Roughness and Metallic (the
    last left at the group's default), fed a Noise-driven ramp through reroutes from outside; the
    group's inside has a frame and reroutes."""
    g, gin, gout = group("wrapped_principled", [("Base Color", "NodeSocketColor", rgba(0.8, 0.8, 0.8)),
                                                ("Roughness", "NodeSocketFloat", 0.5),
                                                ("Metallic", "NodeSocketFloat", 0.25)],
                         [("BSDF", "NodeSocketShader")])
    frame = new(g, "NodeFrame", label="inside")
    p = new(g, "ShaderNodeBsdfPrincipled", frame)
    g.links.new(reroute(g, gin.outputs["Base Color"], 2), p.inputs["Base Color"])
    g.links.new(gin.outputs["Roughness"], p.inputs["Roughness"])
    g.links.new(gin.outputs["Metallic"], p.inputs["Metallic"])
    g.links.new(p.outputs[0], gout.inputs[0])
    node = group_node(tree, g)
    node.inputs["Roughness"].default_value = 0.35
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0, in_Detail=3.0)
    r = ramp(tree, [(0.35, (0.6, 0.15, 0.05)), (0.65, (0.9, 0.7, 0.3))])
    ln(tree, noise.outputs["Fac"], r, "Fac")
    ln(tree, reroute(tree, r.outputs["Color"], 3), node, "Base Color")
    surface(tree, out, node)


def nested_groups_mix(tree, out):
    """A group holding a group: the inner one mixes Diffuse and Glossy by its Fac input; the outer
    passes a Wave texture into it and a Mix Shader outside mixes the result with a metal."""
    inner, iin, iout = group("inner_mix", [("Fac", "NodeSocketFloat", 0.5), ("Color", "NodeSocketColor",
                                                                              rgba(0.5, 0.5, 0.5))],
                             [("Shader", "NodeSocketShader")])
    d = new(inner, "ShaderNodeBsdfDiffuse")
    gl = new(inner, GLOSSY, in_Roughness=0.25)
    inner.links.new(iin.outputs["Color"], d.inputs["Color"])
    m = new(inner, "ShaderNodeMixShader")
    inner.links.new(iin.outputs["Fac"], m.inputs["Fac"])
    inner.links.new(d.outputs[0], m.inputs[1])
    inner.links.new(gl.outputs[0], m.inputs[2])
    inner.links.new(m.outputs[0], iout.inputs[0])
    outer, oin, oout = group("outer_mix", [("Color", "NodeSocketColor", rgba(0.2, 0.6, 0.3))],
                             [("Shader", "NodeSocketShader")])
    wave = new(outer, "ShaderNodeTexWave", in_Scale=3.0)
    inner_node = group_node(outer, inner)
    outer.links.new(wave.outputs["Fac"], inner_node.inputs["Fac"])
    outer.links.new(oin.outputs["Color"], inner_node.inputs["Color"])
    outer.links.new(inner_node.outputs[0], oout.inputs[0])
    outer_node = group_node(tree, outer)
    metal = new(tree, "ShaderNodeBsdfPrincipled", in_Metallic=1.0, in_Roughness=0.4)
    surface(tree, out, mix_shader(tree, outer_node, metal, fac=0.3))


def mix_of_mixes_textured(tree, out):
    """Mix(Mix(Diffuse, Glossy; Noise), Mix(Glossy, Diffuse; Wave); Checker): three textured factors,
    two on every lobe's weight."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=5.0)
    wave = new(tree, "ShaderNodeTexWave", in_Scale=4.0)
    checker = new(tree, "ShaderNodeTexChecker", in_Scale=4.0, in_Color1=rgba(0.8, 0.8, 0.8),
                  in_Color2=rgba(0.2, 0.2, 0.2))
    a = mix_shader(tree, new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.8, 0.3, 0.1)),
                   new(tree, GLOSSY, in_Roughness=0.2), fac_output=noise.outputs["Fac"])
    b = mix_shader(tree, new(tree, GLOSSY, in_Color=rgba(0.4, 0.6, 0.9), in_Roughness=0.5),
                   new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.2, 0.5, 0.2)), fac_output=wave.outputs["Fac"])
    surface(tree, out, mix_shader(tree, a, b, fac_output=checker.outputs["Fac"]))


def mix_of_mixes_three_deep(tree, out):
    """Three Mix Shaders nested, each with a textured factor (noise, voronoi, gradient): the innermost
    lobes carry three textured factors."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=5.0)
    gradient = new(tree, "ShaderNodeTexGradient", gradient_type="SPHERICAL")
    innermost = mix_shader(tree, new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.9, 0.1, 0.1)),
                           new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.1, 0.1, 0.9)),
                           fac_output=noise.outputs["Fac"])
    middle = mix_shader(tree, innermost, new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.1, 0.8, 0.1)),
                        fac_output=voronoi.outputs["Distance"])
    surface(tree, out, mix_shader(tree, middle, new(tree, GLOSSY, in_Roughness=0.3),
                                  fac_output=gradient.outputs["Fac"]))


def frames_reroutes_mixrgb(tree, out):
    """Frames around a texture stage and a shading stage, long reroute chains between them, the new
    Mix node in Lighten and Multiply blends, a muted Hue/Saturation node."""
    tex_frame, shade_frame = new(tree, "NodeFrame", label="textures"), new(tree, "NodeFrame", label="shading")
    noise = new(tree, "ShaderNodeTexNoise", tex_frame, in_Scale=6.0)
    voronoi = new(tree, "ShaderNodeTexVoronoi", tex_frame, in_Scale=8.0)
    lighten = new(tree, "ShaderNodeMix", tex_frame, data_type="RGBA", blend_type="LIGHTEN")
    lighten.inputs[0].default_value = 0.7
    ln(tree, noise.outputs["Color"], lighten, 6)
    ln(tree, voronoi.outputs["Color"], lighten, 7)
    multiply = new(tree, "ShaderNodeMix", tex_frame, data_type="RGBA", blend_type="MULTIPLY")
    multiply.inputs[0].default_value = 1.0
    multiply.inputs[7].default_value = rgba(0.9, 0.6, 0.4)
    ln(tree, lighten.outputs[2], multiply, 6)
    muted = new(tree, "ShaderNodeHueSaturation", shade_frame, in_Hue=0.1)
    muted.mute = True
    ln(tree, reroute(tree, multiply.outputs[2], 4), muted, "Color")
    p = new(tree, "ShaderNodeBsdfPrincipled", shade_frame, in_Roughness=0.45)
    ln(tree, muted.outputs["Color"], p, "Base Color")
    surface(tree, out, p)


# ---------------------------------------------------------------- textures on sockets

def ramp_noise_roughness_color(tree, out):
    """Noise -> ColorRamp -> Base Color; the same Noise -> Map Range -> Roughness; Voronoi -> constant
    ColorRamp -> Metallic."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=5.0, in_Detail=5.0)
    r = ramp(tree, [(0.3, (0.5, 0.35, 0.2)), (0.7, (0.9, 0.85, 0.75))])
    ln(tree, noise.outputs["Fac"], r, "Fac")
    remap = new(tree, "ShaderNodeMapRange", **{"in_From Min": 0.3, "in_From Max": 0.7, "in_To Min": 0.15,
                                               "in_To Max": 0.7})
    ln(tree, noise.outputs["Fac"], remap, "Value")
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=5.0)
    steps = ramp(tree, [(0.0, (0.0, 0.0, 0.0)), (0.5, (1.0, 1.0, 1.0))], "CONSTANT")
    ln(tree, voronoi.outputs["Distance"], steps, "Fac")
    p = new(tree, "ShaderNodeBsdfPrincipled")
    ln(tree, r.outputs["Color"], p, "Base Color")
    ln(tree, remap.outputs["Result"], p, "Roughness")
    ln(tree, steps.outputs["Color"], p, "Metallic")
    surface(tree, out, p)


def color_adjust_chain(tree, out):
    """Checker -> Hue/Saturation -> Invert -> Gamma -> Bright/Contrast -> Base Color."""
    checker = new(tree, "ShaderNodeTexChecker", in_Scale=5.0, in_Color1=rgba(0.8, 0.4, 0.1),
                  in_Color2=rgba(0.1, 0.3, 0.6))
    hsv = new(tree, "ShaderNodeHueSaturation", in_Hue=0.6, in_Saturation=1.3, in_Value=0.9)
    inv = new(tree, "ShaderNodeInvert", in_Fac=0.3)
    gamma = new(tree, "ShaderNodeGamma", in_Gamma=1.8)
    bc = new(tree, "ShaderNodeBrightContrast", in_Bright=0.05, in_Contrast=0.2)
    ln(tree, checker.outputs["Color"], hsv, "Color")
    ln(tree, hsv.outputs["Color"], inv, "Color")
    ln(tree, inv.outputs["Color"], gamma, "Color")
    ln(tree, gamma.outputs["Color"], bc, "Color")
    p = new(tree, "ShaderNodeBsdfPrincipled", in_Roughness=0.4)
    ln(tree, bc.outputs["Color"], p, "Base Color")
    surface(tree, out, p)


def math_roughness(tree, out):
    """Roughness = clamp(noise^2 * 1.5 + 0.05) on a Glossy, its colour a Separate/Combine HSV swap."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    square = new(tree, "ShaderNodeMath", operation="POWER")
    square.inputs[1].default_value = 2.0
    ln(tree, noise.outputs["Fac"], square, 0)
    madd = new(tree, "ShaderNodeMath", operation="MULTIPLY_ADD", use_clamp=True)
    madd.inputs[1].default_value, madd.inputs[2].default_value = 1.5, 0.05
    ln(tree, square.outputs[0], madd, 0)
    sep = new(tree, "ShaderNodeSeparateColor", mode="HSV")
    sep.inputs[0].default_value = rgba(0.9, 0.6, 0.2)
    comb = new(tree, "ShaderNodeCombineColor", mode="HSV")
    ln(tree, sep.outputs[0], comb, 0)
    ln(tree, sep.outputs[2], comb, 1)
    ln(tree, sep.outputs[1], comb, 2)
    glossy = new(tree, GLOSSY)
    ln(tree, madd.outputs[0], glossy, "Roughness")
    ln(tree, comb.outputs[0], glossy, "Color")
    surface(tree, out, glossy)


def bump_normal_map_chain(tree, out):
    """A Normal Map of a Noise colour feeding a Bump's Normal (its height a Voronoi): the usual
    'detail over a normal map' chain into a Principled."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    nmap = new(tree, "ShaderNodeNormalMap", in_Strength=0.5)
    ln(tree, noise.outputs["Color"], nmap, "Color")
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=10.0)
    bump = new(tree, "ShaderNodeBump", in_Strength=0.4)
    ln(tree, voronoi.outputs["Distance"], bump, "Height")
    ln(tree, nmap.outputs["Normal"], bump, "Normal")
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.6, 0.6, 0.55)}, in_Roughness=0.3)
    ln(tree, bump.outputs["Normal"], p, "Normal")
    surface(tree, out, p)


def textured_coat(tree, out):
    """Principled with Coat Weight from a Noise (a patchy varnish) and a Coat Tint."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.5, 0.25, 0.1),
                                                 "in_Coat Tint": rgba(0.9, 0.7, 0.5)}, in_Roughness=0.6)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    r = ramp(tree, [(0.4, (0.0, 0.0, 0.0)), (0.6, (1.0, 1.0, 1.0))])
    ln(tree, noise.outputs["Fac"], r, "Fac")
    ln(tree, r.outputs["Color"], p, "Coat Weight")
    surface(tree, out, p)


def textured_sheen(tree, out):
    """Velvet cloth: Principled with Sheen Weight 1 and Sheen Tint from a Wave texture."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.3, 0.05, 0.1), "in_Sheen Weight": 1.0},
            in_Roughness=0.8)
    wave = new(tree, "ShaderNodeTexWave", in_Scale=5.0)
    r = ramp(tree, [(0.0, (1.0, 0.6, 0.7)), (1.0, (0.6, 0.6, 1.0))])
    ln(tree, wave.outputs["Fac"], r, "Fac")
    ln(tree, r.outputs["Color"], p, "Sheen Tint")
    surface(tree, out, p)


def textured_specular_tint(tree, out):
    """Principled metal (F82) whose Specular Tint (edge tint) comes from a Noise's colour."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.95, 0.6, 0.4)}, in_Metallic=1.0,
            in_Roughness=0.3)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    ln(tree, noise.outputs["Color"], p, "Specular Tint")
    surface(tree, out, p)


def textured_emission_mix(tree, out):
    """Mix(Diffuse, Emission) at 0.3 with the emission colour from a Magic texture (lava glow)."""
    magic = new(tree, "ShaderNodeTexMagic", in_Scale=3.0)
    glow = new(tree, "ShaderNodeEmission", in_Strength=1.5)
    ln(tree, magic.outputs["Color"], glow, "Color")
    rock = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.2, 0.15, 0.1))
    surface(tree, out, mix_shader(tree, rock, glow, fac=0.3))


# ---------------------------------------------------------------- glass and thin materials

def glass_transparent_fresnel(tree, out):
    """Soap-bubble-like: Mix(Transparent, Glass) by Layer Weight's Fresnel."""
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.3)
    clear = new(tree, "ShaderNodeBsdfTransparent", in_Color=rgba(0.9, 0.95, 1.0))
    glass = new(tree, "ShaderNodeBsdfGlass", in_IOR=1.45, in_Roughness=0.05)
    surface(tree, out, mix_shader(tree, clear, glass, fac_output=weight.outputs["Fresnel"]))


def frosted_glass_noise(tree, out):
    """Glass whose roughness a Noise through a ColorRamp varies (frosted patches), mixed with a little
    Translucent."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=5.0)
    r = ramp(tree, [(0.4, (0.05, 0.05, 0.05)), (0.6, (0.5, 0.5, 0.5))])
    ln(tree, noise.outputs["Fac"], r, "Fac")
    glass = new(tree, "ShaderNodeBsdfGlass", in_IOR=1.5, in_Color=rgba(0.85, 0.95, 0.9))
    ln(tree, r.outputs["Color"], glass, "Roughness")
    translucent = new(tree, "ShaderNodeBsdfTranslucent", in_Color=rgba(0.8, 0.9, 0.85))
    surface(tree, out, mix_shader(tree, glass, translucent, fac=0.15))


def translucent_diffuse_noise(tree, out):
    """Paper: Mix(Diffuse, Translucent) by a Noise; the colour from an Invert of a Gradient."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    gradient = new(tree, "ShaderNodeTexGradient", gradient_type="QUADRATIC")
    inv = new(tree, "ShaderNodeInvert")
    ln(tree, gradient.outputs["Color"], inv, "Color")
    diffuse = new(tree, "ShaderNodeBsdfDiffuse")
    ln(tree, inv.outputs["Color"], diffuse, "Color")
    translucent = new(tree, "ShaderNodeBsdfTranslucent", in_Color=rgba(0.9, 0.85, 0.7))
    surface(tree, out, mix_shader(tree, diffuse, translucent, fac_output=noise.outputs["Fac"]))


# ---------------------------------------------------------------- round two: what users combine

def bumped_coat(tree, out):
    """Car paint with orange peel: a Principled coat over a red base, its Normal from a strong Bump
    of fine noise; Coat Normal unlinked (Cycles keeps the coat smooth then)."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.6, 0.05, 0.05), "in_Coat Weight": 1.0,
                                                 "in_Coat Roughness": 0.02}, in_Roughness=0.5)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=20.0)
    bump = new(tree, "ShaderNodeBump", in_Strength=1.0, in_Distance=0.2)
    ln(tree, noise.outputs["Fac"], bump, "Height")
    ln(tree, bump.outputs["Normal"], p, "Normal")
    surface(tree, out, p)


def coat_normal_bump(tree, out):
    """The other way round: a bumped coat (Coat Normal from a Bump) over a smooth metal base."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.9, 0.6, 0.3), "in_Coat Weight": 1.0,
                                                 "in_Coat Roughness": 0.02}, in_Metallic=1.0, in_Roughness=0.2)
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=20.0)
    bump = new(tree, "ShaderNodeBump", in_Strength=1.0, in_Distance=0.2)
    ln(tree, noise.outputs["Fac"], bump, "Height")
    ln(tree, bump.outputs["Normal"], p, "Coat Normal")
    surface(tree, out, p)


def glass_ray_length_absorption(tree, out):
    """Fake volume absorption in glass: Glass Color = exp(-2 * Ray Length) of the Light Path node,
    tinted by a Combine Color (a common tutorial setup)."""
    path = new(tree, "ShaderNodeLightPath")
    scaled = new(tree, "ShaderNodeMath", operation="MULTIPLY")
    scaled.inputs[1].default_value = -1.5
    ln(tree, path.outputs["Ray Length"], scaled, 0)
    exp = new(tree, "ShaderNodeMath", operation="EXPONENT")
    ln(tree, scaled.outputs[0], exp, 0)
    tint = new(tree, "ShaderNodeMix", data_type="RGBA", blend_type="MULTIPLY")
    tint.inputs[0].default_value = 1.0
    tint.inputs[7].default_value = rgba(0.5, 0.9, 0.7)
    ln(tree, exp.outputs[0], tint, 6)
    glass = new(tree, "ShaderNodeBsdfGlass", in_IOR=1.45, in_Roughness=0.0)
    ln(tree, tint.outputs[2], glass, "Color")
    surface(tree, out, glass)


def glass_shadow_trick(tree, out):
    """Glass that casts a clear shadow: Mix(Glass, Transparent) by Light Path Is Shadow Ray."""
    path = new(tree, "ShaderNodeLightPath")
    glass = new(tree, "ShaderNodeBsdfGlass", in_IOR=1.5, in_Color=rgba(0.9, 0.95, 1.0))
    clear = new(tree, "ShaderNodeBsdfTransparent")
    surface(tree, out, mix_shader(tree, glass, clear, fac_output=path.outputs["Is Shadow Ray"]))


def camera_only_emission(tree, out):
    """A glow seen by the camera that lights nothing: Mix(Diffuse, Emission) by Is Camera Ray."""
    path = new(tree, "ShaderNodeLightPath")
    diffuse = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.3, 0.3, 0.3))
    glow = new(tree, "ShaderNodeEmission", in_Color=rgba(1.0, 0.4, 0.1), in_Strength=1.0)
    surface(tree, out, mix_shader(tree, diffuse, glow, fac_output=path.outputs["Is Camera Ray"]))


def metallic_rim(tree, out):
    """Metallic from Layer Weight's Fresnel (metal at the rim, paint facing the view)."""
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.6)
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.2, 0.5, 0.8)}, in_Roughness=0.3)
    ln(tree, weight.outputs["Fresnel"], p, "Metallic")
    surface(tree, out, p)


def layer_weight_textured_blend(tree, out):
    """Layer Weight whose Blend comes from a Noise, its Facing mixing a glossy over a diffuse."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    weight = new(tree, "ShaderNodeLayerWeight")
    ln(tree, noise.outputs["Fac"], weight, "Blend")
    diffuse = new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.7, 0.6, 0.1))
    glossy = new(tree, GLOSSY, in_Roughness=0.2)
    surface(tree, out, mix_shader(tree, diffuse, glossy, fac_output=weight.outputs["Facing"]))


def glass_fresnel_overlay(tree, out):
    """Glass with an extra reflection layer: Mix(Glass, Glossy) by a Fresnel of IOR 1.5."""
    fresnel = new(tree, "ShaderNodeFresnel", in_IOR=1.5)
    glass = new(tree, "ShaderNodeBsdfGlass", in_IOR=1.5, in_Color=rgba(0.95, 0.9, 0.8))
    glossy = new(tree, GLOSSY, in_Roughness=0.0)
    surface(tree, out, mix_shader(tree, glass, glossy, fac_output=fresnel.outputs["Fac"]))


def hologram_alpha(tree, out):
    """A hologram: Principled with Alpha from Layer Weight Facing (opaque at the rim) and a cyan
    Emission Color."""
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.3)
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.1, 0.6, 0.8),
                                                 "in_Emission Color": rgba(0.1, 0.6, 0.8),
                                                 "in_Emission Strength": 0.5})
    ln(tree, weight.outputs["Facing"], p, "Alpha")
    surface(tree, out, p)


def two_principled_textured(tree, out):
    """Two textured Principled BSDFs (colour, roughness, metallic each) mixed by a Voronoi mask, a Bump
    on both: more textured sockets than a material takes."""
    mask = new(tree, "ShaderNodeTexVoronoi", in_Scale=3.0)
    shaders = []
    for scale, colours in ((4.0, ((0.6, 0.2, 0.1), (0.9, 0.6, 0.3))), (9.0, ((0.1, 0.3, 0.5), (0.6, 0.8, 0.9)))):
        noise = new(tree, "ShaderNodeTexNoise", in_Scale=scale)
        r = ramp(tree, [(0.3, colours[0]), (0.7, colours[1])])
        ln(tree, noise.outputs["Fac"], r, "Fac")
        rough = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.2, "in_To Max": 0.8})
        ln(tree, noise.outputs["Fac"], rough, "Value")
        metal = new(tree, "ShaderNodeMath", operation="GREATER_THAN")
        metal.inputs[1].default_value = 0.55
        ln(tree, noise.outputs["Fac"], metal, 0)
        p = new(tree, "ShaderNodeBsdfPrincipled")
        ln(tree, r.outputs["Color"], p, "Base Color")
        ln(tree, rough.outputs["Result"], p, "Roughness")
        ln(tree, metal.outputs[0], p, "Metallic")
        shaders.append(p)
    surface(tree, out, mix_shader(tree, *shaders, fac_output=mask.outputs["Distance"]))


def position_gradient(tree, out):
    """A height gradient from the Geometry Position's Z through a ColorRamp, and Camera coordinates'
    depth darkening the roughness."""
    geometry = new(tree, "ShaderNodeNewGeometry")
    sep = new(tree, "ShaderNodeSeparateXYZ")
    ln(tree, geometry.outputs["Position"], sep, 0)
    r = ramp(tree, [(0.0, (0.8, 0.2, 0.1)), (1.0, (0.9, 0.9, 0.2))])
    remap = new(tree, "ShaderNodeMapRange", **{"in_From Min": -1.0, "in_From Max": 1.0})
    ln(tree, sep.outputs["Z"], remap, "Value")
    ln(tree, remap.outputs["Result"], r, "Fac")
    coords = new(tree, "ShaderNodeTexCoord")
    depth = new(tree, "ShaderNodeSeparateXYZ")
    ln(tree, coords.outputs["Camera"], depth, 0)
    rough = new(tree, "ShaderNodeMapRange", **{"in_From Min": -6.0, "in_From Max": -4.0})
    ln(tree, depth.outputs["Z"], rough, "Value")
    p = new(tree, "ShaderNodeBsdfPrincipled")
    ln(tree, r.outputs["Color"], p, "Base Color")
    ln(tree, rough.outputs["Result"], p, "Roughness")
    surface(tree, out, p)


def reflection_env_fake(tree, out):
    """A fake chrome: Texture Coordinate Reflection's Z through a ColorRamp (sky over ground) as an
    Emission, added to a dark glossy."""
    coords = new(tree, "ShaderNodeTexCoord")
    sep = new(tree, "ShaderNodeSeparateXYZ")
    ln(tree, coords.outputs["Reflection"], sep, 0)
    r = ramp(tree, [(0.45, (0.3, 0.2, 0.1)), (0.55, (0.4, 0.6, 0.9))])
    remap = new(tree, "ShaderNodeMapRange", **{"in_From Min": -1.0, "in_From Max": 1.0})
    ln(tree, sep.outputs["Z"], remap, "Value")
    ln(tree, remap.outputs["Result"], r, "Fac")
    glow = new(tree, "ShaderNodeEmission")
    ln(tree, r.outputs["Color"], glow, "Color")
    glossy = new(tree, GLOSSY, in_Color=rgba(0.2, 0.2, 0.2), in_Roughness=0.1)
    a = new(tree, "ShaderNodeAddShader")
    ln(tree, glossy.outputs[0], a, 0)
    ln(tree, glow.outputs[0], a, 1)
    surface(tree, out, a)


def ior_textured_glass(tree, out):
    """Glass whose IOR a Noise varies (1.3 to 1.7): a common 'dispersion-ish' trick."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    remap = new(tree, "ShaderNodeMapRange", **{"in_To Min": 1.3, "in_To Max": 1.7})
    ln(tree, noise.outputs["Fac"], remap, "Value")
    glass = new(tree, "ShaderNodeBsdfGlass")
    ln(tree, remap.outputs["Result"], glass, "IOR")
    surface(tree, out, glass)


def specular_level_textured(tree, out):
    """Principled plastic whose Specular IOR Level comes from a Voronoi (fingerprints)."""
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=6.0)
    p = new(tree, "ShaderNodeBsdfPrincipled", **{"in_Base Color": rgba(0.05, 0.05, 0.05)}, in_Roughness=0.15)
    ln(tree, voronoi.outputs["Distance"], p, "Specular IOR Level")
    surface(tree, out, p)


def strongly_bumped(shader_node):
    """`shader_node`'s Normal from a strong Bump of fine noise (scale 20, strength 1, distance 0.2)."""
    def build(tree, out):
        shader = shader_node(tree)
        noise = new(tree, "ShaderNodeTexNoise", in_Scale=20.0)
        bump = new(tree, "ShaderNodeBump", in_Strength=1.0, in_Distance=0.2)
        ln(tree, noise.outputs["Fac"], bump, "Height")
        ln(tree, bump.outputs["Normal"], shader, "Normal")
        surface(tree, out, shader)
    return build


def no_bump_map_correction(builder):
    """`builder`'s material with Cycles' Bump Map Correction (a material setting) off."""
    def build(tree, out):
        builder(tree, out)
        next(m for m in bpy.data.materials if m.node_tree == tree).cycles.use_bump_map_correction = False
    return build


BUMPED_GLOSSY = strongly_bumped(lambda tree: new(tree, GLOSSY, in_Color=rgba(0.9, 0.9, 0.9), in_Roughness=0.3))
BUMPED_DIFFUSE = strongly_bumped(lambda tree: new(tree, "ShaderNodeBsdfDiffuse", in_Color=rgba(0.6, 0.6, 0.6)))
BUMPED_PLASTIC = strongly_bumped(lambda tree: new(tree, "ShaderNodeBsdfPrincipled", in_Roughness=0.5,
                                                  **{"in_Base Color": rgba(0.6, 0.05, 0.05)}))


MATERIALS = {
    "brushed_tangent_radial": brushed_tangent_radial,
    "brushed_tangent_uv": brushed_tangent_uv,
    "brushed_rotation_noise": brushed_rotation_noise,
    "brushed_tangent_vector_math": brushed_tangent_vector_math,
    "principled_brushed_voronoi": principled_brushed_voronoi,
    "principled_brushed_textured_anisotropy": principled_brushed_textured_anisotropy,
    "car_paint_layer_weight": car_paint_layer_weight,
    "car_paint_flip_flop": car_paint_flip_flop,
    "fresnel_plastic": fresnel_plastic,
    "rim_light_emission": rim_light_emission,
    "fresnel_ramp_glaze": fresnel_ramp_glaze,
    "leaf_backfacing": leaf_backfacing,
    "leaf_backfacing_translucent": leaf_backfacing_translucent,
    "incoming_dot_normal": incoming_dot_normal,
    "incoming_roughness": incoming_roughness,
    "worn_edges_pointiness": worn_edges_pointiness,
    "snow_on_top": snow_on_top,
    "wrapped_principled_group": wrapped_principled_group,
    "nested_groups_mix": nested_groups_mix,
    "mix_of_mixes_textured": mix_of_mixes_textured,
    "mix_of_mixes_three_deep": mix_of_mixes_three_deep,
    "frames_reroutes_mixrgb": frames_reroutes_mixrgb,
    "ramp_noise_roughness_color": ramp_noise_roughness_color,
    "color_adjust_chain": color_adjust_chain,
    "math_roughness": math_roughness,
    "bump_normal_map_chain": bump_normal_map_chain,
    "textured_coat": textured_coat,
    "textured_sheen": textured_sheen,
    "textured_specular_tint": textured_specular_tint,
    "textured_emission_mix": textured_emission_mix,
    "glass_transparent_fresnel": glass_transparent_fresnel,
    "frosted_glass_noise": frosted_glass_noise,
    "translucent_diffuse_noise": translucent_diffuse_noise,
    "bumped_coat": bumped_coat,
    "coat_normal_bump": coat_normal_bump,
    "glass_ray_length_absorption": glass_ray_length_absorption,
    "glass_shadow_trick": glass_shadow_trick,
    "camera_only_emission": camera_only_emission,
    "metallic_rim": metallic_rim,
    "layer_weight_textured_blend": layer_weight_textured_blend,
    "glass_fresnel_overlay": glass_fresnel_overlay,
    "hologram_alpha": hologram_alpha,
    "two_principled_textured": two_principled_textured,
    "position_gradient": position_gradient,
    "reflection_env_fake": reflection_env_fake,
    "ior_textured_glass": ior_textured_glass,
    "specular_level_textured": specular_level_textured,
    "bumped_glossy": BUMPED_GLOSSY,
    "bumped_glossy_no_correction": no_bump_map_correction(BUMPED_GLOSSY),
    "bumped_diffuse": BUMPED_DIFFUSE,
    "bumped_diffuse_no_correction": no_bump_map_correction(BUMPED_DIFFUSE),
    "bumped_plastic": BUMPED_PLASTIC,
}


def make_material(name):
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None:
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    MATERIALS[name](tree, out)
    return mat
