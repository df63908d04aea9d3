"""Procedural materials in the style artists build them (wood, marble, tiles, rust, car paint flakes,
bumped plaster, ...): texture and utility nodes driving Principled and other BSDF sockets, each a
builder(tree, out) as in material_library.py, which adds them to its MATERIALS. Built for 3.4 and
4.x/5.x socket names.
"""

import bpy

V4 = bpy.app.version >= (4, 0, 0)
PRINCIPLED_3X = {"Coat Weight": "Clearcoat", "Coat Roughness": "Clearcoat Roughness", "Emission Color": "Emission"}


def new(tree, kind, **settings):
    """A node; keyword arguments set inputs (by name, `in_` prefixed) or properties."""
    n = tree.nodes.new(kind)
    for key, value in settings.items():
        if key.startswith("in_"):
            name = key[3:].replace("_", " ")
            n.inputs[name if V4 else PRINCIPLED_3X.get(name, name)].default_value = value
        else:
            setattr(n, key, value)
    return n


def link(tree, output, node, socket):
    name = socket if V4 or node.bl_idname != "ShaderNodeBsdfPrincipled" else PRINCIPLED_3X.get(socket, socket)
    tree.links.new(output, node.inputs[name])


def bsdf(tree, out, **inputs):
    """A Principled BSDF on the output."""
    p = new(tree, "ShaderNodeBsdfPrincipled", **{f"in_{k}": v for k, v in inputs.items()})
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    return p


def ramp(tree, stops, interpolation="LINEAR"):
    """A ColorRamp of (position, rgb) stops."""
    r = tree.nodes.new("ShaderNodeValToRGB")
    r.color_ramp.interpolation = interpolation
    elements = r.color_ramp.elements
    while len(elements) < len(stops):
        elements.new(0.5)
    for element, (position, rgb) in zip(elements, stops):
        element.position, element.color = position, (*rgb, 1.0)
    return r


def bump(tree, height_output, strength=0.5, distance=0.05):
    b = new(tree, "ShaderNodeBump", in_Strength=strength, in_Distance=distance)
    tree.links.new(height_output, b.inputs["Height"])
    return b


def wood(tree, out):
    """Rings of a Wave texture, distorted, through a ramp of browns; the rings bump the surface."""
    wave = new(tree, "ShaderNodeTexWave", wave_type="RINGS", in_Scale=3.0, in_Distortion=4.0, in_Detail=3.0)
    r = ramp(tree, [(0.2, (0.35, 0.17, 0.06)), (0.8, (0.65, 0.38, 0.16))])
    tree.links.new(wave.outputs["Fac"], r.inputs["Fac"])
    p = bsdf(tree, out, Roughness=0.45)
    link(tree, r.outputs["Color"], p, "Base Color")
    link(tree, bump(tree, wave.outputs["Fac"], 0.3).outputs["Normal"], p, "Normal")


def marble(tree, out):
    """Distorted bands of white and grey veins, polished."""
    wave = new(tree, "ShaderNodeTexWave", in_Scale=2.0, in_Distortion=12.0, in_Detail=6.0,
               **{"in_Detail Scale": 2.0})
    r = ramp(tree, [(0.0, (0.9, 0.9, 0.88)), (0.7, (0.75, 0.75, 0.72)), (1.0, (0.2, 0.2, 0.22))])
    tree.links.new(wave.outputs["Fac"], r.inputs["Fac"])
    p = bsdf(tree, out, Roughness=0.3)
    link(tree, r.outputs["Color"], p, "Base Color")


def tiles(tree, out):
    """Bricks with mortar, the mortar recessed by a bump of the Fac."""
    b = new(tree, "ShaderNodeTexBrick", in_Scale=4.0, in_Color1=(0.6, 0.25, 0.15, 1.0), in_Color2=(0.5, 0.2, 0.1, 1.0),
            in_Mortar=(0.7, 0.7, 0.65, 1.0), **{"in_Mortar Size": 0.03})
    p = bsdf(tree, out, Roughness=0.6)
    link(tree, b.outputs["Color"], p, "Base Color")
    inverted = new(tree, "ShaderNodeMath", operation="SUBTRACT", in_Value=1.0)
    tree.links.new(b.outputs["Fac"], inverted.inputs[1])
    link(tree, bump(tree, inverted.outputs[0], 0.4).outputs["Normal"], p, "Normal")


