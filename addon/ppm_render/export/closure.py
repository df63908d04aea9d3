"""A material's node tree as the core's mixture: weighted lobes.

Walks from the active Material Output's Surface through Mix Shader and Add Shader nodes, node
groups (nested, their inputs' defaults), reroutes and muted nodes (passed through as Blender does),
folding every constant factor into the lobes' weights and dropping branches of weight zero. A
socket's value is its own, or that of the group input or the Value/RGB node feeding it; any other
node driving it counts as the socket's own value with one warning (texture and utility nodes are
the Materials II issue), except an Image Texture on a colour, which becomes the material's texture
(one per material). The Principled BSDF is layered as Cycles layers it (see `principled_v2`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import nodes

MAX_DEPTH = 256  # links followed from one socket: a deeper chain is a cycle through node groups
MAX_LOBES = 8  # the core's limit
MAX_NESTING = 64  # Mix and Add shaders inside each other
CUTOFF = 1e-6  # Cycles drops closures of smaller weight too (CLOSURE_WEIGHT_CUTOFF)


@dataclass
class Closure:
    lobes: list = field(default_factory=list)  # dicts for Scene.add_material(lobes=...)
    emission: np.ndarray = field(default_factory=lambda: np.zeros(3))
    holdout: float = 0.0
    image: object = None  # the bpy image its textured lobes multiply their colours by

    def add(self, weight, **lobe):
        if float(np.max(weight)) > CUTOFF:
            self.lobes.append({"weight": tuple(float(c) for c in weight), **lobe})


def _rgb(value):
    try:
        return np.array(tuple(value)[:3], dtype=float)
    except TypeError:
        return np.full(3, float(value))


class ClosureReader:
    """Reads one material's surface closure; `warn` gets each problem once, naming material and node."""

    def __init__(self, material_name, warn):
        self.material, self.warn_once = material_name, warn
        self.warned = set()
        self.out = Closure()
        self.depth = 0  # Mix and Add shaders entered

    def warn(self, node, message):
        key = (node.name if node is not None else "", message)
        if key not in self.warned:
            self.warned.add(key)
            where = f"node '{node.name}'" if node is not None else "its node tree"
            self.warn_once(f"material '{self.material}': {where}: {message}")

    # ------------------------------------------------------------ following links

    def source(self, socket, ctx=()):
        """(output socket, its group context, the last input socket reached) for an input socket:
        through reroutes, muted nodes, node groups and group inputs. The output is None when nothing
        drives the socket: its value is then the last input's own."""
        for _ in range(MAX_DEPTH):
            links = [link for link in socket.links if nodes.link_renders(link)]
            if not links:
                return None, ctx, socket
            out = links[0].from_socket
            node = out.node
            if node.bl_idname == "NodeReroute":
                socket = node.inputs[0]
            elif node.mute:
                through = [link for link in node.internal_links if link.to_socket == out]
                if not through:
                    return None, ctx, socket
                socket = through[0].from_socket
            elif node.bl_idname == "ShaderNodeGroup":
                entered = self.enter_group(node, out, ctx)
                if entered is None:
                    return None, ctx, socket
                socket, ctx = entered
            elif node.bl_idname == "NodeGroupInput":
                if not ctx:
                    return None, ctx, socket
                socket, ctx = _matching(ctx[-1].inputs, out), ctx[:-1]
                if socket is None:
                    return None, ctx, socket
            else:
                return out, ctx, socket
        self.warn(socket.node, "its links form a cycle (through node groups); left out")
        return None, ctx, socket

    def enter_group(self, group, out, ctx):
        """The group output's input that `out` of `group` shows, and the context inside; None if the
        group is missing, empty or contains itself."""
        tree = group.node_tree
        if tree is None:
            self.warn(group, "its node group is missing; left out")
            return None
        if any(g.node_tree == tree for g in ctx) or len(ctx) > 32:
            self.warn(group, f"node group '{tree.name}' contains itself; left out")
            return None
        outputs = [n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"]
        active = [n for n in outputs if n.is_active_output] or outputs
        socket = _matching(active[0].inputs, out) if active else None
        return (socket, ctx + (group,)) if socket is not None else None

    # ------------------------------------------------------------ values

    def value(self, node, name, ctx, default=0.0, color=False):
        """The value of input `name` of `node` (a float, or an RGB array with color)."""
        socket = node.inputs.get(name)
        if socket is None:
            return _rgb(default) if color else float(default)
        out, _, last = self.source(socket, ctx)
        if out is None:
            raw = last.default_value if hasattr(last, "default_value") else default
        elif out.node.bl_idname in ("ShaderNodeValue", "ShaderNodeRGB"):
            raw = out.default_value
        else:
            self.warn(node, f"'{name}' is driven by '{out.node.name}' ({out.node.bl_idname}), which is not "
                            "supported yet; using the socket's own value")
            raw = socket.default_value
        if color:
            return _rgb(raw)  # not finite or out of range: clamped with the material's one warning
        return _finite(float(np.mean(_rgb(raw))) if _is_vector(raw) else float(raw), node, name, self)

    def color(self, node, name, ctx, default=(0.8, 0.8, 0.8)):
        """(rgb, textured): an Image Texture's Color on the socket makes the lobe textured."""
        socket = node.inputs.get(name)
        if socket is not None:
            out, _, _ = self.source(socket, ctx)
            if out is not None and out.node.bl_idname == "ShaderNodeTexImage" and out.node.image is not None:
                image = out.node.image
                if self.out.image in (None, image):
                    self.out.image = image
                    return np.ones(3), True
                self.warn(node, f"a second image texture ('{image.name}') in one material is not supported yet; "
                                "using the socket's own colour")
                return _rgb(socket.default_value), False
        return self.value(node, name, ctx, default, color=True), False

    # ------------------------------------------------------------ closures

    def closure(self, socket, ctx, weight):
        """Adds what the closure on input `socket` contributes, times `weight` (RGB)."""
        if socket is None or float(np.max(weight)) <= CUTOFF:
            return
        out, ctx, _ = self.source(socket, ctx)
        if out is None:
            return  # nothing connected: black, as in Cycles
        node = out.node
        handler = SHADERS.get(node.bl_idname)
        if handler is None:
            self.warn(node, f"{node.bl_idname} is not supported yet; rendered as grey diffuse")
            self.out.add(weight, kind="diffuse", color=(0.8, 0.8, 0.8))
            return
        if self.depth >= MAX_NESTING:  # Blender invalidates cyclic links; this guards against the rest
            self.warn(node, f"shaders nested deeper than {MAX_NESTING}; the rest is left out")
            return
        self.depth += 1
        handler(self, node, ctx, np.asarray(weight, dtype=float))
        self.depth -= 1


def _matching(sockets, socket):
    """The socket of `sockets` with `socket`'s identifier (group node <-> group input/output)."""
    for s in sockets:
        if s.identifier == socket.identifier:
            return s
    return None


def _is_vector(raw):
    try:
        len(raw)
        return True
    except TypeError:
        return False


def _finite(value, node, name, reader):
    if math.isfinite(value):
        return value
    reader.warn(node, f"'{name}' is not a finite number; using 0")
    return 0.0


# ---------------------------------------------------------------- shader nodes

def _mix(reader, node, ctx, w):
    fac = min(max(reader.value(node, "Fac", ctx, 0.5), 0.0), 1.0)
    reader.closure(node.inputs[1], ctx, w * (1.0 - fac))
    reader.closure(node.inputs[2], ctx, w * fac)


def _add(reader, node, ctx, w):
    reader.closure(node.inputs[0], ctx, w)
    reader.closure(node.inputs[1], ctx, w)


def _roughness(reader, node, ctx, name="Roughness", default=0.5):
    return min(max(reader.value(node, name, ctx, default), 0.0), 1.0)


def _multiscatter(node):
    """Whether the node's microfacet distribution restores multiple scattering's energy (Cycles'
    Multiscatter GGX, the default of the Principled, Glossy and Metallic BSDFs from Blender 4.0)."""
    return getattr(node, "distribution", "GGX") == "MULTI_GGX"


def _diffuse(reader, node, ctx, w):
    color, textured = reader.color(node, "Color", ctx)
    reader.out.add(w, kind="diffuse", color=tuple(color), textured=textured)


def _translucent(reader, node, ctx, w):
    color, textured = reader.color(node, "Color", ctx)
    reader.out.add(w, kind="translucent", color=tuple(color), textured=textured)


def _transparent(reader, node, ctx, w):
    reader.out.add(w, kind="transparent", color=tuple(reader.value(node, "Color", ctx, 1.0, color=True)))


def _glossy(reader, node, ctx, w):
    color, textured = reader.color(node, "Color", ctx, (1.0, 1.0, 1.0))
    if reader.value(node, "Anisotropy", ctx, 0.0) != 0.0 or reader.value(node, "Anisotropic", ctx, 0.0) != 0.0:
        reader.warn(node, "anisotropy is not supported yet; rendered isotropic")
    reader.out.add(w, kind="glossy", color=tuple(color), textured=textured, multiscatter=_multiscatter(node),
                   roughness=_roughness(reader, node, ctx, default=0.5))


def _metallic(reader, node, ctx, w):
    if getattr(node, "fresnel_type", "F82") != "F82":
        reader.warn(node, "the physical conductor (IOR and extinction) is not supported yet; using Base Color "
                          "and Edge Tint")
    color, textured = reader.color(node, "Base Color", ctx)
    tint = reader.value(node, "Edge Tint", ctx, 1.0, color=True)
    reader.out.add(w, kind="conductor", color=tuple(np.clip(color, 0.0, 1.0)), tint=tuple(np.clip(tint, 0.0, 1.0)),
                   textured=textured, multiscatter=_multiscatter(node), roughness=_roughness(reader, node, ctx))


def _glass(reader, node, ctx, w, parts="both"):
    color, textured = reader.color(node, "Color", ctx, (1.0, 1.0, 1.0))
    ior = max(reader.value(node, "IOR", ctx, 1.45), 1e-5)
    reader.out.add(w, kind="dielectric", parts=parts, color=tuple(color), tint=tuple(color), textured=textured,
                   ior=ior, roughness=_roughness(reader, node, ctx, default=0.0))


def _refraction(reader, node, ctx, w):
    _glass(reader, node, ctx, w, parts="refraction")


def _emission(reader, node, ctx, w):
    color = reader.value(node, "Color", ctx, 1.0, color=True)
    reader.out.emission += w * color * reader.value(node, "Strength", ctx, 1.0)


def _holdout(reader, node, ctx, w):
    reader.out.holdout += float(np.mean(w))


def _as_diffuse(what):
    def handler(reader, node, ctx, w):
        reader.warn(node, f"{what} is rendered as diffuse in its colour")
        color, textured = reader.color(node, "Color", ctx) if "Color" in node.inputs else reader.color(
            node, "Base Color", ctx)
        reader.out.add(w, kind="diffuse", color=tuple(color), textured=textured)
    return handler


def _left_out(what):
    def handler(reader, node, ctx, w):
        reader.warn(node, f"{what} is not supported; left out")
    return handler


def f0_from_ior(ior):
    return ((ior - 1.0) / (ior + 1.0)) ** 2


def ior_from_f0(f0):
    root = math.sqrt(min(max(f0, 0.0), 0.999999))
    return (1.0 + root) / (1.0 - root)


def _alpha(reader, node, ctx, w):
    """The Principled BSDF's Alpha, applied first as Cycles does: a transparent lobe of 1 - alpha;
    the weight left for the rest."""
    alpha = min(max(reader.value(node, "Alpha", ctx, 1.0), 0.0), 1.0)
    if alpha < 1.0:
        reader.out.add(w * (1.0 - alpha), kind="transparent", color=(1.0, 1.0, 1.0))
    return w * alpha


def principled_v2(reader, node, ctx, w):
    """Cycles' Principled BSDF of Blender 4.0 and later, top to bottom: alpha (transparency), sheen
    (not yet: warned), coat (a dielectric layer, its tint at normal incidence), emission, metal (F82
    tint conductor), transmission (glass, tinted by the square root of the base colour at each
    crossing), the dielectric specular layer (IOR scaled by IOR Level, tinted by Specular Tint), and
    diffuse (subsurface as diffuse). Each layer takes its share of the weight below it as Cycles does."""
    v = lambda name, default=0.0: reader.value(node, name, ctx, default)  # noqa: E731
    base, textured = reader.color(node, "Base Color", ctx)
    roughness = _roughness(reader, node, ctx)
    w = _alpha(reader, node, ctx, w)
    if v("Sheen Weight") > CUTOFF:
        reader.warn(node, "sheen is not supported yet; left out")
    if v("Anisotropic") > 0.0:
        reader.warn(node, "anisotropy is not supported yet; rendered isotropic")
    coat = max(v("Coat Weight"), 0.0)
    if coat > CUTOFF:
        coat_roughness = _roughness(reader, node, ctx, "Coat Roughness", 0.03)
        reader.out.add(w, kind="dielectric", parts="reflection", layer=True, tint=(coat,) * 3,
                       ior=max(v("Coat IOR", 1.5), 1.0), roughness=coat_roughness)
        tint = np.clip(reader.value(node, "Coat Tint", ctx, 1.0, color=True), 0.0, None)
        w = w * (1.0 + coat * (tint - 1.0))
    emission = reader.value(node, "Emission Color", ctx, 1.0, color=True) * v("Emission Strength", 0.0)
    # The coat's attenuation of emission depends on the view; here its value at normal incidence.
    reader.out.emission += w * emission * (1.0 - coat * f0_from_ior(max(v("Coat IOR", 1.5), 1.0)))
    metallic = min(max(v("Metallic"), 0.0), 1.0)
    if metallic > CUTOFF:
        f82 = np.clip(reader.value(node, "Specular Tint", ctx, 1.0, color=True), 0.0, 1.0)
        reader.out.add(w * metallic, kind="conductor", color=tuple(np.clip(base, 0.0, 1.0)), tint=tuple(f82),
                       textured=textured, multiscatter=_multiscatter(node), roughness=roughness)
        w = w * (1.0 - metallic)
    ior = max(v("IOR", 1.5), 1e-5)
    specular_tint = np.clip(reader.value(node, "Specular Tint", ctx, 1.0, color=True), 0.0, None)
    transmission = min(max(v("Transmission Weight"), 0.0), 1.0)
    if transmission > CUTOFF:
        reader.out.add(w * transmission, kind="dielectric", color=tuple(np.sqrt(np.clip(base, 0.0, 1.0))),
                       tint=tuple(specular_tint), tint_f0=True, textured=textured, ior=ior, roughness=roughness)
        w = w * (1.0 - transmission)
    level = max(v("Specular IOR Level", 0.5), 0.0)
    eta = ior if level == 0.5 else ior_from_f0(f0_from_ior(ior) * 2.0 * level)
    if abs(eta - 1.0) > 1e-6:
        reader.out.add(w, kind="dielectric", parts="reflection", layer=True, tint=tuple(specular_tint),
                       tint_f0=True, multiscatter=_multiscatter(node), ior=eta if eta > 1.0 else 1.0 / eta,
                       roughness=roughness)
    if v("Subsurface Weight") > CUTOFF:
        reader.warn(node, "subsurface scattering is rendered as diffuse in the base colour")
    reader.out.add(w, kind="diffuse", color=tuple(base), textured=textured)


def principled_v1(reader, node, ctx, w):
    """Cycles' Principled BSDF of Blender 3.x: diffuse (1 - transmission)(1 - metallic) of the base
    colour; a specular lobe of weight 1 - transmission (1 - metallic), added on top (not layered, as
    in 3.x), of Fresnel F0 between 0.08 * Specular (tinted towards the base colour by Specular Tint)
    and the base colour by Metallic; glass for transmission (1 - metallic); a clearcoat lobe of
    weight 0.25 * Clearcoat; emission."""
    v = lambda name, default=0.0: reader.value(node, name, ctx, default)  # noqa: E731
    base, textured = reader.color(node, "Base Color", ctx)
    roughness = _roughness(reader, node, ctx)
    w = _alpha(reader, node, ctx, w)
    if v("Sheen") > CUTOFF:
        reader.warn(node, "sheen is not supported yet; left out")
    metallic = min(max(v("Metallic"), 0.0), 1.0)
    diffuse = (1.0 - metallic) * (1.0 - min(max(v("Transmission"), 0.0), 1.0))
    transmission = min(max(v("Transmission"), 0.0), 1.0) * (1.0 - metallic)
    reader.out.emission += w * reader.value(node, "Emission", ctx, 0.0, color=True) * v("Emission Strength", 1.0)
    if v("Subsurface") > CUTOFF:
        reader.warn(node, "subsurface scattering is rendered as diffuse in the base colour")
    reader.out.add(w * diffuse, kind="diffuse", color=tuple(base), textured=textured)
    lum = float(np.dot(base, (0.3, 0.6, 0.1)))
    hue = base / lum if lum > 0.0 else np.ones(3)
    tint = min(max(v("Specular Tint"), 0.0), 1.0)
    dielectric_f0 = 0.08 * max(v("Specular", 0.5), 0.0) * (1.0 - tint + tint * hue)
    f0 = (1.0 - metallic) * dielectric_f0 + metallic * np.clip(base, 0.0, 1.0)
    reader.out.add(w * (1.0 - transmission), kind="conductor", color=tuple(np.clip(f0, 0.0, 1.0)),
                   multiscatter=_multiscatter(node), roughness=roughness)
    if transmission > CUTOFF:
        reader.out.add(w * transmission, kind="dielectric", color=tuple(base), tint=(1.0, 1.0, 1.0),
                       ior=max(v("IOR", 1.45), 1e-5), roughness=roughness)
    clearcoat = max(v("Clearcoat"), 0.0)
    if clearcoat > CUTOFF:
        reader.out.add(w * 0.25 * clearcoat, kind="dielectric", parts="reflection", ior=1.5,
                       roughness=_roughness(reader, node, ctx, "Clearcoat Roughness", 0.03))


def _principled(reader, node, ctx, w):
    (principled_v2 if node.inputs.get("Coat Weight") is not None else principled_v1)(reader, node, ctx, w)


SHADERS = {
    "ShaderNodeMixShader": _mix,
    "ShaderNodeAddShader": _add,
    "ShaderNodeBsdfPrincipled": _principled,
    "ShaderNodeBsdfDiffuse": _diffuse,
    "ShaderNodeBsdfTranslucent": _translucent,
    "ShaderNodeBsdfTransparent": _transparent,
    "ShaderNodeBsdfGlossy": _glossy,
    "ShaderNodeBsdfAnisotropic": _glossy,
    "ShaderNodeBsdfMetallic": _metallic,
    "ShaderNodeBsdfGlass": _glass,
    "ShaderNodeBsdfRefraction": _refraction,
    "ShaderNodeEmission": _emission,
    "ShaderNodeHoldout": _holdout,
    "ShaderNodeSubsurfaceScattering": _as_diffuse("subsurface scattering"),
    "ShaderNodeBsdfSheen": _left_out("the Sheen BSDF (not yet)"),
    "ShaderNodeBsdfVelvet": _left_out("the Velvet BSDF (not yet)"),
    "ShaderNodeBsdfToon": _as_diffuse("the Toon BSDF"),
    "ShaderNodeBsdfHair": _left_out("a hair BSDF"),
    "ShaderNodeBsdfHairPrincipled": _left_out("a hair BSDF"),
    "ShaderNodeBackground": _left_out("a Background shader in a material"),
    "ShaderNodeVolumeAbsorption": _left_out("a volume shader on a surface"),
    "ShaderNodeVolumeScatter": _left_out("a volume shader on a surface"),
    "ShaderNodeVolumePrincipled": _left_out("a volume shader on a surface"),
    "ShaderNodeBsdfRayPortal": _left_out("the Ray Portal BSDF"),
}


def read_surface(material, warn):
    """The closure of `material`'s active surface output (None if it has no node tree in use)."""
    if not nodes.uses_nodes(material):
        return None
    outputs = [n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    active = ([n for n in outputs if n.is_active_output and n.target in ("ALL", "CYCLES")] or
              [n for n in outputs if n.is_active_output] or outputs)
    if not active:
        return None
    reader = ClosureReader(material.name, warn)
    reader.closure(active[0].inputs["Surface"], (), np.ones(3))
    lobes = reader.out.lobes
    if len(lobes) > MAX_LOBES:
        reader.warn(None, f"{len(lobes)} shader lobes; the {MAX_LOBES} of largest weight are kept")
        kept = sorted(sorted(range(len(lobes)), key=lambda i: -max(lobes[i]["weight"]))[:MAX_LOBES])
        reader.out.lobes = [lobes[i] for i in kept]  # in their order: a layer stays above what it covers
    return reader.out
