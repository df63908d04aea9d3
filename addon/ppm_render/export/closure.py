"""A material's node tree as the core's mixture: weighted lobes.

Walks from the active Material Output's Surface through Mix Shader and Add Shader nodes, node
groups (nested, their inputs' defaults), reroutes and muted nodes (passed through as Blender does),
folding every constant factor into the lobes' weights and dropping branches of weight zero. A
socket's value is its own, or what the texture and utility nodes driving it compute: a constant
network is folded at export, any other is compiled into the material's node program
(node_program.py), whose outputs are the material's inputs. A colour, a roughness, a Mix Shader's
factor, the Principled BSDF's Base Color, Roughness, Metallic, Transmission Weight or Alpha, an
emission colour and the shaders' Normal can be driven that way (up to 8 inputs per material; a
lobe parameter is its constant times an input, a weight takes up to two textured factors); other
sockets take a network's value only when it is constant (warned otherwise). The Principled BSDF
is layered as Cycles layers it (see `principled_v2`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import bpy
import numpy as np

from . import nodes, unrendered
from .node_program import ProgramCompiler, Unsupported

MAX_LOBES = 8  # the core's limit
MAX_WEIGHT_INPUTS = 2  # the core's limit of textured factors per lobe weight
MAX_NESTING = 64  # Mix and Add shaders inside each other
CUTOFF = 1e-6  # Cycles drops closures of smaller weight too (CLOSURE_WEIGHT_CUTOFF)


@dataclass(frozen=True)
class Weight:
    """A closure's weight: an RGB constant times textured factors ((input index, 'fraction' or
    'complement'), as the core's weight_inputs), the Mix Shader factors and Principled weights that
    an image drives."""
    rgb: np.ndarray
    factors: tuple = ()

    def __mul__(self, other):
        return Weight(self.rgb * other, self.factors)

    def times_input(self, index, transform):
        return Weight(self.rgb, self.factors + ((index, transform),))

    def peak(self):
        return float(np.max(self.rgb))


@dataclass
class Closure:
    lobes: list = field(default_factory=list)  # dicts for Scene.add_material(lobes=...)
    emission: np.ndarray = field(default_factory=lambda: np.zeros(3))
    holdout: float = 0.0
    program: dict = None  # for Scene.add_material(program=...): computes the inputs
    # Per input: the core texture it is, when it is an image's colour read at the UV, else None
    simple_images: list = field(default_factory=list)
    normal_map: dict = None  # for Scene.add_material(normal_map=...): input, space
    unmapped: bool = False  # a shader without the normal map (it applies to all of them)
    tangents: str = None  # what the meshes' tangents must be: "uv", or "radial_x" / "_y" / "_z" (generated)
    attribute: str = None  # the mesh attribute its program reads ("": the render colour attribute)
    emission_input: int = None  # the input the emission is textured by
    emission_parts: int = 0  # emissions added (a textured one applies its texture to all, warned)

    def add(self, weight, **lobe):
        if weight.peak() > CUTOFF:
            lobe = {key: value for key, value in lobe.items() if value is not None}  # no input: constant
            if weight.factors:
                lobe["weight_inputs"] = list(weight.factors)
            self.lobes.append({"weight": tuple(float(c) for c in weight.rgb), **lobe})


def _rgb(value):
    try:
        return np.array(tuple(value)[:3], dtype=float)
    except TypeError:
        return np.full(3, float(value))


class ClosureReader:
    """Reads one material's surface closure; `warn` gets each problem once, naming material and node."""

    def __init__(self, material_name, warn, texture=None, core=None, kind="material", attributes=None):
        self.material, self.warn_once, self.kind = material_name, warn, kind
        self.attributes = attributes  # object_info.AttributeTable, if the export has objects
        self.warned = set()
        self.out = Closure()
        self.depth = 0  # Mix and Add shaders entered
        self.normal_node = None  # the shader whose Normal is the material's normal map
        self.program = ProgramCompiler(self, texture, core) if core is not None else None
        # What a warning says of a socket that takes only constants when a texture drives it
        self.varying_note = "is driven by a texture, which is not supported for it"
        self.grid_names = None  # smoke.GridNames where Attribute nodes read grids (volume.py)

    def warn(self, node, message):
        key = (node.name if node is not None else "", message)
        if key not in self.warned:
            self.warned.add(key)
            where = f"node '{node.name}'" if node is not None else "its node tree"
            self.warn_once(f"{self.kind} '{self.material}': {where}: {message}")

    # ------------------------------------------------------------ following links

    def source(self, socket, ctx=()):
        """(output socket, its group context, the last input socket reached) for an input socket:
        through reroutes, muted nodes, node groups and group inputs. The output is None when nothing
        drives the socket: its value is then the last input's own."""
        visited = set()  # (socket, group context) pairs: a repeat is a cycle
        while (place := (socket.as_pointer(), tuple(g.as_pointer() for g in ctx))) not in visited:
            visited.add(place)
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
        self.warn(socket.node, "its links form a cycle (through node groups); left out")  # Blender allows none
        return None, ctx, socket

    def enter_group(self, group, out, ctx):
        """The group output's input that `out` of `group` shows, and the context inside; None if the
        group is missing, empty or contains itself."""
        tree = group.node_tree
        if tree is None:
            self.warn(group, "its node group is missing; left out")
            return None
        if any(g.node_tree == tree for g in ctx):  # however deep groups nest, only this is a cycle
            self.warn(group, f"node group '{tree.name}' contains itself; left out")
            return None
        outputs = [n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"]
        active = [n for n in outputs if n.is_active_output] or outputs
        socket = _matching(active[0].inputs, out) if active else None
        return (socket, ctx + (group,)) if socket is not None else None

    # ------------------------------------------------------------ values

    def value(self, node, name, ctx, default=0.0, color=False):
        """The value of input `name` of `node` (a float, or an RGB array with color): its own, or a
        constant network's; a varying network counts as the socket's own value, warned."""
        socket = node.inputs.get(name)
        if socket is None:
            return _rgb(default) if color else float(default)
        out, _, last = self.source(socket, ctx)
        if out is None:
            raw = last.default_value if hasattr(last, "default_value") else default
        elif out.node.bl_idname in ("ShaderNodeValue", "ShaderNodeRGB"):
            raw = out.default_value
        else:
            raw = self.driven(node, name, ctx, "color" if color else "float", varying=False)
            if raw is None:
                raw = socket.default_value
        if color:
            return _rgb(raw)  # not finite or out of range: clamped with the material's one warning
        return _finite(float(np.mean(_rgb(raw))) if _is_vector(raw) else float(raw), node, name, self)

    def driven(self, node, name, ctx, kind, varying=True):
        """What a node network computes for input `name` of `node`: a constant (an RGB array, or a
        float for kind 'float'), or the index of the material input (a program output) computing it
        per shading point; None when nothing drives the socket or the network cannot be taken (its
        own value counts, warned), or (varying=False) the network is not constant (warned)."""
        socket = node.inputs.get(name)
        if socket is None or self.program is None or self.source(socket, ctx)[0] is None:
            return None
        mark = self.program.mark()
        try:
            value = self.program.socket(socket, ctx, kind)
            if not value.varying:
                return self.program.constant_value(value)
            if not varying:
                self.program.rewind(mark)
                self.warn(node, f"'{name}' {self.varying_note}; using the socket's own value")
                return None
            return self.program.add_output(value)
        except Unsupported as error:
            self.program.rewind(mark)
            self.warn(node, f"'{name}': {error}; using the socket's own value")
            return None

    def color(self, node, name, ctx, default=(0.8, 0.8, 0.8)):
        """(rgb, input): a textured colour is its input (rgb is then 1)."""
        driven = self.driven(node, name, ctx, "color")
        if isinstance(driven, int):
            return np.ones(3), driven
        if driven is not None:
            return _rgb(driven), None
        return self.value(node, name, ctx, default, color=True), None

    def scalar(self, node, name, ctx, default=0.0):
        """(value, input) of a float socket, as `color`."""
        driven = self.driven(node, name, ctx, "float")
        if isinstance(driven, int):
            return 1.0, driven
        if driven is not None:
            return _finite(float(driven), node, name, self), None
        return self.value(node, name, ctx, default), None

    def split(self, w, node, name, ctx, default):
        """(w * (1 - f), w * f) for the factor f on input `name`, clamped to [0, 1] as Cycles does;
        a textured factor becomes a factor of the weights (the constant part if a weight has its
        MAX_WEIGHT_INPUTS already, warned)."""
        fac, index = self.scalar(node, name, ctx, default)
        if index is None:
            fac = min(max(fac, 0.0), 1.0)
            return w * (1.0 - fac), w * fac
        if len(w.factors) >= MAX_WEIGHT_INPUTS:
            self.warn(node, f"textured weights nested more than {MAX_WEIGHT_INPUTS} deep; '{name}' is taken as 0.5")
            return w * 0.5, w * 0.5
        return w.times_input(index, "complement"), w.times_input(index, "fraction")

    def use_tangents(self, kind, node):
        """Notes the tangents the material's meshes need (one kind per material)."""
        if self.out.tangents is None:
            self.out.tangents = kind
        elif self.out.tangents != kind:
            self.warn(node, f"a second kind of tangent ({kind}) in one material is not supported; using "
                            f"{self.out.tangents}")

    def use_attribute(self, name, node):
        """Notes the mesh attribute the material's program reads (one per material)."""
        if self.out.attribute is None:
            self.out.attribute = name
        elif self.out.attribute != name:
            self.warn(node, f"a second attribute ('{name}') in one material is not supported; it reads "
                            f"'{self.out.attribute or 'the render colour attribute'}'")

    def anisotropy(self, node, ctx, anisotropy, rotation, stretch):
        """{stretch, rotation} for a lobe of `node`, its tangent noted (the Tangent socket: a Tangent
        node, or unlinked, Cycles' default, radial about Z); {} when isotropic. `stretch` maps the
        node's Anisotropy to (along, across) the tangent."""
        value = self.value(node, anisotropy, ctx, 0.0)
        if abs(value) <= 1e-4 or node.inputs.get(anisotropy) is None:
            return {}
        kind = "radial_z"
        socket = node.inputs.get("Tangent")
        out, _, _ = self.source(socket, ctx) if socket is not None else (None, None, None)
        if out is not None and out.node.bl_idname == "ShaderNodeTangent":
            tangent = out.node
            kind = "uv" if tangent.direction_type == "UV_MAP" else "radial_" + tangent.axis.lower()
            if kind == "uv" and tangent.uv_map:
                self.warn(tangent, f"tangents come from the mesh's active UV map, not '{tangent.uv_map}'")
        elif out is not None:
            self.warn(node, f"'Tangent' is driven by '{out.node.name}' ({out.node.bl_idname}), which is not "
                            "supported; using the default radial tangent")
        self.use_tangents(kind, node)
        return {"stretch": stretch(value), "rotation": self.value(node, rotation, ctx, 0.0)}

    # ------------------------------------------------------------ closures

    def closure(self, socket, ctx, weight):
        """Adds what the closure on input `socket` contributes, times `weight` (RGB)."""
        if socket is None or weight.peak() <= CUTOFF:
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
        if "Normal" in node.inputs:
            self.normal(node, "Normal", ctx)
        handler(self, node, ctx, weight)
        self.depth -= 1

    def normal(self, node, name, ctx):
        """Notes the normal on input `name` of a shader (a Normal Map, a Bump, any vector network:
        a program output); one per material, applied to all its shaders (warned where they differ)."""
        socket = node.inputs[name]
        if self.source(socket, ctx)[0] is None or self.program is None:
            self.out.unmapped = True
            return
        mark = self.program.mark()
        try:
            value = self.program.socket(socket, ctx, "vector")
            if not value.varying or self.program.is_coordinate(value, "shading_normal"):
                self.program.rewind(mark)  # the surface's own normal (a constant one is not supported)
                self.out.unmapped = True
                return
            index = self.program.add_output(value)
        except Unsupported as error:
            self.program.rewind(mark)
            self.warn(node, f"'{name}': {error}; using the surface's own normal")
            return
        mapping = {"input": index, "space": "direct", "softening": BUMP_SOFTENING,
                   "valid_reflection": VALID_REFLECTION}
        if self.out.normal_map is None:
            self.out.normal_map = mapping
            self.normal_node = node
        elif self.out.normal_map != mapping:
            self.warn(node, "a second normal in one material is not supported; the first applies to all its "
                            "shaders")


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
    first, second = reader.split(w, node, "Fac", ctx, 0.5)
    reader.closure(node.inputs[1], ctx, first)
    reader.closure(node.inputs[2], ctx, second)


def _add(reader, node, ctx, w):
    reader.closure(node.inputs[0], ctx, w)
    reader.closure(node.inputs[1], ctx, w)


def _roughness(reader, node, ctx, name="Roughness", default=0.5):
    """(roughness in [0, 1], input or None): a textured roughness is the image's value (the core clamps it);
    0 for 3.x's Sharp distribution."""
    if name == "Roughness" and _sharp(node):
        return 0.0, None
    value, index = reader.scalar(node, name, ctx, default)
    return min(max(value, 0.0), 1.0), index


def _beckmann(node):
    """Whether the node's microfacet distribution is Beckmann's (the Glossy, Anisotropic, Metallic,
    Glass and Refraction BSDFs offer it); Ashikhmin-Shirley (3.x to 4.x's Glossy) renders as GGX."""
    return getattr(node, "distribution", "GGX") == "BECKMANN"


def _sharp(node):
    """3.x's Sharp distribution: a perfect mirror or smooth glass, whatever the roughness."""
    return getattr(node, "distribution", "GGX") == "SHARP"


def _multiscatter(node):
    """Whether the node's microfacet distribution restores multiple scattering's energy (Cycles'
    Multiscatter GGX, the default of the Principled, Glossy and Metallic BSDFs from Blender 4.0)."""
    return getattr(node, "distribution", "GGX") == "MULTI_GGX"


# How Cycles softens light at a normal-mapped terminator (NormalMap::Softening in the core): measured
# Chiang's in 3.4 and 4.2, Conty Estevez's in 4.5 and 5.0 (tests/blenders/materials_compare.py,
# normal_mapped); 4.3 and 4.4 untested, taken as the newer.
BUMP_SOFTENING = "conty_estevez" if bpy.app.version >= (4, 3, 0) else "chiang"
# Cycles 3.x turns every closure's normal until the view's reflection lies above the surface; 4.0
# and later do not (measured: a noise read as a normal map, proc_noise_normal_map, was 12% off in 3.4).
VALID_REFLECTION = bpy.app.version < (4, 0, 0)
# Lobes whose normal Cycles 4.0+ turns until the view's reflection lies above the surface when the
# material's Bump Map Correction is on (maybe_ensure_valid_specular_reflection: Glossy, Glass,
# Refraction, Translucent, the Principled BSDF's metal, glass and specular); diffuse and sheen keep it.
VALID_REFLECTION_KINDS = ("glossy", "conductor", "dielectric", "translucent")
# Cycles' Oren-Nayar gained its multiple-scattering energy compensation in Blender 4.3.
OREN_NAYAR_MULTISCATTER = bpy.app.version >= (4, 3, 0)


def _diffuse(reader, node, ctx, w):
    """Lambert, or Oren-Nayar when rough (Cycles switches at roughness 1e-5)."""
    color, index = reader.color(node, "Color", ctx)
    roughness, roughness_input = _roughness(reader, node, ctx, default=0.0)
    rough = roughness >= 1e-5 or roughness_input is not None
    reader.out.add(w, kind="diffuse", color=tuple(color), color_input=index,
                   roughness=roughness if rough else None, roughness_input=roughness_input,
                   multiscatter=OREN_NAYAR_MULTISCATTER if rough else None)


def _translucent(reader, node, ctx, w):
    color, index = reader.color(node, "Color", ctx)
    reader.out.add(w, kind="translucent", color=tuple(color), color_input=index)


def _transparent(reader, node, ctx, w):
    reader.out.add(w, kind="transparent", color=tuple(reader.value(node, "Color", ctx, 1.0, color=True)))


def glossy_stretch(anisotropy):
    """Cycles' Glossy (and 3.x Anisotropic) BSDF: alpha along and across the tangent."""
    a = min(max(anisotropy, -0.99), 0.99)
    return (1.0 - a, 1.0 / (1.0 - a)) if a >= 0.0 else (1.0 / (1.0 + a), 1.0 + a)


def metal_stretch(anisotropy):
    """Cycles' Metallic and Principled BSDFs: alpha / aspect along the tangent, times aspect across."""
    aspect = math.sqrt(1.0 - min(max(anisotropy, 0.0), 1.0) * 0.9)
    return (1.0 / aspect, aspect)


def _glossy(reader, node, ctx, w):
    color, index = reader.color(node, "Color", ctx, (1.0, 1.0, 1.0))
    roughness, roughness_input = _roughness(reader, node, ctx)
    reader.out.add(w, kind="glossy", color=tuple(color), color_input=index, multiscatter=_multiscatter(node),
                   beckmann=_beckmann(node), roughness=roughness, roughness_input=roughness_input,
                   **reader.anisotropy(node, ctx, "Anisotropy", "Rotation", glossy_stretch))


def conductor_fresnel(cos_theta, n, k):
    """The exact Fresnel reflectance of a conductor of complex index n + ik (unpolarised), per channel."""
    c2 = cos_theta * cos_theta
    s2 = 1.0 - c2
    t0 = n * n - k * k - s2
    a2b2 = np.sqrt(t0 * t0 + 4.0 * n * n * k * k)
    a = np.sqrt(np.maximum(0.5 * (a2b2 + t0), 0.0))
    t1, t2 = a2b2 + c2, 2.0 * cos_theta * a
    rs = (t1 - t2) / (t1 + t2)
    t3, t4 = c2 * a2b2 + s2 * s2, t2 * s2
    return 0.5 * (rs + rs * (t3 - t4) / (t3 + t4))


def f82_from_physical(n, k):
    """(F0, F82 tint) of the F82-tint model through a conductor's exact Fresnel at 0 and 82 degrees (cos
    1/7), the fit Cycles itself uses for the conductor's multiple-scattering energy. Cycles renders
    the exact Fresnel; the model stays within 0.025 of it at every angle for gold (test_materials)."""
    n, k = np.maximum(n, 1e-5), np.maximum(k, 0.0)
    f0 = np.clip(conductor_fresnel(1.0, n, k), 0.0, 1.0)
    schlick_82 = f0 + (1.0 - f0) * (1.0 - 1.0 / 7.0) ** 5
    return f0, np.clip(conductor_fresnel(1.0 / 7.0, n, k) / schlick_82, 0.0, 1.0)


def _metallic(reader, node, ctx, w):
    if getattr(node, "fresnel_type", "F82") == "PHYSICAL_CONDUCTOR":
        color, tint = f82_from_physical(reader.value(node, "IOR", ctx, 1.0, color=True),
                                        reader.value(node, "Extinction", ctx, 0.0, color=True))
        index = None
    else:
        color, index = reader.color(node, "Base Color", ctx)
        tint = reader.value(node, "Edge Tint", ctx, 1.0, color=True)
    roughness, roughness_input = _roughness(reader, node, ctx)
    reader.out.add(w, kind="conductor", color=tuple(np.clip(color, 0.0, 1.0)), tint=tuple(np.clip(tint, 0.0, 1.0)),
                   color_input=index, multiscatter=_multiscatter(node), beckmann=_beckmann(node), roughness=roughness,
                   roughness_input=roughness_input,
                   **reader.anisotropy(node, ctx, "Anisotropy", "Rotation", metal_stretch))


def _glass(reader, node, ctx, w, parts="both"):
    color, index = reader.color(node, "Color", ctx, (1.0, 1.0, 1.0))
    ior = max(reader.value(node, "IOR", ctx, 1.45), 1e-5)
    roughness, roughness_input = _roughness(reader, node, ctx, default=0.0)
    if index is not None:
        reader.warn(node, "a textured glass colour tints refraction only (reflection stays white)")
    reader.out.add(w, kind="dielectric", parts=parts, color=tuple(color), tint=tuple(color) if index is None else None,
                   color_input=index, ior=ior, roughness=roughness, roughness_input=roughness_input,
                   multiscatter=parts == "both" and _multiscatter(node), beckmann=_beckmann(node))


def _sheen(reader, node, ctx, w):
    """The Velvet BSDF (3.x) and the Sheen BSDF: Ashikhmin's velvet in its Ashikhmin mode, Cycles'
    microfiber sheen (Zeltner et al. 2022; the core's microfiber_sheen.h) in its default mode."""
    color, index = reader.color(node, "Color", ctx)
    if getattr(node, "distribution", "ASHIKHMIN") == "MICROFIBER":
        roughness, roughness_input = _roughness(reader, node, ctx)
        reader.out.add(w, kind="microfiber_sheen", color=tuple(color), color_input=index, roughness=roughness,
                       roughness_input=roughness_input)
        return
    sigma = reader.value(node, "Sigma" if "Sigma" in node.inputs else "Roughness", ctx, 0.5)
    reader.out.add(w, kind="velvet", color=tuple(color), color_input=index, roughness=min(max(sigma, 0.0), 1.0))


def _refraction(reader, node, ctx, w):
    _glass(reader, node, ctx, w, parts="refraction")


def _untextured(reader, node, w, what):
    """w's constant part, for what the core cannot texture (emission, holdout); warned if textured."""
    if w.factors:
        reader.warn(node, f"{what} under a textured factor takes the factor as 1")
    return w.rgb


def _add_emission(reader, node, w, color, index, strength):
    """Adds w * color * strength to the closure's emission; `index`: the input texturing it (one per
    material: it applies to all of the material's emission, warned where that is not so)."""
    if not (float(np.max(color)) * strength > 0.0 and w.peak() > 0.0):
        return
    radiance = _untextured(reader, node, w, "emission") * color * strength
    reader.out.emission_parts += 1
    if index is not None and reader.out.emission_input not in (None, index):
        reader.warn(node, "a second textured emission in one material is not supported; using the first texture")
    elif index is not None:
        reader.out.emission_input = index
    if reader.out.emission_input is not None and reader.out.emission_parts > 1:
        reader.warn(node, "its textured emission applies its texture to all of the material's emission")
    reader.out.emission += radiance


def _emission(reader, node, ctx, w):
    color, index = reader.color(node, "Color", ctx, (1.0, 1.0, 1.0))
    _add_emission(reader, node, w, color, index, reader.value(node, "Strength", ctx, 1.0))


def _holdout(reader, node, ctx, w):
    reader.out.holdout += float(np.mean(_untextured(reader, node, w, "a holdout")))


def _as_diffuse(what):
    def handler(reader, node, ctx, w):
        reader.warn(node, f"{what} is rendered as diffuse in its colour")
        color, index = reader.color(node, "Color" if "Color" in node.inputs else "Base Color", ctx)
        reader.out.add(w, kind="diffuse", color=tuple(color), color_input=index)
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
    transparent, w = reader.split(w, node, "Alpha", ctx, 1.0)
    reader.out.add(transparent, kind="transparent", color=(1.0, 1.0, 1.0))
    return w


def _principled_sheen(reader, node, ctx, w):
    """The Principled BSDF's sheen (4.0 and later), a microfiber sheen of Sheen Weight times Sheen
    Tint on top of the rest, a layer: the core attenuates what lies below by its albedo towards the
    viewer, as Cycles does."""
    sheen = max(reader.value(node, "Sheen Weight", ctx, 0.0), 0.0)
    if sheen <= CUTOFF:
        return
    tint = np.clip(reader.value(node, "Sheen Tint", ctx, 1.0, color=True), 0.0, None)
    roughness, roughness_input = _roughness(reader, node, ctx, "Sheen Roughness", 0.5)
    reader.out.add(w, kind="microfiber_sheen", layer=True, color=tuple(sheen * tint), roughness=roughness,
                   roughness_input=roughness_input)


def principled_v2(reader, node, ctx, w):
    """Cycles' Principled BSDF of Blender 4.0 and later, top to bottom: alpha (transparency), sheen
    (microfiber), coat (a dielectric layer, its tint at normal incidence), emission, metal (F82
    tint conductor), transmission (glass, tinted by the square root of the base colour at each
    crossing), the dielectric specular layer (IOR scaled by IOR Level, tinted by Specular Tint), and
    diffuse (subsurface as diffuse). Each layer takes its share of the weight below it as Cycles does.
    Base Color, Roughness, Metallic, Transmission Weight and Alpha may come from images."""
    v = lambda name, default=0.0: reader.value(node, name, ctx, default)  # noqa: E731
    base, base_input = reader.color(node, "Base Color", ctx)
    roughness, roughness_input = _roughness(reader, node, ctx)
    rough = {"roughness": roughness, "roughness_input": roughness_input}
    w = _alpha(reader, node, ctx, w)
    _principled_sheen(reader, node, ctx, w)
    anisotropic = reader.anisotropy(node, ctx, "Anisotropic", "Anisotropic Rotation", metal_stretch)
    coat = max(v("Coat Weight"), 0.0)
    if coat > CUTOFF:
        coat_roughness, coat_input = _roughness(reader, node, ctx, "Coat Roughness", 0.03)
        reader.out.add(w, kind="dielectric", parts="reflection", layer=True, tint=(coat,) * 3,
                       ior=max(v("Coat IOR", 1.5), 1.0), roughness=coat_roughness, roughness_input=coat_input)
        tint = np.clip(reader.value(node, "Coat Tint", ctx, 1.0, color=True), 0.0, None)
        w = w * (1.0 + coat * (tint - 1.0))
    emission, index = reader.color(node, "Emission Color", ctx, (1.0, 1.0, 1.0))
    # The coat's attenuation of emission depends on the view; here its value at normal incidence.
    _add_emission(reader, node, w, emission, index,
                  v("Emission Strength", 0.0) * (1.0 - coat * f0_from_ior(max(v("Coat IOR", 1.5), 1.0))))
    w_rest, w_metal = reader.split(w, node, "Metallic", ctx, 0.0)
    if w_metal.peak() > CUTOFF:
        f82 = np.clip(reader.value(node, "Specular Tint", ctx, 1.0, color=True), 0.0, 1.0)
        reader.out.add(w_metal, kind="conductor", color=tuple(np.clip(base, 0.0, 1.0)), tint=tuple(f82),
                       color_input=base_input, multiscatter=_multiscatter(node), **rough, **anisotropic)
    w = w_rest
    if anisotropic and w.peak() > CUTOFF:
        reader.warn(node, "anisotropy applies to the metal only; the dielectric specular stays isotropic")
    ior = max(v("IOR", 1.5), 1e-5)
    specular_tint = np.clip(reader.value(node, "Specular Tint", ctx, 1.0, color=True), 0.0, None)
    w_opaque, w_transmission = reader.split(w, node, "Transmission Weight", ctx, 0.0)
    if w_transmission.peak() > CUTOFF:
        color_input = None if base_input is None else (base_input, "sqrt")
        reader.out.add(w_transmission, kind="dielectric", color=tuple(np.sqrt(np.clip(base, 0.0, 1.0))),
                       tint=tuple(specular_tint), tint_f0=True, color_input=color_input, ior=ior,
                       multiscatter=_multiscatter(node), **rough)
    w = w_opaque
    level = max(v("Specular IOR Level", 0.5), 0.0)
    eta = ior if level == 0.5 else ior_from_f0(f0_from_ior(ior) * 2.0 * level)
    if abs(eta - 1.0) > 1e-6:
        reader.out.add(w, kind="dielectric", parts="reflection", layer=True, tint=tuple(specular_tint),
                       tint_f0=True, multiscatter=_multiscatter(node), ior=eta if eta > 1.0 else 1.0 / eta, **rough)
    if v("Subsurface Weight") > CUTOFF:
        reader.warn(node, "subsurface scattering is rendered as diffuse in the base colour")
    diffuse_roughness, diffuse_input = _roughness(reader, node, ctx, "Diffuse Roughness", 0.0)
    oren_nayar = diffuse_roughness >= 1e-5 or diffuse_input is not None  # where Cycles switches to it
    reader.out.add(w, kind="diffuse", color=tuple(base), color_input=base_input,
                   roughness=diffuse_roughness if oren_nayar else None, roughness_input=diffuse_input,
                   multiscatter=True if oren_nayar else None)


def principled_v1(reader, node, ctx, w):
    """Cycles' Principled BSDF of Blender 3.x: diffuse (1 - transmission)(1 - metallic) of the base
    colour; a specular lobe of weight 1 - transmission (1 - metallic), added on top (not layered, as
    in 3.x), of Fresnel F0 between 0.08 * Specular (tinted towards the base colour by Specular Tint)
    and the base colour by Metallic; glass for transmission (1 - metallic); a clearcoat lobe of
    weight 0.25 * Clearcoat; emission. Base Color (except in the specular F0, which mixes it with
    constants), Roughness and Alpha may come from images."""
    v = lambda name, default=0.0: reader.value(node, name, ctx, default)  # noqa: E731
    base, base_input = reader.color(node, "Base Color", ctx)
    roughness, roughness_input = _roughness(reader, node, ctx)
    rough = {"roughness": roughness, "roughness_input": roughness_input}
    w = _alpha(reader, node, ctx, w)
    specular = {**rough, **reader.anisotropy(node, ctx, "Anisotropic", "Anisotropic Rotation", metal_stretch)}
    if v("Transmission") <= 0.0 and (base_input is not None or _has_image(reader, node, "Metallic", ctx)):
        _principled_v1_opaque_textured(reader, node, ctx, w, base, base_input, specular)
        return
    metallic = min(max(v("Metallic"), 0.0), 1.0)
    diffuse = (1.0 - metallic) * (1.0 - min(max(v("Transmission"), 0.0), 1.0))
    transmission = min(max(v("Transmission"), 0.0), 1.0) * (1.0 - metallic)
    emission, index = reader.color(node, "Emission", ctx, (0.0, 0.0, 0.0))
    _add_emission(reader, node, w, emission, index, v("Emission Strength", 1.0))
    if v("Subsurface") > CUTOFF:
        reader.warn(node, "subsurface scattering is rendered as diffuse in the base colour")
    reader.out.add(w * diffuse, kind="diffuse", color=tuple(base), color_input=base_input)
    hue, dielectric_f0 = _principled_v1_dielectric(reader, node, ctx, base, None)
    _principled_v1_sheen(reader, node, ctx, w * diffuse, hue if base_input is None else np.ones(3))
    f0 = (1.0 - metallic) * dielectric_f0 + metallic * np.clip(base, 0.0, 1.0)
    reader.out.add(w * (1.0 - transmission), kind="conductor", color=tuple(np.clip(f0, 0.0, 1.0)),
                   multiscatter=_multiscatter(node), **specular)
    if transmission > CUTOFF:
        reader.out.add(w * transmission, kind="dielectric", color=tuple(base), tint=(1.0, 1.0, 1.0),
                       color_input=base_input, ior=max(v("IOR", 1.45), 1e-5), multiscatter=_multiscatter(node),
                       **rough)
    _principled_v1_clearcoat(reader, node, ctx, w)


def _has_image(reader, node, name, ctx):
    out, _, _ = reader.source(node.inputs[name], ctx)
    return out is not None and out.node.bl_idname == "ShaderNodeTexImage" and out.node.image is not None


def _principled_v1_dielectric(reader, node, ctx, base, base_input):
    """(hue, F0) of 3.x's dielectric specular: 0.08 Specular, tinted towards the base colour's hue
    (its colour over Cycles' rough luminance) by Specular Tint; untinted for an image's base colour."""
    lum = float(np.dot(base, (0.3, 0.6, 0.1)))
    hue = base / lum if lum > 0.0 and base_input is None else np.ones(3)
    tint = min(max(reader.value(node, "Specular Tint", ctx, 0.0), 0.0), 1.0)
    if base_input is not None and tint > 0.0:
        reader.warn(node, "Specular Tint with an image on Base Color is not supported; untinted")
    return hue, 0.08 * max(reader.value(node, "Specular", ctx, 0.5), 0.0) * (1.0 - tint + tint * hue)


def _principled_v1_clearcoat(reader, node, ctx, w):
    """3.x's clearcoat: a dielectric reflection of IOR 1.5, weight 0.25 Clearcoat, added on top."""
    clearcoat = max(reader.value(node, "Clearcoat", ctx, 0.0), 0.0)
    if clearcoat > CUTOFF:
        coat_roughness, coat_input = _roughness(reader, node, ctx, "Clearcoat Roughness", 0.03)
        reader.out.add(w * 0.25 * clearcoat, kind="dielectric", parts="reflection", ior=1.5,
                       roughness=coat_roughness, roughness_input=coat_input)


def _principled_v1_sheen(reader, node, ctx, w, hue):
    """3.x's Principled sheen: Sheen times white tinted towards the base colour's hue by Sheen Tint,
    on the diffuse part's weight, added (not layered)."""
    sheen = max(reader.value(node, "Sheen", ctx, 0.0), 0.0)
    if sheen > CUTOFF:
        tint = min(max(reader.value(node, "Sheen Tint", ctx, 0.5), 0.0), 1.0)
        reader.out.add(w * sheen, kind="schlick_sheen", color=tuple(1.0 - tint + tint * hue))


def _principled_v1_opaque_textured(reader, node, ctx, w, base, base_input, specular):
    """principled_v1 without transmission, Base Color or Metallic from images: the specular F0,
    (1 - metallic) dielectric F0 + metallic base colour, is split into two lobes of those F0s (Schlick's
    Fresnel is linear in F0, so the sum is Cycles' one lobe)."""
    w_dielectric, w_metal = reader.split(w, node, "Metallic", ctx, 0.0)
    hue, dielectric_f0 = _principled_v1_dielectric(reader, node, ctx, base, base_input)
    reader.out.add(w_dielectric, kind="diffuse", color=tuple(base), color_input=base_input)
    _principled_v1_sheen(reader, node, ctx, w_dielectric, hue)
    reader.out.add(w_dielectric, kind="conductor", color=tuple(np.clip(dielectric_f0, 0.0, 1.0)),
                   multiscatter=_multiscatter(node), **specular)
    reader.out.add(w_metal, kind="conductor", color=tuple(np.clip(base, 0.0, 1.0)), color_input=base_input,
                   multiscatter=_multiscatter(node), **specular)
    _principled_v1_clearcoat(reader, node, ctx, w)


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
    "ShaderNodeBsdfSheen": _sheen,
    "ShaderNodeBsdfVelvet": _sheen,
    "ShaderNodeBsdfToon": _as_diffuse("the Toon BSDF"),
    "ShaderNodeBsdfHair": _left_out("a hair BSDF"),
    "ShaderNodeBsdfHairPrincipled": _left_out("a hair BSDF"),
    "ShaderNodeBackground": _left_out("a Background shader in a material"),
    "ShaderNodeVolumeAbsorption": _left_out("a volume shader on a surface"),
    "ShaderNodeVolumeScatter": _left_out("a volume shader on a surface"),
    "ShaderNodeVolumePrincipled": _left_out("a volume shader on a surface"),
    "ShaderNodeBsdfRayPortal": _left_out("the Ray Portal BSDF"),
}


