"""A material's texture and utility nodes -> the core's node program (engine/shading/node_program.h).

Each socket a shader reads that a node network drives is compiled once into instructions over
float-triple registers (a float sits in all three channels), as Cycles compiles its SVM: the
network below the socket is walked through reroutes, muted nodes and groups (ClosureReader.source),
each node emitting its instruction once per group context. A node whose inputs are all constants is
run at once by the core and becomes a constant, so a socket the network drives with constants costs
nothing per shading point. The program's outputs are the material's inputs, which lobes, the normal
and the emission refer to.

A Bump node compiles its Height three times: at the shading point and at two points beside it
(BumpOffset), as Cycles does. A node the core does not have gives the value Cycles would in the
simplest case, with one warning naming material and node.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import bpy
import numpy as np

MAX_REGISTERS = 256  # the core's limit
MAX_OUTPUTS = 8  # the core's limit of inputs per material
# Nodes compiled inside each other (a handler compiles its inputs first) before the compile turns to the
# deepest one on its own: a chain of any length then needs no more of Python's stack than this.
MAX_NESTED_NODES = 40
RAMP_TABLE = 257 if bpy.app.version >= (4, 0, 0) else 256  # Cycles' baked ColorRamp (i / (size - 1))
LEGACY_TEXTURES = bpy.app.version < (4, 0, 0)  # Blender 3.x's Noise and Wave distortion
MAGIC_WRAPPED = bpy.app.version >= (4, 0, 0)
VORONOI_PCG = bpy.app.version >= (5, 0, 0)  # cells hashed by integer coordinates (measured: 4.5 not, 5.0 so)
NORMAL_MAP_NORMALISES_FIRST = bpy.app.version < (4, 0, 0)  # measured: 3.4 does, 4.2 does not
GREY = 0 if bpy.app.version >= (5, 0, 0) else 2  # colour -> float weights (measured: 4.5 old, 5.0 new)


class Unsupported(Exception):
    """A node the program cannot take; the socket it drives keeps its own value (warned)."""


class _TooDeep(Exception):  # noqa: N818 - not an error: a node to compile before the one being compiled
    """A node reached MAX_NESTED_NODES inside the node being compiled: it is compiled first, on its own."""

    def __init__(self, out, ctx):
        super().__init__()
        self.out, self.ctx = out, ctx


@dataclass(frozen=True)
class Value:
    reg: int
    kind: str  # "float", "color" or "vector"
    varying: bool  # depends on where it is evaluated


def _triple(raw):
    try:
        values = [float(v) for v in tuple(raw)[:3]]
    except TypeError:
        values = [float(raw)]
    values = [v if np.isfinite(v) else 0.0 for v in values]
    return tuple(values * 3)[:3] if len(values) == 1 else tuple(values + [0.0] * (3 - len(values)))


def _writes(instruction):
    """The registers an instruction writes (a Voronoi writes its W output into the one its data names)."""
    return instruction["out"] + ([instruction["data"]] if instruction["op"] == "voronoi" else [])


def _allocate(code, registers, outputs):
    """(code, register of each value, register count): `code` with each value written in a register
    freed by a value no longer read (`registers` maps the constants and 0; the `outputs` live to the
    end). An instruction's results never share a register with its own inputs."""
    registers = dict(registers)
    last_read = {reg: i for i, ins in enumerate(code) for reg in ins["in"]}
    last_read.update({reg: len(code) for reg in outputs})
    fixed, free, count, allocated = set(registers), [], len(registers), []
    for i, ins in enumerate(code):
        renamed = dict(ins, **{"in": [registers[r] for r in ins["in"]]})
        for reg in _writes(ins):
            if reg == 0:
                continue
            if free:
                registers[reg] = free.pop()
            else:
                registers[reg], count = count, count + 1
        renamed["out"] = [registers[r] for r in ins["out"]]
        if ins["op"] == "voronoi":
            renamed["data"] = registers[ins["data"]]
        allocated.append(renamed)
        dead = {r for r in ins["in"] + _writes(ins) if r not in fixed and last_read.get(r, -1) <= i}
        free += sorted(registers[r] for r in dead)
    return allocated, registers, count


def socket_kind(socket):
    return {"VALUE": "float", "INT": "float", "BOOLEAN": "float", "RGBA": "color"}.get(socket.type, "vector")


