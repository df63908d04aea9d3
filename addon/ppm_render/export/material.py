"""Blender materials -> core materials.

Reads the closure on the active Material Output's Surface (closure.py: Mix and Add shaders, node
groups, every BSDF node, the Principled BSDF's layers; node_program.py: the texture and utility
nodes driving their sockets) and adds it as the cheapest core material that renders it: a diffuse
material (with its image texture) when every lobe is diffuse, a holdout
or an emission-only material, else a mixture of lobes. A material without a node tree in use is
diffuse in its viewport colour; a Surface with nothing connected is black, as in Cycles.
"""

import math

import numpy as np

from . import closure, nodes, smoke, volume
from . import image as image_export

DEFAULT_GREY = (0.8, 0.8, 0.8)

MAX_EMISSION = 1e20  # radiance, the core's limit


class MaterialExporter:
    """Adds each Blender material to the core once; remembers its index."""

    def __init__(self, core_scene, warn, attributes=None, grid_names=None):
        self.scene = core_scene
        self.warn = warn
        self.attributes_table = attributes  # object_info.AttributeTable: object and view-layer attributes
        self.grid_names = grid_names  # smoke.GridNames: the slots of the grids Volumes read
        self.indices = {}
        self.emissive = set()
        self.textures = {}
        self.default = None
        self.non_emissive = {}
        self.tangents = {}  # core material -> the tangents its meshes need ("uv", "radial_z", ...)
        self.needed_tangents = None  # those of the material describe() read last
        self.with_program = set()  # core materials with a node program (their objects need object info)
        self.medium_varies = False  # whether the medium volume() read last has one
        self.attributes = {}  # core material -> the mesh attribute its program reads
        self.needed_attribute = None  # that of the material describe() read last
        self.copied = set()  # core materials with a copy without emission (without_emission)
        self.pass_indices = {}  # core material -> its Blender material's Pass Index (Material Index pass)
        self.with_volume = set()  # core materials with a Volume output (a medium, or a boundary only)
        self.grid_slots = ()  # the smoke grid slots the medium volume() read last reads
        self.grid_slots_of = {}  # core material -> the smoke grid slots its medium reads

    def index(self, material, grids=False):
        """Core material index for a Blender material (None = default grey); with `grids`, as it is on a
        smoke domain (its Volume reads the domain's grids: a material of its own where it has a Volume)."""
        if material is None:
            if self.default is None:
                self.default = self.scene.add_material("default", "diffuse", base_color=DEFAULT_GREY)
            return self.default
        key = material_key(material)
        if grids and self.volume_driven(material):
            key = (key, "on a smoke domain")
        if key not in self.indices:
            params = {**self.in_range(self.describe(material), material.name), **self.volume(material, grids)}
            self.indices[key] = self.scene.add_material(material.name, **params)
            if self.grid_slots:
                self.grid_slots_of[self.indices[key]] = self.grid_slots
            if "surface" in params:
                self.with_volume.add(self.indices[key])
            self.pass_indices[self.indices[key]] = material.pass_index
            if self.needed_tangents:
                self.tangents[self.indices[key]] = self.needed_tangents
            if "program" in params or self.medium_varies:
                self.with_program.add(self.indices[key])
            if "program" in params:
                if self.needed_attribute is not None:
                    self.attributes[self.indices[key]] = self.needed_attribute
            if any(c > 0.0 for c in params.get("emission", (0, 0, 0))):
                self.emissive.add(self.indices[key])
                self.non_emissive[self.indices[key]] = {**params, "emission": (0.0, 0.0, 0.0)}
        return self.indices[key]

    def in_range(self, params, name):
        """`params` brought into the core's ranges, as Cycles renders them where it has a rule: roughness
        clamped to [0, 1] (silently, as Cycles does). Colours that are not finite, negative, or above 1
        (a surface reflecting more than it receives, which photons would multiply without bound), an
        emission above the core's 1e20 and a non-positive IOR are clamped with one warning."""
        changes = []
        out = _values_in_range(params, "", changes)
        if "lobes" in out:
            out["lobes"] = [_values_in_range(lobe, f"{lobe['kind']} ", changes) for lobe in out["lobes"]]
        if changes:
            self.warn(f"material '{name}': outside what can be rendered, clamped: {'; '.join(changes)}")
        return out

    def without_emission(self, index, what):
        """A copy of material `index` without emission, for surfaces the core cannot make emissive."""
        if index not in self.emissive:
            return index
        self.copied.add(index)
        self.warn(f"{what}: emission is not supported on Bezier revolve surfaces; rendered without it")
        params = self.non_emissive[index]
        copy = self.scene.add_material(f"{what} (no emission)", **params)
        self.pass_indices[copy] = self.pass_indices.get(index, 0)
        return copy

    def pass_index_table(self):
        """Pass Index by core material index (0 where it has none)."""
        table = np.zeros(max(self.pass_indices, default=-1) + 1, dtype=np.float32)
        for index, value in self.pass_indices.items():
            table[index] = value
        return table

    def update(self, material):
        """Writes an edited `material` into its core slot (the surfaces keep their BVH). False where
        that is not enough: a material not added before, one copied for revolves, one a revolve cannot
        take, or one whose meshes or objects must now carry other data (tangents, an attribute,
        object info for a node program, an object attribute no material read before)."""
        index = self.indices.get(material_key(material))
        if index is None or index in self.copied or index in self.with_volume or self.volume_driven(material):
            return False  # (media are added once: a changed one needs the whole export)
        slots = len(self.attributes_table.slots) if self.attributes_table is not None else 0
        params = self.in_range(self.describe(material), material.name)
        program = "program" in params
        if ((self.needed_tangents or None) != self.tangents.get(index) or program != (index in self.with_program)
                or (self.needed_attribute if program else None) != self.attributes.get(index)
                or slots != (len(self.attributes_table.slots) if self.attributes_table is not None else 0)):
            return False
        try:
            self.scene.add_material(material.name, **params, replace=index)
        except ValueError:  # a revolve's material made emissive: the whole export copies it
            return False
        self.pass_indices[index] = material.pass_index
        self.emissive.discard(index)
        self.non_emissive.pop(index, None)
        if any(c > 0.0 for c in params.get("emission", (0, 0, 0))):
            self.emissive.add(index)
            self.non_emissive[index] = {**params, "emission": (0.0, 0.0, 0.0)}
        return True

    @staticmethod
    def volume_driven(material):
        """Whether anything drives `material`'s Volume output."""
        return nodes.uses_nodes(material) and volume.volume_socket(material.node_tree,
                                                                   "ShaderNodeOutputMaterial") is not None

    def volume(self, material, grids=False):
        """add_material's medium keywords for `material`'s Volume output (on a smoke domain with `grids`):
        {} without one; else its medium (None where it has no coefficient) and surface=False where
        nothing drives its Surface (Cycles renders that surface invisible: a boundary only)."""
        self.medium_varies = False  # whether its medium has a node program (its objects need object info)
        self.grid_slots = ()
        if not self.volume_driven(material):
            return {}
        names = (self.grid_names if self.grid_names is not None else smoke.GridNames()) if grids else None
        keywords = volume.material_medium(material, self.warn, self.scene, self.texture, names)
        self.medium_varies = keywords is not None and "program" in keywords
        if self.medium_varies:
            code = keywords["program"]["code"]
            self.grid_slots = tuple(sorted({i["data"] for i in code if i["op"] == "grid"}))
        name = volume.add(self.scene, f"material '{material_key(material)}'", keywords, self.warn)
        return {"medium": name, "surface": volume.surface_driven(material.node_tree)}

    def describe(self, material):
        """Keyword arguments for Scene.add_material."""
        read = closure.read_surface(material, self.warn, self.texture, self.scene, self.attributes_table)
        self.needed_tangents = read.tangents if read is not None else None
        self.needed_attribute = read.attribute if read is not None else None
        if read is None:
            return {"kind": "diffuse", "base_color": tuple(material.diffuse_color)[:3]}
        program = {"program": read.program} if read.program is not None else {}
        emission = tuple(float(c) for c in read.emission)
        holdout = min(read.holdout, 1.0)
        if holdout >= 0.999 and not read.lobes:
            return {"kind": "holdout"}
        lobes = read.lobes
        if holdout > 0.0 and not lobes:  # part holdout, part black: a black lobe carries the rest
            lobes = [{"kind": "diffuse", "weight": (1.0, 1.0, 1.0), "color": (0.0, 0.0, 0.0)}]
        textured_emission = {}
        if read.emission_input is not None and max(emission) > 0.0:
            textured_emission = {**program, "emission_input": read.emission_input}
        if not lobes:
            kind = "emission" if max(emission) > 0.0 else "diffuse"
            return {"kind": kind, "base_color": (0.0, 0.0, 0.0), "emission": emission, **textured_emission}
        normal_map = read.normal_map
        texture = _diffuse_texture(lobes, read.simple_images)
        if holdout == 0.0 and texture is not None and normal_map is None and not textured_emission:
            color = sum(np.asarray(lobe["weight"]) * np.asarray(lobe["color"]) for lobe in lobes)
            return {"kind": "diffuse", "base_color": tuple(float(c) for c in color), "texture": texture,
                    "emission": emission}
        return {"kind": "mixture", "lobes": lobes, **program, "emission": emission, "holdout": holdout,
                **({"normal_map": normal_map} if normal_map else {}),
                **({"emission_input": read.emission_input} if textured_emission else {})}

    def texture(self, image, premultiplied=False):
        key = (image.name_full if hasattr(image, "name_full") else image.name, premultiplied)
        if key not in self.textures:
            add = image_export.add_tiles if image.source == "TILED" else image_export.add_texture
            self.textures[key], repaired = add(self.scene, image, premultiplied)
            if repaired:
                self.warn(f"image '{image.name}': {repaired}")
        return self.textures[key]


