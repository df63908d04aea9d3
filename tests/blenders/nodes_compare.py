"""Texture and utility nodes: Cycles against the add-on's node program, pixel by pixel.

Each case shows one node network through an Emission shader on a plane (emission_plane.py: one
sample at each pixel centre). The same material goes through the add-on's exporter (closure.py,
node_program.py) and the core runs the program it compiled at each pixel centre's position, normal
and UV (Scene.run_program). Deterministic nodes agree to float rounding; a Bump differs where
Cycles' ray differentials and the core's short steps see different detail.

    .venv/bin/python tests/blenders/nodes_compare.py [NAMES]                                   # 5.0
    .venvs/bpy-4.2/bin/python tests/blenders/nodes_compare.py [NAMES]                          # 4.2
    blender -b --factory-startup --python-exit-code 1 -P tests/blenders/nodes_compare.py -- [NAMES]  # 3.4
"""

import importlib
import os
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import bpy
import numpy as np

import emission_plane

SIZE = 48
EXTENT = 2.0  # emission_plane.render_cycles's default
PIXEL = EXTENT * emission_plane.SCALE / SIZE  # a pixel's width on the plane: its ray differential
V4 = bpy.app.version >= (4, 0, 0)
V41 = bpy.app.version >= (4, 1, 0)
V43 = bpy.app.version >= (4, 3, 0)  # the Gabor Texture
MIRROR = "MIRROR" in bpy.types.ShaderNodeTexImage.bl_rna.properties["extension"].enum_items.keys()


def node(nodes, kind, **settings):
    n = nodes.new(kind)
    for key, value in settings.items():
        if key.startswith("in_"):
            name = key[3:]
            socket = next((s for s in n.inputs if s.identifier == name), None) or n.inputs[name.replace("_", " ")]
            socket.default_value = value
        else:
            setattr(n, key, value)
    return n


def link(tree, socket, target):
    tree.links.new(socket, target)
    return target.node


def texture(kind, output, vector=None, **settings):
    def build(tree, nodes):
        n = node(nodes, kind, **settings)
        if vector is not None:
            tree.links.new(vector(tree, nodes), n.inputs["Vector"])
        return n.outputs[output]
    return build


def coordinate(name):
    return lambda tree, nodes: nodes.new("ShaderNodeTexCoord").outputs[name]


def through(kind, first_input, source, output=0, **settings):
    """`source` into input `first_input` of a new `kind` node; its output `output`."""
    def build(tree, nodes):
        n = node(nodes, kind, **settings)
        tree.links.new(source(tree, nodes), n.inputs[first_input])
        return n.outputs[output]
    return build


def noise_fac(**settings):
    return texture("ShaderNodeTexNoise", "Fac", **settings)


def mix_of(blend, **settings):
    def build(tree, nodes):
        kind = "ShaderNodeMixRGB" if not hasattr(bpy.types, "ShaderNodeMix") else "ShaderNodeMix"
        n = nodes.new(kind)
        if kind == "ShaderNodeMix":
            n.data_type = "RGBA"
            a, b, fac = n.inputs["A_Color" if "A_Color" in n.inputs else 6], n.inputs[7], n.inputs[0]
            a = next(s for s in n.inputs if s.identifier == "A_Color")
            b = next(s for s in n.inputs if s.identifier == "B_Color")
            out = next(s for s in n.outputs if s.identifier == "Result_Color")
            n.clamp_result = settings.get("clamp", False)
        else:
            fac, a, b, out = n.inputs[0], n.inputs[1], n.inputs[2], n.outputs[0]
            n.use_clamp = settings.get("clamp", False)
        n.blend_type = blend
        fac.default_value = 0.7
        tree.links.new(texture("ShaderNodeTexNoise", "Color", in_Scale=3.0)(tree, nodes), a)
        tree.links.new(texture("ShaderNodeTexVoronoi", "Color", in_Scale=4.0)(tree, nodes), b)
        return out
    return build


def math_of(operation, a=None, b=0.35, c=0.5):
    def build(tree, nodes):
        n = node(nodes, "ShaderNodeMath", operation=operation)
        tree.links.new((a or noise_fac(in_Scale=4.0))(tree, nodes), n.inputs[0])
        n.inputs[1].default_value, n.inputs[2].default_value = b, c
        return n.outputs[0]
    return build


def vector_math_of(operation):
    def build(tree, nodes):
        n = node(nodes, "ShaderNodeVectorMath", operation=operation)
        tree.links.new(coordinate("Generated")(tree, nodes), n.inputs[0])
        tree.links.new(texture("ShaderNodeTexNoise", "Color", in_Scale=2.0)(tree, nodes), n.inputs[1])
        n.inputs[2].default_value = (0.2, -0.4, 0.7)
        n.inputs[3].default_value = 1.3
        return n.outputs["Value" if operation in ("DOT_PRODUCT", "DISTANCE", "LENGTH") else "Vector"]
    return build


