"""Blender lights -> core lights, in the units of the running Blender's Cycles.

The core takes point/sphere/spot power in W (intensity P/4pi), area lights as
emitted flux (radiance P/(pi A)) and sun irradiance in W/m^2 (see the core's
README). Blender's conventions, measured against Cycles of each version:
- point and spot: intensity P/(4 pi) in 3.4 and 5.0 -> power passes through;
- area: radiance P/(4A) in 3.x, P/(pi A) in 4.x+ (P/pi without `normalize`)
  -> we compute Blender's radiance and hand the core flux = radiance * pi * A;
- sun: strength = irradiance;
- Blender 4.5+ without `normalize`: radiance P/pi for area and sphere lights, and a sun's
  irradiance scaled by its disk's area pi tan^2(angle/2).
Blender 4.5+'s `exposure` multiplies everything by 2^exposure. A is the light's
area after the object's scale (Cycles scales the size by the matrix, and so
does the core when given the matrix).
"""

import math

import bpy
import numpy as np

from . import blackbody, nodes, visibility

AREA_RADIANCE_IS_OVER_PI = bpy.app.version >= (4, 0, 0)
# Cycles 3.x multiplies a spot's intensity by the cosine to its axis; 4.0 dropped the factor.
SPOT_COSINE_FALLOFF = bpy.app.version < (4, 0, 0)
# Cycles 3.4 renders a sun of Blender's largest angle (180 degrees) as no light, 4.2 and later as a
# hemisphere (both measured, tests/blenders/cycles_compare.py; 3.5-4.1 not tested).
SUN_OF_180_DEGREES_IS_DARK = bpy.app.version < (4, 0, 0)
MAX_POWER = 1e20  # the core's limit of a light's power, irradiance or flux (scene.h: kMaxPower)


def _soft_falloff(light):
    """Cycles' soft falloff of sphere lights: the only behaviour before 4.0, a light option since."""
    return bpy.app.version < (4, 0, 0) or bool(getattr(light, "use_soft_falloff", True))


def _strength(light):
    """Blender's colour * energy * 2^exposure as an RGB triple."""
    scale = light.energy * 2.0 ** getattr(light, "exposure", 0.0)
    return tuple(float(c) * scale for c in light.color)


def _clamped(power, name, warn):
    """`power` (a light's power, irradiance or flux) at most the core's MAX_POWER, with a warning where it
    was above: Cycles renders such a light, and so does PPM, as bright as it can (as emission is)."""
    if not max(power) > MAX_POWER:
        return power
    warn(f"light '{name}': its power {max(power):g} is above the supported {MAX_POWER:g}; clamped to it")
    return tuple(min(c, MAX_POWER) for c in power)


def _normalized(light):
    return getattr(light, "normalize", True)


def _area_size(light):
    """(size_x, size_y, is_disk) of an area light in its local units."""
    shape = light.shape
    sx = light.size
    sy = light.size_y if shape in ("RECTANGLE", "ELLIPSE") else light.size
    return sx, sy, shape in ("DISK", "ELLIPSE")


def area_flux(light, matrix):
    """The core's flux for a Blender area light so that its radiance is Cycles'."""
    sx, sy, disk = _area_size(light)
    m = np.asarray(matrix, dtype=float)
    area = sx * np.linalg.norm(m[:3, 0]) * sy * np.linalg.norm(m[:3, 1])
    if disk:
        area *= math.pi / 4.0
    if not area > 0.0:
        raise ValueError("its area is zero, so it emits no light (as in Cycles)")
    strength = np.array(_strength(light))
    if AREA_RADIANCE_IS_OVER_PI:
        radiance = strength / (math.pi * area) if _normalized(light) else strength / math.pi
    else:
        radiance = strength / (4.0 * area)
    return tuple(radiance * math.pi * area), (sx, sy), disk


def _sphere_power(light, radius):
    """Point/spot power. Without `normalize` (4.5+), Cycles gives a sphere light the radiance P/pi
    (measured, like area lights), i.e. intensity P r^2: the core's power is then 4 pi r^2 P."""
    strength = _strength(light)
    if radius > 0.0 and not _normalized(light):
        return tuple(c * 4.0 * math.pi * radius * radius for c in strength)
    return strength


def _sun_irradiance(light):
    """Sun strength is irradiance; without `normalize` (4.5+) Cycles multiplies it by the sun disk's
    area on the unit-distance plane, pi tan^2(angle/2) (measured; a sharp sun stays normalised)."""
    strength = _strength(light)
    half = 0.5 * float(light.angle)
    if half > 0.0 and not _normalized(light):
        return tuple(c * math.pi * math.tan(half) ** 2 for c in strength)
    return strength


