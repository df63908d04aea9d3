"""Blender world -> the core's constant background radiance (colour * strength).

Reads the Background node feeding the active World Output; a texture or any
other node linked to its colour falls back to the socket's own colour with a
warning (the core's background is constant).
"""


import bpy


def _uses_nodes(world):
    # Blender 5.0 deprecates use_nodes (nodes are always used); 3.x still honours it.
    if world.node_tree is None:
        return False
    return True if bpy.app.version >= (5, 0, 0) else world.use_nodes


def _background_node(world):
    if not _uses_nodes(world):
        return None
    tree = world.node_tree
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    active = [n for n in outputs if n.is_active_output] or outputs
    if not active or not active[0].inputs["Surface"].links:
        return None
    return active[0].inputs["Surface"].links[0].from_node


def background_radiance(world, warn):
    """RGB radiance of the world as Cycles renders a constant background."""
    if world is None:
        return (0.0, 0.0, 0.0)
    node = _background_node(world)
    if node is None:
        if _uses_nodes(world):
            return (0.0, 0.0, 0.0)  # a node tree with nothing connected renders black in Cycles
        return tuple(world.color)
    if node.bl_idname != "ShaderNodeBackground":
        warn(f"world '{world.name}': node '{node.name}' ({node.bl_idname}) is not supported; background is black")
        return (0.0, 0.0, 0.0)
    color_socket, strength_socket = node.inputs["Color"], node.inputs["Strength"]
    for socket in (color_socket, strength_socket):
        if socket.links:
            warn(f"world '{world.name}': '{socket.name}' of node '{node.name}' is driven by "
                 f"'{socket.links[0].from_node.name}', which is not supported; using the socket's value")
    strength = float(strength_socket.default_value)
    return tuple(float(c) * strength for c in tuple(color_socket.default_value)[:3])


def add_world(core_scene, world, warn):
    """The world's background; one the core refuses (negative, NaN, Inf) renders black with a warning."""
    radiance = background_radiance(world, warn)
    try:
        core_scene.set_background(radiance)
    except ValueError as error:
        warn(f"world '{world.name}': not rendered ({error}); the background is black")
        core_scene.set_background((0.0, 0.0, 0.0))