def read_surface(material, warn, texture=None, core=None, attributes=None):
    """The closure of `material`'s active surface output (None if it has no node tree in use).
    Texture and utility nodes are compiled when `core` (a ppm_core.Scene, which runs constant
    networks) and `texture(image, premultiplied)` (its texture index) are given; `attributes`: the
    export's object_info.AttributeTable."""
    if not nodes.uses_nodes(material):
        return None
    output = nodes.active_output(material.node_tree, "ShaderNodeOutputMaterial")
    if output is None:
        return None
    reader = ClosureReader(material.name, warn, texture, core, attributes=attributes)
    reader.closure(output.inputs["Surface"], (), Weight(np.ones(3)))
    for message in unrendered.material_outputs(output):
        reader.warn(None, message)
    if reader.program is not None and reader.program.outputs:
        reader.out.program = reader.program.program()
        reader.out.simple_images = reader.program.output_images()
    if reader.out.normal_map is not None and reader.out.unmapped:
        reader.warn(None, "its normal map applies to all its shaders, also those without it")
    lobes = reader.out.lobes
    if len(lobes) > MAX_LOBES:
        reader.warn(None, f"{len(lobes)} shader lobes; the {MAX_LOBES} of largest weight are kept")
        kept = sorted(sorted(range(len(lobes)), key=lambda i: -max(lobes[i]["weight"]))[:MAX_LOBES])
        reader.out.lobes = [lobes[i] for i in kept]  # in their order: a layer stays above what it covers
    _bump_map_correction(reader, material)
    return reader.out


