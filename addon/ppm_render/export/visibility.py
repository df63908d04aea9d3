"""Cycles' ray visibility of objects and lights (Object > Visibility > Ray Visibility), as the core's
`visibility` lists of ray kinds, objects' Holdout, whether a light casts shadows, and how many
bounces a light or the world reaches.

Volume scatter has no counterpart: the core has no volumes.
"""

import bpy

RAY_FLAGS = (("camera", "visible_camera"), ("diffuse", "visible_diffuse"), ("glossy", "visible_glossy"),
             ("transmission", "visible_transmission"), ("shadow", "visible_shadow"))


def ray_visibility(obj):
    """The ray kinds that see `obj` (all of them in a Blender without the flags)."""
    return [kind for kind, flag in RAY_FLAGS if getattr(obj, flag, True)]


def object_flags(obj):
    """The core's `visibility` and `holdout` keywords for an object's geometry (Object > Visibility:
    Ray Visibility, and Holdout: a hole in the image for camera rays, itself for other rays)."""
    return {"visibility": ray_visibility(obj), "holdout": bool(getattr(obj, "is_holdout", False))}


def casts_shadow(light):
    """Cycles 3.x reads the light's Cycles setting `cast_shadow`, 4.0 and later `use_shadow`."""
    cycles = getattr(light, "cycles", None)
    if bpy.app.version < (4, 0, 0) and hasattr(cycles, "cast_shadow"):
        return bool(cycles.cast_shadow)
    return bool(getattr(light, "use_shadow", True))


def own_max_bounces(light_or_world):
    """A light's or the world's Cycles Max Bounces: the longest path it lights (1024, no limit, where
    the Cycles add-on is absent)."""
    return int(getattr(getattr(light_or_world, "cycles", None), "max_bounces", 1024))