def ramp(interpolation, source=None):
    def build(tree, nodes):
        n = nodes.new("ShaderNodeValToRGB")
        r = n.color_ramp
        r.interpolation = interpolation
        r.elements[0].position, r.elements[0].color = 0.3, (0.9, 0.2, 0.1, 1.0)
        r.elements[1].position, r.elements[1].color = 0.7, (0.1, 0.3, 0.8, 1.0)
        middle = r.elements.new(0.5)
        middle.color = (0.2, 0.9, 0.3, 1.0)
        tree.links.new((source or noise_fac(in_Scale=3.0))(tree, nodes), n.inputs["Fac"])
        return n.outputs["Color"]
    return build


def bump_normal(tree, nodes):
    n = node(nodes, "ShaderNodeBump", in_Strength=0.8, in_Distance=0.05)
    tree.links.new(noise_fac(in_Scale=3.0)(tree, nodes), n.inputs["Height"])
    return n.outputs["Normal"]


def normal_map_of_noise(space, strength):
    def build(tree, nodes):
        n = node(nodes, "ShaderNodeNormalMap", space=space, in_Strength=strength)
        tree.links.new(texture("ShaderNodeTexNoise", "Color", in_Scale=3.0)(tree, nodes), n.inputs["Color"])
        return n.outputs["Normal"]
    return build


def tilted(kind, output, **settings):
    """A node of `kind` whose Normal is a noise's normal map (so that the angle to the viewer varies)."""
    def build(tree, nodes):
        n = node(nodes, kind, **settings)
        tree.links.new(normal_map_of_noise("TANGENT", 1.0)(tree, nodes), n.inputs["Normal"])
        return n.outputs[output]
    return build


def combined(kind, output, names, source, **settings):
    """Separate `source` (a noise colour) with a node, then recombine its parts in another order."""
    def build(tree, nodes):
        split = node(nodes, kind.replace("Combine", "Separate"), **settings)
        tree.links.new(source(tree, nodes), split.inputs[0])
        join = node(nodes, kind, **settings)
        for a, b in zip(names, names[1:] + names[:1]):
            tree.links.new(split.outputs[a], join.inputs[b])
        return join.outputs[output]
    return build


def mix_data(data_type, uniform=True):
    def build(tree, nodes):
        n = node(nodes, "ShaderNodeMix", data_type=data_type, factor_mode="UNIFORM" if uniform else "NON_UNIFORM")
        ident = {"FLOAT": "Float", "VECTOR": "Vector"}[data_type]
        sockets = {s.identifier: s for s in n.inputs}
        tree.links.new(noise_fac(in_Scale=2.0)(tree, nodes) if uniform else
                       texture("ShaderNodeTexNoise", "Color", in_Scale=2.0)(tree, nodes),
                       sockets["Factor_Float" if uniform else "Factor_Vector"])
        tree.links.new(coordinate("Generated")(tree, nodes), sockets[f"A_{ident}"])
        tree.links.new(texture("ShaderNodeTexVoronoi", "Color")(tree, nodes), sockets[f"B_{ident}"])
        return next(o for o in n.outputs if o.identifier == f"Result_{ident}")
    return build


def curves(kind, output, source, value_input):
    """A Curves node of a few bent curves (RGB Curves also the combined one) applied to `source`."""
    def build(tree, nodes):
        n = nodes.new(kind)
        for i, curve in enumerate(n.mapping.curves):
            curve.points.new(0.3, 0.55 + 0.1 * i)
            curve.points.new(0.7, 0.45 - 0.05 * i)
        n.mapping.curves[0].points[0].location = (-0.2, 0.1)  # a curve beyond [0, 1]: the range widens
        n.mapping.update()
        tree.links.new(source(tree, nodes), n.inputs[value_input])
        return n.outputs[output]
    return build


def mapped_noise(tree, nodes):
    m = node(nodes, "ShaderNodeMapping", vector_type="POINT")
    m.inputs["Location"].default_value = (0.3, -0.2, 0.5)
    m.inputs["Rotation"].default_value = (0.3, 0.5, 1.1)
    m.inputs["Scale"].default_value = (2.0, 1.0, 0.5)
    tree.links.new(coordinate("Object")(tree, nodes), m.inputs["Vector"])
    n = node(nodes, "ShaderNodeTexNoise")
    tree.links.new(m.outputs[0], n.inputs["Vector"])
    return n.outputs["Color"]


