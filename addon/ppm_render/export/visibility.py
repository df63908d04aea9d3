"""Cycles' ray visibility of objects and lights (Object > Visibility > Ray Visibility), as the core's
`visibility` lists of ray kinds, and whether a light casts shadows.

Volume scatter has no counterpart: the core has no volumes.
"""

import bpy

RAY_FLAGS = (("camera", "visible_camera"), ("diffuse", "visible_diffuse"), ("glossy", "visible_glossy"),
             ("transmission", "visible_transmission"), ("shadow", "visible_shadow"))


def ray_visibility(obj):
    """The ray kinds that see `obj` (all of them in a Blender without the flags)."""
    return [kind for kind, flag in RAY_FLAGS if getattr(obj, flag, True)]


def casts_shadow(light):
    """Cycles 3.x reads the light's Cycles setting `cast_shadow`, 4.0 and later `use_shadow`."""
    cycles = getattr(light, "cycles", None)
    if bpy.app.version < (4, 0, 0) and hasattr(cycles, "cast_shadow"):
        return bool(cycles.cast_shadow)
    return bool(getattr(light, "use_shadow", True))