class ProgramCompiler:
    """Compiles the sockets of one material into one program; `reader` follows links and warns,
    `texture(image, premultiplied)` gives a core texture index (a UDIM image: [(tile number, index)];
    ValueError: unusable), `core` runs programs (ppm_core.Scene.run_program)."""

    def __init__(self, reader, texture, core):
        self.reader, self.texture, self.core = reader, texture, core
        # The module of the scene's class is ppm_core's; a recorded scene (farm/scene_record.py) names it.
        module = getattr(core, "core_module", None) or sys.modules[type(core).__module__]
        self.modes = module.node_modes()
        self.constants, self.constant_regs = [], {}
        self.code, self.data, self.outputs = [], [], []
        self.registers = 1
        self.cache = {}
        self.variant = 0  # which of a Bump node's three heights is being compiled (0: none)
        self.nested = 0  # nodes being compiled inside each other
        self.simple_images = {}  # output index -> texture index of a plain UV image colour

    # ------------------------------------------------------------ registers and instructions

    def constant(self, value):
        key = _triple(value)
        if key not in self.constant_regs:
            # Constants are numbered among the values as they come; program() puts those it reads first.
            self.constant_regs[key] = self.registers
            self.constants.append((self.registers, key))
            self.registers += 1
        return Value(self.constant_regs[key], "float" if len(set(key)) == 1 else "color", False)

    def register(self):
        """A new value's number (program() gives it a core register where it is live)."""
        self.registers += 1
        return self.registers - 1

    def emit(self, op, ins, outs=1, kinds=("float",), varying=None, mode=0, flags=0, extra=0, data=0,
             pure=True):
        """Appends an instruction reading Values `ins`; returns its output Values. A pure one whose
        inputs are all constant is run now and its outputs become constants."""
        regs = [self.register() for _ in range(outs)]
        ins = list(ins)
        instruction = {"op": op, "mode": int(mode), "flags": int(flags), "extra": int(extra),
                       "in": [v.reg for v in ins], "out": regs + [0] * (3 - len(regs)), "data": int(data)}
        if varying is None:
            varying = not pure or any(v.varying for v in ins)
        self.code.append(instruction)
        values = [Value(r, k, varying) for r, k in zip(regs, kinds)]
        if not varying:
            return self.fold(values)
        return values

    def fold(self, values):
        """Runs the program so far and turns `values` into constants (dropping what only they used)."""
        result = self.core.run_program(self.program([v.reg for v in values]), np.zeros((1, 3)))[0]
        self.code.pop()
        return [self.constant(tuple(float(c) for c in result[i])) for i in range(len(values))]

    def program(self, outputs=None):
        """The dict for Scene.add_material(program=...): the constants it reads in registers 1.., then
        each value in a register only while it is live (a chain of any length needs a few). Unsupported
        if it needs more than the core's MAX_REGISTERS."""
        outputs = list(outputs if outputs is not None else self.outputs)
        read = {reg for ins in self.code for reg in ins["in"]} | set(outputs)
        constants = [(reg, key) for reg, key in sorted(self.constants) if reg in read]
        registers = {reg: i + 1 for i, (reg, _) in enumerate(constants)}
        registers[0] = 0
        code, registers, count = _allocate(self.code, registers, outputs)
        if count > MAX_REGISTERS:
            raise Unsupported(f"more than {MAX_REGISTERS} values live at once in one material")
        return {"constants": [key for _, key in constants], "code": code, "data": list(self.data),
                "outputs": [registers[r] for r in outputs], "registers": count}

    def convert(self, value, kind):
        """`value` as a socket of `kind` reads it (colour -> float: luminance; vector -> float: mean;
        a float fills all three channels already)."""
        if kind == "float" and value.kind != "float":
            key = ("convert", value.reg, value.kind)
            if key not in self.cache:
                self.cache[key] = self.emit("convert", [value], mode=GREY if value.kind == "color" else 1)[0]
            return self.cache[key]
        return value if value.kind == kind else Value(value.reg, kind, value.varying)

    def constant_value(self, value):
        """A constant Value's number (float) or triple (array)."""
        key = next(k for reg, k in self.constants if reg == value.reg)
        return key[0] if value.kind == "float" else np.array(key)

    def mark(self):
        return len(self.code), set(self.cache), len(self.outputs), len(self.constants), self.registers

    def rewind(self, mark):
        """Forgets what was compiled since `mark` (a network that turned out unusable), and frees its
        registers and constants."""
        length, cached, outputs, constants, registers = mark
        del self.code[length:]
        del self.outputs[outputs:]
        for key in set(self.cache) - cached:
            del self.cache[key]
        for _, key in self.constants[constants:]:
            del self.constant_regs[key]
        del self.constants[constants:]
        self.registers = registers  # the numbers of what was undone are given out again
        for reg in [reg for reg in self.simple_images if reg >= registers]:
            del self.simple_images[reg]

    def output_images(self):
        """Per output: the core texture when it is an image's colour read at the UV, else None."""
        return [self.simple_images.get(reg) for reg in self.outputs]

    def mode(self, op, name):
        names = self.modes[op]
        key = name.lower()
        if key not in names:
            raise Unsupported(f"{op.replace('_', ' ')} '{name}' is not supported")
        return names.index(key)

    # ------------------------------------------------------------ sockets

    def input(self, node, name, ctx, kind=None, default=None):
        """The Value of input `name` of `node` (by name or identifier), as `kind` (its own by default)."""
        socket = _input(node, name)
        if socket is None:
            if default is None:
                raise Unsupported(f"'{node.name}' has no input '{name}'")
            return self.constant(default)
        return self.socket(socket, ctx, kind or socket_kind(socket))

    def socket(self, socket, ctx, kind):
        out, inner, last = self.reader.source(socket, ctx)
        if out is None:
            own = self.constant(getattr(last, "default_value", 0.0))
            return self.convert(Value(own.reg, socket_kind(last), False), kind)
        if self.nested == 0:
            return self.convert(self.deepest_first(out, inner), kind)
        return self.convert(self.node_output(out, inner), kind)

    def deepest_first(self, out, ctx):
        """node_output(out, ctx), the nodes of a long chain compiled from its far end: where the compile
        reaches MAX_NESTED_NODES, what it did is undone and the node reached is compiled first, on its own
        (then cached), without Python recursion that grows with the chain."""
        pending = [(out, ctx)]
        while True:
            mark = self.mark()
            try:
                value = self.node_output(*pending[-1])
            except _TooDeep as deeper:
                self.rewind(mark)
                pending.append((deeper.out, deeper.ctx))
                continue
            pending.pop()
            if not pending:
                return value

    def node_output(self, out, ctx):
        node = out.node
        key = (node.as_pointer(), tuple(g.as_pointer() for g in ctx), self.variant)
        if key not in self.cache:
            handler = NODES.get(node.bl_idname)
            if handler is None:
                raise Unsupported(f"'{node.name}' ({node.bl_idname}) is not supported yet")
            if self.nested >= MAX_NESTED_NODES and self.variant == 0:  # (a Bump's heights follow its offsets)
                raise _TooDeep(out, ctx)
            self.nested += 1
            try:
                self.cache[key] = handler(self, node, ctx)
            except RecursionError:
                raise Unsupported("its node network is nested too deeply inside a Bump's Height") from None
            finally:
                self.nested -= 1
        outputs = self.cache[key]
        value = outputs.get(out.identifier, outputs.get(out.name))
        if value is None:
            raise Unsupported(f"output '{out.name}' of '{node.name}' is not supported yet")
        return value

    def add_output(self, value):
        """The material input index for `value` (an output of the program)."""
        if value.reg in self.outputs:
            return self.outputs.index(value.reg)
        if len(self.outputs) >= MAX_OUTPUTS:
            raise Unsupported(f"more than {MAX_OUTPUTS} textured sockets in one material")
        self.program(self.outputs + [value.reg])  # fits the core's registers (Unsupported if not)
        self.outputs.append(value.reg)
        return len(self.outputs) - 1

    def reads_light_path(self):
        """Whether the program so far reads a Light Path output."""
        first = self.mode("coord", "is_camera_ray")
        return any(i["op"] == "coord" and i["mode"] >= first for i in self.code)

    def coordinate(self, name):
        return self.emit("coord", [], kinds=("vector",), mode=self.mode("coord", name), pure=False)[0]

    def is_coordinate(self, value, name):
        """Whether `value` is the coordinate `name` itself (as Cycles' shading normal for a Normal)."""
        return any(i["op"] == "coord" and i["out"][0] == value.reg and i["mode"] == self.mode("coord", name)
                   for i in self.code)

    def vector_or(self, node, ctx, default_coordinate):
        """A texture's Vector input, or the coordinate Cycles uses when it is not linked."""
        socket = _input(node, "Vector")
        if socket is not None and any(link for link in socket.links):
            return self.socket(socket, ctx, "vector")
        return self.coordinate(default_coordinate)


