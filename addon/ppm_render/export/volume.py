"""A material's or the world's Volume output -> the core's medium (Scene.add_medium).

Walks the Volume socket as closure.py walks the Surface (Mix and Add shaders, node groups, reroutes,
muted nodes; constant networks folded) and sums what each volume shader adds, as Cycles' SVM computes
it (intern/cycles/kernel/svm/closure.h, svm_node_closure_volume, svm_node_principled_volume,
svm_node_volume_coefficients; the core's shading/medium_coefficients.h says the same in C++):
- Volume Absorption: sigma_a += (1 - Color) Density;
- Volume Scatter: sigma_s += Color Density, with its phase function (Henyey-Greenstein, or in
  Blender 4.4+ Fournier-Forand, Draine, Rayleigh or Mie);
- Principled Volume: sigma_s = Color Density, sigma_a = (1 - Color)(1 - sqrt(Absorption Color))
  Density, emission = Emission Strength Emission Color plus its blackbody term;
- Volume Coefficients (Blender 5.0+): the coefficients as given;
- Emission: Color Strength, radiance per metre.
Each times its Mix Shader factors. Densities are per Blender unit, as in Cycles.

A material's medium may vary in space: where a texture drives a Density, a Color, an Emission
Strength or Color, a coefficient or a Mix factor (a Noise cloud), that product of sockets is
compiled into the material's node program (node_program.py) and becomes a term, RGB coefficients
times a program output that the core runs where the path is (Generated and Object coordinates as in
Cycles' volumes: the object's, through its texture space). Other sockets (Anisotropy, Absorption
Color, the blackbody's) and the World's medium take their own value where a texture drives them,
with one warning naming the material and node. Principled Volume's Density, Color and Temperature
Attributes multiply only where the object has that grid (a smoke domain's, smoke.py, or a Volume
object's, volume_object.py), so on a mesh they are 1, as in Cycles; a material on such an object
(read with `grids`) multiplies by the grid, its blackbody then a term of the temperature there, and
its Attribute nodes read the grids. Where scattering shaders with different phase functions mix,
the core takes one: the Henyey-Greenstein of their scattering-weighted mean anisotropy (warned;
Cycles samples each).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import blackbody, nodes, unrendered
from .closure import ClosureReader
from .node_program import Unsupported

MAX_NESTING = 64  # Mix and Add shaders inside each other, as closure.py
CUTOFF = 1e-6  # Cycles' CLOSURE_WEIGHT_CUTOFF
STEFAN_BOLTZMANN = 5.670373e-8  # W m^-2 K^-4, as Cycles' Principled Volume writes it
# Cycles' phase enum -> the core's phase name and the node inputs it reads (core keyword, socket).
PHASES = {
    "HENYEY_GREENSTEIN": ("henyey_greenstein", (("anisotropy", "Anisotropy"),)),
    "FOURNIER_FORAND": ("fournier_forand", (("backscatter", "Backscatter"), ("ior", "IOR"))),
    "DRAINE": ("draine", (("anisotropy", "Anisotropy"), ("alpha", "Alpha"))),
    "RAYLEIGH": ("rayleigh", ()),
    "MIE": ("mie", (("diameter", "Diameter"),)),
}
# What a warning says of a socket a texture drives where the core takes only a constant.
VARYING = {"material": "varies in space (a texture drives it), which only Density, Color, Emission Strength and "
                       "Color, the coefficients and Mix factors can yet",
           "world": "varies in space (a texture drives it): the World's medium is homogeneous here"}


@dataclass
class Medium:
    """Coefficients per Blender unit, summed over the volume shaders read: constants, and terms that a
    texture scales (each RGB coefficients times a program Value, for Scene.add_medium's `terms`)."""
    sigma_a: np.ndarray = field(default_factory=lambda: np.zeros(3))
    sigma_s: np.ndarray = field(default_factory=lambda: np.zeros(3))
    emission: np.ndarray = field(default_factory=lambda: np.zeros(3))
    phases: list = field(default_factory=list)  # (sigma_s part, phase keywords) per scattering shader
    terms: list = field(default_factory=list)  # (coefficient name, RGB, Value)

    def empty(self):
        constant = max(np.max(self.sigma_a), np.max(self.sigma_s), np.max(self.emission))
        return constant <= 0.0 and not any(np.max(rgb) > 0.0 for _, rgb, _ in self.terms)


@dataclass(frozen=True)
class Part:
    """A socket's value in a product: a constant `c` (a float or an RGB array) times the program Value
    `v` a texture computes (None: constant)."""
    c: object = 1.0
    v: object = None


class VolumeReader:
    """Reads one Volume socket; warnings name the material (or world) and node, each once. A material's
    sockets that a texture drives become program Values (the medium varies in space); the World's take
    their own value (warned): the core's World medium is homogeneous."""

    def __init__(self, owner, name, warn, core, texture=None, grids=None):
        self.values = ClosureReader(name, warn, texture, core, kind=owner)
        self.values.varying_note = VARYING[owner]
        self.program = self.values.program if owner == "material" else None
        # On a smoke domain or a Volume object (smoke.GridNames): attributes are its grids.
        self.grids = grids if self.program is not None else None
        self.values.grid_names = self.grids
        self.out = Medium()
        self.depth = 0

    def warn(self, node, message):
        self.values.warn(node, message)

    def number(self, node, name, ctx, default=0.0):
        return self.values.value(node, name, ctx, default)

    def color(self, node, name, ctx, default=(1.0, 1.0, 1.0)):
        rgb = self.values.value(node, name, ctx, default, color=True)
        if not np.all(np.isfinite(rgb)):
            self.warn(node, f"'{name}' is not finite; using 0")
            rgb = np.nan_to_num(rgb, nan=0.0, posinf=0.0, neginf=0.0)
        return rgb

    def part(self, node, name, ctx, default, color=False):
        """Input `name` as a Part: a texture's Value (a material's), else its constant (as number/color)."""
        socket = node.inputs.get(name)
        if self.program is not None and socket is not None and self.values.source(socket, ctx)[0] is not None:
            mark = self.program.mark()
            try:
                value = self.program.socket(socket, ctx, "color" if color else "float")
                if value.varying:
                    return Part(np.ones(3) if color else 1.0, value)
            except Unsupported as error:
                self.warn(node, f"'{name}': {error}; using the socket's own value")
            self.program.rewind(mark)
        return Part(self.color(node, name, ctx, default) if color else self.number(node, name, ctx, default))

    def attribute(self, node, name, color=False):
        """Principled Volume's attribute socket `name` (e.g. "Density Attribute") as a Part: the grid it
        names where the object has it, 1 elsewhere (Cycles multiplies only by an attribute it finds);
        1 outside the material of a smoke domain or a Volume object, or where the socket names none."""
        one = Part(np.ones(3) if color else 1.0)
        socket = node.inputs.get(name)
        grid_name = getattr(socket, "default_value", "") or getattr(node, name.lower().replace(" ", "_"), "")
        if self.grids is None or not grid_name:
            return one
        grid = self.grids.slot(grid_name)
        rgb, fac, _ = self.program.emit("grid", [self.program.coordinate("object")], outs=3,
                                        kinds=("color", "float", "float"), data=grid, flags=1, pure=False)
        return Part(one.c, rgb if color else fac)

    def complement(self, part, color=False):
        """1 - part (per channel for a colour), as a Part."""
        if part.v is None:
            return Part(1.0 - part.c)
        one = self.program.constant((1.0, 1.0, 1.0))
        if color:
            zero = self.program.constant((0.0, 0.0, 0.0))
            value = self.program.emit("vector_math", [one, part.v, zero, zero], outs=2, kinds=("color", "float"),
                                      mode=self.program.mode("vector_math", "subtract"))[0]
        else:
            value = self.program.emit("math", [one, part.v, one], mode=self.program.mode("math", "subtract"))[0]
        return Part(np.ones(3) if color else 1.0, value)

    def unit(self, part):
        """`part` clamped to [0, 1] (a Mix Shader's factor, as Cycles clamps it)."""
        if part.v is None:
            return Part(min(max(part.c, 0.0), 1.0))
        zero = self.program.constant(0.0)
        return Part(1.0, self.program.emit("math", [part.v, zero, zero], mode=self.program.mode("math", "add"),
                                           flags=1)[0])

    def add(self, coefficient, rgb, *parts):
        """Adds rgb times the product of `parts` to `coefficient` (sigma_a, sigma_s or emission); returns
        the constant RGB it adds (times the textures' Value where any varies)."""
        rgb = np.asarray(rgb, float)
        value = None
        for p in parts:
            rgb = rgb * p.c
            if p.v is not None:
                value = p.v if value is None else self.product(value, p.v)
        rgb = np.maximum(rgb, 0.0)
        if np.max(rgb) <= 0.0:
            return rgb
        if value is None:
            setattr(self.out, coefficient, getattr(self.out, coefficient) + rgb)
        else:
            self.out.terms.append((coefficient, rgb, value))
        return rgb

    def product(self, a, b):
        """The program Value a * b (per channel)."""
        zero = self.program.constant((0.0, 0.0, 0.0))
        kind = "color" if "color" in (a.kind, b.kind) else "float"
        return self.program.emit("vector_math", [a, b, zero, zero], outs=2, kinds=(kind, "float"),
                                 mode=self.program.mode("vector_math", "multiply"))[0]

    def scatter(self, rgb, phase, *parts):
        added = self.add("sigma_s", rgb, *parts)
        if np.max(added) > 0.0:
            self.out.phases.append((added, phase))

    def closure(self, socket, ctx, weight):
        """Adds what the volume closure on input `socket` contributes, times `weight` (a Part: the Mix
        factors above it)."""
        if socket is None or (weight.v is None and weight.c <= CUTOFF):
            return
        out, ctx, _ = self.values.source(socket, ctx)
        if out is None:
            return
        node = out.node
        handler = SHADERS.get(node.bl_idname)
        if handler is None:
            self.warn(node, f"{node.bl_idname} is not a volume shader (Cycles ignores it in a Volume output); "
                            "left out")
            return
        if self.depth >= MAX_NESTING:
            self.warn(node, f"shaders nested deeper than {MAX_NESTING}; the rest is left out")
            return
        self.depth += 1
        handler(self, node, ctx, weight)
        self.depth -= 1

    def phase(self, node, ctx):
        """The core's phase keywords for a scattering node: its `phase` enum where the version has one."""
        kind, inputs = PHASES.get(getattr(node, "phase", "HENYEY_GREENSTEIN"), PHASES["HENYEY_GREENSTEIN"])
        keywords = {"phase": kind}
        for keyword, socket in inputs:
            keywords[keyword] = self.number(node, socket, ctx)
        if "anisotropy" in keywords:  # Cycles clamps it to +-0.999; the core refuses |g| > 1
            keywords["anisotropy"] = min(max(keywords["anisotropy"], -1.0), 1.0)
        if "diameter" in keywords:
            keywords["diameter"] = min(max(keywords["diameter"], 0.0), 50.0)  # Cycles' range of the fit
        return keywords

    def density(self, node, ctx):
        """The Density input as a Part (Cycles takes max(density, 0); the core counts a negative
        textured value as 0)."""
        d = self.part(node, "Density", ctx, 1.0)
        return d if d.v is not None else Part(max(d.c, 0.0))

    def blackbody(self, node, ctx, weight):
        """Principled Volume's blackbody emission: tint sigma/pi 1e-6 (1 + (T^4 - 1) intensity) times the
        blackbody colour of T = Temperature times the temperature grid where there is one (a term of
        the program then), as Cycles' svm_node_principled_volume."""
        intensity = self.number(node, "Blackbody Intensity", ctx)
        temperature = max(self.number(node, "Temperature", ctx, 1000.0), 0.0)
        if intensity <= CUTOFF or temperature <= 0.0:
            return
        tint = np.maximum(self.color(node, "Blackbody Tint", ctx), 0.0)
        scale = STEFAN_BOLTZMANN * 1e-6 / math.pi
        grid = self.attribute(node, "Temperature Attribute")
        if grid.v is None:
            radiance = scale * (1.0 + (temperature ** 4 - 1.0) * intensity)
            color = blackbody.blackbody_rgb(temperature, blackbody.kernel_rec709_to_scene_linear())  # the kernel's
            self.add("emission", radiance * tint * np.asarray(color), weight)
            return
        self.add("emission", tint, Part(1.0, self.blackbody_radiance(temperature, grid.v, intensity, scale)), weight)

    def blackbody_radiance(self, temperature, grid, intensity, scale):
        """The program Value scale (1 + (T^4 - 1) intensity) blackbody(T), T = temperature max(grid, 0)."""
        p = self.program
        math_mode = lambda name: p.mode("math", name)  # noqa: E731
        zero = p.constant(0.0)
        t = p.emit("math", [grid, zero, zero], mode=math_mode("maximum"))[0]
        t = p.emit("math", [t, p.constant(temperature), zero], mode=math_mode("multiply"))[0]
        t4 = p.emit("math", [t, p.constant(4.0), zero], mode=math_mode("power"))[0]
        radiance = p.emit("math", [t4, p.constant(scale * intensity), p.constant(scale * (1.0 - intensity))],
                          mode=math_mode("multiply_add"))[0]
        offset = len(p.data)
        p.data += blackbody.program_data()
        color = p.emit("blackbody", [t], kinds=("color",), data=offset)[0]
        return self.product(color, radiance)

    def field(self):
        """Scene.add_medium's `program` and `terms` for the terms read ({} when nothing varies)."""
        if not self.out.terms:
            return {}
        terms = []
        for coefficient, rgb, value in self.out.terms:
            try:
                index = self.program.add_output(value)
            except Unsupported as error:
                self.warn(None, f"its Volume: {error}; that part is taken as its constant")
                setattr(self.out, coefficient, getattr(self.out, coefficient) + rgb)
                continue
            terms.append({coefficient: _tuple(rgb), "input": index})
        return {"program": self.program.program(), "terms": terms} if terms else {}


def _mix(reader, node, ctx, weight):
    fac = reader.unit(reader.part(node, "Fac", ctx, 0.5))
    complement = reader.complement(fac)
    for part, socket in ((complement, node.inputs[1]), (fac, node.inputs[2])):
        reader.closure(socket, ctx, _times(reader, weight, part))


def _times(reader, a, b):
    """The Part a * b (floats, or colours)."""
    if a.v is None or b.v is None:
        return Part(a.c * b.c, a.v if b.v is None else b.v)
    return Part(a.c * b.c, reader.product(a.v, b.v))


def _add(reader, node, ctx, weight):
    reader.closure(node.inputs[0], ctx, weight)
    reader.closure(node.inputs[1], ctx, weight)


def _absorption(reader, node, ctx, weight):
    color = reader.part(node, "Color", ctx, (0.8, 0.8, 0.8), color=True)
    reader.add("sigma_a", np.ones(3), reader.complement(color, color=True), reader.density(node, ctx), weight)


def _scatter(reader, node, ctx, weight):
    color = reader.part(node, "Color", ctx, (0.8, 0.8, 0.8), color=True)
    reader.scatter(np.ones(3), reader.phase(node, ctx), color, reader.density(node, ctx), weight)


def _principled(reader, node, ctx, weight):
    density = _times(reader, reader.density(node, ctx), reader.attribute(node, "Density Attribute"))
    color = _times(reader, reader.part(node, "Color", ctx, (0.5, 0.5, 0.5), color=True),
                   reader.attribute(node, "Color Attribute", color=True))
    absorption = reader.color(node, "Absorption Color", ctx, (0.0, 0.0, 0.0))
    reader.scatter(np.ones(3), {"phase": "henyey_greenstein",
                                "anisotropy": min(max(reader.number(node, "Anisotropy", ctx), -1.0), 1.0)},
                   color, density, weight)
    reader.add("sigma_a", np.maximum(1.0 - np.sqrt(np.maximum(absorption, 0.0)), 0.0),
               reader.complement(color, color=True), density, weight)
    reader.add("emission", np.ones(3), reader.part(node, "Emission Strength", ctx, 0.0),
               reader.part(node, "Emission Color", ctx, (1.0, 1.0, 1.0), color=True), weight)
    reader.blackbody(node, ctx, weight)


def _coefficients(reader, node, ctx, weight):
    """Blender 5.0's Volume Coefficients: the coefficients given (negative ones are 0 here)."""
    reader.add("sigma_a", np.ones(3), reader.part(node, "Absorption Coefficients", ctx, (0.0,) * 3, color=True),
               weight)
    reader.scatter(np.ones(3), reader.phase(node, ctx),
                   reader.part(node, "Scatter Coefficients", ctx, (0.0,) * 3, color=True), weight)
    reader.add("emission", np.ones(3), reader.part(node, "Emission Coefficients", ctx, (0.0,) * 3, color=True),
               weight)


def _emission(reader, node, ctx, weight):
    strength = reader.part(node, "Strength", ctx, 1.0)
    reader.add("emission", np.ones(3), strength if strength.v is not None else Part(max(strength.c, 0.0)),
               reader.part(node, "Color", ctx, (1.0, 1.0, 1.0), color=True), weight)


SHADERS = {
    "ShaderNodeMixShader": _mix,
    "ShaderNodeAddShader": _add,
    "ShaderNodeVolumeAbsorption": _absorption,
    "ShaderNodeVolumeScatter": _scatter,
    "ShaderNodeVolumePrincipled": _principled,
    "ShaderNodeVolumeCoefficients": _coefficients,
    "ShaderNodeEmission": _emission,
}


def read(socket, owner, name, warn, core, texture=None, grids=None):
    """add_medium's keywords (without the name) for the Volume `socket` of material or world `name`
    (`owner`: "material" or "world"; `texture` as closure.py's; `grids`: smoke.GridNames where it is
    read for a smoke domain or a Volume object); None when nothing is connected or every coefficient
    is 0."""
    reader = VolumeReader(owner, name, warn, core, texture, grids)
    reader.closure(socket, (), Part(1.0))
    medium = reader.out
    if medium.empty():
        return None
    field = reader.field()
    keywords = {"sigma_a": _tuple(medium.sigma_a), "sigma_s": _tuple(medium.sigma_s),
                "emission": _tuple(medium.emission), **field}
    keywords.update(_one_phase(reader, medium.phases))
    # A material's emitting medium is a light (the core emits photons from the closed mesh it fills);
    # the World's fills infinite space, whose power the core cannot emit.
    if owner == "world" and np.max(medium.emission) > 0.0:  # (the World's has no terms)
        reader.warn(None, "its Volume emits light, which is seen along rays but lights nothing else (the World's "
                          "medium fills infinite space and emits no photons): darker than in Cycles")
    return keywords


def _one_phase(reader, phases):
    """The core's one phase function for the scattering shaders read."""
    distinct = {tuple(sorted(p.items())) for _, p in phases}
    if len(distinct) <= 1:
        return phases[0][1] if phases else {}
    weights = np.array([float(np.mean(s)) for s, _ in phases])
    mean = sum(w * _mean_cosine(p) for w, (_, p) in zip(weights, phases)) / weights.sum()
    reader.warn(None, "its Volume mixes scattering with different phase functions, which the core cannot yet; "
                      f"rendered with one Henyey-Greenstein of their mean anisotropy {mean:.3g}")
    return {"phase": "henyey_greenstein", "anisotropy": float(mean)}


def _mean_cosine(phase):
    """A phase function's mean cosine where it is its anisotropy (Henyey-Greenstein, and about so for
    Draine and the rest); 0 for Rayleigh."""
    return phase.get("anisotropy", 0.0) if phase["phase"] in ("henyey_greenstein", "draine") else 0.0


def _tuple(rgb):
    return tuple(float(c) for c in rgb)


def volume_socket(tree, output_type):
    """The Volume input of the active output node of `tree` (ShaderNodeOutputMaterial or
    ShaderNodeOutputWorld) when something drives it, else None."""
    output = nodes.active_output(tree, output_type)
    socket = output.inputs.get("Volume") if output is not None else None
    return socket if unrendered.output_driven(socket) else None


def surface_driven(tree):
    """Whether anything drives the Surface of a material tree's active output."""
    output = nodes.active_output(tree, "ShaderNodeOutputMaterial")
    return output is not None and unrendered.output_driven(output.inputs["Surface"])


def material_medium(material, warn, core, texture=None, grids=None):
    """add_medium's keywords for `material`'s Volume output (with `grids` as read()'s), or None."""
    if not nodes.uses_nodes(material):
        return None
    socket = volume_socket(material.node_tree, "ShaderNodeOutputMaterial")
    return read(socket, "material", material.name, warn, core, texture, grids) if socket is not None else None


def add(core, name, keywords, warn):
    """Adds the medium of `keywords` (add_medium's; None: none) to `core` under `name`, or under the
    first of "name (2)", "name (3)"... still free (the viewport adds a world's medium again after each
    edit); returns the name used, or None (a medium the core refuses is left out, warned)."""
    if keywords is None:
        return None
    taken, unique, n = set(core.media), name, 1
    while unique in taken:
        n += 1
        unique = f"{name} ({n})"
    try:
        core.add_medium(unique, **keywords)
    except ValueError as error:
        warn(f"{name}: its Volume is not rendered ({error}); the air inside is clear")
        return None
    return unique


def world_medium(world, warn, core):
    """add_medium's keywords for `world`'s Volume output, or None."""
    if world is None or not nodes.uses_nodes(world):
        return None
    socket = volume_socket(world.node_tree, "ShaderNodeOutputWorld")
    return read(socket, "world", world.name, warn, core) if socket is not None else None
