"""Blender materials -> core materials.

Reads the shader node connected to the active Material Output's Surface:
Principled BSDF (Blender 3.x and 4.x+ socket names), Diffuse, Glossy
(Anisotropic in 4.x), Glass and Emission BSDFs, the Holdout shader, and an
Image Texture linked to the base colour. The core has one lobe per material, so a Principled BSDF
becomes glass if Transmission >= 0.5, else metal if Metallic >= 0.5, else
diffuse (its dielectric specular layer is dropped). Anything else (another
node, a linked input we cannot read) falls back to a diffuse surface of the
material's viewport colour, with one warning naming the material and node.
"""

import math

import numpy as np

from . import image as image_export
from . import nodes

DEFAULT_GREY = (0.8, 0.8, 0.8)

# Principled BSDF socket names: Blender 4.0+ first, 3.x second.
PRINCIPLED_SOCKETS = {
    "transmission": ("Transmission Weight", "Transmission"),
    "emission": ("Emission Color", "Emission"),
    "emission_strength": ("Emission Strength",),
}


MAX_EMISSION = 1e20  # radiance, the core's limit


def _socket(node, *names):
    for name in names:
        socket = node.inputs.get(name)
        if socket is not None:
            return socket
    return None


def _value(node, *names, default=0.0):
    socket = _socket(node, *names)
    if socket is None:
        return default
    value = socket.default_value
    try:
        return tuple(value)[:3]
    except TypeError:
        return float(value)


class MaterialExporter:
    """Adds each Blender material to the core once; remembers its index."""

    def __init__(self, core_scene, warn):
        self.scene = core_scene
        self.warn = warn
        self.indices = {}
        self.emissive = set()
        self.textures = {}
        self.default = None
        self.non_emissive = {}

    def index(self, material):
        """Core material index for a Blender material (None = default grey)."""
        if material is None:
            if self.default is None:
                self.default = self.scene.add_material("default", "diffuse", base_color=DEFAULT_GREY)
            return self.default
        key = material.name_full if hasattr(material, "name_full") else material.name
        if key not in self.indices:
            params = self.in_range(self.describe(material), material.name)
            self.indices[key] = self.scene.add_material(material.name, **params)
            if any(c > 0.0 for c in params.get("emission", (0, 0, 0))):
                self.emissive.add(self.indices[key])
                self.non_emissive[self.indices[key]] = {**params, "emission": (0.0, 0.0, 0.0)}
        return self.indices[key]

    def in_range(self, params, name):
        """`params` brought into the core's ranges, as Cycles renders them where it has a rule: roughness
        clamped to [0, 1] (silently, as Cycles does). Colours that are not finite, negative, or above 1
        (a surface reflecting more than it receives, which photons would multiply without bound), an
        emission above the core's 1e20 and a non-positive IOR are clamped with one warning."""
        out, changes = dict(params), []
        for key, lo, hi, nan in (("base_color", 0.0, 1.0, 0.0), ("emission", 0.0, MAX_EMISSION, 0.0)):
            if key in out:
                value = np.asarray(out[key], dtype=float)
                fixed = np.clip(np.nan_to_num(value, nan=nan, posinf=hi, neginf=lo), lo, hi)
                if not np.array_equal(value, fixed):
                    changes.append(f"{key.replace('_', ' ')} {_rgb(value)} -> {_rgb(fixed)}")
                out[key] = tuple(float(c) for c in fixed)
        if "roughness" in out:
            roughness = float(out["roughness"])
            if not math.isfinite(roughness):
                changes.append(f"roughness {roughness} -> 0.5")
            out["roughness"] = min(max(roughness, 0.0), 1.0) if math.isfinite(roughness) else 0.5
        if "ior" in out and not (math.isfinite(out["ior"]) and out["ior"] > 0.0):
            changes.append(f"ior {out['ior']} -> 1.45")
            out["ior"] = 1.45
        if changes:
            self.warn(f"material '{name}': outside what can be rendered, clamped: {'; '.join(changes)}")
        return out

    def without_emission(self, index, what):
        """A copy of material `index` without emission, for surfaces the core cannot make emissive."""
        if index not in self.emissive:
            return index
        self.warn(f"{what}: emission is not supported on Bezier revolve surfaces; rendered without it")
        params = self.non_emissive[index]
        return self.scene.add_material(f"{what} (no emission)", **params)

    def describe(self, material):
        """Keyword arguments for Scene.add_material."""
        node = (nodes.surface_source(material.node_tree, "ShaderNodeOutputMaterial", targets=("ALL", "CYCLES"))
                if nodes.uses_nodes(material) else None)
        if node is None:
            return {"kind": "diffuse", "base_color": tuple(material.diffuse_color)[:3]}
        handler = NODE_HANDLERS.get(node.bl_idname)
        if handler is None:
            self.warn(f"material '{material.name}': node '{node.name}' ({node.bl_idname}) is not supported; "
                      "rendered as diffuse in the material's viewport colour")
            return {"kind": "diffuse", "base_color": tuple(material.diffuse_color)[:3]}
        return handler(self, material, node)

    def base_color(self, material, node, socket_name):
        """(colour, texture index) of a colour socket: its value, or an Image Texture linked to it."""
        socket = _socket(node, socket_name)
        if socket is None:
            return DEFAULT_GREY, -1
        if not socket.links:
            return tuple(socket.default_value)[:3], -1
        source = socket.links[0].from_node
        if source.bl_idname == "ShaderNodeTexImage" and source.image is not None:
            try:
                return (1.0, 1.0, 1.0), self.texture(source.image)
            except ValueError as error:
                self.warn(f"material '{material.name}': node '{source.name}': {error}; using the socket's colour")
                return tuple(socket.default_value)[:3], -1
        self.warn(f"material '{material.name}': node '{source.name}' ({source.bl_idname}) linked to "
                  f"'{socket_name}' is not supported; using the socket's colour")
        return tuple(socket.default_value)[:3], -1

    def texture(self, image):
        key = image.name_full if hasattr(image, "name_full") else image.name
        if key not in self.textures:
            self.textures[key], repaired = image_export.add_texture(self.scene, image)
            if repaired:
                self.warn(f"image '{image.name}': {repaired}")
        return self.textures[key]


