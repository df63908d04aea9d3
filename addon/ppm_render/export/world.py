"""Blender world -> the core's background: a constant radiance (colour * strength), or an image
around the scene (an Environment Texture feeding the Background's colour, equirectangular or mirror
ball, optionally turned by a Mapping node), times the strength.

Reads the Background node feeding the active World Output. Anything else linked to its sockets falls
back to the socket's own value with a warning. The world's ray visibility (World > Settings > Ray
Visibility, `cycles_visibility`) decides which escaping rays see it, and its Max Bounces (World >
Settings > Light Path) the longest path it lights.
"""

import math

import numpy as np

from . import image as image_export
from . import nodes
from .visibility import own_max_bounces

PROJECTIONS = {"EQUIRECTANGULAR": "equirectangular", "MIRROR_BALL": "mirror_ball"}
WORLD_RAY_FLAGS = ("camera", "diffuse", "glossy", "transmission", "shadow")


def _linked_node(socket):
    return socket.links[0].from_node if socket.links else None


def visibility(world):
    settings = getattr(world, "cycles_visibility", None)
    return [kind for kind in WORLD_RAY_FLAGS if getattr(settings, kind, True)]


class WorldExporter:
    """One world's export: warnings name the world and the node."""

    def __init__(self, core_scene, world, warn):
        self.scene, self.world, self.warn = core_scene, world, warn

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
        if strength_socket.links:
            self.unsupported(node, strength_socket, _linked_node(strength_socket))
        strength = float(strength_socket.default_value)
        source = _linked_node(color_socket)
        if source is not None and source.bl_idname == "ShaderNodeTexEnvironment" and self.add_environment(
                source, strength):
            return
        if source is not None and source.bl_idname != "ShaderNodeTexEnvironment":
            self.unsupported(node, color_socket, source)
        color = tuple(float(c) * strength for c in tuple(color_socket.default_value)[:3])
        self.scene.set_background(color, **self.reach())

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


def euler_xyz(angles):
    """Blender's XYZ Euler rotation (X first): Rz @ Ry @ Rx."""
    x, y, z = angles
    rx = np.array([[1, 0, 0], [0, math.cos(x), -math.sin(x)], [0, math.sin(x), math.cos(x)]])
    ry = np.array([[math.cos(y), 0, math.sin(y)], [0, 1, 0], [-math.sin(y), 0, math.cos(y)]])
    rz = np.array([[math.cos(z), -math.sin(z), 0], [math.sin(z), math.cos(z), 0], [0, 0, 1]])
    return rz @ ry @ rx


def add_world(core_scene, world, warn):
    """The world's background; one the core refuses (negative, NaN, Inf) renders black with a warning."""
    if world is None:
        core_scene.set_background((0.0, 0.0, 0.0))
        return
    try:
        WorldExporter(core_scene, world, warn).export()
    except ValueError as error:
        warn(f"world '{world.name}': not rendered ({error}); the background is black")
        core_scene.set_background((0.0, 0.0, 0.0))
