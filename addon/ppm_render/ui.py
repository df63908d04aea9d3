"""Panels: the PPM render settings, the revolve flag on curves, and the
standard Blender panels (dimensions, output, camera, light, material, world)
opened to the PPM engine through their COMPAT_ENGINES sets."""

import textwrap

import bpy

from . import core

ENGINE = "PPM"

# Standard panels an artist expects; names that a Blender version lacks are skipped.
# Cycles' own panels are left out: they share one COMPAT_ENGINES set and would
# bring every Cycles setting along.
STANDARD_PANELS = (
    "RENDER_PT_format", "RENDER_PT_format_presets", "RENDER_PT_frame_range", "RENDER_PT_time_stretching",
    "RENDER_PT_color_management", "RENDER_PT_color_management_curves", "RENDER_PT_post_processing",
    "RENDER_PT_stamp", "RENDER_PT_stamp_note", "RENDER_PT_stamp_burn",
    "RENDER_PT_output", "RENDER_PT_output_views", "RENDER_PT_encoding", "RENDER_PT_encoding_video",
    "RENDER_PT_encoding_audio", "RENDER_PT_output_color_management",
    "DATA_PT_context_camera", "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof",
    "DATA_PT_camera_dof_aperture", "DATA_PT_camera_display", "DATA_PT_camera_safe_areas",
    "DATA_PT_camera_background_image", "DATA_PT_custom_props_camera",
    "DATA_PT_context_light", "DATA_PT_light", "DATA_PT_EEVEE_light", "DATA_PT_spot", "DATA_PT_area",
    "DATA_PT_custom_props_light",
    "MATERIAL_PT_context_material", "MATERIAL_PT_preview", "MATERIAL_PT_viewport", "MATERIAL_PT_custom_props",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
    "EEVEE_NEXT_MATERIAL_PT_surface", "EEVEE_NEXT_WORLD_PT_surface", "DATA_PT_EEVEE_light_distance",
    "EEVEE_MATERIAL_PT_settings", "EEVEE_NEXT_MATERIAL_PT_settings",
    "WORLD_PT_context_world", "WORLD_PT_custom_props", "EEVEE_WORLD_PT_surface",
    "VIEWLAYER_PT_layer", "VIEWLAYER_PT_layer_passes",
)


def _standard_panels():
    for name in STANDARD_PANELS:
        panel = getattr(bpy.types, name, None)
        if panel is not None and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def draw_core_problem(layout):
    """A red box with the reason when this Blender has no usable compiled core (renders would fail)."""
    problem = core.problem()
    if problem is None:
        return
    box = layout.box()
    box.alert = True
    for i, line in enumerate(textwrap.wrap(problem, 60)):
        box.label(text=line, icon="ERROR" if i == 0 else "BLANK1")


class PPMRenderPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}  # noqa: RUF012 - Blender convention: a mutable set

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RENDER_PT_ppm_sampling(PPMRenderPanel, bpy.types.Panel):
    bl_label = "Photon Mapping"

    def draw(self, context):
        layout = self.layout
        draw_core_problem(layout)
        layout.use_property_split = True
        settings = context.scene.ppm
        col = layout.column()
        col.prop(settings, "passes")
        col.prop(settings, "time_limit")
        col.prop(settings, "target_error")
        sub = col.column()
        sub.active = settings.target_error > 0.0
        sub.prop(settings, "error_confidence")
        if settings.target_error > 0.0 and settings.hit_points == 'FIXED' and settings.samples_per_pixel == 1:
            sub.label(text="1 sample per pixel: anti-aliasing not estimated", icon='ERROR')
        col.prop(settings, "error_passes")
        col.prop(settings, "denoise")
        col.prop(settings, "denoising_data")
        col.prop(settings, "photons_per_pass")
        col.separator()
        col.prop(settings, "alpha")
        col.prop(settings, "threshold")
        col.prop(settings, "cycles_light_paths")
        sub = col.column()
        sub.active = not settings.cycles_light_paths
        sub.prop(settings, "max_bounces")
        col.prop(settings, "samples_per_pixel")
        sub = col.column()
        sub.active = settings.hit_points != 'FIXED'
        sub.prop(settings, "adaptive_samples")
        col.prop(settings, "photon_guiding")
        col.prop(settings, "volume_beams")


class RENDER_PT_ppm_viewport(PPMRenderPanel, bpy.types.Panel):
    bl_label = "Viewport"
    bl_options = {"DEFAULT_CLOSED"}  # noqa: RUF012 - Blender reads a plain set

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.ppm
        col = layout.column()
        col.prop(settings, "viewport_passes", text="Passes")
        col.prop(settings, "viewport_time_limit", text="Time Limit")
        col.prop(settings, "viewport_photons_per_pass", text="Photons per Pass")


class RENDER_PT_ppm_camera(PPMRenderPanel, bpy.types.Panel):
    bl_label = "Camera and Performance"
    bl_options = {"DEFAULT_CLOSED"}  # noqa: RUF012 - Blender reads a plain set

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        settings = context.scene.ppm
        layout.prop(settings, "dof_mode")
        layout.prop(settings, "hit_points")
        layout.prop(settings, "seed")
        layout.prop(settings, "animated_seed")
        layout.prop(settings, "threads")


class VIEWLAYER_PT_ppm_passes(PPMRenderPanel, bpy.types.Panel):
    """The passes PPM writes, under View Layer Properties > Passes (Blender's own subpanels there are
    EEVEE's and would offer passes PPM does not write)."""
    bl_label = "PPM Passes"
    bl_context = "view_layer"
    bl_parent_id = "VIEWLAYER_PT_layer_passes"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layer, settings = context.view_layer, context.scene.ppm
        col = layout.column(heading="Data", align=True)
        col.prop(layer, "use_pass_z")
        col.prop(layer, "use_pass_normal")
        col.prop(layer, "use_pass_object_index")
        col.prop(layer, "use_pass_material_index")
        col.prop(settings, "denoising_data")
        col = layout.column(heading="Light", align=True)
        for kind, heading in (("diffuse", "Diffuse"), ("glossy", "Glossy"), ("transmission", "Transmission")):
            row = col.row(heading=heading, align=True)
            for part in ("direct", "indirect", "color"):
                row.prop(layer, f"use_pass_{kind}_{part}", text=part.capitalize(), toggle=True)
        col.prop(layer, "use_pass_emit", text="Emission")
        col.prop(layer, "use_pass_environment")
        col.prop(settings, "caustic_pass")
        col = layout.column(heading="Error", align=True)
        col.prop(settings, "error_passes")


class OBJECT_PT_ppm_revolve(bpy.types.Panel):
    bl_label = "PPM Bezier Revolve"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "CURVE"

    def draw(self, context):
        layout = self.layout
        layout.prop(context.object.ppm, "revolve")
        layout.label(text="Profile in local XY: radius = X, height = Y, axis = local Y")


classes = (RENDER_PT_ppm_sampling, RENDER_PT_ppm_viewport, RENDER_PT_ppm_camera, VIEWLAYER_PT_ppm_passes,
           OBJECT_PT_ppm_revolve)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    for panel in _standard_panels():
        # A new set on this class: panels may share their base class's set (Cycles' do).
        panel.COMPAT_ENGINES = set(panel.COMPAT_ENGINES) | {ENGINE}


def unregister():
    for panel in _standard_panels():
        panel.COMPAT_ENGINES = set(panel.COMPAT_ENGINES) - {ENGINE}
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