def material_key(material):
    """What names a Blender material among those of all libraries."""
    return material.name_full if hasattr(material, "name_full") else material.name


def _diffuse_texture(lobes, images):
    """The core texture (-1: none) of a closure that is one plain diffuse material: every lobe
    diffuse with a constant weight, all untextured or all of one image's colour read at the UV
    (`images`: the texture each input is, or None). None otherwise."""
    if not all(lobe["kind"] == "diffuse" and "weight_inputs" not in lobe and "roughness" not in lobe
               for lobe in lobes):
        return None
    used = {lobe.get("color_input") for lobe in lobes}
    if used == {None}:
        return -1
    if len(used) == 1 and images[next(iter(used))] is not None:
        return images[next(iter(used))]
    return None


# A lobe's weight comes from Mix factors (in [0, 1]) and tints: above 1 only from values out of range.
COLOUR_RANGES = {"base_color": (0.0, 1.0), "color": (0.0, 1.0), "tint": (0.0, 1.0), "weight": (0.0, 1.0),
                 "emission": (0.0, MAX_EMISSION)}


def _values_in_range(params, prefix, changes):
    """A copy of `params` (a material's or a lobe's) in the core's ranges; what changed goes to `changes`."""
    out = dict(params)
    for key, (lo, hi) in COLOUR_RANGES.items():
        if key in out:
            value = np.asarray(out[key], dtype=float)
            fixed = np.clip(np.nan_to_num(value, nan=0.0, posinf=hi, neginf=lo), lo, hi)
            if not np.array_equal(value, fixed):
                changes.append(f"{prefix}{key.replace('_', ' ')} {_rgb(value)} -> {_rgb(fixed)}")
            out[key] = tuple(float(c) for c in fixed)
    if "roughness" in out:
        roughness = float(out["roughness"])
        if not math.isfinite(roughness):
            changes.append(f"{prefix}roughness {roughness} -> 0.5")
        out["roughness"] = min(max(roughness, 0.0), 1.0) if math.isfinite(roughness) else 0.5
    if "ior" in out and not (math.isfinite(out["ior"]) and out["ior"] > 0.0):
        changes.append(f"{prefix}ior {out['ior']} -> 1.45")
        out["ior"] = 1.45
    return out


def _rgb(values):
    return "(" + ", ".join(f"{float(v):g}" for v in values) + ")"