def rust(tree, out):
    """Noise patches of rough orange rust over polished steel: the patches a Mix Shader factor."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0, in_Detail=6.0)
    mask = ramp(tree, [(0.45, (0.0, 0.0, 0.0)), (0.55, (1.0, 1.0, 1.0))])
    tree.links.new(noise.outputs["Fac"], mask.inputs["Fac"])
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(mask.outputs["Color"], mix.inputs["Fac"])
    steel = new(tree, "ShaderNodeBsdfPrincipled", in_Metallic=1.0, in_Roughness=0.3,
                **{"in_Base Color": (0.8, 0.8, 0.8, 1.0)})
    rusty = new(tree, "ShaderNodeBsdfDiffuse", in_Color=(0.45, 0.16, 0.05, 1.0))
    tree.links.new(steel.outputs[0], mix.inputs[1])
    tree.links.new(rusty.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])


def car_paint(tree, out):
    """A deep red base with metallic flakes (a small Voronoi's cell colours mixed in) under a coat."""
    flakes = new(tree, "ShaderNodeTexVoronoi", in_Scale=80.0)
    mix = new(tree, "ShaderNodeMixRGB", blend_type="OVERLAY", in_Fac=0.3, in_Color1=(0.5, 0.02, 0.03, 1.0))
    tree.links.new(flakes.outputs["Color"], mix.inputs["Color2"])
    p = bsdf(tree, out, Metallic=0.6, Roughness=0.35, **{"Coat Weight": 1.0, "Coat Roughness": 0.05})
    link(tree, mix.outputs["Color"], p, "Base Color")


def plaster(tree, out):
    """Off-white, bumped by fine noise."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=12.0, in_Detail=8.0, in_Roughness=0.6)
    p = bsdf(tree, out, Roughness=0.9, **{"Base Color": (0.8, 0.78, 0.72, 1.0)})
    link(tree, bump(tree, noise.outputs["Fac"], 0.6, 0.1).outputs["Normal"], p, "Normal")


def checker_floor(tree, out):
    checker = new(tree, "ShaderNodeTexChecker", in_Scale=6.0, in_Color1=(0.9, 0.9, 0.9, 1.0),
                  in_Color2=(0.05, 0.05, 0.05, 1.0))
    p = bsdf(tree, out, Roughness=0.2)
    link(tree, checker.outputs["Color"], p, "Base Color")


def gradient_glow(tree, out):
    """An emission whose colour runs through a ramp along the object's height (Gradient of Object z)."""
    coords = tree.nodes.new("ShaderNodeTexCoord")
    rotate = new(tree, "ShaderNodeMapping", vector_type="POINT")
    rotate.inputs["Rotation"].default_value = (0.0, 1.5708, 0.0)  # z onto x, which Linear reads
    tree.links.new(coords.outputs["Object"], rotate.inputs["Vector"])
    gradient = tree.nodes.new("ShaderNodeTexGradient")
    tree.links.new(rotate.outputs["Vector"], gradient.inputs["Vector"])
    r = ramp(tree, [(0.0, (1.0, 0.3, 0.05)), (1.0, (0.1, 0.3, 1.0))])
    tree.links.new(gradient.outputs["Fac"], r.inputs["Fac"])
    emission = new(tree, "ShaderNodeEmission", in_Strength=1.5)
    tree.links.new(r.outputs["Color"], emission.inputs["Color"])
    tree.links.new(emission.outputs[0], out.inputs["Surface"])


def magic_pattern(tree, out):
    magic = new(tree, "ShaderNodeTexMagic", turbulence_depth=3, in_Scale=3.0)
    p = bsdf(tree, out, Roughness=0.5)
    link(tree, magic.outputs["Color"], p, "Base Color")


def cells(tree, out):
    """Voronoi cells: their colours, darkened at the edges (F1 distance through a ramp)."""
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=6.0)
    edge = ramp(tree, [(0.0, (1.0, 1.0, 1.0)), (0.6, (0.2, 0.2, 0.2))])
    tree.links.new(voronoi.outputs["Distance"], edge.inputs["Fac"])
    multiply = new(tree, "ShaderNodeMixRGB", blend_type="MULTIPLY", in_Fac=1.0)
    tree.links.new(voronoi.outputs["Color"], multiply.inputs["Color1"])
    tree.links.new(edge.outputs["Color"], multiply.inputs["Color2"])
    p = bsdf(tree, out, Roughness=0.5)
    link(tree, multiply.outputs["Color"], p, "Base Color")