def image_texture(interpolation, extension, projection="FLAT", blend=0.0, vector="UV"):
    def build(tree, nodes):
        image = bpy.data.images.get("checks") or bpy.data.images.new("checks", 8, 8, alpha=True)
        pixels = np.random.default_rng(3).random((8, 8, 4)).astype(np.float32)
        pixels[..., 3] = 1.0
        image.pixels.foreach_set(pixels.ravel())
        n = node(nodes, "ShaderNodeTexImage", interpolation=interpolation, extension=extension,
                 projection=projection, projection_blend=blend)
        n.image = image
        m = node(nodes, "ShaderNodeMapping", vector_type="POINT")
        m.inputs["Scale"].default_value = (1.7, 1.3, 1.0)
        m.inputs["Location"].default_value = (-0.35, -0.1, 0.0)
        tree.links.new(coordinate(vector)(tree, nodes), m.inputs["Vector"])
        tree.links.new(m.outputs[0], n.inputs["Vector"])
        return n.outputs["Color"]
    return build


def value_node(number):
    def build(tree, nodes):
        n = nodes.new("ShaderNodeValue")
        n.outputs[0].default_value = number
        return n.outputs[0]
    return build


def environment_texture(projection, vector=None):
    """An Environment Texture of the random checks on a material, looked up at `vector` (a coordinate
    name) or at its default."""
    def build(tree, nodes):
        image = bpy.data.images.get("checks") or bpy.data.images.new("checks", 8, 8, alpha=True)
        pixels = np.random.default_rng(3).random((8, 8, 4)).astype(np.float32)
        pixels[..., 3] = 1.0
        image.pixels.foreach_set(pixels.ravel())
        n = node(nodes, "ShaderNodeTexEnvironment", projection=projection)
        n.image = image
        if vector is not None:
            tree.links.new(coordinate(vector)(tree, nodes), n.inputs["Vector"])
        return n.outputs["Color"]
    return build


FOLDERS_TO_REMOVE = []  # the tile files of a case, removed once it is compared


def udim_tiles(tree, nodes, packed=False):
    """A UDIM image of tiles 1001, 1002 and 1011 (random 4 x 4 PNG files) read at the UV scaled to span
    -0.3..2.2: the three tiles, tiles that are missing (Cycles shows those magenta) and negative UVs.
    `packed`: packed into the file, and the tile files removed."""
    folder = tempfile.mkdtemp(prefix="nodes_compare_udim_")
    FOLDERS_TO_REMOVE.append(folder)
    for number in (1001, 1002, 1011):
        tile = bpy.data.images.new(f"tile {number}", 4, 4)
        pixels = np.random.default_rng(number).random((4, 4, 4)).astype(np.float32)
        pixels[..., 3] = 1.0
        tile.pixels.foreach_set(pixels.ravel())
        tile.filepath_raw, tile.file_format = os.path.join(folder, f"tiles.{number}.png"), "PNG"
        tile.save()
        bpy.data.images.remove(tile)
    image = bpy.data.images.load(os.path.join(folder, "tiles.1001.png"))
    image.source = "TILED"  # Blender finds the other tiles by the file name
    if packed:
        image.pack()
        shutil.rmtree(folder)
    n = node(nodes, "ShaderNodeTexImage", interpolation="Closest")
    n.image = image
    m = node(nodes, "ShaderNodeMapping", vector_type="POINT")
    m.inputs["Scale"].default_value = (2.5, 2.5, 1.0)
    m.inputs["Location"].default_value = (-0.3, -0.3, 0.0)
    tree.links.new(coordinate("UV")(tree, nodes), m.inputs["Vector"])
    tree.links.new(m.outputs[0], n.inputs["Vector"])
    return n.outputs["Color"]


def other_objects_coordinates(tree, nodes):
    """Texture Coordinate's Object in the space of an Empty moved, turned and scaled."""
    empty = bpy.data.objects.new("frame", None)
    empty.location, empty.rotation_euler, empty.scale = (0.4, -0.3, 0.2), (0.3, -0.2, 0.9), (0.5, 2.0, 1.5)
    bpy.context.scene.collection.objects.link(empty)
    bpy.context.view_layer.update()
    n = node(nodes, "ShaderNodeTexCoord", object=empty)
    return n.outputs["Object"]


def attribute(kind, name, output):
    def build(tree, nodes):
        return node(nodes, "ShaderNodeAttribute", attribute_type=kind, attribute_name=name).outputs[output]
    return build


