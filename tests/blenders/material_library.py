"""A library of node materials covering every closure the exporter reads: each BSDF node, Mix and Add
shaders nested, node groups, muted nodes and reroutes, the Principled BSDF's layers, and images
(packed into the saved file) on colour, roughness, metallic, alpha and Mix factor sockets; and
procedural_library.py's materials of texture and utility nodes. Built
by script in the running Blender (3.4 and 4.x/5.x socket names); used by materials_compare.py.

`MATERIALS` maps a name to a builder(tree, out) that fills a material's node tree. `APPROXIMATED`
names those the add-on documents as approximations (reported by the comparison, not asserted).
"""

import math

import bpy

import procedural_library

V4 = bpy.app.version >= (4, 0, 0)
GLOSSY = "ShaderNodeBsdfGlossy" if not V4 else "ShaderNodeBsdfAnisotropic"


def node(tree, kind, **inputs):
    n = tree.nodes.new(kind)
    for key, value in inputs.items():
        n.inputs[key].default_value = value
    return n


def rgba(r, g, b):
    return (r, g, b, 1.0)


def link(tree, a, b, out=0):
    tree.links.new(a.outputs[out] if isinstance(out, int) else a.outputs[out], b)


def shader(kind, **inputs):
    def build(tree, out):
        link(tree, node(tree, kind, **inputs), out.inputs["Surface"])
    return build


def mix(fac, first, second):
    """A Mix Shader of two builders' shaders (a builder here takes (tree, socket))."""
    def build(tree, socket):
        m = node(tree, "ShaderNodeMixShader", Fac=fac)
        first(tree, m.inputs[1])
        second(tree, m.inputs[2])
        link(tree, m, socket)
    return build


def add(first, second):
    def build(tree, socket):
        a = node(tree, "ShaderNodeAddShader")
        first(tree, a.inputs[0])
        second(tree, a.inputs[1])
        link(tree, a, socket)
    return build


def leaf(kind, **inputs):
    def build(tree, socket):
        link(tree, node(tree, kind, **inputs), socket)
    return build


def to_surface(builder):
    return lambda tree, out: builder(tree, out.inputs["Surface"])


NAMES_3X = {"Transmission Weight": "Transmission", "Coat Weight": "Clearcoat", "Coat Roughness": "Clearcoat Roughness",
            "Emission Color": "Emission", "Subsurface Weight": "Subsurface", "Sheen Weight": "Sheen"}


def principled(**inputs):
    """A Principled BSDF; Blender 4+ names, mapped to 3.x names where they differ."""
    def build(tree, out):
        values = inputs if V4 else {NAMES_3X.get(k, k): v for k, v in inputs.items() if k != "Specular IOR Level"}
        if not V4 and "Specular IOR Level" in inputs:
            values["Specular"] = inputs["Specular IOR Level"]
        link(tree, node(tree, "ShaderNodeBsdfPrincipled", **values), out.inputs["Surface"])
    return build


def grouped(tree, out):
    """A node group holding Mix(Diffuse of the group's Color, Glossy), fed a colour from outside
    through a reroute."""
    group = bpy.data.node_groups.new("diffuse_glossy", "ShaderNodeTree")
    if hasattr(group, "interface"):
        group.interface.new_socket("Color", in_out="INPUT", socket_type="NodeSocketColor")
        group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    else:
        group.inputs.new("NodeSocketColor", "Color")
        group.outputs.new("NodeSocketShader", "Shader")
    gin, gout = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    diffuse = node(group, "ShaderNodeBsdfDiffuse")
    glossy = node(group, GLOSSY, Roughness=0.3)
    m = node(group, "ShaderNodeMixShader", Fac=0.3)
    group.links.new(gin.outputs[0], diffuse.inputs["Color"])
    group.links.new(diffuse.outputs[0], m.inputs[1])
    group.links.new(glossy.outputs[0], m.inputs[2])
    group.links.new(m.outputs[0], gout.inputs[0])
    g = tree.nodes.new("ShaderNodeGroup")
    g.node_tree = group
    rgb = tree.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = rgba(0.2, 0.5, 0.8)
    reroute = tree.nodes.new("NodeReroute")
    tree.links.new(rgb.outputs[0], reroute.inputs[0])
    tree.links.new(reroute.outputs[0], g.inputs[0])
    tree.links.new(g.outputs[0], out.inputs["Surface"])