def noisy_roughness(tree, out):
    """Gold whose roughness a noise varies between 0.2 and 0.6."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=5.0)
    remap = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.2, "in_To Max": 0.6})
    tree.links.new(noise.outputs["Fac"], remap.inputs["Value"])
    p = bsdf(tree, out, Metallic=1.0, **{"Base Color": (1.0, 0.76, 0.33, 1.0)})
    link(tree, remap.outputs["Result"], p, "Roughness")


def facing_paint(tree, out):
    """Layer Weight's Facing mixes a blue diffuse into a glossy rim (a paint's flop)."""
    weight = new(tree, "ShaderNodeLayerWeight", in_Blend=0.3)
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(weight.outputs["Facing"], mix.inputs["Fac"])
    diffuse = new(tree, "ShaderNodeBsdfDiffuse", in_Color=(0.1, 0.2, 0.7, 1.0))
    glossy = new(tree, "ShaderNodeBsdfGlossy" if not V4 else "ShaderNodeBsdfAnisotropic", in_Roughness=0.3,
                 in_Color=(0.9, 0.9, 0.9, 1.0))
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(glossy.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])


def fresnel_glaze(tree, out):
    """A ceramic glaze: the Fresnel node mixes a glossy coat over an orange diffuse."""
    fresnel = new(tree, "ShaderNodeFresnel", in_IOR=1.5)
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(fresnel.outputs["Fac"], mix.inputs["Fac"])
    diffuse = new(tree, "ShaderNodeBsdfDiffuse", in_Color=(0.8, 0.35, 0.1, 1.0))
    glossy = new(tree, "ShaderNodeBsdfGlossy" if not V4 else "ShaderNodeBsdfAnisotropic", in_Roughness=0.1)
    tree.links.new(diffuse.outputs[0], mix.inputs[1])
    tree.links.new(glossy.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])


def hue_shifted(tree, out):
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=2.0, in_Detail=3.0)
    hsv = new(tree, "ShaderNodeHueSaturation", in_Hue=0.8, in_Saturation=1.5, in_Value=1.0)
    tree.links.new(noise.outputs["Color"], hsv.inputs["Color"])
    p = bsdf(tree, out, Roughness=0.5)
    link(tree, hsv.outputs["Color"], p, "Base Color")


def stripes(tree, out):
    """Sine stripes along the object's x (Math), between two colours (MixRGB)."""
    coords = tree.nodes.new("ShaderNodeTexCoord")
    split = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coords.outputs["Object"], split.inputs[0])
    times = new(tree, "ShaderNodeMath", operation="MULTIPLY", in_Value=1.0)
    times.inputs[1].default_value = 12.0
    tree.links.new(split.outputs["X"], times.inputs[0])
    sine = new(tree, "ShaderNodeMath", operation="SINE")
    tree.links.new(times.outputs[0], sine.inputs[0])
    remap = new(tree, "ShaderNodeMapRange", **{"in_From Min": -1.0})
    tree.links.new(sine.outputs[0], remap.inputs["Value"])
    mix = new(tree, "ShaderNodeMixRGB", in_Color1=(0.9, 0.8, 0.1, 1.0), in_Color2=(0.1, 0.1, 0.1, 1.0))
    tree.links.new(remap.outputs["Result"], mix.inputs["Fac"])
    p = bsdf(tree, out, Roughness=0.5)
    link(tree, mix.outputs["Color"], p, "Base Color")


def mosaic(tree, out):
    """White noise of the cell a point falls in (object coordinates floored): a random tile colour."""
    coords = tree.nodes.new("ShaderNodeTexCoord")
    scale = new(tree, "ShaderNodeVectorMath", operation="MULTIPLY_ADD")
    scale.inputs[1].default_value = (5.0, 5.0, 5.0)
    scale.inputs[2].default_value = (0.1, 0.2, 0.3)
    tree.links.new(coords.outputs["Object"], scale.inputs[0])
    floor = new(tree, "ShaderNodeVectorMath", operation="FLOOR")
    tree.links.new(scale.outputs[0], floor.inputs[0])
    noise = tree.nodes.new("ShaderNodeTexWhiteNoise")
    tree.links.new(floor.outputs[0], noise.inputs["Vector"])
    p = bsdf(tree, out, Roughness=0.4)
    link(tree, noise.outputs["Color"], p, "Base Color")


def leather(tree, out):
    """Dark brown, bumped by smooth Voronoi cells."""
    voronoi = new(tree, "ShaderNodeTexVoronoi", feature="SMOOTH_F1", in_Scale=25.0)
    p = bsdf(tree, out, Roughness=0.55, **{"Base Color": (0.15, 0.07, 0.03, 1.0)})
    link(tree, bump(tree, voronoi.outputs["Distance"], 0.5, 0.02).outputs["Normal"], p, "Normal")


def camouflage(tree, out):
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=2.5, in_Detail=2.0)
    r = ramp(tree, [(0.0, (0.1, 0.12, 0.05)), (0.45, (0.25, 0.3, 0.1)), (0.55, (0.4, 0.35, 0.2)),
                    (0.6, (0.05, 0.05, 0.04))], interpolation="CONSTANT")
    tree.links.new(noise.outputs["Fac"], r.inputs["Fac"])
    p = bsdf(tree, out, Roughness=0.8)
    link(tree, r.outputs["Color"], p, "Base Color")


