"""Blender world -> the core's background: a constant radiance (colour * strength), or an image
around the scene (an Environment Texture feeding the Background's colour, equirectangular or mirror
ball, optionally turned by a Mapping node), times the strength, or a node network on the
Background's Color and Strength (a procedural sky, a tinted HDRI): compiled as materials' networks
are (node_program.py), run by the core at every texel of a BAKE_WIDTH x BAKE_HEIGHT
equirectangular image, which then lights the scene as an HDRI does (the directions seen as Cycles
sees them: Generated, Object and Position are the direction, Normal and Incoming its opposite).
A network that reads Light Path is baked twice: as camera rays see it (the core's camera
background) and as diffuse rays see it (the world that lights the scene).

Reads the Background node feeding the active World Output. A network the compiler cannot take falls
back to the socket's own value with a warning. The world's ray visibility (World > Settings > Ray
Visibility, `cycles_visibility`) decides which escaping rays see it, and its Max Bounces (World >
Settings > Light Path) the longest path it lights. The world's Volume output is the medium filling
all space outside the meshes with media of their own (volume.py).
"""

import math

import numpy as np

from . import closure, nodes, object_info, volume
from . import image as image_export
from .node_program import Unsupported
from .visibility import own_max_bounces

PROJECTIONS = {"EQUIRECTANGULAR": "equirectangular", "MIRROR_BALL": "mirror_ball"}
WORLD_RAY_FLAGS = ("camera", "diffuse", "glossy", "transmission", "shadow")
BAKE_WIDTH, BAKE_HEIGHT = 1024, 512
WORLD_OBJECT = object_info.MAX_OBJECT_ID  # the id past the objects': the core keeps its info apart


def _linked_node(socket):
    return socket.links[0].from_node if socket.links else None


def visibility(world):
    settings = getattr(world, "cycles_visibility", None)
    return [kind for kind in WORLD_RAY_FLAGS if getattr(settings, kind, True)]