def muted(tree, out):
    """A muted Mix Shader passes its first shader (red diffuse)."""
    m = node(tree, "ShaderNodeMixShader", Fac=0.9)
    link(tree, node(tree, "ShaderNodeBsdfDiffuse", Color=rgba(0.8, 0.1, 0.1)), m.inputs[1])
    link(tree, node(tree, GLOSSY, Roughness=0.0), m.inputs[2])
    m.mute = True
    link(tree, m, out.inputs["Surface"])


def bands(name, values, alphas=None, colorspace="Non-Color"):
    """A packed image of vertical bands (along U: around the ball), band i of grey `values[i]` (or an
    RGB triple) and alpha `alphas[i]`; packed so that the saved file carries it."""
    width, height = 16 * len(values), 8
    image = bpy.data.images.new(name, width, height, alpha=True)
    image.colorspace_settings.name = colorspace
    pixels = []
    for _ in range(height):
        for x in range(width):
            value = values[x // 16]
            rgb = value if isinstance(value, tuple) else (value,) * 3
            pixels += [*rgb, 1.0 if alphas is None else alphas[x // 16]]
    image.pixels.foreach_set(pixels)
    image.pack()
    return image


def image_on(tree, image, socket, output="Color"):
    texture = tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    tree.links.new(texture.outputs[output], socket)


def textured_principled(image_sockets, **inputs):
    """A Principled BSDF (Blender 4+ names as `principled`) with images on some sockets:
    image_sockets maps a socket name to (image builder, output)."""
    build_principled = principled(**inputs)

    def build(tree, out):
        build_principled(tree, out)
        bsdf = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
        for socket, (make_image, output) in image_sockets.items():
            image_on(tree, make_image(), bsdf.inputs[socket if V4 else NAMES_3X.get(socket, socket)], output)
    return build


def textured_mix(tree, out):
    """Mix(Diffuse blue, rough Glossy) with an image's bands as the factor."""
    m = node(tree, "ShaderNodeMixShader")
    DIFFUSE_BLUE(tree, m.inputs[1])
    GLOSSY_ROUGH(tree, m.inputs[2])
    image_on(tree, bands("mix_bands", [0.1, 0.9, 0.4, 0.7, 0.1, 0.9, 0.4, 0.7]), m.inputs["Fac"])
    link(tree, m, out.inputs["Surface"])


def normal_mapped(tree, out):
    """A Principled BSDF whose Normal comes from a tangent-space normal map: bands of normals tilted
    35 degrees to either side along U (the bitangent in between: a mapped axis each way)."""
    build_principled = principled(**{"Base Color": rgba(0.7, 0.7, 0.7), "Roughness": 0.4})
    build_principled(tree, out)
    bsdf = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    tilt = math.sin(math.radians(35)) / 2
    up = math.cos(math.radians(35)) / 2 + 0.5
    normals = [(0.5 + tilt, 0.5, up), (0.5, 0.5 + tilt, up), (0.5 - tilt, 0.5, up), (0.5, 0.5 - tilt, up)] * 2
    normal_map = tree.nodes.new("ShaderNodeNormalMap")
    image_on(tree, bands("normal_bands", normals), normal_map.inputs["Color"])
    tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])


def frosted(kind, distribution, **inputs):
    """A BSDF node (Principled or another) in microfacet `distribution`: Beckmann, or Multiscatter
    GGX for rough glass (the default from Blender 4.0; single scattering alone loses up to half the
    light inside glass)."""
    def build(tree, out):
        if kind == "ShaderNodeBsdfPrincipled":
            principled(**inputs)(tree, out)
            glass = next(n for n in tree.nodes if n.bl_idname == kind)
        else:
            glass = node(tree, kind, **inputs)
            link(tree, glass, out.inputs["Surface"])
        glass.distribution = distribution
    return build


def sheen_bsdf(tree, out, distribution):
    """The Sheen BSDF (Blender 4+) in `distribution`; 3.x's Velvet BSDF (Ashikhmin's) for both."""
    color = rgba(0.8, 0.3, 0.5)
    if not V4:
        link(tree, node(tree, "ShaderNodeBsdfVelvet", Color=color, Sigma=0.5), out.inputs["Surface"])
        return
    sheen = node(tree, "ShaderNodeBsdfSheen", Color=color, Roughness=0.5)
    sheen.distribution = distribution
    link(tree, sheen, out.inputs["Surface"])


def physical_gold(tree, out):
    """The Metallic BSDF (Blender 4.3+) as a physical conductor of gold's complex index; before 4.3
    there is no Metallic BSDF, and a Principled metal of gold's colour stands in."""
    if bpy.app.version < (4, 3, 0):
        principled(**{"Base Color": rgba(1.0, 0.78, 0.34), "Metallic": 1.0, "Roughness": 0.3})(tree, out)
        return
    metal = tree.nodes.new("ShaderNodeBsdfMetallic")
    metal.fresnel_type = "PHYSICAL_CONDUCTOR"
    metal.inputs["Roughness"].default_value = 0.3
    for name, value in (("IOR", (0.18, 0.42, 1.37)), ("Extinction", (3.42, 2.35, 1.77))):
        socket = next(s for s in metal.inputs if s.name == name)
        socket.default_value = value
    link(tree, metal, out.inputs["Surface"])


ROUGHNESS_BANDS = lambda: bands("roughness_bands", [0.1, 0.6, 0.3, 0.8] * 2)  # noqa: E731
METAL_BANDS = lambda: bands("metal_bands", [0.0, 1.0] * 4)  # noqa: E731
CHECKER_COLOURS = lambda: bands("colour_bands", [(0.8, 0.2, 0.1), (0.1, 0.5, 0.8)] * 4,  # noqa: E731
                                alphas=[1.0, 0.3] * 4, colorspace="sRGB")

DIFFUSE_BLUE = leaf("ShaderNodeBsdfDiffuse", Color=rgba(0.1, 0.3, 0.8))
GLOSSY_ROUGH = leaf(GLOSSY, Color=rgba(0.9, 0.9, 0.9), Roughness=0.3)

MATERIALS = {
    "diffuse_red": shader("ShaderNodeBsdfDiffuse", Color=rgba(0.8, 0.2, 0.1)),
    "diffuse_rough": shader("ShaderNodeBsdfDiffuse", Color=rgba(0.9, 0.6, 0.2), Roughness=1.0),
    "glossy_rough": shader(GLOSSY, Color=rgba(0.8, 0.7, 0.5), Roughness=0.4),
    "glossy_mirror": shader(GLOSSY, Color=rgba(0.9, 0.9, 0.9), Roughness=0.0),
    "glass_clear": shader("ShaderNodeBsdfGlass", IOR=1.45, Roughness=0.0),
    "glass_rough": shader("ShaderNodeBsdfGlass", IOR=1.45, Roughness=0.3),
    "glass_tinted": shader("ShaderNodeBsdfGlass", Color=rgba(0.6, 0.9, 0.7), IOR=1.5, Roughness=0.0),
    "refraction": shader("ShaderNodeBsdfRefraction", IOR=1.5, Roughness=0.1),
    "translucent": shader("ShaderNodeBsdfTranslucent", Color=rgba(0.7, 0.7, 0.3)),
    "transparent_mix": to_surface(mix(0.5, DIFFUSE_BLUE, leaf("ShaderNodeBsdfTransparent"))),
    "diffuse_plus_emission": to_surface(add(leaf("ShaderNodeBsdfDiffuse", Color=rgba(0.5, 0.5, 0.5)),
                                            leaf("ShaderNodeEmission", Color=rgba(1.0, 0.5, 0.1), Strength=0.5))),
    "mix_diffuse_glossy": to_surface(mix(0.3, DIFFUSE_BLUE, GLOSSY_ROUGH)),
    "add_diffuse_glossy": to_surface(add(leaf("ShaderNodeBsdfDiffuse", Color=rgba(0.4, 0.4, 0.4)),
                                         leaf(GLOSSY, Color=rgba(0.4, 0.4, 0.4), Roughness=0.3))),
    "nested_mix_glass": to_surface(mix(0.4, mix(0.5, DIFFUSE_BLUE, GLOSSY_ROUGH),
                                       leaf("ShaderNodeBsdfGlass", IOR=1.45, Roughness=0.0))),
    "node_group": grouped,
    "muted_mix": muted,
    "principled_default": principled(),
    "principled_plastic_red": principled(**{"Base Color": rgba(0.8, 0.05, 0.05), "Roughness": 0.3}),
    "principled_gold": principled(**{"Base Color": rgba(1.0, 0.76, 0.33), "Metallic": 1.0, "Roughness": 0.25}),
    "principled_metal_rough": principled(**{"Base Color": rgba(0.9, 0.9, 0.9), "Metallic": 1.0, "Roughness": 0.7}),
    "principled_half_metal": principled(**{"Base Color": rgba(0.5, 0.6, 0.8), "Metallic": 0.5}),
    "principled_glass": principled(**{"Transmission Weight": 1.0, "Roughness": 0.0, "IOR": 1.45}),
    "principled_glass_rough": principled(**{"Transmission Weight": 1.0, "Roughness": 0.2, "IOR": 1.45}),
    "principled_coat": principled(**{"Base Color": rgba(0.6, 0.1, 0.1), "Coat Weight": 1.0, "Roughness": 0.6}),
    "principled_coat_metal": principled(**{"Base Color": rgba(0.8, 0.8, 0.8), "Metallic": 1.0,
                                           "Roughness": 0.5, "Coat Weight": 1.0}),
    "principled_emission": principled(**{"Base Color": rgba(0.2, 0.2, 0.2), "Emission Color": rgba(0.2, 0.6, 1.0),
                                         "Emission Strength": 1.0}),
    "principled_alpha": principled(**{"Base Color": rgba(0.8, 0.8, 0.2), "Alpha": 0.5}),
    "principled_specular_high": principled(**{"Base Color": rgba(0.1, 0.1, 0.1), "Specular IOR Level": 1.0,
                                              "Roughness": 0.2}),
    "principled_middle": principled(**{"Metallic": 0.5, "Roughness": 0.5, "Transmission Weight": 0.5,
                                       "Coat Weight": 0.5, "Specular IOR Level": 0.5}),
    "principled_subsurface": principled(**{"Base Color": rgba(0.8, 0.5, 0.4), "Subsurface Weight": 1.0}),
    "principled_sheen": principled(**{"Base Color": rgba(0.2, 0.2, 0.5), "Sheen Weight": 1.0}),
    "toon": shader("ShaderNodeBsdfToon", Color=rgba(0.8, 0.4, 0.2)),
    "textured_base_color": textured_principled({"Base Color": (CHECKER_COLOURS, "Color")}, Roughness=0.4),
    "textured_roughness": textured_principled({"Roughness": (ROUGHNESS_BANDS, "Color")},
                                              **{"Base Color": rgba(0.8, 0.5, 0.3)}),
    "textured_metallic": textured_principled({"Metallic": (METAL_BANDS, "Color")},
                                             **{"Base Color": rgba(1.0, 0.76, 0.33), "Roughness": 0.3}),
    "textured_alpha": textured_principled({"Base Color": (CHECKER_COLOURS, "Color"),
                                           "Alpha": (CHECKER_COLOURS, "Alpha")}),
    "textured_mix_factor": textured_mix,
    "normal_mapped": normal_mapped,
    "textured_emission": textured_principled(
        {"Emission Color": (lambda: bands("emission_bands", [(1.0, 0.5, 0.1), (0.1, 0.3, 1.0)] * 4,
                                          colorspace="sRGB"), "Color")},
        **{"Base Color": rgba(0.1, 0.1, 0.1), "Emission Strength": 1.5}),
    "glossy_anisotropic": shader("ShaderNodeBsdfAnisotropic", Color=rgba(0.9, 0.8, 0.6), Roughness=0.4,
                                 Anisotropy=0.8),
    "metallic_physical_gold": lambda tree, out: physical_gold(tree, out),
    "velvet": lambda tree, out: sheen_bsdf(tree, out, "ASHIKHMIN"),
    "sheen_microfiber": lambda tree, out: sheen_bsdf(tree, out, "MICROFIBER"),
    "glossy_beckmann": frosted(GLOSSY, "BECKMANN", Color=rgba(0.8, 0.7, 0.5), Roughness=0.4),
    "glass_beckmann": frosted("ShaderNodeBsdfGlass", "BECKMANN", IOR=1.45, Roughness=0.4),
    "glass_frosted": frosted("ShaderNodeBsdfGlass", "MULTI_GGX", Color=rgba(0.6, 0.9, 0.7), IOR=1.45, Roughness=0.8),
    "principled_glass_frosted": frosted("ShaderNodeBsdfPrincipled", "MULTI_GGX",
                                        **{"Transmission Weight": 1.0, "Roughness": 0.8, "IOR": 1.45}),
    "principled_brushed": principled(**{"Base Color": rgba(0.9, 0.9, 0.9), "Metallic": 1.0, "Roughness": 0.35,
                                        "Anisotropic": 0.9, "Anisotropic Rotation": 0.15}),
}

MATERIALS.update(procedural_library.MATERIALS)  # texture and utility nodes (Materials II)

# Documented approximations: measured and reported, not held to the tolerance.
# In 3.x Multiscatter GGX glass is a random walk over the microsurface (Heitz et al. 2016), which the
# add-on approximates by 4.x's energy compensation: rough tinted glass differs by 5-8%, rough
# Principled glass by 20-22% (too dark).
# In 3.x the car paint (the 3.x Principled BSDF's clearcoat over metal, textured base) reads 5.0% off
# in its dark channels with eye paths gathering the metal (256 passes), 5.7% following it (R 2.5%
# bright, G and B 11% dark; Blender 3.4.1, 2026-12-08): docs/LIMITATIONS.md.
APPROXIMATED = {"principled_subsurface", "toon"} | (
    set() if V4 else {"glass_frosted", "principled_glass_frosted", "proc_car_paint"})
# The materials whose ball, alone under the sun and the world, stores photons at all: at least 0.2% of
# the emitted ones (light passing through it to its far side, a bumped surface lighting itself). On the
# others a photon leaves the convex ball for the sky after its first bounce, so the image is direct
# light and eye paths only, whatever the photon count (measured in bpy 5.0.1, 2026-12-06: a 2-pass
# render's Renderer.stats() photons_deposited / photons_emitted, 0.17% and less for the 52 others).
PHOTON_LIT = {"principled_alpha", "translucent", "transparent_mix", "textured_alpha", "nested_mix_glass",
              "principled_middle", "diffuse_plus_emission", "principled_emission", "textured_emission",
              "normal_mapped", "proc_lava", "proc_noise_normal_map", "principled_gold", "proc_noisy_roughness",
              "metallic_physical_gold", "proc_plaster", "proc_brushed_steel", "textured_metallic"}


def make_material(name):
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None or bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    MATERIALS[name](tree, out)
    return mat
