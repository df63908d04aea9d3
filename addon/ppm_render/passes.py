"""Depth and Normal render passes, when the view layer enables them.

Both come from one ray per pixel centre through the core's batch ray caster
(`Scene.intersect`), with the camera model of engine/scene/camera.cpp:
image-plane coordinates in units of the fitted extent plus shift, looking down
local -Z. Depth is Cycles' Z pass: the distance along the view axis (1e10 where
nothing is hit); Normal is the world-space normal (zero where nothing is hit).
Rows come out bottom-up, as Blender stores them.
"""

import math

import numpy as np

MISS_DEPTH = 1e10  # what Cycles writes for the background


def camera_rays(args):
    """(origins, directions, view axis) for every pixel centre, bottom row first."""
    w, h = args["width"], args["height"]
    m = np.asarray(args["matrix"], dtype=float)
    right, up, back, eye = m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3]
    ortho = args["projection"] == "orthographic"
    extent = args["ortho_scale"] if ortho else 2.0 * math.tan(0.5 * args["fov"])
    pixel = extent / w  # the add-on always fits horizontally (export/camera.py)
    x = (np.arange(w) + 0.5 - 0.5 * w) * pixel + args["shift_x"] * extent
    y = (np.arange(h) + 0.5 - 0.5 * h) * pixel + args["shift_y"] * extent
    X, Y = np.meshgrid(x, y)
    if ortho:
        origins = eye + X[..., None] * right + Y[..., None] * up
        directions = np.broadcast_to(-back, origins.shape)
    else:
        directions = X[..., None] * right + Y[..., None] * up - back
        directions = directions / np.linalg.norm(directions, axis=-1, keepdims=True)
        origins = np.broadcast_to(eye, directions.shape)
    return origins.reshape(-1, 3), np.ascontiguousarray(directions.reshape(-1, 3)), -back


def depth_and_normal(core_scene, args):
    """(H, W) depth along the view axis and (H, W, 3) world normals, bottom row first."""
    origins, directions, axis = camera_rays(args)
    hits = core_scene.intersect(np.ascontiguousarray(origins), directions, ray_kind="camera")
    t = np.asarray(hits["t"])
    hit = np.isfinite(t)
    depth = np.full(t.shape, MISS_DEPTH, dtype=np.float32)
    along = directions[hit] @ axis
    depth[hit] = t[hit] * along
    if args["projection"] == "orthographic":
        depth[hit] = t[hit]
    normal = np.where(hit[:, None], np.asarray(hits["normal"]), 0.0).astype(np.float32)
    h, w = args["height"], args["width"]
    return depth.reshape(h, w), normal.reshape(h, w, 3)


def write_pass(result, name, pixels):
    """Copies a bottom-up (H, W[, C]) array into a named pass of the result, if it exists."""
    render_pass = result.layers[0].passes.get(name)
    if render_pass is None:
        return
    flat = np.ascontiguousarray(pixels, dtype=np.float32)
    try:
        render_pass.rect.foreach_set(flat.ravel())
    except (TypeError, ValueError, RuntimeError):
        render_pass.rect.foreach_set(flat.reshape(flat.shape[0] * flat.shape[1], -1))