class WorldExporter:
    """One world's export: warnings name the world and the node."""

    def __init__(self, core_scene, world, warn, attributes=None):
        self.scene, self.world, self.warn = core_scene, world, warn
        self.attributes = attributes

    def reach(self):
        """The rays that see the world, and the paths it lights."""
        return {"visibility": visibility(self.world), "max_bounces": own_max_bounces(self.world)}

    def unsupported(self, node, socket, source):
        self.warn(f"world '{self.world.name}': '{socket.name}' of node '{node.name}' is driven by "
                  f"'{source.name}' ({source.bl_idname}), which is not supported; using the socket's value")

    def export(self):
        node = (nodes.surface_source(self.world.node_tree, "ShaderNodeOutputWorld")
                if nodes.uses_nodes(self.world) else None)
        if node is None:
            # A node tree with nothing connected renders black in Cycles; without nodes, the world colour.
            color = (0.0, 0.0, 0.0) if nodes.uses_nodes(self.world) else tuple(self.world.color)
            self.scene.set_background(color, **self.reach())
            return
        if node.bl_idname != "ShaderNodeBackground":
            self.warn(f"world '{self.world.name}': node '{node.name}' ({node.bl_idname}) is not supported; "
                      "background is black")
            self.scene.set_background((0.0, 0.0, 0.0))
            return
        color_socket, strength_socket = node.inputs["Color"], node.inputs["Strength"]
        source = _linked_node(color_socket)
        if not strength_socket.links and (source is None or self.plain_environment(source)):
            strength = float(strength_socket.default_value)
            if source is not None and self.add_environment(source, strength):
                return
            color = tuple(float(c) * strength for c in tuple(color_socket.default_value)[:3])
            self.scene.set_background(color, **self.reach())
            return
        self.add_network(node)

    @staticmethod
    def plain_environment(source):
        """An Environment Texture fed by nothing, Texture Coordinates or a Mapping of them: the image
        itself lights the scene (no resampling)."""
        if source.bl_idname != "ShaderNodeTexEnvironment":
            return False
        mapping = _linked_node(source.inputs["Vector"])
        if mapping is None or mapping.bl_idname == "ShaderNodeTexCoord":
            return True
        feed = _linked_node(mapping.inputs["Vector"]) if mapping.bl_idname == "ShaderNodeMapping" else mapping
        return mapping.bl_idname == "ShaderNodeMapping" and (feed is None or feed.bl_idname == "ShaderNodeTexCoord")

    def add_network(self, node):
        """The Background's Color and Strength from a node network, baked into an image around the
        scene (see the module's comment); the sockets' own values where the network cannot be taken."""
        reader = closure.ClosureReader(self.world.name, self.warn, self.texture, self.scene, kind="world",
                                       attributes=self.attributes)
        program = reader.program
        try:
            color = program.socket(node.inputs["Color"], (), "color")
            strength = program.socket(node.inputs["Strength"], (), "float")
        except Unsupported as error:
            reader.warn(node, f"{error}; using the Background's own colour and strength")
            color = tuple(float(c) * node.inputs["Strength"].default_value
                          for c in tuple(node.inputs["Color"].default_value)[:3])
            self.scene.set_background(color, **self.reach())
            return
        if not color.varying and not strength.varying:
            rgb = np.asarray(program.constant_value(color), dtype=float) * float(program.constant_value(strength))
            self.scene.set_background(tuple(float(c) for c in np.broadcast_to(rgb, 3)), **self.reach())
            return
        indices = [program.add_output(color), program.add_output(strength)]
        # For the world Generated and Object are the direction: a texture space of [0, 1], unmoved.
        self.scene.set_object_info(WORLD_OBJECT, np.eye(4), texspace_location=(0.5, 0.5, 0.5),
                                   texspace_size=(0.5, 0.5, 0.5))
        reach = self.reach()
        if not program.reads_light_path():
            self.scene.set_environment(self.bake(program, indices, "camera"), **reach)
            return
        # Light Path tells camera rays apart (the artists' "Is Camera Ray" backdrop): camera rays see
        # the world as they read it, everything else as a diffuse ray reads it.
        seen = reach["visibility"]
        reach["visibility"] = [kind for kind in seen if kind != "camera"]
        self.scene.set_environment(self.bake(program, indices, "diffuse"), **reach)
        if "camera" in seen:
            self.scene.set_camera_background(self.bake(program, indices, "camera"))

    def bake(self, program, indices, ray):
        """The Background's colour times strength over all directions as rays of kind `ray` see it: a
        texture (equirectangular, half floats)."""
        directions = bake_directions(BAKE_WIDTH, BAKE_HEIGHT)
        values = self.scene.run_program(program.program(), directions, normal=-directions, incoming=-directions,
                                        object=WORLD_OBJECT, ray=ray)
        rgb = values[:, indices[0]] * values[:, indices[1], :1]
        pixels = np.ones((BAKE_HEIGHT, BAKE_WIDTH, 4), dtype=np.float32)
        pixels[..., :3] = np.clip(rgb, 0.0, 6.0e4).reshape(BAKE_HEIGHT, BAKE_WIDTH, 3)  # half floats' range
        return self.scene.add_texture(f"world '{self.world.name}' (baked for {ray} rays)", pixels, storage="half")

    def texture(self, image, premultiplied=False):
        texture, repaired = image_export.add_texture(self.scene, image, premultiplied)
        if repaired:
            self.warn(f"image '{image.name}': {repaired}")
        return texture

    def add_environment(self, node, strength):
        """The Environment Texture `node` as the background; False (with a warning) if it cannot be."""
        if node.image is None:
            self.warn(f"world '{self.world.name}': node '{node.name}' has no image; using the Background colour")
            return False
        try:
            texture, repaired = image_export.add_texture(self.scene, node.image)
        except ValueError as error:
            self.warn(f"world '{self.world.name}': node '{node.name}': {error}; using the Background colour")
            return False
        if repaired:
            self.warn(f"image '{node.image.name}': {repaired}")
        self.scene.set_environment(texture, world_to_texture=self.mapping(node), strength=(strength,) * 3,
                                   projection=PROJECTIONS.get(node.projection, "equirectangular"),
                                   **self.reach())
        return True

    def mapping(self, node):
        """The rotation a Mapping node in front of `node` applies to directions (identity without one)."""
        mapping = _linked_node(node.inputs["Vector"])
        if mapping is None:
            return np.eye(4)
        if mapping.bl_idname != "ShaderNodeMapping":
            if mapping.bl_idname != "ShaderNodeTexCoord":
                self.unsupported(node, node.inputs["Vector"], mapping)
            return np.eye(4)
        source = _linked_node(mapping.inputs["Vector"])
        if source is not None and source.bl_idname != "ShaderNodeTexCoord":
            self.unsupported(mapping, mapping.inputs["Vector"], source)
        values = {name: tuple(mapping.inputs[name].default_value) for name in ("Location", "Rotation", "Scale")
                  if name in mapping.inputs}
        scale = values.get("Scale", (1.0, 1.0, 1.0))
        if not (scale[0] == scale[1] == scale[2] and scale[0] > 0.0) or (
                mapping.vector_type in ("POINT", "TEXTURE") and any(values.get("Location", (0.0,)))):
            self.warn(f"world '{self.world.name}': node '{mapping.name}': only its rotation is applied to the "
                      "environment (a location or an unequal scale is ignored)")
        rotation = np.eye(4)
        rotation[:3, :3] = euler_xyz(values.get("Rotation", (0.0, 0.0, 0.0)))
        if mapping.vector_type == "TEXTURE":
            rotation[:3, :3] = rotation[:3, :3].T  # the inverse transform
        return rotation