def lava(tree, out):
    """Glowing cracks: a noise through a ramp as the emission colour, over a dark rock."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0, in_Detail=4.0)
    r = ramp(tree, [(0.45, (0.0, 0.0, 0.0)), (0.6, (1.0, 0.3, 0.02))])
    tree.links.new(noise.outputs["Fac"], r.inputs["Fac"])
    p = bsdf(tree, out, Roughness=0.9, **{"Base Color": (0.05, 0.05, 0.05, 1.0)})
    link(tree, r.outputs["Color"], p, "Emission Color")
    if V4:
        p.inputs["Emission Strength"].default_value = 2.0


def brushed_steel(tree, out):
    """Noise stretched along one axis (Mapping) as the roughness of steel."""
    coords = tree.nodes.new("ShaderNodeTexCoord")
    stretch = new(tree, "ShaderNodeMapping")
    stretch.inputs["Scale"].default_value = (60.0, 1.0, 1.0)
    tree.links.new(coords.outputs["Object"], stretch.inputs["Vector"])
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=4.0)
    tree.links.new(stretch.outputs["Vector"], noise.inputs["Vector"])
    remap = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.25, "in_To Max": 0.45})
    tree.links.new(noise.outputs["Fac"], remap.inputs["Value"])
    p = bsdf(tree, out, Metallic=1.0, **{"Base Color": (0.85, 0.85, 0.85, 1.0)})
    link(tree, remap.outputs["Result"], p, "Roughness")


def noise_normal_map(tree, out):
    """A noise's colour read as a tangent-space normal map, at half strength."""
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=6.0)
    normal_map = new(tree, "ShaderNodeNormalMap", in_Strength=0.5)
    tree.links.new(noise.outputs["Color"], normal_map.inputs["Color"])
    p = bsdf(tree, out, Roughness=0.5, **{"Base Color": (0.6, 0.6, 0.65, 1.0)})
    link(tree, normal_map.outputs["Normal"], p, "Normal")


def scratched_metal(tree, out):
    """Voronoi edges (distance to edge) as scratches of higher roughness on aluminium (rough enough
    that 256 Cycles samples of the sun's glint do not move the mean by percents)."""
    voronoi = new(tree, "ShaderNodeTexVoronoi", feature="DISTANCE_TO_EDGE", in_Scale=10.0)
    r = ramp(tree, [(0.0, (0.75, 0.75, 0.75)), (0.05, (0.4, 0.4, 0.4))])
    tree.links.new(voronoi.outputs["Distance"], r.inputs["Fac"])
    p = bsdf(tree, out, Metallic=1.0, **{"Base Color": (0.9, 0.91, 0.92, 1.0)})
    link(tree, r.outputs["Color"], p, "Roughness")


def stone(tree, out):
    """A noise-distorted Voronoi (Vector Math adds noise to the coordinates) as grey stone."""
    coords = tree.nodes.new("ShaderNodeTexCoord")
    noise = new(tree, "ShaderNodeTexNoise", in_Scale=3.0)
    warp = new(tree, "ShaderNodeVectorMath", operation="ADD")
    tree.links.new(coords.outputs["Generated"], warp.inputs[0])
    tree.links.new(noise.outputs["Color"], warp.inputs[1])
    voronoi = new(tree, "ShaderNodeTexVoronoi", in_Scale=4.0)
    tree.links.new(warp.outputs[0], voronoi.inputs["Vector"])
    grey = tree.nodes.new("ShaderNodeRGBToBW")
    tree.links.new(voronoi.outputs["Color"], grey.inputs["Color"])
    shade = new(tree, "ShaderNodeMapRange", **{"in_To Min": 0.25, "in_To Max": 0.6})
    tree.links.new(grey.outputs[0], shade.inputs["Value"])
    p = bsdf(tree, out, Roughness=0.7)
    link(tree, shade.outputs["Result"], p, "Base Color")


MATERIALS = {
    "proc_wood": wood,
    "proc_marble": marble,
    "proc_tiles": tiles,
    "proc_rust": rust,
    "proc_car_paint": car_paint,
    "proc_plaster": plaster,
    "proc_checker": checker_floor,
    "proc_gradient_glow": gradient_glow,
    "proc_magic": magic_pattern,
    "proc_cells": cells,
    "proc_noisy_roughness": noisy_roughness,
    "proc_facing_paint": facing_paint,
    "proc_fresnel_glaze": fresnel_glaze,
    "proc_hue_shifted": hue_shifted,
    "proc_stripes": stripes,
    "proc_mosaic": mosaic,
    "proc_leather": leather,
    "proc_camouflage": camouflage,
    "proc_lava": lava,
    "proc_brushed_steel": brushed_steel,
    "proc_noise_normal_map": noise_normal_map,
    "proc_scratched_metal": scratched_metal,
    "proc_stone": stone,
}