def give_properties(obj):
    """The properties the attribute cases read: custom ones on the plane, its mesh, the scene and the
    world (an int pair, a float, a colour, one name both the object's custom and RNA), its colour."""
    obj["tint"] = (0.2, 0.6, 0.9)
    obj["pair"] = [2, 3]
    obj.data["level"] = 0.7
    obj.color = (0.3, 0.5, 0.1, 0.8)
    obj["pass_index"] = 0.25  # a custom property before the RNA property of that name
    obj.pass_index = 3
    bpy.context.scene["sky"] = (0.1, 0.4, 0.8, 0.5)
    bpy.context.scene.world["glow"] = 0.35


def vector_transform(source, convert_from, convert_to, vector_type):
    return through("ShaderNodeVectorTransform", "Vector", source, convert_from=convert_from,
                   convert_to=convert_to, vector_type=vector_type)


def geometry(output):
    return lambda tree, nodes: nodes.new("ShaderNodeNewGeometry").outputs[output]


# name -> (build, tolerance, available in this Blender)
CASES = {
    "noise_3d": (texture("ShaderNodeTexNoise", "Fac"), 1e-5, True),
    "noise_color": (texture("ShaderNodeTexNoise", "Color", in_Scale=3.0, in_Detail=4.5, in_Distortion=0.8), 1e-5,
                    True),
    "noise_2d": (texture("ShaderNodeTexNoise", "Color", noise_dimensions="2D", in_Roughness=0.7), 1e-5, True),
    "noise_1d": (texture("ShaderNodeTexNoise", "Color", noise_dimensions="1D", vector=None, in_W=0.3), 1e-5, True),
    "noise_4d": (texture("ShaderNodeTexNoise", "Color", noise_dimensions="4D", in_W=1.7, in_Detail=3.0), 1e-5, True),
    "noise_ridged": (texture("ShaderNodeTexNoise", "Fac", noise_type="RIDGED_MULTIFRACTAL", in_Detail=3.0) if V41
                     else None, 1e-4, V41),
    "noise_hybrid": (texture("ShaderNodeTexNoise", "Fac", noise_type="HYBRID_MULTIFRACTAL", in_Detail=3.0) if V41
                     else None, 1e-4, V41),
    "noise_hetero": (texture("ShaderNodeTexNoise", "Fac", noise_type="HETERO_TERRAIN", in_Detail=2.5) if V41
                     else None, 1e-4, V41),
    "noise_multifractal": (texture("ShaderNodeTexNoise", "Fac", noise_type="MULTIFRACTAL", in_Detail=2.5) if V41
                           else None, 1e-4, V41),
    "musgrave_fbm": (texture("ShaderNodeTexMusgrave", "Fac", in_Detail=3.5) if not V4 else None, 1e-5, not V4),
    "musgrave_ridged": (texture("ShaderNodeTexMusgrave", "Fac", musgrave_type="RIDGED_MULTIFRACTAL", in_Detail=3.0)
                        if not V4 else None, 1e-5, not V4),
    "musgrave_hybrid_4d": (texture("ShaderNodeTexMusgrave", "Fac", musgrave_type="HYBRID_MULTIFRACTAL",
                                   musgrave_dimensions="4D", in_W=0.4, in_Detail=2.5) if not V4 else None, 1e-5,
                           not V4),
    "musgrave_hetero": (texture("ShaderNodeTexMusgrave", "Fac", musgrave_type="HETERO_TERRAIN", in_Detail=2.5)
                        if not V4 else None, 1e-5, not V4),
    "musgrave_multifractal_2d": (texture("ShaderNodeTexMusgrave", "Fac", musgrave_type="MULTIFRACTAL",
                                         musgrave_dimensions="2D", in_Detail=2.5) if not V4 else None, 1e-5, not V4),
    "voronoi_f1": (texture("ShaderNodeTexVoronoi", "Distance"), 1e-5, True),
    "voronoi_color": (texture("ShaderNodeTexVoronoi", "Color"), 1e-5, True),
    "voronoi_position": (texture("ShaderNodeTexVoronoi", "Position"), 1e-5, True),
    "voronoi_f2_manhattan": (texture("ShaderNodeTexVoronoi", "Distance", feature="F2", distance="MANHATTAN"), 1e-5,
                             True),
    "voronoi_smooth": (texture("ShaderNodeTexVoronoi", "Color", feature="SMOOTH_F1"), 1e-5, True),
    "voronoi_edge": (texture("ShaderNodeTexVoronoi", "Distance", feature="DISTANCE_TO_EDGE"), 1e-5, True),
    "voronoi_radius": (texture("ShaderNodeTexVoronoi", "Radius", feature="N_SPHERE_RADIUS"), 1e-5, True),
    "voronoi_2d_chebychev": (texture("ShaderNodeTexVoronoi", "Distance", voronoi_dimensions="2D",
                                     distance="CHEBYCHEV"), 1e-5, True),
    "voronoi_fractal": (texture("ShaderNodeTexVoronoi", "Distance", in_Detail=2.5) if V4 else None, 1e-5, V4),
    # Whole-number cells (a hash of a coordinate's bits changes with its last bit); z = 0.5 * 6 + 0.1,
    # clear of a cell border.
    "white_noise_cells": (texture("ShaderNodeTexWhiteNoise", "Color", vector=through(
        "ShaderNodeVectorMath", 0, through("ShaderNodeVectorMath", 0, coordinate("Generated"), operation="MULTIPLY_ADD",
                                           in_Vector_001=(6.0, 6.0, 6.0), in_Vector_002=(0.1, 0.1, 0.1)),
        operation="FLOOR")), 1e-6, True),
    "checker": (texture("ShaderNodeTexChecker", "Color"), 1e-6, True),
    "gradient_radial": (texture("ShaderNodeTexGradient", "Fac", gradient_type="RADIAL",
                                vector=coordinate("Object")), 1e-5, True),
    "gradient_sphere": (texture("ShaderNodeTexGradient", "Fac", gradient_type="QUADRATIC_SPHERE",
                                vector=coordinate("Object")), 1e-5, True),
    "wave_bands": (texture("ShaderNodeTexWave", "Color", in_Distortion=2.0), 1e-4, True),
    "wave_rings_saw": (texture("ShaderNodeTexWave", "Fac", wave_type="RINGS", wave_profile="SAW"), 1e-4, True),
    "magic": (texture("ShaderNodeTexMagic", "Color", turbulence_depth=3), 1e-4, True),
    "brick": (texture("ShaderNodeTexBrick", "Color"), 1e-5, True),
    "ramp_linear": (ramp("LINEAR"), 1e-4, True),
    "ramp_ease": (ramp("EASE"), 1e-4, True),
    "ramp_constant": (ramp("CONSTANT"), 1e-4, True),
    "ramp_b_spline": (ramp("B_SPLINE"), 1e-4, True),
    "rgb_curves": (curves("ShaderNodeRGBCurve", "Color", texture("ShaderNodeTexNoise", "Color", in_Scale=2.0,
                                                                  in_Distortion=3.0), "Color"), 1e-4, True),
    "vector_curves": (curves("ShaderNodeVectorCurve", "Vector", coordinate("Object"), "Vector"), 1e-4, True),
    "float_curve": (curves("ShaderNodeFloatCurve", "Value", noise_fac(in_Scale=2.0), "Value")
                    if hasattr(bpy.types, "ShaderNodeFloatCurve") else None, 1e-4,
                    hasattr(bpy.types, "ShaderNodeFloatCurve")),
    "math_sine": (math_of("SINE"), 1e-5, True),
    "math_power": (math_of("POWER", b=2.5), 1e-5, True),
    "math_smooth_min": (math_of("SMOOTH_MIN", b=0.45, c=0.2), 1e-5, True),
    "math_pingpong": (math_of("PINGPONG", b=0.2), 1e-5, True),
    "vector_cross": (vector_math_of("CROSS_PRODUCT"), 1e-5, True),
    "vector_reflect": (vector_math_of("REFLECT"), 1e-5, True),
    "vector_distance": (vector_math_of("DISTANCE"), 1e-5, True),
    "mix_overlay": (mix_of("OVERLAY"), 1e-5, True),
    "mix_soft_light": (mix_of("SOFT_LIGHT"), 1e-5, True),
    "mix_hue": (mix_of("HUE"), 1e-5, True),
    "mix_dodge": (mix_of("DODGE", clamp=True), 1e-5, True),
    "mix_burn": (mix_of("BURN"), 1e-5, True),
    "hue_saturation": (through("ShaderNodeHueSaturation", "Color", texture("ShaderNodeTexNoise", "Color"),
                               in_Hue=0.3, in_Saturation=1.4, in_Value=0.8), 1e-5, True),
    "map_range_smoother": (through("ShaderNodeMapRange", "Value", noise_fac(), interpolation_type="SMOOTHERSTEP",
                                   **{"in_From Min": 0.3, "in_From Max": 0.7}), 1e-5, True),
    "mapping": (mapped_noise, 1e-5, True),
    "image_linear_repeat": (image_texture("Linear", "REPEAT"), 1e-4, True),
    "image_closest_mirror": (image_texture("Closest", "MIRROR"), 1e-4, MIRROR),
    "image_cubic_clip": (image_texture("Cubic", "CLIP"), 1e-3, True),
    "image_cubic_repeat": (image_texture("Cubic", "REPEAT"), 1e-4, True),
    "image_linear_clip": (image_texture("Linear", "CLIP"), 1e-4, True),
    "image_linear_extend": (image_texture("Linear", "EXTEND"), 1e-4, True),
    "bump": (bump_normal, 1e-3, True),
    "fresnel": (tilted("ShaderNodeFresnel", "Fac", in_IOR=1.6), 1e-5, True),
    "layer_weight_facing": (tilted("ShaderNodeLayerWeight", "Facing", in_Blend=0.3), 1e-5, True),
    "layer_weight_fresnel": (tilted("ShaderNodeLayerWeight", "Fresnel", in_Blend=0.6), 1e-5, True),
    "vector_rotate": (through("ShaderNodeVectorRotate", "Vector", coordinate("Object"), rotation_type="AXIS_ANGLE",
                              in_Axis=(0.3, 0.5, 0.8), in_Angle=0.7), 1e-5, True),
    "vector_rotate_euler": (through("ShaderNodeVectorRotate", "Vector", coordinate("Object"),
                                    rotation_type="EULER_XYZ", invert=True, in_Rotation=(0.4, -0.3, 1.2)), 1e-5,
                            True),
    "clamp_range": (through("ShaderNodeClamp", "Value", noise_fac(), clamp_type="RANGE", in_Min=0.6, in_Max=0.4),
                    1e-6, True),
    "gamma": (through("ShaderNodeGamma", "Color", texture("ShaderNodeTexNoise", "Color"), in_Gamma=2.2), 1e-5,
              True),
    "bright_contrast": (through("ShaderNodeBrightContrast", "Color", texture("ShaderNodeTexNoise", "Color"),
                                in_Bright=0.1, in_Contrast=0.6), 1e-5, True),
    "invert": (through("ShaderNodeInvert", "Color", texture("ShaderNodeTexNoise", "Color"), in_Fac=0.8), 1e-5,
               True),
    "rgb_to_bw": (through("ShaderNodeRGBToBW", "Color", texture("ShaderNodeTexNoise", "Color")), 1e-5, True),
    "separate_combine_xyz": (combined("ShaderNodeCombineXYZ", "Vector", ["X", "Y", "Z"], coordinate("Object")),
                             1e-6, True),
    "separate_combine_hsv": (combined("ShaderNodeCombineColor" if V4 else "ShaderNodeCombineHSV", "Color",
                                      ["Red", "Green", "Blue"] if V4 else ["H", "S", "V"],
                                      texture("ShaderNodeTexNoise", "Color"), **({"mode": "HSV"} if V4 else {})),
                             1e-5, True),
    "wavelength": (through("ShaderNodeWavelength", "Wavelength", math_of("MULTIPLY_ADD", b=600.0, c=250.0)),
                   1e-5, True),
    "separate_combine_hsl": (combined("ShaderNodeCombineColor", "Color", ["Red", "Green", "Blue"],
                                      texture("ShaderNodeTexNoise", "Color"), mode="HSL"), 1e-5, True),
    "map_range_stepped": (through("ShaderNodeMapRange", "Value", noise_fac(), interpolation_type="STEPPED",
                                  in_Steps=5.0, **{"in_To Min": 0.2}), 1e-5, True),
    "mix_float": (mix_data("FLOAT"), 1e-5, True),
    "mix_vector_non_uniform": (mix_data("VECTOR", uniform=False), 1e-5, True),
    "object_random": (lambda tree, nodes: nodes.new("ShaderNodeObjectInfo").outputs["Random"], 1e-6, True),
    "geometry_incoming": (lambda tree, nodes: nodes.new("ShaderNodeNewGeometry").outputs["Incoming"], 1e-6, True),
    "gradient_easing": (texture("ShaderNodeTexGradient", "Fac", gradient_type="EASING"), 1e-5, True),
    "wave_triangle_z": (texture("ShaderNodeTexWave", "Fac", wave_profile="TRI", bands_direction="Z",
                                vector=coordinate("Object")) if V4 else None, 1e-4, V4),
    "voronoi_4d": (texture("ShaderNodeTexVoronoi", "Color", voronoi_dimensions="4D", in_W=0.7), 1e-5, True),
    "white_noise_1d": (texture("ShaderNodeTexWhiteNoise", "Value", noise_dimensions="1D", in_W=0.25), 1e-6,
                       True),
    "normal_map_tangent": (normal_map_of_noise("TANGENT", 0.5), 1e-4, True),
    "normal_map_tangent_full": (normal_map_of_noise("TANGENT", 1.0), 1e-4, True),
    "normal_map_object": (normal_map_of_noise("OBJECT", 1.0), 1e-4, True),
    "normal_map_world": (normal_map_of_noise("WORLD", 0.7), 1e-4, True),
    "texcoord_camera": (coordinate("Camera"), 1e-5, True),
    "texcoord_window": (coordinate("Window"), 1e-5, True),
    "texcoord_other_object": (other_objects_coordinates, 1e-5, True),
    "image_udim": (udim_tiles, 1e-5, True),
    "image_udim_packed": (lambda tree, nodes: udim_tiles(tree, nodes, packed=True), 1e-5, True),
    "environment_default_vector": (environment_texture("EQUIRECTANGULAR"), 1e-4, True),
    "environment_mirror_ball_normal": (environment_texture("MIRROR_BALL", "Normal"), 1e-4, True),
    "vector_transform_object_camera_point": (vector_transform(coordinate("Object"), "OBJECT", "CAMERA", "POINT"),
                                             1e-5, True),
    "vector_transform_camera_world_vector": (vector_transform(texture("ShaderNodeTexNoise", "Color"), "CAMERA",
                                                              "WORLD", "VECTOR"), 1e-5, True),
    "vector_transform_world_object_normal": (vector_transform(geometry("Normal"), "WORLD", "OBJECT", "NORMAL"),
                                             1e-4, True),
    "image_box": (image_texture("Linear", "REPEAT", "BOX", 0.0, "Object"), 1e-4, True),
    "image_box_blend": (image_texture("Linear", "REPEAT", "BOX", 0.4, "Object"), 1e-4, True),
    "image_sphere": (image_texture("Linear", "REPEAT", "SPHERE", vector="Generated"), 1e-4, True),
    "image_tube": (image_texture("Closest", "EXTEND", "TUBE", vector="Object"), 1e-4, True),
    # -500 to 13500 K across the plane: below, through every interval of, and above Cycles' fit.
    "blackbody_varying": (through("ShaderNodeBlackbody", "Temperature",
                                  math_of("MULTIPLY_ADD", a=texture("ShaderNodeTexGradient", "Fac"), b=14000.0,
                                          c=-500.0)), 1e-4, True),
    "gabor_2d": (texture("ShaderNodeTexGabor", "Value") if V43 else None, 1e-4, V43),
    "gabor_2d_phase": (texture("ShaderNodeTexGabor", "Phase", **{"in_Anisotropy": 0.3, "in_Frequency": 3.0,
                                                                  "in_Orientation 2D": 1.0}) if V43 else None,
                       1e-4, V43),
    "gabor_3d_value": (texture("ShaderNodeTexGabor", "Value", gabor_type="3D") if V43 else None, 1e-4, V43),
    "gabor_3d_intensity": (texture("ShaderNodeTexGabor", "Intensity", gabor_type="3D", in_Anisotropy=0.4,
                                   **{"in_Orientation 3D": (0.2, -0.5, 0.8)}) if V43 else None, 1e-4, V43),
    "object_attribute_custom": (attribute("OBJECT", "tint", "Color"), 1e-6, True),
    "object_attribute_int_pair": (attribute("OBJECT", "pair", "Vector"), 1e-6, True),
    "object_attribute_of_the_mesh": (attribute("OBJECT", "level", "Fac"), 1e-6, True),
    "object_attribute_rna_alpha": (attribute("OBJECT", "color", "Alpha"), 1e-6, True),
    "object_attribute_custom_first": (attribute("OBJECT", "pass_index", "Fac"), 1e-6, True),
    "object_attribute_missing": (attribute("OBJECT", "nothing", "Alpha"), 1e-6, True),
    "instancer_attribute_of_an_object": (attribute("INSTANCER", "tint", "Color"), 1e-6, True),
    "view_layer_attribute_of_the_scene": (attribute("VIEW_LAYER", "sky", "Color"), 1e-6, True),
    "view_layer_attribute_of_the_world": (attribute("VIEW_LAYER", "glow", "Fac"), 1e-6, True),
    "object_info_color": (lambda tree, nodes: node(nodes, "ShaderNodeObjectInfo").outputs["Color"], 1e-6, True),
    "object_info_alpha": (lambda tree, nodes: node(nodes, "ShaderNodeObjectInfo").outputs["Alpha"], 1e-6, True),
    "object_info_index": (lambda tree, nodes: node(nodes, "ShaderNodeObjectInfo").outputs["Object Index"], 1e-6,
                          True),
    "blackbody_folded": (through("ShaderNodeBlackbody", "Temperature",
                                 math_of("MULTIPLY", a=value_node(1.7), b=2000.0)), 1e-4, True),
}
# Cases shown on a plane whose smooth normals vary (emission_plane.CORNER_NORMALS).
CURVED = {"vector_transform_world_object_normal", "image_box", "image_box_blend"}