def bake_directions(width, height):
    """(height * width, 3) unit directions at the texel centres of an equirectangular image, rows
    from the bottom (the core's and Blender's image order), as Cycles maps directions to it."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    phi = (0.5 - u) * 2.0 * math.pi            # u = 1/2 - atan2(y, x) / 2 pi
    theta = (v - 0.5) * math.pi                # v = 1/2 + elevation / pi
    cos_t = np.cos(theta)[:, None]
    return np.stack([cos_t * np.cos(phi)[None, :], cos_t * np.sin(phi)[None, :],
                     np.broadcast_to(np.sin(theta)[:, None], (height, width))], axis=-1).reshape(-1, 3)


def euler_xyz(angles):
    """Blender's XYZ Euler rotation (X first): Rz @ Ry @ Rx."""
    x, y, z = angles
    rx = np.array([[1, 0, 0], [0, math.cos(x), -math.sin(x)], [0, math.sin(x), math.cos(x)]])
    ry = np.array([[math.cos(y), 0, math.sin(y)], [0, 1, 0], [-math.sin(y), 0, math.cos(y)]])
    rz = np.array([[math.cos(z), -math.sin(z), 0], [math.sin(z), math.cos(z), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _emits(world):
    """Whether the world's Surface may emit light: anything but a Background of black or strength 0."""
    if not nodes.uses_nodes(world):
        return max(world.color) > 0.0
    node = nodes.surface_source(world.node_tree, "ShaderNodeOutputWorld")
    if node is None or node.bl_idname != "ShaderNodeBackground":
        return False
    strength, color = node.inputs["Strength"], node.inputs["Color"]
    return (bool(strength.links) or strength.default_value > 0.0) and \
        (bool(color.links) or max(tuple(color.default_value)[:3]) > 0.0)


def add_world(core_scene, world, warn, attributes=None, suns=0):
    """The world's background; one the core refuses (negative, NaN, Inf) renders black with a warning.
    `attributes`: the export's object_info.AttributeTable (its view-layer attributes); `suns`: how many
    sun lamps the scene has (a world Volume leaves them no effect: warned)."""
    if world is None:
        core_scene.set_background((0.0, 0.0, 0.0))
        core_scene.set_world_medium(None)
        return
    keywords = volume.world_medium(world, warn, core_scene)
    core_scene.set_world_medium(volume.add(core_scene, f"world '{world.name}'", keywords, warn))
    try:
        WorldExporter(core_scene, world, warn, attributes).export()
    except ValueError as error:
        warn(f"world '{world.name}': not rendered ({error}); the background is black")
        core_scene.set_background((0.0, 0.0, 0.0))
    attenuates = keywords is not None and max(keywords["sigma_a"]) + max(keywords["sigma_s"]) > 0.0
    if attenuates and (suns > 0 or _emits(world)):
        warn(f"world '{world.name}': its Volume fills all space, so sun lamps and the world's own light, "
             "infinitely far away, reach nothing through it (as in Cycles); for fog in sunlight, give the "
             "volume to an object around the scene")