def _input(node, name):
    """Input `name` of `node`: the enabled socket with that identifier, else with that name."""
    for socket in node.inputs:
        if socket.identifier == name and socket.enabled:
            return socket
    for socket in node.inputs:
        if socket.name == name and socket.enabled:
            return socket
    return node.inputs.get(name)


# ---------------------------------------------------------------- input nodes

def _texture_coordinate(c, node, ctx):
    out = {name: c.coordinate(name) for name in ("Generated", "Normal", "UV", "Object", "Camera", "Window",
                                                  "Reflection")}
    other = getattr(node, "object", None)
    if other is not None:  # Object in that object's space, as Cycles (the other outputs stay this object's)
        offset = len(c.data)
        c.data += [float(v) for row in other.matrix_world.inverted_safe()[:3] for v in row]
        out["Object"] = c.emit("transform", [c.coordinate("position")], kinds=("vector",), data=offset)[0]
    return out


def _geometry(c, node, ctx):
    out = {"Position": c.coordinate("position"), "Normal": c.coordinate("shading_normal"),
           "True Normal": c.coordinate("true_normal"), "Incoming": c.coordinate("incoming"),
           "Backfacing": Value(c.coordinate("backfacing").reg, "float", True),
           "Tangent": c.coordinate("tangent")}
    for name, value in (("Pointiness", 0.5), ("Random Per Island", 0.0), ("Parametric", (0.0, 0.0, 0.0))):
        if node.outputs[name].links:
            c.reader.warn(node, f"its {name} output is not supported; using {value}")
        out[name] = c.constant(value)
    return out


LIGHT_PATH_FLAGS = ("Is Camera Ray", "Is Shadow Ray", "Is Diffuse Ray", "Is Glossy Ray", "Is Singular Ray",
                    "Is Reflection Ray", "Is Transmission Ray")
LIGHT_PATH_NUMBERS = ("Ray Length", "Ray Depth", "Diffuse Depth", "Glossy Depth", "Transmission Depth")


def _light_path(c, node, ctx):
    """The ray that reached the point, as the core knows it (LightPath in node_program.h): camera paths
    as in Cycles; photons arrive on a shadow ray from their light, then on their last scattering's kind."""
    out = {name: Value(c.coordinate(name.replace(" ", "_")).reg, "float", True)
           for name in LIGHT_PATH_FLAGS + LIGHT_PATH_NUMBERS}
    out["Is Volume Scatter Ray"] = c.constant(0.0)  # no volumes
    if node.outputs["Transparent Depth"].links:
        c.reader.warn(node, "its Transparent Depth is not counted; using 0")
    out["Transparent Depth"] = c.constant(0.0)
    return out


def _uv_map(c, node, ctx):
    if node.uv_map:
        c.reader.warn(node, f"UVs come from the mesh's active UV map, not '{node.uv_map}'")
    return {"UV": c.coordinate("uv")}


def _object_info(c, node, ctx):
    random = c.coordinate("object_random")
    index = c.coordinate("object_index")
    return {"Location": c.coordinate("object_location"), "Random": Value(random.reg, "float", True),
            "Object Index": Value(index.reg, "float", True), "Material Index": c.constant(0.0),
            "Color": Value(c.coordinate("object_color").reg, "color", True),
            "Alpha": Value(c.coordinate("object_alpha").reg, "float", True)}


def _attribute_outputs(c, node, name):
    """A mesh attribute's outputs (one attribute per material: the mesh carries it)."""
    c.reader.use_attribute(name, node)
    color = c.coordinate("attribute")
    alpha = Value(c.coordinate("attribute_alpha").reg, "float", True)
    mean = Value(c.coordinate("attribute_mean").reg, "float", True)
    return {"Color": Value(color.reg, "color", True), "Vector": color, "Fac": mean, "Alpha": alpha}


def _grid_outputs(c, slot):
    """An object's grid `slot` (smoke.GridNames: a smoke domain's or a Volume object's) at the point's
    Object coordinate (each grid maps it to its voxels): 0 on an object without it, as Cycles' Attribute
    node reads a missing attribute."""
    color, fac, alpha = c.emit("grid", [c.coordinate("object")], outs=3, kinds=("color", "float", "float"),
                               data=slot, pure=False)
    return {"Color": color, "Vector": Value(color.reg, "vector", True), "Fac": fac, "Alpha": alpha}


def _attribute(c, node, ctx):
    kind = getattr(node, "attribute_type", "GEOMETRY")
    names = getattr(c.reader, "grid_names", None)  # a Volume on a smoke domain or a Volume object
    if kind == "GEOMETRY" and names is not None and node.attribute_name:
        return _grid_outputs(c, names.slot(node.attribute_name))
    if kind == "GEOMETRY":
        return _attribute_outputs(c, node, node.attribute_name)
    table = c.reader.attributes
    if kind == "VIEW_LAYER" and table is not None:  # a constant of the render
        rgba = table.view_layer_value(node.attribute_name)
        return {"Color": c.constant(rgba[:3]), "Vector": c.constant(rgba[:3]), "Fac": c.constant(sum(rgba[:3]) / 3),
                "Alpha": c.constant(rgba[3])}
    if table is None or c.reader.kind == "world":  # no object to read
        c.reader.warn(node, f"{kind.lower().replace('_', ' ')} attributes read 0 here")
        return {name: c.constant(0.0) for name in ("Color", "Vector", "Fac", "Alpha")}
    slot = table.slot(kind, node.attribute_name)

    def read(mode, value_kind):
        return c.emit("coord", [], kinds=(value_kind,), mode=c.mode("coord", mode), data=slot, pure=False)[0]

    color = read("object_attribute", "color")
    return {"Color": color, "Vector": Value(color.reg, "vector", True), "Fac": read("object_attribute_mean", "float"),
            "Alpha": read("object_attribute_alpha", "float")}