def _turned_by_cycles(lobe):
    """Whether Cycles 4.0+ turns this lobe's bumped normal (VALID_REFLECTION_KINDS), leaving out the
    Principled BSDF's specular layer (a reflection-only dielectric tinting its F0)."""
    specular_layer = lobe["kind"] == "dielectric" and lobe.get("parts") == "reflection" and lobe.get("tint_f0")
    return lobe["kind"] in VALID_REFLECTION_KINDS and not specular_layer


def _bump_map_correction(reader, material):
    """Cycles' Bump Map Correction (the material's setting, on by default) for a bumped or normal-mapped
    material. On, Cycles 4.0+ turns the normal of its glossy, glass, refraction and translucent lobes
    and the Principled BSDF's (not of diffuse and sheen) until the view's reflection lies above the
    surface, which the core does for all of a material's lobes or none (all in 3.x, as Cycles 3.x):
    warned where such lobes are bumped, except the Principled BSDF's dielectric specular layer alone
    (its F0 of a few percent: a normal-mapped Principled BSDF is common and mostly close; a strongly
    bumped red plastic measured 12% darker in green and blue, unwarned). Off, Cycles skips the diffuse
    terminator's softening but still refuses light from beyond the smooth normal; the core's softening
    does both or neither (warned). Measured on a ball bumped by a Noise of scale 20 at strength 1
    (tests/blenders/community_compare.py): a Glossy 22% darker than Cycles; with the setting off, a
    diffuse 8% and a Glossy 9% darker (the core's 'none': the diffuse 2%, the Glossy 11% brighter)."""
    mapping = reader.out.normal_map
    if mapping is None:
        return
    if not getattr(getattr(material, "cycles", None), "use_bump_map_correction", True):
        reader.warn(reader.normal_node, "Bump Map Correction is off, so Cycles leaves the shadow terminator of its "
                    "bumped diffuse parts unsoftened, which is softened here (a strong bump renders darker than "
                    "Cycles)")
        return
    if VALID_REFLECTION or not any(_turned_by_cycles(lobe) for lobe in reader.out.lobes):
        return
    reader.warn(reader.normal_node, "its glossy, coat, metal, glass and translucent parts keep the bumped normal, "
                "which Cycles' Bump Map Correction turns until the view's reflection lies above the surface: a "
                "strong bump renders them darker than Cycles")