def ppm_values(material, out, package):
    """What the add-on's program gives at each pixel centre (emission times its input); the add-on's
    warnings. `package`: the add-on's module (the checkout's ppm_render, or an installed zip's)."""
    ppm_core = importlib.import_module(package + ".core").load()
    material_export = importlib.import_module(package + ".export.material")
    object_info = importlib.import_module(package + ".export.object_info")
    scene = ppm_core.Scene()
    warnings = []
    attributes = object_info.AttributeTable(bpy.context.view_layer, bpy.context.scene)
    exporter = material_export.MaterialExporter(scene, warnings.append, attributes)
    params = exporter.describe(material)
    emission = np.array(params.get("emission", (0.0, 0.0, 0.0)), dtype=float)
    shape = out["P"].shape
    if "emission_input" not in params:
        return np.broadcast_to(emission, shape), warnings
    obj = bpy.data.objects["emission_plane"]
    instance = importlib.import_module(package + ".export.instance")
    item = instance.Instance(obj, obj.name, out["matrix"], 0, object_info.random_of_name(obj.name))
    object_info.add_object_info(scene, item, attributes)
    camera = importlib.import_module(package + ".export.camera")
    scene.set_camera(**camera.camera_arguments(bpy.context.scene.camera, camera.Frame(SIZE, SIZE), warnings.append))
    normals = out["N"].reshape(-1, 3)
    u_axis = out["matrix"][:3, 0] / np.linalg.norm(out["matrix"][:3, 0])  # U runs along object x
    tangents = np.tile([*u_axis, 1.0], (len(normals), 1))
    values = scene.run_program(params["program"], out["P"].reshape(-1, 3), normal=normals, incoming=normals,
                               uv=out["uv"].reshape(-1, 2), tangent=tangents, object=0, footprint=PIXEL)
    return emission * values[:, params["emission_input"]].reshape(shape), warnings