def _color_attribute(c, node, ctx):
    return _attribute_outputs(c, node, node.layer_name)  # "": the mesh's render colour attribute


def _value(c, node, ctx):
    return {"Value": c.constant(node.outputs[0].default_value)}


def _rgb(c, node, ctx):
    return {"Color": c.constant(node.outputs[0].default_value)}


def _tangent(c, node, ctx):
    if node.direction_type != "UV_MAP":
        raise Unsupported(f"'{node.name}': radial tangents in a node network are not supported yet")
    return {"Tangent": c.coordinate("tangent")}


def _fresnel(c, node, ctx):
    normal = _normal_input(c, node, ctx)
    return {"Fac": c.emit("fresnel", [c.input(node, "IOR", ctx, "float"), normal], pure=False)[0]}


def _layer_weight(c, node, ctx):
    normal = _normal_input(c, node, ctx)
    fresnel, facing = c.emit("layer_weight", [c.input(node, "Blend", ctx, "float"), normal], outs=2,
                             kinds=("float", "float"), pure=False)
    return {"Fresnel": fresnel, "Facing": facing}


def _normal_input(c, node, ctx):
    socket = _input(node, "Normal")
    if socket is not None and any(socket.links):
        return c.socket(socket, ctx, "vector")
    return c.coordinate("shading_normal")


# ---------------------------------------------------------------- textures

def _image(c, node, ctx):
    image = node.image
    if image is None:
        return {"Color": c.constant((0.0, 0.0, 0.0)), "Alpha": c.constant(0.0)}
    try:
        index = c.texture(image, premultiplied(node))
    except ValueError as error:
        return _missing_image(c, node, image, error)
    interpolation = {"Linear": 0, "Closest": 1, "Cubic": 2, "Smart": 2}.get(node.interpolation, 0)
    extension = {"REPEAT": 0, "EXTEND": 1, "CLIP": 2, "MIRROR": 3}.get(node.extension, 0)
    vector = c.vector_or(node, ctx, "uv")
    projection = ["FLAT", "BOX", "SPHERE", "TUBE"].index(node.projection)
    ins = [vector]
    if node.projection == "BOX":  # faces weighted by the object-space normal (Texture Coordinate's Normal)
        ins += [c.coordinate("normal"), c.constant(float(node.projection_blend))]
    flags = 0
    if isinstance(index, list):  # UDIM: (tile number, texture) pairs, laid out for the core's lookup
        flags, tiles, index = 1, index, len(c.data)
        c.data += [float(len(tiles))] + [float(v) for pair in tiles for v in pair]
    color, alpha = c.emit("image", ins, outs=2, kinds=("color", "float"), mode=interpolation | extension << 2,
                          extra=projection, flags=flags, data=index, pure=False)
    plain = (interpolation, extension, projection, flags) == (0, 0, 0, 0) and c.is_coordinate(vector, "uv")
    c.simple_images[color.reg] = index if plain else None
    return {"Color": color, "Alpha": alpha}


def premultiplied(texture_node):
    """Whether Cycles gives this Image Texture's Color premultiplied by its alpha: an image of straight
    alpha in a colour space that is not data, whose node's Alpha output is not linked (Cycles keeps
    images premultiplied and divides by alpha again only for a node whose Alpha is used)."""
    image = texture_node.image
    alpha = texture_node.outputs.get("Alpha")
    return (getattr(image, "alpha_mode", "STRAIGHT") == "STRAIGHT" and not getattr(image, "is_data", False)
            and image.colorspace_settings.name not in ("Non-Color", "Raw") and alpha is not None and not alpha.links)


def _missing_image(c, node, image, error):
    """What Cycles reads from an image it cannot load: magenta, opaque (TEX_IMAGE_MISSING_R/G/B/A)."""
    c.reader.warn(node, f"image '{image.name}': {error}; it reads magenta, as in Cycles")
    return {"Color": c.constant((1.0, 0.0, 1.0)), "Alpha": c.constant(1.0)}


def _environment(c, node, ctx):
    """An Environment Texture: the image at its Vector's equirectangular or mirror-ball coordinates; by
    default the position, as Cycles (for a world, the direction)."""
    image = node.image
    if image is None:
        return {"Color": c.constant((1.0, 0.0, 1.0)), "Alpha": c.constant(1.0)}  # Cycles' missing image
    try:
        index = c.texture(image, False)
    except ValueError as error:
        return _missing_image(c, node, image, error)
    uv = c.emit("environment_uv", [c.vector_or(node, ctx, "position")], kinds=("vector",),
                mode=int(node.projection == "MIRROR_BALL"))[0]
    interpolation = {"Linear": 0, "Closest": 1, "Cubic": 2, "Smart": 2}.get(node.interpolation, 0)
    color, alpha = c.emit("image", [uv], outs=2, kinds=("color", "float"), mode=interpolation, data=index,
                          pure=False)
    return {"Color": color, "Alpha": alpha}


def _dimensions(node, attribute):
    return int(getattr(node, attribute, "3D")[0])


def _noise(c, node, ctx):
    dims = _dimensions(node, "noise_dimensions")
    vector = c.vector_or(node, ctx, "generated")
    kind = getattr(node, "noise_type", "FBM")
    normalize = getattr(node, "normalize", True)
    names = ("W", "Scale", "Detail", "Roughness", "Lacunarity", "Offset", "Gain", "Distortion")
    defaults = (0.0, 5.0, 2.0, 0.5, 2.0, 0.0, 1.0, 0.0)
    ins = [c.input(node, n, ctx, "float", d) for n, d in zip(names, defaults)]
    extra = dims | (16 if LEGACY_TEXTURES else 0) | (32 if normalize else 0)
    fac, color = c.emit("noise", [vector, *ins], outs=2, kinds=("float", "color"),
                        mode=c.mode("noise", kind), extra=extra)
    return {"Fac": fac, "Color": color}


