"""The 3D viewport's view as a core camera.

Blender hands a viewport's view to an engine as two matrices (RegionView3D): `view_matrix` (world
to view) and `window_matrix` (the projection of the whole region). Every kind of view is read from
them the same way: a user perspective or orthographic view, and the camera view, whose projection
already holds the camera's lens, shift, zoom and pan and the passepartout around its frame. So the
region is rendered as Cycles renders it: all of it (or its render region, `render_region`), the
camera's frame where the camera sees.

Perspective (OpenGL convention, looking down -Z): x_ndc = P00 x / -z + P02, so the image's centre
lies at x / -z = P02 / P00 and the region's width at distance 1 is 2 / P00; orthographic:
x_ndc = P00 x + P03. Clipping planes come from the third row either way.
"""

import math

import numpy as np


def camera_from_projection(view_matrix, window_matrix, width, height):
    """Keyword arguments for Scene.set_camera (width x height pixels) of a view given by its
    world-to-view and projection matrices (4 x 4, rows)."""
    view = np.array(view_matrix, dtype=float)
    p = np.array(window_matrix, dtype=float)
    camera_to_world = np.linalg.inv(view)
    perspective = abs(p[3, 3]) < 0.5  # an orthographic projection has (0, 0, 0, 1) as last row
    args = {"matrix": camera_to_world, "width": int(width), "height": int(height), "sensor_fit": "horizontal",
            "frame": (0, 0, int(width), int(height))}
    if perspective:
        near, far = p[2, 3] / (p[2, 2] - 1.0), p[2, 3] / (p[2, 2] + 1.0)
        # Shifts in units of the image's width (the fitted side), as set_camera takes them.
        args.update(projection="perspective", fov=2.0 * math.atan(1.0 / p[0, 0]), shift_x=0.5 * p[0, 2],
                    shift_y=0.5 * p[1, 2] * p[0, 0] / p[1, 1])
    else:
        near, far = (p[2, 3] + 1.0) / p[2, 2], (p[2, 3] - 1.0) / p[2, 2]
        args.update(projection="orthographic", ortho_scale=2.0 / p[0, 0], shift_x=-0.5 * p[0, 3],
                    shift_y=-0.5 * p[1, 3] * p[0, 0] / p[1, 1])
        # Blender's orthographic views see behind their eye (near < 0); the core's rays start at
        # the near plane, so the eye moves back to it.
        camera_to_world[:3, 3] -= camera_to_world[:3, 2] * near
        near, far = 0.0, far - near
    args.update(clip_start=float(max(near, 0.0)), clip_end=float(far))
    return args


def with_camera_lens(view, camera_object, dof_mode):
    """`view` with the depth of field of the scene camera it looks through (Cycles shows it in the
    camera view): its focus distance, aperture and focal length, where `dof_mode` is not OFF."""
    from .export.camera import Frame, camera_arguments

    if dof_mode == "OFF" or camera_object is None or camera_object.type != "CAMERA":
        return view
    lens = camera_arguments(camera_object, Frame(view["width"], view["height"]), lambda _: None, dof_mode)
    return {**view, **{key: lens[key] for key in ("focus_distance", "aperture_radius", "focal_length")
                       if key in lens}}


def sub_window(args, x, y, width, height):
    """`args` (a whole region's camera) narrowed to the window of `width` x `height` pixels whose
    bottom-left pixel is (x, y): the same pixels, as a render border renders them."""
    from .export.camera import Frame, window_of

    full_width, full_height = args["frame"][2], args["frame"][3]
    perspective = args["projection"] == "perspective"
    extent = 2.0 * math.tan(0.5 * args["fov"]) if perspective else args["ortho_scale"]  # the region's width
    window_extent, shift_x, shift_y = window_of(Frame(full_width, full_height, x, y, width, height),
                                                extent / full_width, extent, args["shift_x"], args["shift_y"])
    narrowed = {**args, "width": int(width), "height": int(height), "shift_x": shift_x, "shift_y": shift_y,
                "frame": (int(x), int(y), full_width, full_height)}
    if perspective:
        narrowed["fov"] = 2.0 * math.atan(0.5 * window_extent)
    else:
        narrowed["ortho_scale"] = window_extent
    return narrowed


def render_region(context, depsgraph):
    """(x, y, width, height) in region pixels of the part Cycles renders: in the camera view the scene's
    render border within the camera's frame (where Render Region is on), elsewhere the viewport's own
    Render Region; None for the whole region."""
    region, view, space = context.region, context.region_data, context.space_data
    render = depsgraph.scene.render
    if view.view_perspective == "CAMERA":
        camera = depsgraph.scene.camera
        if not render.use_border or camera is None or camera.type != "CAMERA":
            return None
        from bpy_extras.view3d_utils import location_3d_to_region_2d

        corners = [location_3d_to_region_2d(region, view, camera.matrix_world @ corner)
                   for corner in camera.data.view_frame(scene=depsgraph.scene)]
        if any(c is None for c in corners):
            return None
        x0, x1 = min(c.x for c in corners), max(c.x for c in corners)
        y0, y1 = min(c.y for c in corners), max(c.y for c in corners)
        box = (render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y)
    elif getattr(space, "use_render_border", False):
        x0, x1, y0, y1 = 0.0, region.width, 0.0, region.height
        box = (space.render_border_min_x, space.render_border_max_x, space.render_border_min_y,
               space.render_border_max_y)
    else:
        return None
    left = max(0, int(round(x0 + box[0] * (x1 - x0))))
    right = min(region.width, int(round(x0 + box[1] * (x1 - x0))))
    bottom = max(0, int(round(y0 + box[2] * (y1 - y0))))
    top = min(region.height, int(round(y0 + box[3] * (y1 - y0))))
    if right - left < 1 or top - bottom < 1:
        return None
    return left, bottom, right - left, top - bottom


def region_view(context, depsgraph):
    """The set_camera arguments of the viewport region being drawn (`context` of view_draw), narrowed
    to its render region if it has one."""
    region, view = context.region, context.region_data
    args = camera_from_projection(view.view_matrix, view.window_matrix, region.width, region.height)
    window = render_region(context, depsgraph)
    if window is not None:
        args = sub_window(args, *window)
    if view.view_perspective != "CAMERA":
        return args
    scene = depsgraph.scene
    camera = scene.camera.evaluated_get(depsgraph) if scene.camera else None
    return with_camera_lens(args, camera, scene.ppm.dof_mode)
