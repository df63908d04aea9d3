"""Bezier revolve curves -> the core's exact surface of revolution.

Convention (also used by the Add > Curve > Bezier Revolve operator): the
profile is drawn in the curve's local XY plane (a 2-D curve), radius = local
x, height = local y, and the surface revolves about the curve's local Y axis
(the Screw preview uses axis Y too). The core revolves about its local Z, so
the matrix handed to it is matrix_world @ R, R mapping core (x, y, z) to
Blender local (x, z, -y). Each Bezier spline is a chain of cubics sent with
its exact control points p0, h0_right, h1_left, p1, ... (3k+1 points; a
cyclic spline closes back to p0). Local z is ignored.
"""

import numpy as np

from . import visibility

# Core local (x, y, z) -> curve local (x, z, -y): core Z (the axis) becomes curve Y.
CORE_TO_CURVE = np.array([[1.0, 0.0, 0.0, 0.0],
                          [0.0, 0.0, 1.0, 0.0],
                          [0.0, -1.0, 0.0, 0.0],
                          [0.0, 0.0, 0.0, 1.0]])


def is_revolve(obj):
    """True for a curve object flagged as a Bezier revolve (evaluated or original)."""
    if obj is None or obj.type != "CURVE":
        return False
    original = getattr(obj, "original", obj)
    settings = getattr(original, "ppm", None)
    return bool(settings and settings.revolve)


def _points(collection, attribute):
    out = np.empty(len(collection) * 3, dtype=np.float64)
    collection.foreach_get(attribute, out)
    return out.reshape(-1, 3)


def spline_profile(spline):
    """(3k+1, 2) control points (radius, height) of one Bezier spline, or None if it has no segment.

    A one-point spline has none, cyclic or not: Blender draws nothing for it (nor does the Screw preview)."""
    points = spline.bezier_points
    n = len(points)
    if n < 2:
        return None
    co = _points(points, "co")
    left = _points(points, "handle_left")
    right = _points(points, "handle_right")
    segments = n if spline.use_cyclic_u else n - 1
    chain = [co[0]]
    for i in range(segments):
        j = (i + 1) % n
        chain += [right[i], left[j], co[j]]
    return np.asarray(chain)[:, :2].copy()


def add_revolve(core_scene, item, material_index, warn):
    """Adds every Bezier spline of a curve (an Instance, evaluated) as a revolve, with its object's
    ray visibility and holdout; returns how many."""
    name = item.name
    core_matrix = item.matrix @ CORE_TO_CURVE
    flags = visibility.object_flags(item.obj)
    added = 0
    for index, spline in enumerate(item.obj.data.splines):
        if spline.type != "BEZIER":
            warn(f"'{name}': spline {index} is {spline.type}, not Bezier; skipped by the revolve export")
            continue
        profile = spline_profile(spline)
        if profile is None:
            warn(f"'{name}': spline {index} has fewer than 2 points, so no profile to revolve; skipped")
            continue
        if not np.any(profile[:, 0]):
            warn(f"'{name}': spline {index} lies on the revolve axis (radius 0 everywhere), so it has no "
                 "surface; skipped")
            continue
        core_scene.add_bezier_revolve(f"{name}.{index}", profile, kind="chain", matrix=core_matrix,
                                      material=material_index, object_id=item.object_id, **flags)
        added += 1
    return added