def _musgrave(c, node, ctx):
    """Blender 3.x's Musgrave texture (4.1 made it the Noise texture's types)."""
    dims = _dimensions(node, "musgrave_dimensions")
    vector = c.vector_or(node, ctx, "generated")
    names = ("W", "Scale", "Detail", "Dimension", "Lacunarity", "Offset", "Gain")
    defaults = (0.0, 5.0, 2.0, 2.0, 2.0, 0.0, 1.0)
    ins = [c.input(node, n, ctx, "float", d) for n, d in zip(names, defaults)]
    fac = c.emit("noise", [vector, *ins, c.constant(0.0)], mode=c.mode("noise", node.musgrave_type),
                 extra=dims | 64)[0]
    return {"Fac": fac}


def _voronoi(c, node, ctx):
    dims = _dimensions(node, "voronoi_dimensions")
    vector = c.vector_or(node, ctx, "generated")
    names = ("W", "Scale", "Detail", "Roughness", "Lacunarity", "Smoothness", "Exponent", "Randomness")
    defaults = (0.0, 5.0, 0.0, 0.5, 2.0, 1.0, 0.5, 1.0)
    ins = [c.input(node, n, ctx, "float", d) for n, d in zip(names, defaults)]
    w = c.register()
    distance, color, position = c.emit(
        "voronoi", [vector, *ins], outs=3, kinds=("float", "color", "vector"), mode=c.mode("voronoi", node.feature),
        flags=c.mode("voronoi_metric", node.distance),
        extra=dims | (32 if getattr(node, "normalize", False) else 0) | (64 if VORONOI_PCG else 0),
        data=w)
    w_value = Value(w, "float", distance.varying)
    if not distance.varying:  # folded: W was computed with the rest; fold it separately
        raise Unsupported(f"'{node.name}': a Voronoi texture of constant coordinates is not supported")
    return {"Distance": distance, "Color": color, "Position": position, "W": w_value, "Radius": distance}


def _white_noise(c, node, ctx):
    dims = _dimensions(node, "noise_dimensions")
    vector = c.vector_or(node, ctx, "generated")
    value, color = c.emit("white_noise", [vector, c.input(node, "W", ctx, "float", 0.0)], outs=2,
                          kinds=("float", "color"), extra=dims)
    return {"Value": value, "Color": color}


def _checker(c, node, ctx):
    vector = c.vector_or(node, ctx, "generated")
    ins = [vector, c.input(node, "Color1", ctx, "color"), c.input(node, "Color2", ctx, "color"),
           c.input(node, "Scale", ctx, "float")]
    color, fac = c.emit("checker", ins, outs=2, kinds=("color", "float"))
    return {"Color": color, "Fac": fac}


def _gradient(c, node, ctx):
    vector = c.vector_or(node, ctx, "generated")
    color, fac = c.emit("gradient", [vector], outs=2, kinds=("color", "float"),
                        mode=c.mode("gradient", node.gradient_type))
    return {"Color": color, "Fac": fac}


def _wave(c, node, ctx):
    vector = c.vector_or(node, ctx, "generated")
    rings = node.wave_type == "RINGS"
    direction = node.rings_direction if rings else node.bands_direction
    axis = ("X", "Y", "Z").index(direction) if direction in ("X", "Y", "Z") else 3  # diagonal, spherical
    mode = int(rings) | axis << 1 | ("SIN", "SAW", "TRI").index(node.wave_profile) << 3
    names = ("Scale", "Distortion", "Detail", "Detail Scale", "Detail Roughness", "Phase Offset")
    defaults = (5.0, 0.0, 2.0, 1.0, 0.5, 0.0)
    ins = [c.input(node, n, ctx, "float", d) for n, d in zip(names, defaults)]
    color, fac = c.emit("wave", [vector, *ins], outs=2, kinds=("color", "float"), mode=mode,
                        extra=1 if LEGACY_TEXTURES else 0)
    return {"Color": color, "Fac": fac}


def _magic(c, node, ctx):
    vector = c.vector_or(node, ctx, "generated")
    ins = [vector, c.input(node, "Scale", ctx, "float"), c.input(node, "Distortion", ctx, "float")]
    color, fac = c.emit("magic", ins, outs=2, kinds=("color", "float"), extra=node.turbulence_depth,
                        flags=int(MAGIC_WRAPPED))
    return {"Color": color, "Fac": fac}


def _gabor(c, node, ctx):
    """Blender 4.3's Gabor Texture (textures/gabor.h); the orientation the type does not use is 0."""
    vector = c.vector_or(node, ctx, "generated")
    three_d = node.gabor_type == "3D"
    ins = [vector] + [c.input(node, name, ctx, "float") for name in ("Scale", "Frequency", "Anisotropy")]
    ins.append(c.constant(0.0) if three_d else c.input(node, "Orientation 2D", ctx, "float"))
    ins.append(c.input(node, "Orientation 3D", ctx, "vector") if three_d else c.constant(0.0))
    value, phase, intensity = c.emit("gabor", ins, outs=3, kinds=("float",) * 3, mode=int(three_d))
    return {"Value": value, "Phase": phase, "Intensity": intensity}


def _brick(c, node, ctx):
    vector = c.vector_or(node, ctx, "generated")
    offset = len(c.data)
    c.data += [float(node.offset), float(node.offset_frequency), float(node.squash), float(node.squash_frequency)]
    colors = [c.input(node, n, ctx, "color") for n in ("Color1", "Color2", "Mortar")]
    names = ("Scale", "Mortar Size", "Mortar Smooth", "Bias", "Brick Width", "Row Height")
    floats = [c.input(node, n, ctx, "float") for n in names]
    color, fac = c.emit("brick", [vector, *colors, *floats], outs=2, kinds=("color", "float"), data=offset)
    return {"Color": color, "Fac": fac}


