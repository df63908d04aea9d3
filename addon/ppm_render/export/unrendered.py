"""What the export meets in a scene and cannot render yet, each said once, naming what carries it.

Nothing Blender hands over is dropped silently: a material's Volume and Displacement outputs, a
world's Volume output, light and shadow linking, light groups, shadow catchers, AOV outputs,
Cryptomatte and hair particles drawn as strands. Each message says what is rendered instead. (Object
types the core has no geometry for, hair Curves, point clouds and Volume objects, are left out by the
exporter itself: export/__init__.py, UNRENDERED_TYPES.)
"""

from . import nodes


def output_driven(socket):
    """Whether anything drives an output node's input (through reroutes; a group counts as driving)."""
    return socket is not None and nodes.driving_node(socket) is not None


def material_outputs(output):
    """Messages about a material's active output node: its Volume and Displacement inputs."""
    messages = []
    if output_driven(output.inputs.get("Volume")):
        surface = output_driven(output.inputs.get("Surface"))
        messages.append("its Volume output is not rendered yet (no participating media); "
                        + ("its surface is" if surface else
                           "its surface is transparent, as Cycles renders a volume-only material, and") +
                        " rendered without the volume")
    if output_driven(output.inputs.get("Displacement")):
        messages.append("its Displacement output is not rendered yet (Cycles' default, Bump Only, shades it "
                        "as a bump); the surface is shaded undisplaced")
    return messages


def world_outputs(world):
    """Messages about a world's active output: its Volume input."""
    if world is None or not nodes.uses_nodes(world):
        return []
    outputs = [n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    active = [n for n in outputs if n.is_active_output] or outputs
    if active and output_driven(active[0].inputs.get("Volume")):
        return ["its Volume output is not rendered yet (no participating media); the air is left clear"]
    return []


def object_features(obj):
    """Messages about an evaluated object's settings that are not rendered yet."""
    messages = []
    linking = getattr(obj, "light_linking", None)  # Blender 4.0+
    if linking is not None and linking.receiver_collection is not None:
        messages.append("light linking is not rendered yet; it lights every object")
    if linking is not None and linking.blocker_collection is not None:
        messages.append("shadow linking is not rendered yet; every object shadows its light")
    if obj.type != "LIGHT" and getattr(obj, "is_shadow_catcher", False):  # lights report it set
        messages.append("shadow catcher is not rendered yet; it renders as itself")
    if getattr(obj, "lightgroup", ""):
        messages.append(f"light group '{obj.lightgroup}' is not rendered yet; no Light Group pass")
    for system in getattr(obj, "particle_systems", ()):
        settings = system.settings
        if settings.type == "HAIR" and settings.render_type == "PATH":
            messages.append(f"hair of particle system '{system.name}' is not rendered yet; left out")
    return messages


def view_layer_features(view_layer, scene):
    """Messages about the view layer's and the world's settings that are not rendered yet."""
    messages = []
    groups = [group.name for group in getattr(view_layer, "lightgroups", ())]  # Blender 3.5+
    if groups:
        messages.append(f"view layer '{view_layer.name}': light groups ({', '.join(groups)}) are not rendered "
                        "yet; no Light Group passes")
    aovs = [aov.name for aov in getattr(view_layer, "aovs", ())]
    if aovs:
        messages.append(f"view layer '{view_layer.name}': shader AOVs ({', '.join(aovs)}) are not rendered yet; "
                        "their passes stay empty")
    cryptomatte = [kind for kind in ("object", "material", "asset")
                   if getattr(view_layer, f"use_pass_cryptomatte_{kind}", False)]
    if cryptomatte:
        messages.append(f"view layer '{view_layer.name}': Cryptomatte ({', '.join(cryptomatte)}) is not rendered "
                        "yet; no Cryptomatte passes")
    world = scene.world
    if world is not None and getattr(world, "lightgroup", ""):
        messages.append(f"world '{world.name}': light group '{world.lightgroup}' is not rendered yet; "
                        "no Light Group pass")
    messages += [f"world '{world.name}': {message}" for message in world_outputs(world)]
    return messages
