"""What the export meets in a scene and cannot render yet, each said once, naming what carries it.

Nothing Blender hands over is dropped silently: a material's Displacement output, light and shadow
linking, light groups, shadow catchers, AOV outputs, Cryptomatte and hair particles drawn as
strands. Each message says what is rendered instead. (Object types the core has no geometry for,
hair Curves, point clouds and Volume objects, are left out by the exporter itself:
export/__init__.py, UNRENDERED_TYPES.)
"""

from . import nodes


def output_driven(socket):
    """Whether anything drives an output node's input (through reroutes; a group counts as driving)."""
    return socket is not None and nodes.driving_node(socket) is not None


def material_outputs(output):
    """Messages about a material's active output node: its Displacement input (its Volume is a
    medium: volume.py)."""
    if output_driven(output.inputs.get("Displacement")):
        return ["its Displacement output is not rendered yet (Cycles' default, Bump Only, shades it as a bump); "
                "the surface is shaded undisplaced"]
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
    return messages