# ---------------------------------------------------------------- converters

def _math(c, node, ctx):
    ins = [c.socket(node.inputs[i], ctx, "float") for i in range(3)]
    value = c.emit("math", ins, mode=c.mode("math", node.operation), flags=int(node.use_clamp))[0]
    return {"Value": value}


def _vector_math(c, node, ctx):
    ins = [c.socket(node.inputs[i], ctx, "vector") for i in range(3)]
    scale = c.socket(node.inputs[3], ctx, "float")  # Scale, or Refract's IOR
    vector, value = c.emit("vector_math", [*ins, scale], outs=2, kinds=("vector", "float"),
                           mode=c.mode("vector_math", node.operation))
    return {"Vector": vector, "Value": value}


BLEND_NAMES = {"MIX": "mix", "ADD": "add", "MULTIPLY": "multiply", "SCREEN": "screen", "OVERLAY": "overlay",
               "SUBTRACT": "subtract", "DIVIDE": "divide", "DIFFERENCE": "difference", "EXCLUSION": "exclusion",
               "DARKEN": "darken", "LIGHTEN": "lighten", "DODGE": "dodge", "BURN": "burn", "HUE": "hue",
               "SATURATION": "saturation", "VALUE": "value", "COLOR": "color", "SOFT_LIGHT": "soft_light",
               "LINEAR_LIGHT": "linear_light"}


def _mix_rgb(c, node, ctx):
    fac = c.socket(node.inputs[0], ctx, "float")
    a, b = c.socket(node.inputs[1], ctx, "color"), c.socket(node.inputs[2], ctx, "color")
    color = c.emit("mix", [fac, a, b], kinds=("color",), mode=c.mode("mix", BLEND_NAMES[node.blend_type]),
                   flags=1 | (2 if node.use_clamp else 0))[0]
    return {"Color": color}


def _mix(c, node, ctx):
    kind = node.data_type
    if kind == "RGBA":
        fac = c.input(node, "Factor_Float", ctx, "float")
        a, b = c.input(node, "A_Color", ctx, "color"), c.input(node, "B_Color", ctx, "color")
        flags = int(node.clamp_factor) | (2 if node.clamp_result else 0)
        result = c.emit("mix", [fac, a, b], kinds=("color",), mode=c.mode("mix", BLEND_NAMES[node.blend_type]),
                        flags=flags)[0]
        return {"Result_Color": result}
    if kind == "FLOAT":
        fac = c.input(node, "Factor_Float", ctx, "float")
        a, b = c.input(node, "A_Float", ctx, "float"), c.input(node, "B_Float", ctx, "float")
        result = c.emit("mix", [fac, a, b], mode=0, flags=int(node.clamp_factor))[0]
        return {"Result_Float": result}
    if kind == "VECTOR":
        uniform = node.factor_mode == "UNIFORM"
        fac = c.input(node, "Factor_Float" if uniform else "Factor_Vector", ctx, "float" if uniform else "vector")
        a, b = c.input(node, "A_Vector", ctx, "vector"), c.input(node, "B_Vector", ctx, "vector")
        result = c.emit("mix_vector", [fac, a, b], kinds=("vector",), flags=int(node.clamp_factor))[0]
        return {"Result_Vector": result}
    raise Unsupported(f"'{node.name}': a Mix node of {kind.lower()} is not supported")


def _color_ramp(c, node, ctx):
    ramp = node.color_ramp
    offset = len(c.data)
    for i in range(RAMP_TABLE):
        c.data += [float(v) for v in ramp.evaluate(i / (RAMP_TABLE - 1))]
    fac = c.input(node, "Fac", ctx, "float")
    color, alpha = c.emit("table", [fac], outs=2, kinds=("color", "float"), data=offset, extra=RAMP_TABLE - 2,
                          flags=int(ramp.interpolation != "CONSTANT"))
    return {"Color": color, "Alpha": alpha}


def _curve_table(c, mapping, curves, combined=None):
    """Bakes curves into the program's data as Cycles does (RAMP_TABLE entries over the curves' x
    range, the combined curve applied first); the table's offset."""
    mapping.update()
    lo = min(curve.points[0].location[0] for curve in list(curves) + ([combined] if combined else []))
    hi = max(curve.points[-1].location[0] for curve in list(curves) + ([combined] if combined else []))
    c.data += [float(lo), float(hi)]
    offset = len(c.data)
    for i in range(RAMP_TABLE):
        t = lo + i / (RAMP_TABLE - 1) * (hi - lo)
        x = mapping.evaluate(combined, t) if combined is not None else t
        values = [mapping.evaluate(curve, x) for curve in curves]
        c.data += [float(v) for v in (values * 3)[:3]] + [1.0]
    return offset


def _rgb_curves(c, node, ctx):
    curves = node.mapping.curves
    offset = _curve_table(c, node.mapping, curves[:3], curves[3])
    ins = [c.input(node, "Fac", ctx, "float"), c.input(node, "Color", ctx, "color")]
    return {"Color": c.emit("table", ins, kinds=("color",), mode=1, data=offset, extra=RAMP_TABLE - 2)[0]}


def _vector_curves(c, node, ctx):
    offset = _curve_table(c, node.mapping, node.mapping.curves[:3])
    ins = [c.input(node, "Fac", ctx, "float"), c.input(node, "Vector", ctx, "vector")]
    return {"Vector": c.emit("table", ins, kinds=("vector",), mode=1, data=offset, extra=RAMP_TABLE - 2)[0]}


def _float_curve(c, node, ctx):
    offset = _curve_table(c, node.mapping, node.mapping.curves[:1])
    ins = [c.input(node, "Factor", ctx, "float"), c.input(node, "Value", ctx, "float")]
    return {"Value": c.emit("table", ins, mode=2, data=offset, extra=RAMP_TABLE - 2)[0]}


