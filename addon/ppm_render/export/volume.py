"""A material's or the world's Volume output -> the core's homogeneous medium (Scene.add_medium).

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

The core's media are homogeneous for now: a socket driven by a texture or an attribute (a density
that varies in space, a Noise cloud) takes its own value, with one warning naming the material and
node. Principled Volume's Density and Temperature Attributes multiply only on Volume objects and
smoke domains, which the export leaves out (warned there), so on a mesh they are 1, as in Cycles.
A medium's emission is seen along the rays through it but lights nothing yet (warned). Where
scattering shaders with different phase functions mix, the core takes one: the
Henyey-Greenstein of their scattering-weighted mean anisotropy (warned; Cycles samples each).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import blackbody, nodes, unrendered
from .closure import ClosureReader

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
VARYING = "varies in space (a texture or an attribute drives it): heterogeneous media are not rendered yet"


@dataclass
class Medium:
    """Coefficients per Blender unit, summed over the volume shaders read."""
    sigma_a: np.ndarray = field(default_factory=lambda: np.zeros(3))
    sigma_s: np.ndarray = field(default_factory=lambda: np.zeros(3))
    emission: np.ndarray = field(default_factory=lambda: np.zeros(3))
    phases: list = field(default_factory=list)  # (sigma_s part, phase keywords) per scattering shader

    def empty(self):
        return max(np.max(self.sigma_a), np.max(self.sigma_s), np.max(self.emission)) <= 0.0

    def scatter(self, sigma_s, phase):
        if np.max(sigma_s) > 0.0:
            self.sigma_s += sigma_s
            self.phases.append((sigma_s, phase))


class VolumeReader:
    """Reads one Volume socket; warnings name the material (or world) and node, each once."""

    def __init__(self, owner, name, warn, core):
        self.values = ClosureReader(name, warn, None, core, kind=owner)
        self.values.varying_note = VARYING
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

    def closure(self, socket, ctx, weight):
        """Adds what the volume closure on input `socket` contributes, times `weight` (a Mix factor)."""
        if socket is None or weight <= CUTOFF:
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

    def density(self, node, ctx, weight):
        return weight * max(self.number(node, "Density", ctx, 1.0), 0.0)


def _mix(reader, node, ctx, weight):
    fac = min(max(reader.number(node, "Fac", ctx, 0.5), 0.0), 1.0)
    reader.closure(node.inputs[1], ctx, weight * (1.0 - fac))
    reader.closure(node.inputs[2], ctx, weight * fac)


def _add(reader, node, ctx, weight):
    reader.closure(node.inputs[0], ctx, weight)
    reader.closure(node.inputs[1], ctx, weight)


def _absorption(reader, node, ctx, weight):
    color = reader.color(node, "Color", ctx, (0.8, 0.8, 0.8))
    reader.out.sigma_a += np.maximum(1.0 - color, 0.0) * reader.density(node, ctx, weight)


def _scatter(reader, node, ctx, weight):
    color = np.maximum(reader.color(node, "Color", ctx, (0.8, 0.8, 0.8)), 0.0)
    reader.out.scatter(color * reader.density(node, ctx, weight), reader.phase(node, ctx))


def _principled(reader, node, ctx, weight):
    density = reader.density(node, ctx, weight)
    color = reader.color(node, "Color", ctx, (0.5, 0.5, 0.5))
    absorption = reader.color(node, "Absorption Color", ctx, (0.0, 0.0, 0.0))
    reader.out.scatter(np.maximum(color, 0.0) * density,
                       {"phase": "henyey_greenstein",
                        "anisotropy": min(max(reader.number(node, "Anisotropy", ctx), -1.0), 1.0)})
    reader.out.sigma_a += (np.maximum(1.0 - color, 0.0) * np.maximum(1.0 - np.sqrt(np.maximum(absorption, 0.0)), 0.0)
                           * density)
    strength = reader.number(node, "Emission Strength", ctx)
    reader.out.emission += weight * strength * np.maximum(reader.color(node, "Emission Color", ctx), 0.0)
    intensity = reader.number(node, "Blackbody Intensity", ctx)
    temperature = max(reader.number(node, "Temperature", ctx, 1000.0), 0.0)
    if intensity > CUTOFF and temperature > 0.0:
        radiance = STEFAN_BOLTZMANN * 1e-6 / math.pi * (1.0 + (temperature ** 4 - 1.0) * intensity)
        tint = np.maximum(reader.color(node, "Blackbody Tint", ctx), 0.0)
        color = blackbody.blackbody_rgb(temperature, blackbody.kernel_rec709_to_scene_linear())  # the kernel's
        reader.out.emission += weight * radiance * tint * np.asarray(color)


def _coefficients(reader, node, ctx, weight):
    """Blender 5.0's Volume Coefficients: the coefficients given (negative ones are 0 here)."""
    reader.out.sigma_a += weight * np.maximum(reader.color(node, "Absorption Coefficients", ctx), 0.0)
    reader.out.scatter(weight * np.maximum(reader.color(node, "Scatter Coefficients", ctx), 0.0),
                       reader.phase(node, ctx))
    reader.out.emission += weight * np.maximum(reader.color(node, "Emission Coefficients", ctx, (0.0, 0.0, 0.0)), 0.0)


def _emission(reader, node, ctx, weight):
    color = np.maximum(reader.color(node, "Color", ctx), 0.0)
    reader.out.emission += weight * max(reader.number(node, "Strength", ctx, 1.0), 0.0) * color


SHADERS = {
    "ShaderNodeMixShader": _mix,
    "ShaderNodeAddShader": _add,
    "ShaderNodeVolumeAbsorption": _absorption,
    "ShaderNodeVolumeScatter": _scatter,
    "ShaderNodeVolumePrincipled": _principled,
    "ShaderNodeVolumeCoefficients": _coefficients,
    "ShaderNodeEmission": _emission,
}


def read(socket, owner, name, warn, core):
    """add_medium's keywords (without the name) for the Volume `socket` of material or world `name`
    (`owner`: "material" or "world"); None when nothing is connected or every coefficient is 0."""
    reader = VolumeReader(owner, name, warn, core)
    reader.closure(socket, (), 1.0)
    medium = reader.out
    if medium.empty():
        return None
    keywords = {"sigma_a": _tuple(medium.sigma_a), "sigma_s": _tuple(medium.sigma_s),
                "emission": _tuple(medium.emission)}
    keywords.update(_one_phase(reader, medium.phases))
    # A material's emitting medium is a light (the core emits photons from the closed mesh it fills);
    # the World's fills infinite space, whose power the core cannot emit.
    if owner == "world" and np.max(medium.emission) > 0.0:
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


def material_medium(material, warn, core):
    """add_medium's keywords for `material`'s Volume output, or None."""
    if not nodes.uses_nodes(material):
        return None
    socket = volume_socket(material.node_tree, "ShaderNodeOutputMaterial")
    return read(socket, "material", material.name, warn, core) if socket is not None else None


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