def _is_fixed_blackbody(node):
    """Whether `node` is an unmuted Blackbody node whose Temperature nothing drives: Cycles folds it
    to one colour."""
    return (node.bl_idname == "ShaderNodeBlackbody" and not node.mute
            and nodes.driving_node(node.inputs["Temperature"]) is None)


def node_emission(light, name, warn):
    """Strength x Color of the Emission node feeding a light's node tree output, which Cycles
    multiplies the light's power by: (1, 1, 1) without a node tree, black with nothing connected.
    A Color driven (through reroutes) by a Blackbody node of fixed temperature is its colour; a
    socket driven by any other node counts as its own value, with a warning."""
    if not nodes.uses_nodes(light, always_from=(5, 1, 0)):  # lights' use_nodes went at 5.1
        return (1.0, 1.0, 1.0)
    node = nodes.surface_source(light.node_tree, "ShaderNodeOutputLight")
    if node is None:
        return (0.0, 0.0, 0.0)
    if node.bl_idname != "ShaderNodeEmission":
        warn(f"light '{name}': node '{node.name}' ({node.bl_idname}) is not supported; the light's own power is used")
        return (1.0, 1.0, 1.0)
    color = tuple(float(c) for c in tuple(node.inputs["Color"].default_value)[:3])
    strength = float(node.inputs["Strength"].default_value)
    for socket in (node.inputs["Color"], node.inputs["Strength"]):
        source = nodes.driving_node(socket)
        if source is None:
            continue
        if socket.name == "Color" and _is_fixed_blackbody(source):
            color = blackbody.blackbody_rgb(source.inputs["Temperature"].default_value)
            continue
        hint = " (a Blackbody only with an unlinked Temperature)" if source.bl_idname == "ShaderNodeBlackbody" else ""
        warn(f"light '{name}': '{socket.name}' of node '{node.name}' is driven by '{source.name}', which is not "
             f"supported{hint}; using the socket's value")
    return tuple(c * strength for c in color)


def add_light(core_scene, item, warn):
    """Adds one Blender light (an Instance of an object of type LIGHT) to the core scene."""
    light, name, m = item.obj.data, item.name, item.matrix
    kind = light.type
    seen = {"visibility": visibility.ray_visibility(item.obj), "cast_shadow": visibility.casts_shadow(light),
            "max_bounces": visibility.own_max_bounces(light),
            "color": node_emission(light, name, warn)}
    if light.energy < 0.0:
        raise ValueError("its power is negative (Cycles subtracts such a light's contribution; PPM does not "
                         "render negative lights)")
    if kind == "POINT":
        radius = float(light.shadow_soft_size)
        core_scene.add_light("point", name=name, power=_clamped(_sphere_power(light, radius), name, warn), matrix=m,
                             radius=radius, soft_falloff=_soft_falloff(light), **seen)
    elif kind == "SPOT":
        radius = float(light.shadow_soft_size)
        core_scene.add_light("spot", name=name, power=_clamped(_sphere_power(light, radius), name, warn), matrix=m,
                             radius=radius, spot_angle=float(light.spot_size), spot_blend=float(light.spot_blend),
                             spot_cosine_falloff=SPOT_COSINE_FALLOFF, soft_falloff=_soft_falloff(light), **seen)
    elif kind == "AREA":
        try:
            flux, size, disk = area_flux(light, m)
        except ValueError as error:
            raise ValueError(f"light '{name}': {error}") from None
        # Blender's largest spread, pi in float32, is a hair above pi in double.
        spread = min(float(getattr(light, "spread", math.pi)), math.pi)
        core_scene.add_light("disk" if disk else "rectangle", name=name, power=_clamped(flux, name, warn), matrix=m,
                             size=size, spread=spread, **seen)
    elif kind == "SUN":
        if SUN_OF_180_DEGREES_IS_DARK and light.angle >= math.pi - 1e-6:
            raise ValueError("its angle is 180 degrees, for which Cycles of this Blender emits no light; left "
                             "out as Cycles does")
        # Blender's largest angle, pi in float32, is a hair above pi in double.
        core_scene.add_light("sun", name=name, power=_clamped(_sun_irradiance(light), name, warn), matrix=m,
                             angle=min(float(light.angle), math.pi), **seen)
    else:
        warn(f"light '{name}': type {kind} is not supported; skipped")