# Float rounding: every Blender's Cycles build rounds a little differently (Blender 5.2's noise and
# Fresnel by up to 1e-4, its curves by 1.5e-4 at the 99th percentile); a wrong formula is off by 1e-2 and
# more. A case's own tolerance is used where it is looser.
ROUNDING = 3e-4


def compare(name, package="ppm_render"):
    """The case's row: its largest and 99th-percentile per-pixel differences, or None if this Blender
    lacks its nodes."""
    build, tolerance, available = CASES[name]
    if not available:
        return None
    bpy.ops.wm.read_factory_settings(use_empty=True)
    material = emission_plane.emission_material(name, build)
    out = emission_plane.render_cycles(material, size=SIZE,
                                       normals=emission_plane.CORNER_NORMALS if name in CURVED else None,
                                       prepare=give_properties)
    ours, warnings = ppm_values(material, out, package)
    while FOLDERS_TO_REMOVE:
        shutil.rmtree(FOLDERS_TO_REMOVE.pop(), ignore_errors=True)
    difference = np.abs(ours - out["rgb"])
    p99 = float(np.quantile(difference, 0.99))
    tolerance = max(tolerance, ROUNDING)
    return {"case": name, "max": float(difference.max()), "p99": p99, "tolerance": tolerance,
            "range": (float(out["rgb"].min()), float(out["rgb"].max())), "warnings": warnings,
            "ok": p99 <= tolerance and not warnings}


def compare_cases(names=None, package="ppm_render"):
    """compare() for each case (all by default), printing a line each; the rows of those this Blender has."""
    rows = []
    for name in names or CASES:
        row = compare(name, package)
        if row is None:
            print(f"nodes_compare: {name}: not in Blender {bpy.app.version_string}", flush=True)
            continue
        rows.append(row)
        print(f"nodes_compare: {name}: max {row['max']:.2g} p99 {row['p99']:.2g} (values {row['range'][0]:.3g}.."
              f"{row['range'][1]:.3g}) {'ok' if row['ok'] else 'FAILED'} {'; '.join(row['warnings'])}".rstrip(),
              flush=True)
    return rows


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    # After "--" in the blender binary; as given with the bpy module (argv[0] is then this script).
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:] * sys.argv[0].endswith(".py")
    bad = [row["case"] for row in compare_cases(args) if not row["ok"]]
    if bad:
        print(f"nodes_compare: Blender {bpy.app.version_string}: beyond tolerance: {', '.join(bad)}", flush=True)
        sys.exit(1)