def _map_range(c, node, ctx):
    mode = ["LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP"].index(node.interpolation_type)
    if getattr(node, "data_type", "FLOAT") == "FLOAT_VECTOR":
        names = ("Vector", "From_Min_FLOAT3", "From_Max_FLOAT3", "To_Min_FLOAT3", "To_Max_FLOAT3", "Steps_FLOAT3")
        ins = [c.input(node, n, ctx, "vector") for n in names]
        result = c.emit("map_range", ins, kinds=("vector",), mode=mode, flags=int(node.clamp) | 2)[0]
        return {"Vector": result}
    names = ("Value", "From Min", "From Max", "To Min", "To Max", "Steps")
    ins = [c.input(node, n, ctx, "float", 4.0 if n == "Steps" else None) for n in names]
    return {"Result": c.emit("map_range", ins, mode=mode, flags=int(node.clamp))[0]}


def _clamp(c, node, ctx):
    ins = [c.input(node, n, ctx, "float") for n in ("Value", "Min", "Max")]
    return {"Result": c.emit("clamp", ins, mode=int(node.clamp_type == "RANGE"))[0]}


COLOR_MODELS = ("RGB", "HSV", "HSL")  # the core's Separate modes 0-2, 3-5, 6-8 and Combine modes 0, 1, 2


def _separate(c, node, ctx, names, model="RGB"):
    source = c.socket(node.inputs[0], ctx, "color" if names[0] in ("R", "Red", "H") else "vector")
    first = 3 * COLOR_MODELS.index(model)
    return {name: c.emit("separate", [source], mode=first + i)[0] for i, name in enumerate(names)}


def _combine(c, node, ctx, names, kind, model="RGB"):
    ins = [c.input(node, n, ctx, "float") for n in names]
    result = c.emit("combine", ins, kinds=(kind,), mode=COLOR_MODELS.index(model))[0]
    return {node.outputs[0].identifier: result, node.outputs[0].name: result}


def _separate_color(c, node, ctx):
    return _separate(c, node, ctx, ("Red", "Green", "Blue"), getattr(node, "mode", "RGB"))


def _combine_color(c, node, ctx):
    return _combine(c, node, ctx, ("Red", "Green", "Blue"), "color", getattr(node, "mode", "RGB"))


def _invert(c, node, ctx):
    return {"Color": c.emit("invert", [c.input(node, "Fac", ctx, "float"), c.input(node, "Color", ctx, "color")],
                            kinds=("color",))[0]}


def _gamma(c, node, ctx):
    return {"Color": c.emit("gamma", [c.input(node, "Color", ctx, "color"), c.input(node, "Gamma", ctx, "float")],
                            kinds=("color",))[0]}


def _bright_contrast(c, node, ctx):
    ins = [c.input(node, "Color", ctx, "color"), c.input(node, "Bright", ctx, "float"),
           c.input(node, "Contrast", ctx, "float")]
    return {"Color": c.emit("bright_contrast", ins, kinds=("color",))[0]}


def _hue_saturation(c, node, ctx):
    ins = [c.input(node, n, ctx, "float") for n in ("Hue", "Saturation", "Value", "Fac")]
    return {"Color": c.emit("hue_saturation", [*ins, c.input(node, "Color", ctx, "color")], kinds=("color",))[0]}


def _rgb_to_bw(c, node, ctx):
    return {"Val": c.input(node, "Color", ctx, "float")}


def _mapping(c, node, ctx):
    mode = ["POINT", "TEXTURE", "VECTOR", "NORMAL"].index(node.vector_type)
    ins = [c.input(node, "Vector", ctx, "vector"),
           c.input(node, "Location", ctx, "vector", (0.0, 0.0, 0.0)),
           c.input(node, "Rotation", ctx, "vector"), c.input(node, "Scale", ctx, "vector")]
    return {"Vector": c.emit("mapping", ins, kinds=("vector",), mode=mode)[0]}


def _vector_rotate(c, node, ctx):
    mode = ["AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"].index(node.rotation_type)
    ins = [c.input(node, "Vector", ctx, "vector"), c.input(node, "Center", ctx, "vector"),
           c.input(node, "Axis", ctx, "vector", (0.0, 0.0, 1.0)), c.input(node, "Angle", ctx, "float", 0.0),
           c.input(node, "Rotation", ctx, "vector", (0.0, 0.0, 0.0))]
    return {"Vector": c.emit("vector_rotate", ins, kinds=("vector",), mode=mode, flags=int(node.invert))[0]}


def _blackbody(c, node, ctx):
    """Cycles' Blackbody colour (export/blackbody.py): folded for a constant Temperature, else the
    core's instruction with the fit in the program's data."""
    from .blackbody import blackbody_rgb, program_data
    temperature = c.input(node, "Temperature", ctx, "float")
    if not temperature.varying:
        return {"Color": c.constant(blackbody_rgb(c.constant_value(temperature)))}
    offset = len(c.data)
    c.data += program_data()
    return {"Color": c.emit("blackbody", [temperature], kinds=("color",), data=offset)[0]}


def _wavelength(c, node, ctx):
    from .wavelength import program_data
    offset = len(c.data)
    c.data += program_data()
    return {"Color": c.emit("wavelength", [c.input(node, "Wavelength", ctx, "float")], kinds=("color",),
                            data=offset)[0]}


def _vector_transform(c, node, ctx):
    spaces = ["WORLD", "OBJECT", "CAMERA"]
    mode = spaces.index(node.convert_from) * 3 + spaces.index(node.convert_to)
    kind = ["POINT", "VECTOR", "NORMAL"].index(node.vector_type)
    vector = c.input(node, "Vector", ctx, "vector")
    return {"Vector": c.emit("vector_transform", [vector], kinds=("vector",), mode=mode, flags=kind, pure=False)[0]}


def _bump(c, node, ctx):
    """The height at the shading point, then beside it along two directions, as Cycles evaluates it."""
    normal = _normal_input(c, node, ctx)
    strength, distance = c.input(node, "Strength", ctx, "float"), c.input(node, "Distance", ctx, "float")
    width = c.input(node, "Filter Width", ctx, "float", 1.0)  # 4.4+; before, the whole differential
    socket = _input(node, "Height")
    if c.variant != 0:
        c.reader.warn(node, "a Bump inside another Bump's height is not supported; left flat")
        return {"Normal": normal}
    centre = c.socket(socket, ctx, "float")
    if not centre.varying:
        return {"Normal": normal}
    sides = []
    for variant in (1, 2):
        c.emit("bump_offset", [width], outs=0, mode=variant, pure=False)
        c.variant = variant
        try:
            sides.append(c.socket(socket, ctx, "float"))
        finally:
            c.variant = 0
    c.emit("bump_offset", [width], outs=0, mode=0, pure=False)
    result = c.emit("bump", [strength, distance, centre, *sides, normal, width], kinds=("vector",),
                    flags=int(node.invert), pure=False)[0]
    return {"Normal": result}


