"""What materials, worlds and lights share in reading a Blender node tree: whether it is used, and
which node feeds the active output's Surface."""

import bpy


def uses_nodes(datablock, always_from=(5, 0, 0)):
    """Whether Blender renders `datablock` (a material, world or light) from its node tree. From
    Blender `always_from` on, use_nodes is deprecated (it warns) and the tree is always used."""
    if datablock.node_tree is None:
        return False
    return True if bpy.app.version >= always_from else datablock.use_nodes


def active_output(tree, output_type):
    """The output node of type `output_type` Cycles renders from: the active one meant for all engines or
    Cycles, else the active one, else the first; None if the tree has none."""
    outputs = [n for n in tree.nodes if n.bl_idname == output_type]
    active = ([n for n in outputs if n.is_active_output and getattr(n, "target", "ALL") in ("ALL", "CYCLES")] or
              [n for n in outputs if n.is_active_output] or outputs)
    return active[0] if active else None


def surface_source(tree, output_type, targets=None):
    """The node linked to the Surface socket of the tree's active output of type `output_type` (its
    first one if none is active, or none active for one of `targets`), or None."""
    outputs = [n for n in tree.nodes if n.bl_idname == output_type]
    active = [n for n in outputs if n.is_active_output and (targets is None or n.target in targets)] or outputs
    if not active:
        return None
    links = active[0].inputs["Surface"].links
    return links[0].from_node if links else None


def link_renders(link):
    """Whether Cycles uses a link: it drops muted and invalid ones and those to or from a hidden
    (disabled) socket (blender/shader.cpp, "connect nodes")."""
    return (link.is_valid and not getattr(link, "is_muted", False) and link.from_socket.enabled
            and link.to_socket.enabled)


def driving_node(socket):
    """The node whose output drives `socket` in Cycles, through reroutes; None when nothing does (the
    socket's own value counts). A reroute fed by nothing is returned itself: Cycles reads black from it
    up to Blender 4.5 and the socket's own value from 5.0 on (measured), so callers warn."""
    node = None
    while True:
        links = [link for link in socket.links if link_renders(link)]
        if not links:
            return node
        node = links[0].from_node
        if node.bl_idname != "NodeReroute":
            return node
        socket = node.inputs[0]
