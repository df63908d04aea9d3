"""The Bezier revolve object: a Curve object whose 2-D Bezier profile (local
XY: radius = X, height = Y) the renderer revolves exactly about local Y.

Add > Curve > Bezier Revolve creates one (upright: rotated 90 degrees about X
so that local Y is world Z); "Make Bezier Revolve" flags existing curves. A
Screw modifier about local Y shows the swept surface in Solid, EEVEE and
Cycles and follows Edit Mode changes; the PPM exporter ignores that preview
mesh and sends the exact control points (export/bezier.py).
"""

import math

import bpy

PREVIEW_MODIFIER = "PPM Revolve Preview"

# A vase: (radius, height) of the profile's points, bottom centre first.
DEFAULT_PROFILE = ((0.0, 0.0), (0.45, 0.08), (0.55, 0.7), (0.22, 1.3), (0.34, 1.7))


def add_preview(obj):
    """A Screw modifier sweeping the profile about local Y (a viewport and other-engine stand-in)."""
    screw = obj.modifiers.get(PREVIEW_MODIFIER) or obj.modifiers.new(PREVIEW_MODIFIER, "SCREW")
    screw.axis = "Y"
    screw.angle = 2.0 * math.pi
    screw.steps = 48
    screw.render_steps = 96
    screw.use_merge_vertices = True
    screw.use_smooth_shade = True
    return screw


def make_revolve(obj):
    obj.ppm.revolve = True
    obj.data.fill_mode = "NONE" if obj.data.dimensions == "2D" else obj.data.fill_mode
    add_preview(obj)


def new_profile_curve(name):
    curve = bpy.data.curves.new(name, "CURVE")
    curve.dimensions = "2D"
    curve.fill_mode = "NONE"
    spline = curve.splines.new("BEZIER")
    spline.bezier_points.add(len(DEFAULT_PROFILE) - 1)
    for point, (radius, height) in zip(spline.bezier_points, DEFAULT_PROFILE):
        point.co = (radius, height, 0.0)
        point.handle_left_type = point.handle_right_type = "AUTO"
    first = spline.bezier_points[0]
    # The bottom starts on the axis heading outwards, so the base closes flat.
    first.handle_left_type = first.handle_right_type = "FREE"
    first.handle_left = (-0.15, 0.0, 0.0)
    first.handle_right = (0.15, 0.0, 0.0)
    return curve


class CURVE_OT_ppm_bezier_revolve_add(bpy.types.Operator):
    """Add a Bezier profile rendered by PPM as an exact surface of revolution"""

    bl_idname = "curve.ppm_bezier_revolve_add"
    bl_label = "Bezier Revolve"
    bl_options = {"REGISTER", "UNDO"}  # noqa: RUF012 - Blender reads a plain set

    def execute(self, context):
        obj = bpy.data.objects.new("BezierRevolve", new_profile_curve("BezierRevolve"))
        context.collection.objects.link(obj)
        obj.location = context.scene.cursor.location
        obj.rotation_euler = (math.pi / 2.0, 0.0, 0.0)  # local Y (the axis) = world Z
        make_revolve(obj)
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


class OBJECT_OT_ppm_make_revolve(bpy.types.Operator):
    """Render the selected curves as exact surfaces of revolution of their Bezier profiles about local Y"""

    bl_idname = "object.ppm_make_revolve"
    bl_label = "Make Bezier Revolve"
    bl_options = {"REGISTER", "UNDO"}  # noqa: RUF012 - Blender reads a plain set

    @classmethod
    def poll(cls, context):
        return any(o.type == "CURVE" for o in context.selected_objects)

    def execute(self, context):
        curves = [o for o in context.selected_objects if o.type == "CURVE"]
        for obj in curves:
            make_revolve(obj)
        self.report({"INFO"}, f"{len(curves)} curve(s) made Bezier revolve objects")
        return {"FINISHED"}


def add_menu(self, context):
    self.layout.operator(CURVE_OT_ppm_bezier_revolve_add.bl_idname, icon="MOD_SCREW")


def convert_menu(self, context):
    self.layout.operator(OBJECT_OT_ppm_make_revolve.bl_idname, icon="MOD_SCREW")


classes = (CURVE_OT_ppm_bezier_revolve_add, OBJECT_OT_ppm_make_revolve)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_curve_add.append(add_menu)
    bpy.types.VIEW3D_MT_object_convert.append(convert_menu)


def unregister():
    bpy.types.VIEW3D_MT_object_convert.remove(convert_menu)
    bpy.types.VIEW3D_MT_curve_add.remove(add_menu)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