def _rgb(values):
    return "(" + ", ".join(f"{float(v):g}" for v in values) + ")"


def _emission(node, color_names, strength_names):
    color = _value(node, *color_names, default=(0.0, 0.0, 0.0))
    strength = _value(node, *strength_names, default=1.0)
    return tuple(float(c) * strength for c in color)


def _principled(exporter, material, node):
    color, texture = exporter.base_color(material, node, "Base Color")
    metallic = _value(node, "Metallic")
    roughness = _value(node, "Roughness", default=0.5)
    transmission = _value(node, *PRINCIPLED_SOCKETS["transmission"])
    ior = _value(node, "IOR", default=1.45)
    emission = _emission(node, PRINCIPLED_SOCKETS["emission"], PRINCIPLED_SOCKETS["emission_strength"])
    if transmission >= 0.5:
        return {"kind": "glass", "base_color": color, "ior": ior, "roughness": roughness, "emission": emission}
    if metallic >= 0.5:
        return {"kind": "metal", "base_color": color, "roughness": roughness, "emission": emission}
    return {"kind": "diffuse", "base_color": color, "texture": texture, "emission": emission}


def _diffuse(exporter, material, node):
    color, texture = exporter.base_color(material, node, "Color")
    return {"kind": "diffuse", "base_color": color, "texture": texture}


def _glossy(exporter, material, node):
    color = _value(node, "Color", default=(1.0, 1.0, 1.0))
    roughness = _value(node, "Roughness", default=0.0)
    if roughness <= 0.0:
        return {"kind": "mirror", "base_color": color}
    return {"kind": "metal", "base_color": color, "roughness": roughness}


def _glass(exporter, material, node):
    return {"kind": "glass", "base_color": _value(node, "Color", default=(1.0, 1.0, 1.0)),
            "ior": _value(node, "IOR", default=1.45), "roughness": _value(node, "Roughness")}


def _emission_node(exporter, material, node):
    return {"kind": "emission", "base_color": (0.0, 0.0, 0.0),
            "emission": _emission(node, ("Color",), ("Strength",))}


NODE_HANDLERS = {
    "ShaderNodeBsdfPrincipled": _principled,
    "ShaderNodeBsdfDiffuse": _diffuse,
    "ShaderNodeBsdfGlossy": _glossy,
    "ShaderNodeBsdfAnisotropic": _glossy,
    "ShaderNodeBsdfGlass": _glass,
    "ShaderNodeEmission": _emission_node,
    "ShaderNodeHoldout": lambda exporter, material, node: {"kind": "holdout"},
}