def _normal_map(c, node, ctx):
    if node.space not in ("TANGENT", "OBJECT", "WORLD"):
        raise Unsupported(f"a normal map in {node.space.lower().replace('_', ' ')} space is not supported yet")
    space = ("TANGENT", "OBJECT", "WORLD").index(node.space)
    if node.space == "TANGENT" and node.uv_map:
        c.reader.warn(node, f"tangents come from the mesh's active UV map, not '{node.uv_map}'")
    if node.space == "TANGENT":
        c.reader.use_tangents("uv", node)
    ins = [c.input(node, "Strength", ctx, "float"), c.input(node, "Color", ctx, "color")]
    return {"Normal": c.emit("normal_map", ins, kinds=("vector",), mode=space, pure=False,
                             flags=int(NORMAL_MAP_NORMALISES_FIRST))[0]}


def _simplest(what, outputs):
    """A node Cycles computes from the scene around the point (ray tracing, mesh data): the value it
    gives in the simplest case, with a warning. `outputs(c, node, ctx)` gives them."""
    def handler(c, node, ctx):
        c.reader.warn(node, f"{what} is not supported; using {outputs.__doc__}")
        return outputs(c, node, ctx)
    return handler


def _ambient_occlusion(c, node, ctx):
    """its colour, unoccluded (AO 1)"""
    return {"Color": c.input(node, "Color", ctx, "color"), "AO": c.constant(1.0)}


def _wireframe(c, node, ctx):
    """0 (no edge)"""
    return {"Fac": c.constant(0.0)}


def _light_falloff(c, node, ctx):
    """its Strength"""
    strength = c.input(node, "Strength", ctx, "float")
    return {"Quadratic": strength, "Linear": strength, "Constant": strength}


def _bevel(c, node, ctx):
    """the unbevelled normal"""
    return {"Normal": _normal_input(c, node, ctx)}


NODES = {
    "ShaderNodeAmbientOcclusion": _simplest("ambient occlusion", _ambient_occlusion),
    "ShaderNodeWireframe": _simplest("the Wireframe node", _wireframe),
    "ShaderNodeLightFalloff": _simplest("Light Falloff", _light_falloff),
    "ShaderNodeBevel": _simplest("the Bevel node", _bevel),
    "ShaderNodeTexCoord": _texture_coordinate,
    "ShaderNodeNewGeometry": _geometry,
    "ShaderNodeUVMap": _uv_map,
    "ShaderNodeLightPath": _light_path,
    "ShaderNodeObjectInfo": _object_info,
    "ShaderNodeAttribute": _attribute,
    "ShaderNodeVertexColor": _color_attribute,
    "ShaderNodeValue": _value,
    "ShaderNodeRGB": _rgb,
    "ShaderNodeTangent": _tangent,
    "ShaderNodeFresnel": _fresnel,
    "ShaderNodeLayerWeight": _layer_weight,
    "ShaderNodeTexImage": _image,
    "ShaderNodeTexEnvironment": _environment,
    "ShaderNodeTexNoise": _noise,
    "ShaderNodeTexVoronoi": _voronoi,
    "ShaderNodeTexMusgrave": _musgrave,
    "ShaderNodeTexWhiteNoise": _white_noise,
    "ShaderNodeTexChecker": _checker,
    "ShaderNodeTexGradient": _gradient,
    "ShaderNodeTexWave": _wave,
    "ShaderNodeTexMagic": _magic,
    "ShaderNodeTexGabor": _gabor,
    "ShaderNodeTexBrick": _brick,
    "ShaderNodeMath": _math,
    "ShaderNodeVectorMath": _vector_math,
    "ShaderNodeMixRGB": _mix_rgb,
    "ShaderNodeMix": _mix,
    "ShaderNodeValToRGB": _color_ramp,
    "ShaderNodeRGBCurve": _rgb_curves,
    "ShaderNodeVectorCurve": _vector_curves,
    "ShaderNodeFloatCurve": _float_curve,
    "ShaderNodeMapRange": _map_range,
    "ShaderNodeClamp": _clamp,
    "ShaderNodeSeparateRGB": lambda c, n, x: _separate(c, n, x, ("R", "G", "B")),
    "ShaderNodeSeparateXYZ": lambda c, n, x: _separate(c, n, x, ("X", "Y", "Z")),
    "ShaderNodeSeparateHSV": lambda c, n, x: _separate(c, n, x, ("H", "S", "V"), "HSV"),
    "ShaderNodeSeparateColor": _separate_color,
    "ShaderNodeCombineRGB": lambda c, n, x: _combine(c, n, x, ("R", "G", "B"), "color"),
    "ShaderNodeCombineXYZ": lambda c, n, x: _combine(c, n, x, ("X", "Y", "Z"), "vector"),
    "ShaderNodeCombineHSV": lambda c, n, x: _combine(c, n, x, ("H", "S", "V"), "color", "HSV"),
    "ShaderNodeCombineColor": _combine_color,
    "ShaderNodeInvert": _invert,
    "ShaderNodeGamma": _gamma,
    "ShaderNodeBrightContrast": _bright_contrast,
    "ShaderNodeHueSaturation": _hue_saturation,
    "ShaderNodeRGBToBW": _rgb_to_bw,
    "ShaderNodeMapping": _mapping,
    "ShaderNodeVectorRotate": _vector_rotate,
    "ShaderNodeVectorTransform": _vector_transform,
    "ShaderNodeBlackbody": _blackbody,
    "ShaderNodeWavelength": _wavelength,
    "ShaderNodeBump": _bump,
    "ShaderNodeNormalMap": _normal_map,
}
